#pragma once
// Fixed number formats: outputs are byte-identical between runs of the same input.

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

namespace dynamap {

/// `v` printed with a printf `format` of one double ("%.3f"), cut at 63 characters.
inline std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

/// Appends `v` with `decimals` (0-9) fixed decimals, the same characters as fmt("%.<decimals>f",
/// v): std::to_chars is printf's conversion without its format parsing and locale, for the
/// rows written after every scan.
inline void appendFixedExact(std::string& out, double v, int decimals) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf - 1, v, std::chars_format::fixed, decimals);
  if (r.ec == std::errc()) {
    out.append(buf, r.ptr);
  } else {  // longer than fmt's buffer: fmt cuts it the same way
    const char format[] = {'%', '.', static_cast<char>('0' + decimals), 'f', '\0'};
    out += fmt(format, v);
  }
}

/// appendFixed's quick path: v * 10^decimals rounded as an integer, when that is surely the
/// rounding of v's exact value (magnitude below 2^40, where the product's error is under 2^-12
/// of a unit, and not within 1e-3 of a tie). False, appending nothing, otherwise.
inline bool appendFixedScaled(std::string& out, double v, int decimals) {
  static constexpr double kPow10[] = {1, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9};
  if (decimals < 0 || decimals > 9) return false;
  const double scaled = std::fabs(v) * kPow10[decimals];
  if (!(scaled < 1099511627776.0)) return false;  // 2^40; also NaN
  const double whole = std::floor(scaled);
  const double part = scaled - whole;
  if (std::fabs(part - 0.5) < 1e-3) return false;
  auto digits = static_cast<std::uint64_t>(whole) + (part > 0.5 ? 1 : 0);
  char buf[32];
  char* p = buf + sizeof buf;
  for (int i = 0; i < decimals; ++i, digits /= 10) *--p = static_cast<char>('0' + digits % 10);
  if (decimals > 0) *--p = '.';
  do {
    *--p = static_cast<char>('0' + digits % 10);
    digits /= 10;
  } while (digits != 0);
  if (std::signbit(v)) *--p = '-';  // printf keeps the sign of a negative that rounds to 0
  out.append(p, buf + sizeof buf);
  return true;
}

/// Appends `v` as appendFixedExact does, by the quick path where it is sure to agree.
inline void appendFixed(std::string& out, double v, int decimals) {
  if (!appendFixedScaled(out, v, decimals)) appendFixedExact(out, v, decimals);
}

/// Appends an integer in decimal.
template <typename Int>
void appendInt(std::string& out, Int v) {
  char buf[24];
  out.append(buf, std::to_chars(buf, buf + sizeof buf, v).ptr);
}

}  // namespace dynamap
