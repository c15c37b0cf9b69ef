#pragma once
// Statistics shared by the benchmark programs.

#include <algorithm>
#include <vector>

namespace dynamap::bench {

/// The median of `v` (the upper one of an even count); `v` must not be empty.
template <typename T>
T median(std::vector<T> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace dynamap::bench
