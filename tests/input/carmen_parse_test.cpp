// The CARMEN parser line by line: message types, PARAM lines, the laser geometry and numbers read
// bit for bit as strtod reads them. The streaming reader: carmen_reader_test.cpp.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "dynamap/input/carmen_reader.h"

namespace dynamap {
namespace {

constexpr double kDeg = M_PI / 180.0;

TEST(CarmenGeometry, StepFromBeamCountWhenNoParam) {
  const CarmenLaserParams none;
  const CarmenOptions defaults;
  for (const auto& [beams, step_deg] : std::vector<std::pair<std::size_t, double>>{
           {180, 1.0}, {181, 1.0}, {360, 0.5}, {361, 0.5}}) {
    const LaserGeometry g = laserGeometry(beams, none, defaults);
    EXPECT_NEAR(g.start, -90 * kDeg, 1e-12) << beams;
    EXPECT_NEAR(g.step, step_deg * kDeg, 1e-12) << beams;
  }
}

TEST(CarmenGeometry, ParamsAndOverride) {
  CarmenLaserParams params;
  params.resolution_deg = 1.0;
  params.fov_deg = 100;
  EXPECT_NEAR(laserGeometry(100, params, {}).step, 1.0 * kDeg, 1e-12);
  EXPECT_NEAR(laserGeometry(100, params, {}).start, -50 * kDeg, 1e-12);
  CarmenOptions override_fov;
  override_fov.fov_deg = 90;  // wins over the PARAMs; the step follows from the count
  EXPECT_NEAR(laserGeometry(180, params, override_fov).step, 0.5 * kDeg, 1e-12);
  EXPECT_NEAR(laserGeometry(180, params, override_fov).start, -45 * kDeg, 1e-12);
}

TEST(CarmenParse, LineTypes) {
  const CarmenLine odom = parseCarmenLine("ODOM 1 2 3 0.5 0.1 0 12.5 robot 13.0");
  ASSERT_TRUE(odom.odometry);
  EXPECT_DOUBLE_EQ(odom.odometry->pose.y, 2);
  EXPECT_DOUBLE_EQ(odom.odometry->t, 12.5);  // ipc, not logger
  EXPECT_EQ(parseCarmenLine("  # comment").type, "#");
  EXPECT_EQ(parseCarmenLine(" \t").type, "");
  // Vertical tabs and form feeds separate fields too: a line of them is blank, not a crash.
  EXPECT_EQ(parseCarmenLine("\v").type, "");
  EXPECT_EQ(parseCarmenLine(" \f\v ").type, "");
  const CarmenLine sync = parseCarmenLine("SYNC tag 1 h 1");
  EXPECT_EQ(sync.type, "SYNC");
  EXPECT_FALSE(sync.laser || sync.odometry || sync.param);
  const CarmenLine param = parseCarmenLine("PARAM robot_frontlaser_offset 0.0 nohost 0");
  ASSERT_TRUE(param.param);
  EXPECT_EQ(param.param->second, "0.0");
  EXPECT_THROW(parseCarmenLine("FLASER 1 1.0 0 0 0 0 0 0 1 h 1"), CarmenParseError);  // 1 beam
}

TEST(CarmenParams, OnlyTheLaserOnesMatter) {
  CarmenParams p;
  EXPECT_TRUE(p.applyParam("robot_frontlaser_offset", "-0.04"));
  // An offset over 10 m would throw the robot's pose (the line's less the offset) anywhere.
  CarmenParams q;
  EXPECT_TRUE(q.applyParam("robot_rearlaser_offset", "-10"));
  EXPECT_THROW(q.applyParam("robot_frontlaser_offset", "10.5"), CarmenParseError);
  EXPECT_THROW(q.applyParam("robot_rearlaser_offset", "-1e300"), CarmenParseError);
  EXPECT_TRUE(p.applyParam("laser_front_laser_fov", "180"));
  EXPECT_FALSE(p.applyParam("robot_use_sonar", "off"));
  EXPECT_THROW(p.applyParam("laser_front_laser_resolution", "0"), CarmenParseError);
  // An angle over a turn is a damaged number, not an infinite aperture.
  EXPECT_THROW(p.applyParam("laser_front_laser_fov", "1e300"), CarmenParseError);
  EXPECT_THROW(p.applyParam("laser_rear_laser_resolution", "361"), CarmenParseError);
  EXPECT_TRUE(p.applyParam("laser_rear_laser_fov", "360"));
  EXPECT_DOUBLE_EQ(*p.front.offset_x, -0.04);
  EXPECT_DOUBLE_EQ(*p.front.fov_deg, 180);
  EXPECT_FALSE(p.rear.offset_x);
}

TEST(CarmenNumbers, FromCharsAsStrtodDidSubnormalsApart) {
  double v = 0;
  EXPECT_EQ(parseCarmenNumber("+1.5", v), CarmenNumber::kOk);
  EXPECT_DOUBLE_EQ(v, 1.5);
  EXPECT_EQ(parseCarmenNumber("-0.25e1", v), CarmenNumber::kOk);
  EXPECT_DOUBLE_EQ(v, -2.5);
  EXPECT_EQ(parseCarmenNumber("5.45506e-312", v), CarmenNumber::kSubnormal);
  EXPECT_EQ(parseCarmenNumber("1e400", v), CarmenNumber::kNotFinite);
  EXPECT_EQ(parseCarmenNumber("nan", v), CarmenNumber::kNotFinite);
  EXPECT_EQ(parseCarmenNumber("1.5x", v), CarmenNumber::kNotNumber);
  EXPECT_EQ(parseCarmenNumber("+-1", v), CarmenNumber::kNotNumber);
  EXPECT_EQ(parseCarmenNumber("", v), CarmenNumber::kNotNumber);
  // The same double as strtod, bit for bit, for numbers written the ways logs write them.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-2000.0, 2000.0);
  for (int i = 0; i < 20000; ++i) {
    char buf[64];
    const char* fmt = i % 3 == 0 ? "%.6f" : i % 3 == 1 ? "%g" : "%.17g";
    std::snprintf(buf, sizeof buf, fmt, u(rng) * (i % 7 == 0 ? 1e6 : 1.0));
    ASSERT_EQ(parseCarmenNumber(buf, v), CarmenNumber::kOk) << buf;
    ASSERT_EQ(v, std::strtod(buf, nullptr)) << buf;
  }
}

TEST(CarmenNumbers, PlainDecimalsUpToFifteenDigitsAreStrtodsDoubleBitForBit) {
  // The short path for plain decimals: 1 to 17 digits (over 15 take the general one), the point
  // anywhere (also first or last), a sign or none, leading zeros, -0.
  std::mt19937 rng(11);
  for (int i = 0; i < 200000; ++i) {
    const int n = 1 + static_cast<int>(rng() % 17);
    std::string s = rng() % 2 ? "-" : "";
    const int point = static_cast<int>(rng() % static_cast<unsigned>(n + 2)) - 1;  // -1: none
    for (int d = 0; d < n; ++d) {
      if (d == point) s += '.';
      s += static_cast<char>('0' + (d == 0 && rng() % 4 ? 0 : rng() % 10));
    }
    if (point == n) s += '.';
    double v = 0;
    ASSERT_EQ(parseCarmenNumber(s, v), CarmenNumber::kOk) << s;
    const double expected = std::strtod(s.c_str(), nullptr);
    ASSERT_EQ(std::memcmp(&v, &expected, sizeof v), 0) << s << " " << v << " " << expected;
  }
  double v = 0;
  EXPECT_EQ(parseCarmenNumber("-", v), CarmenNumber::kNotNumber);
  EXPECT_EQ(parseCarmenNumber(".", v), CarmenNumber::kNotNumber);
  EXPECT_EQ(parseCarmenNumber("1.2.3", v), CarmenNumber::kNotNumber);
  EXPECT_EQ(parseCarmenNumber("--1", v), CarmenNumber::kNotNumber);
}

}  // namespace
}  // namespace dynamap
