#pragma once
// Angles: the one wrap of the project, so every layer agrees on where an angle's turn begins.

#include <cmath>

namespace dynamap {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegToRad = kPi / 180.0;

/// `a` wrapped into (-pi, pi]: `a` minus the nearest multiple of 2 pi. std::remainder computes
/// that difference exactly (no rounding, however many turns `a` holds); -pi becomes pi.
inline double wrapAngle(double a) {
  constexpr double kTwoPi = 2 * kPi;
  a = std::remainder(a, kTwoPi);
  return a <= -kTwoPi / 2 ? a + kTwoPi : a;
}

}  // namespace dynamap
