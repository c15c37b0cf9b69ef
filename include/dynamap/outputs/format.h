#pragma once
// Fixed number formats: outputs are byte-identical between runs of the same input.

#include <cstdio>
#include <string>

namespace dynamap {

/// `v` printed with a printf `format` of one double ("%.3f").
inline std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

}  // namespace dynamap
