#pragma once
// Fixed number formats: outputs are byte-identical between runs of the same input.

#include <charconv>
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
inline void appendFixed(std::string& out, double v, int decimals) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf - 1, v, std::chars_format::fixed, decimals);
  if (r.ec == std::errc()) {
    out.append(buf, r.ptr);
  } else {  // longer than fmt's buffer: fmt cuts it the same way
    const char format[] = {'%', '.', static_cast<char>('0' + decimals), 'f', '\0'};
    out += fmt(format, v);
  }
}

/// Appends an integer in decimal.
template <typename Int>
void appendInt(std::string& out, Int v) {
  char buf[24];
  out.append(buf, std::to_chars(buf, buf + sizeof buf, v).ptr);
}

}  // namespace dynamap
