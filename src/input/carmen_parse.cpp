#include "dynamap/input/carmen_reader.h"
// The CARMEN log format parsed line by line: fields, numbers, PARAM lines, the laser geometry and
// the MRPT scan of a laser line. The streaming reader and the ScanSource are in carmen_reader.cpp.

#include <mrpt/core/Clock.h>
#include <mrpt/poses/CPose3D.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "carmen_text.h"
#include "dynamap/base/angles.h"

namespace dynamap {

using carmen::formatDeg;

namespace {

// Fields after an old-format laser's ranges: x y theta odom_x odom_y odom_theta ipc host logger.
constexpr std::size_t kOldLaserTail = 9;
// Fields after ROBOTLASER1's remissions: 6 poses, tv rv fwd_safety side_safety turn_axis, ipc
// host logger.
constexpr std::size_t kRobotLaserTail = 14;

// CARMEN's separators: isspace's set in the C locale, without a call per character.
constexpr bool isSeparator(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\v' || c == '\f' || c == '\r';
}

// The line's fields as views into it (a log line has hundreds: no string each).
std::vector<std::string_view> splitFields(const std::string& line) {
  std::vector<std::string_view> fields;
  std::size_t i = 0;
  const std::size_t n = line.size();
  while (i < n) {
    while (i < n && isSeparator(line[i])) ++i;
    std::size_t j = i;
    while (j < n && !isSeparator(line[j])) ++j;
    if (j > i) fields.emplace_back(line.data() + i, j - i);
    i = j;
  }
  return fields;
}

/// Reads the fields of one line in order, each failure naming the field.
class FieldCursor {
 public:
  explicit FieldCursor(const std::vector<std::string_view>& f) : f_(f) {}

  double number(const char* what) {
    const std::string_view s = field(what);
    double v = 0;
    const CarmenNumber r = parseCarmenNumber(s, v);
    if (r == CarmenNumber::kSubnormal) subnormal(what, s);
    if (r != CarmenNumber::kOk) fail(what, "'" + std::string(s) + "' is not a finite number");
    return v;
  }
  /// A range: a number that may be nan or inf (an invalid beam, not a bad line).
  float range() {
    const std::string_view s = field("range");
    double v = 0;
    const CarmenNumber r = parseCarmenNumber(s, v);
    if (r == CarmenNumber::kSubnormal) subnormal("range", s);
    if (r == CarmenNumber::kNotNumber) fail("range", "'" + std::string(s) + "' is not a number");
    return static_cast<float>(v);
  }
  std::size_t count(const char* what) {
    const std::string_view s = field(what);
    const char* first = s.data() + (s.size() > 1 && s[0] == '+' ? 1 : 0);
    const char* last = s.data() + s.size();
    unsigned long long v = 0;
    const auto [end, ec] = std::from_chars(first, last, v);
    if (ec != std::errc() || end != last || first[0] == '-' ||
        v > std::numeric_limits<std::size_t>::max()) {
      fail(what, "'" + std::string(s) + "' is not a count");
    }
    return static_cast<std::size_t>(v);
  }
  mrpt::math::TPose2D pose(const char* what) {
    const double x = number(what), y = number(what), phi = number(what);
    return {x, y, phi};
  }
  void skip(std::size_t n) {
    if (pos_ + n > f_.size()) tooFew("fields");
    pos_ += n;
  }
  std::size_t position() const { return pos_; }
  std::size_t remaining() const { return f_.size() - pos_; }

  [[noreturn]] void fail(const char* what, const std::string& msg) const {
    throw CarmenParseError(std::string(f_[0]) + " field " + std::to_string(pos_) + " (" + what +
                           "): " + msg);
  }
  [[noreturn]] void subnormal(const char* what, std::string_view s) const {
    throw CarmenSubnormalNumber(std::string(f_[0]) + " field " + std::to_string(pos_) + " (" +
                                what + "): '" + std::string(s) +
                                "' is subnormal (a corrupt record)");
  }

 private:
  std::string_view field(const char* what) {
    if (pos_ >= f_.size()) tooFew(what);
    return f_[pos_++];
  }
  [[noreturn]] void tooFew(const char* what) const {
    throw CarmenParseError(std::string(f_[0]) + ": too few fields (" + std::to_string(f_.size()) +
                           ", ran out reading " + what + ")");
  }
  const std::vector<std::string_view>& f_;
  std::size_t pos_ = 1;  // field 0 is the message word
};

void requireFieldCount(const std::vector<std::string_view>& f, std::size_t expected,
                       const std::string& why) {
  if (f.size() == expected) return;
  throw CarmenParseError(std::string(f[0]) + ": " + why + " needs " + std::to_string(expected) +
                         " fields, the line has " + std::to_string(f.size()));
}

/// ipc_timestamp hostname logger_timestamp: the message's time is the ipc one.
double timestampTail(FieldCursor& c) {
  const double ipc = c.number("ipc_timestamp");
  c.skip(1);  // hostname
  c.number("logger_timestamp");
  return ipc;
}

std::vector<float> readRanges(FieldCursor& c, std::size_t n) {
  std::vector<float> ranges(n);
  for (auto& r : ranges) r = c.range();
  return ranges;
}

std::size_t beamCount(FieldCursor& c) {
  const std::size_t n = c.count("num_readings");
  if (n < 2) c.fail("num_readings", "a scan needs at least 2 beams");
  return n;
}

/// FLASER|RLASER num_readings r1..rn x y theta odom_x odom_y odom_theta ipc host logger
CarmenLaser parseOldLaser(const std::vector<std::string_view>& f) {
  FieldCursor c(f);
  CarmenLaser laser;
  laser.kind = f[0] == "RLASER" ? CarmenLaserKind::Rear : CarmenLaserKind::Front;
  const std::size_t n = beamCount(c);
  requireFieldCount(f, 2 + n + kOldLaserTail, std::to_string(n) + " beams");
  laser.ranges = readRanges(c, n);
  laser.pose = c.pose("x y theta");
  laser.odometry = c.pose("odom_x odom_y odom_theta");
  laser.t = timestampTail(c);
  return laser;
}

/// ROBOTLASER1 laser_type start_angle fov angular_resolution max_range accuracy remission_mode
/// num_readings r.. num_remissions e.. laser_x y theta robot_x y theta tv rv fwd side turn_axis
/// ipc host logger
CarmenLaser parseRobotLaser(const std::vector<std::string_view>& f) {
  FieldCursor c(f);
  CarmenLaser laser;
  laser.kind = CarmenLaserKind::Robot;
  c.number("laser_type");
  laser.start_angle = c.number("start_angle");
  laser.fov = c.number("field_of_view");
  laser.angular_resolution = c.number("angular_resolution");
  if (laser.angular_resolution <= 0) c.fail("angular_resolution", "must be positive");
  laser.max_range = c.number("maximum_range");
  if (laser.max_range <= 0) c.fail("maximum_range", "must be positive");
  c.number("accuracy");
  c.number("remission_mode");
  const std::size_t n = beamCount(c);
  if (c.remaining() < n + 1)
    requireFieldCount(f, c.position() + n + 1 + kRobotLaserTail, std::to_string(n) + " beams");
  laser.ranges = readRanges(c, n);
  const std::size_t m = c.count("num_remissions");
  requireFieldCount(f, c.position() + m + kRobotLaserTail,
                    std::to_string(n) + " beams and " + std::to_string(m) + " remissions");
  for (std::size_t i = 0; i < m; ++i) c.number("remission");
  laser.laser_pose = c.pose("laser_pose");
  laser.pose = c.pose("robot_pose");
  for (const char* w :
       {"laser_tv", "laser_rv", "forward_safety_dist", "side_safety_dist", "turn_axis"}) {
    c.number(w);
  }
  laser.t = timestampTail(c);
  return laser;
}

/// ODOM x y theta tv rv accel ipc host logger
CarmenOdometry parseOdometry(const std::vector<std::string_view>& f) {
  requireFieldCount(f, 10, "ODOM");
  FieldCursor c(f);
  CarmenOdometry odo;
  odo.pose = c.pose("x y theta");
  odo.tv = c.number("tv");
  odo.rv = c.number("rv");
  odo.accel = c.number("accel");
  odo.t = timestampTail(c);
  return odo;
}

double paramNumber(const std::string& name, const std::string& value) {
  double v = 0;
  if (parseCarmenNumber(value, v) != CarmenNumber::kOk) {
    throw CarmenParseError("PARAM " + name + ": '" + value + "' is not a number");
  }
  return v;
}

}  // namespace

// --- pure parsing ------------------------------------------------------------------------------

namespace {

// A plain decimal ("1.65", "-0.5", "12", ".5") of at most 15 digits, into v: its digits as an
// integer, below 2^53, over a power of ten up to 1e22, both exact in a double, divided once:
// the correctly rounded value, the one from_chars gives, bit for bit, without its general
// machinery (a CARMEN log is millions of such numbers). False for anything else.
bool plainDecimal(const char* p, const char* end, double& v) {
  static constexpr double kPow10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                      1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                      1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
  const bool negative = p != end && *p == '-';
  if (negative) ++p;
  std::uint64_t digits = 0;
  int count = 0, fraction = -1;  // fraction: digits after the point, -1 before it
  for (; p != end; ++p) {
    if (*p == '.' && fraction < 0) {
      fraction = 0;
      continue;
    }
    if (*p < '0' || *p > '9' || ++count > 15) return false;
    digits = digits * 10 + static_cast<std::uint64_t>(*p - '0');
    if (fraction >= 0) ++fraction;
  }
  if (count == 0) return false;
  const double magnitude = static_cast<double>(digits) / kPow10[fraction < 0 ? 0 : fraction];
  v = negative ? -magnitude : magnitude;
  return true;
}

}  // namespace

CarmenNumber parseCarmenNumber(std::string_view field, double& v) {
  if (plainDecimal(field.data(), field.data() + field.size(), v)) return CarmenNumber::kOk;
  // strtod took a leading '+'; from_chars does not: skip one, unless a sign follows it.
  const bool plus = field.size() > 1 && field[0] == '+' && field[1] != '-' && field[1] != '+';
  const char* first = field.data() + (plus ? 1 : 0);
  const char* last = field.data() + field.size();
  const auto [end, ec] = std::from_chars(first, last, v);
  if (end != last || first == last) return CarmenNumber::kNotNumber;
  if (ec == std::errc::result_out_of_range) return CarmenNumber::kNotFinite;
  if (ec != std::errc()) return CarmenNumber::kNotNumber;
  if (!std::isfinite(v)) return CarmenNumber::kNotFinite;
  if (std::fpclassify(v) == FP_SUBNORMAL) return CarmenNumber::kSubnormal;
  return CarmenNumber::kOk;
}

CarmenOdometrySource parseCarmenOdometry(const std::string& name) {
  if (name == "laser") return CarmenOdometrySource::LaserLines;
  if (name == "odom") return CarmenOdometrySource::OdomLines;
  throw std::invalid_argument("'" + name + "' is not laser or odom");
}

std::string toString(CarmenOdometrySource odometry) {
  return odometry == CarmenOdometrySource::OdomLines ? "odom" : "laser";
}

CarmenLine parseCarmenLine(const std::string& line) {
  CarmenLine out;
  const auto first = line.find_first_not_of(" \t\r\n");
  if (first == std::string::npos) return out;  // blank
  if (line[first] == '#') {
    out.type = "#";
    return out;
  }
  const std::vector<std::string_view> f = splitFields(line);
  if (f.empty()) return out;  // only separators splitFields knows and the test above does not
  out.type = f[0];
  if (out.type == "FLASER" || out.type == "RLASER") {
    out.laser = parseOldLaser(f);
  } else if (out.type == "ROBOTLASER1") {
    out.laser = parseRobotLaser(f);
  } else if (out.type == "ODOM") {
    out.odometry = parseOdometry(f);
  } else if (out.type == "PARAM") {
    if (f.size() < 3) throw CarmenParseError("PARAM: needs a name and a value");
    out.param = std::make_pair(std::string(f[1]), std::string(f[2]));
  }
  return out;
}

bool CarmenParams::applyParam(const std::string& name, const std::string& value,
                              std::string* note) {
  struct Key {
    const char* name;
    std::optional<double> CarmenLaserParams::*field;
    CarmenLaserParams CarmenParams::*laser;
  };
  static const Key kKeys[] = {
      {"laser_front_laser_fov", &CarmenLaserParams::fov_deg, &CarmenParams::front},
      {"laser_front_laser_resolution", &CarmenLaserParams::resolution_deg, &CarmenParams::front},
      {"robot_front_laser_max", &CarmenLaserParams::max_range, &CarmenParams::front},
      {"robot_frontlaser_offset", &CarmenLaserParams::offset_x, &CarmenParams::front},
      {"laser_rear_laser_fov", &CarmenLaserParams::fov_deg, &CarmenParams::rear},
      {"laser_rear_laser_resolution", &CarmenLaserParams::resolution_deg, &CarmenParams::rear},
      {"robot_rear_laser_max", &CarmenLaserParams::max_range, &CarmenParams::rear},
      {"robot_rearlaser_offset", &CarmenLaserParams::offset_x, &CarmenParams::rear},
  };
  for (const Key& k : kKeys) {
    if (name != k.name) continue;
    const double v = paramNumber(name, value);
    const bool offset = k.field == &CarmenLaserParams::offset_x;  // the one that may be negative
    if (!offset && v <= 0) {
      throw CarmenParseError("PARAM " + name + ": " + value + " must be positive");
    }
    // No laser sweeps more than a turn (nor steps more than one between beams): 1e300 is a
    // damaged number, not a geometry to make the scan's aperture infinite with.
    const bool angle =
        k.field == &CarmenLaserParams::fov_deg || k.field == &CarmenLaserParams::resolution_deg;
    if (angle && v > 360) {
      throw CarmenParseError("PARAM " + name + ": " + value +
                             " is no angle of a laser (over 360 deg)");
    }
    // The robot's pose is the line's less the offset: a damaged offset would throw it anywhere.
    if (offset && std::abs(v) > kMaxLaserOffset) {
      throw CarmenParseError("PARAM " + name + ": " + value + " is no laser mount (over " +
                             std::to_string(static_cast<int>(kMaxLaserOffset)) +
                             " m from the robot's centre)");
    }
    const bool radians = k.field == &CarmenLaserParams::fov_deg && v <= kMaxRadianFov;
    (this->*k.laser).*k.field = radians ? v / kDegToRad : v;
    if (radians && note) {
      *note = "PARAM " + name + " " + value + " read as radians (" + formatDeg(v / kDegToRad) +
              " deg): no laser spans under 6.3 deg; --fov DEG overrides it";
    }
    return true;
  }
  return false;
}

LaserGeometry laserGeometry(std::size_t beams, const CarmenLaserParams& params,
                            const CarmenOptions& options) {
  const bool overridden = options.fov_deg > 0;
  const double fov = (overridden ? options.fov_deg : params.fov_deg.value_or(180.0)) * kDegToRad;
  LaserGeometry g;
  g.start = -fov / 2;
  if (!overridden && params.resolution_deg) {
    g.step = *params.resolution_deg * kDegToRad;
  } else {
    // An odd count has a beam at each end of the fov (181, 361); an even one stops a step short.
    g.step = fov / static_cast<double>(beams % 2 == 1 ? beams - 1 : beams);
  }
  return g;
}

std::string geometryDisagreement(std::size_t beams, const CarmenLaserParams& params,
                                 const CarmenOptions& options) {
  if (options.fov_deg > 0 || !params.resolution_deg || beams < 2) return {};
  const double fov = params.fov_deg.value_or(180.0), step = *params.resolution_deg;
  // Beams at both ends span (n-1) steps, CARMEN's even counts n steps: either agrees.
  const double n = static_cast<double>(beams);
  if (std::abs(step * (n - 1) - fov) <= step || std::abs(step * n - fov) <= step) return {};
  return std::to_string(beams) + " beams " + formatDeg(step) +
         " deg apart (PARAM resolution) span " + formatDeg(step * (n - 1)) +
         " deg, not the field of view of " + formatDeg(fov) + " deg (" +
         (params.fov_deg ? "PARAM fov" : "assumed: no PARAM fov") + "); assumed: beams " +
         formatDeg(step) + " deg apart from -" + formatDeg(fov / 2) +
         " deg (--fov DEG spreads them over DEG instead)";
}

mrpt::obs::CObservation2DRangeScan::Ptr makeScan(const CarmenLaser& laser,
                                                 const CarmenParams& params,
                                                 const CarmenOptions& options) {
  const std::size_t n = laser.ranges.size();
  const CarmenLaserParams& lp = params.of(laser.kind);
  LaserGeometry g;
  mrpt::poses::CPose2D mount;  // the laser's pose on the robot, x forward
  double max_range = options.default_max_range;
  if (laser.kind == CarmenLaserKind::Robot) {
    g = options.fov_deg > 0 ? laserGeometry(n, {}, options)
                            : LaserGeometry{laser.start_angle, laser.angular_resolution};
    mount = mrpt::poses::CPose2D(*laser.laser_pose) - mrpt::poses::CPose2D(laser.pose);
    max_range = laser.max_range;
  } else {
    g = laserGeometry(n, lp, options);
    const double facing = laser.kind == CarmenLaserKind::Rear ? M_PI : 0.0;
    mount = mrpt::poses::CPose2D(lp.offset_x.value_or(0.0), 0, facing);
    max_range = lp.max_range.value_or(options.default_max_range);
  }
  // MRPT spreads the beams evenly over `aperture`, symmetric about the sensor's x axis: turn the
  // sensor so that the middle of the beams points where CARMEN says it does.
  const double aperture = g.step * static_cast<double>(n - 1);
  const double centre = g.start + aperture / 2;

  auto scan = std::make_shared<mrpt::obs::CObservation2DRangeScan>();
  scan->sensorLabel = "LASER";
  scan->timestamp = mrpt::Clock::fromDouble(laser.t);
  scan->aperture = static_cast<float>(aperture);
  scan->rightToLeft = true;
  scan->maxRange = static_cast<float>(max_range);
  scan->sensorPose = mrpt::poses::CPose3D(mount + mrpt::poses::CPose2D(0, 0, centre));
  // In one call, not two checked setter calls per beam.
  std::vector<char> valid(n);
  for (std::size_t i = 0; i < n; ++i) {
    const float r = laser.ranges[i];
    valid[i] = std::isfinite(r) && r > 0 && r < scan->maxRange ? 1 : 0;
  }
  scan->loadFromVectors(n, laser.ranges.data(), valid.data());
  return scan;
}

CarmenRobotPoses robotPoses(const CarmenLaser& laser, const CarmenParams& params) {
  CarmenRobotPoses out;
  out.pose = mrpt::poses::CPose2D(laser.pose);
  if (laser.odometry) out.odometry = mrpt::poses::CPose2D(*laser.odometry);
  if (laser.kind == CarmenLaserKind::Robot) return out;
  const CarmenLaserParams& lp = params.of(laser.kind);
  const double offset = lp.offset_x.value_or(0.0);
  // From a TPose2D, as the line's own pose: the heading as logged, not wrapped.
  const auto robot = [offset](const mrpt::math::TPose2D& p) {
    return mrpt::poses::CPose2D(
        mrpt::math::TPose2D(p.x - offset * std::cos(p.phi), p.y - offset * std::sin(p.phi), p.phi));
  };
  out.pose = robot(laser.pose);
  const bool corrected = laser.odometry && laser.odometry->x == laser.pose.x &&
                         laser.odometry->y == laser.pose.y && laser.odometry->phi == laser.pose.phi;
  if (corrected) out.odometry = out.pose;
  return out;
}

namespace carmen {

/// An angle in degrees as a message shows it: at most 3 decimals, no trailing zeros.
std::string formatDeg(double deg) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f", deg);
  std::string s = buf;
  while (s.back() == '0') s.pop_back();
  if (s.back() == '.') s.pop_back();
  return s;
}

}  // namespace carmen

}  // namespace dynamap
