#pragma once
// Reading CARMEN logs (plain or .gz), the text format of the classic public 2D laser datasets.
//
// One message per line: `NAME [contents] ipc_timestamp ipc_hostname logger_timestamp`.
// Read here: FLASER/RLASER (old laser format), ROBOTLASER1 (new laser format), ODOM, and the PARAM
// lines that give a laser's field of view, angular step, maximum range and mounting offset. Every
// other line (SYNC, NEFF, TRUEPOS, sonar, other PARAMs, '#' comments, blank lines) is skipped and
// counted. docs/inputs.md (CARMEN logs) states the format as read and every choice made.
//
// Time: a message's time is its ipc_timestamp (the sender's time of the data); the
// logger_timestamp is only when the logger received it. Beam angles follow CARMEN/GMapping: beam i
// of an old-format line lies at -fov/2 + i*step; a ROBOTLASER1 line carries its own start angle.
//
// The parsing is pure functions over strings (parseCarmenLine, laserGeometry, makeScan); the
// streaming reader (CarmenReader) adds the file, line numbers, PARAM state and counts.

#include <mrpt/math/TPose2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <cstddef>
#include <deque>
#include <exception>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "dynamap/base/pose_track.h"
#include "dynamap/input/scan_source.h"

namespace dynamap {

/// Which of a CARMEN log's two odometry streams pose source odometry reads.
enum class CarmenOdometrySource {
  /// The odometry fields of each FLASER/RLASER line (ROBOTLASER1: the latest ODOM line). In a
  /// "corrected" log they are the corrected pose, not the robot's own odometry.
  LaserLines,
  /// The ODOM lines, the robot's own odometry stream, interpolated to each scan's time.
  OdomLines,
};
/// "laser" | "odom"; throws std::invalid_argument otherwise.
CarmenOdometrySource parseCarmenOdometry(const std::string& name);
std::string toString(CarmenOdometrySource odometry);

/// How a CARMEN log is read.
struct CarmenOptions {
  /// Field of view [deg] of every laser line, overriding the PARAM lines and the ROBOTLASER1
  /// fields; the angular step then follows from the beam count. 0 = not overridden.
  double fov_deg = 0;
  /// The odometry stream of pose source odometry (and scan_matching, slam).
  CarmenOdometrySource odometry = CarmenOdometrySource::LaserLines;
  /// How ODOM lines are interpolated to a scan's time (CarmenOdometrySource::OdomLines).
  PoseTrackOptions odometry_track;
  /// Maximum range [m] when no PARAM gives it (81 m: a SICK LMS reports ~81.9 m for no return).
  double default_max_range = 81.0;
  /// Skip malformed lines of known types (counted as "bad line") instead of failing.
  bool skip_bad_lines = false;
  /// Longest line accepted [bytes]; a longer one is an InputError naming it.
  std::size_t max_line_length = std::size_t{1} << 20;
};

/// A malformed line, before the reader adds the file name and line number.
class CarmenParseError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A line holding a finite number too small to be normal (e.g. a timestamp 5.45506e-312): bits
/// of a corrupt record, not a value. The reader skips and counts such a line ("line with a
/// subnormal number") rather than failing.
class CarmenSubnormalNumber : public CarmenParseError {
 public:
  using CarmenParseError::CarmenParseError;
};

/// How a field of a CARMEN line reads as a number (std::from_chars: no locale, no streams; a
/// leading '+' is accepted as strtod did). kSubnormal: `v` holds the subnormal value.
enum class CarmenNumber { kOk, kNotNumber, kNotFinite, kSubnormal };
CarmenNumber parseCarmenNumber(std::string_view field, double& v);

/// Which laser an old- or new-format line comes from.
enum class CarmenLaserKind { Front, Rear, Robot };

/// A laser line as written in the log (no PARAM applied yet).
struct CarmenLaser {
  CarmenLaserKind kind = CarmenLaserKind::Front;
  std::vector<float> ranges;  ///< [m], as logged (may hold 0, max range, nan)
  mrpt::math::TPose2D pose;   ///< the line's pose: the corrected pose in "corrected" logs
  std::optional<mrpt::math::TPose2D> odometry;  ///< old format: the odom fields
  // New format only (ROBOTLASER1):
  std::optional<mrpt::math::TPose2D> laser_pose;  ///< the laser's pose in the world
  double start_angle = 0;                         ///< [rad] angle of the first beam
  double fov = 0;                                 ///< [rad]
  double angular_resolution = 0;                  ///< [rad]
  double max_range = 0;                           ///< [m]
  double t = 0;                                   ///< ipc_timestamp [s]
};

/// An ODOM line: x y theta tv rv accel.
struct CarmenOdometry {
  mrpt::math::TPose2D pose;
  double tv = 0, rv = 0, accel = 0;
  double t = 0;  ///< ipc_timestamp [s]; 0 means "no time" in the logs seen
};

/// One parsed line. `type` is the message word ("FLASER", "SYNC", ...; "#" for a comment, "" for
/// a blank line); exactly one of laser/odometry/param is set for the types read, none otherwise.
struct CarmenLine {
  std::string type;
  std::optional<CarmenLaser> laser;
  std::optional<CarmenOdometry> odometry;
  std::optional<std::pair<std::string, std::string>> param;  ///< name, value
};

/// Parses one line (without its end of line). Throws CarmenParseError for a malformed line of a
/// type it reads: too few or too many fields, a non-number, a beam count that does not match.
CarmenLine parseCarmenLine(const std::string& line);

/// The PARAM values that matter for one laser (front or rear); unset when absent from the log.
struct CarmenLaserParams {
  std::optional<double> fov_deg;         ///< laser_<front|rear>_laser_fov
  std::optional<double> resolution_deg;  ///< laser_<front|rear>_laser_resolution
  std::optional<double> max_range;       ///< robot_<front|rear>_laser_max
  std::optional<double> offset_x;        ///< robot_<front|rear>laser_offset (along the robot's x)
};

/// The PARAM state of a log. applyParam returns false for a PARAM that does not matter here and
/// throws CarmenParseError when one that matters has a value that is not a number. A field of
/// view of at most kMaxRadianFov is taken as radians (no laser scanner spans under 6.3 deg;
/// logs written as `laser_front_laser_fov 3.14159` exist) and `note`, when given, says so. A
/// laser offset over kMaxLaserOffset (either sign) is a CarmenParseError.
struct CarmenParams {
  static constexpr double kMaxRadianFov = 6.2832;  // 2 pi, rounded up
  static constexpr double kMaxLaserOffset = 10;    // [m] no robot carries its laser farther out
  CarmenLaserParams front, rear;
  /// The PARAMs of an old-format laser line of `kind`: the rear laser's for RLASER, else the
  /// front one's.
  const CarmenLaserParams& of(CarmenLaserKind kind) const {
    return kind == CarmenLaserKind::Rear ? rear : front;
  }
  bool applyParam(const std::string& name, const std::string& value, std::string* note = nullptr);
};

/// Angles of a scan's beams: beam i at start + i * step [rad], in the laser's frame.
struct LaserGeometry {
  double start = 0;
  double step = 0;
};

/// The beam angles of an old-format laser with `beams` beams. fov: options.fov_deg, else the PARAM
/// fov, else 180 deg; step: PARAM resolution (unless the fov is overridden), else from the count:
/// fov/(beams-1) for an odd count (beams at both ends: 181, 361), fov/beams for an even one (180,
/// 360: CARMEN's last beam stops one step short); first beam at -fov/2.
LaserGeometry laserGeometry(std::size_t beams, const CarmenLaserParams& params,
                            const CarmenOptions& options);
/// Empty when the field of view (PARAM or 180 deg), the beam count and the PARAM resolution of
/// an old-format laser agree within a step (or there is no resolution, or --fov overrides);
/// otherwise what disagrees and what laserGeometry assumes.
std::string geometryDisagreement(std::size_t beams, const CarmenLaserParams& params,
                                 const CarmenOptions& options);

/// The MRPT scan of a laser line: aperture and sensor yaw placing every beam at its angle,
/// rightToLeft, maxRange, validity (false for ranges <= 0, >= maxRange or not finite), sensorPose
/// (FLASER/RLASER: the PARAM offset along x, the rear laser facing backwards; ROBOTLASER1: laser
/// pose relative to robot pose), timestamp from `t`, sensorLabel "LASER".
mrpt::obs::CObservation2DRangeScan::Ptr makeScan(const CarmenLaser& laser,
                                                 const CarmenParams& params,
                                                 const CarmenOptions& options);

/// The robot's poses of a laser line, ground truth and odometry. ROBOTLASER1 names both. On
/// FLASER/RLASER, CARMEN's writers put the *laser's* pose in `x y theta` (the robot's pose plus
/// the PARAM offset along its heading) and the robot's odometry in the odom fields: the robot's
/// pose is the line's less the offset. A corrected log writes its corrected pose into both
/// triples, equal on every line; that pose is the laser's (scans laid at it fit each other
/// better than 4 cm off, on Freiburg 079), so there the odom fields lose the offset too.
struct CarmenRobotPoses {
  mrpt::poses::CPose2D pose;
  std::optional<mrpt::poses::CPose2D> odometry;  ///< none: the line has no odom fields
};
CarmenRobotPoses robotPoses(const CarmenLaser& laser, const CarmenParams& params);

/// One thing read from a log, in log order.
struct CarmenEvent {
  enum class Kind { Scan, Odometry };
  Kind kind = Kind::Scan;
  std::size_t line = 0;  ///< 1-based line number in the file
  double t = 0;          ///< ipc_timestamp [s]
  // Kind::Scan:
  mrpt::obs::CObservation2DRangeScan::Ptr scan;
  mrpt::poses::CPose2D pose;                     ///< the robot's (ground-truth) pose: robotPoses
  std::optional<mrpt::poses::CPose2D> odometry;  ///< robotPoses' odometry, else the latest ODOM
  // Kind::Odometry: odometry holds the ODOM pose; tv/rv its velocities.
  double tv = 0, rv = 0;
};

/// Streams a CARMEN log (plain or gz, told by content) line by line; never holds the whole file.
/// stats(): records = lines read, scans = laser lines returned, skipped = lines skipped by reason
/// ("line type SYNC", "comment", "empty line", "PARAM not used", "bad line",
/// "ODOM with zero timestamp", "line with a subnormal number"), warnings = what was assumed (a
/// field of view read as radians, a geometry that does not agree, degenerate timestamps).
///
/// Degenerate timestamps: the first kTimeProbeScans laser lines are read ahead; when they carry
/// at most two distinct times for more scans than that (all 0, say), time says nothing, and
/// every event is retimed by the log's order at kNominalRate: scan k at k / kNominalRate s, an
/// ODOM line at the time of the scan before it. A warning says so.
class CarmenReader {
 public:
  /// Throws InputError when the file cannot be opened.
  CarmenReader(const std::string& path, const CarmenOptions& options);
  ~CarmenReader();
  CarmenReader(const CarmenReader&) = delete;
  CarmenReader& operator=(const CarmenReader&) = delete;

  /// The next scan or ODOM line; false at the end. Throws InputError "<file>:<line>: <what>" for
  /// a malformed line (unless options.skip_bad_lines) or an over-long line.
  bool next(CarmenEvent& out);

  static constexpr std::size_t kTimeProbeScans = 20;
  static constexpr std::size_t kTimeProbeEvents = 5000;  // read ahead at most (ODOM lines too)
  static constexpr double kNominalRate = 10.0;           // [Hz]
  /// True once timestamps were found degenerate (known after the first next()).
  bool retimed() const { return retime_; }

  const SourceStats& stats() const { return stats_; }
  const std::string& path() const { return path_; }
  /// Share of the file's (compressed) bytes consumed so far, in [0, 1]; negative if unknown.
  double fractionRead() const;

 private:
  struct LineInput;
  bool readEvent(CarmenEvent& out);
  bool handleLine(const std::string& line, CarmenEvent& out);
  void applyParam(const std::string& name, const std::string& value);
  void checkGeometry(const CarmenLaser& laser);
  void probeTimes();
  void retime(CarmenEvent& e);
  void skip(const std::string& reason) { ++stats_.skipped[reason]; }
  void warn(const std::string& what) { stats_.warnings.push_back(path_ + ": " + what); }

  std::string path_;
  CarmenOptions options_;
  std::unique_ptr<LineInput> input_;
  double text_size_ = 0;  // bytes of text in the file, for fractionRead (0: unknown)
  CarmenParams params_;
  std::optional<mrpt::poses::CPose2D> last_odometry_;
  SourceStats stats_;
  bool probed_ = false, retime_ = false;
  std::deque<CarmenEvent> ahead_;   // events read while probing the timestamps
  std::exception_ptr probe_fault_;  // an InputError met while probing, thrown after ahead_
  std::size_t retimed_scans_ = 0;
  double retimed_t_ = 0;                              // the last retimed scan's time
  bool geometry_checked_[3] = {false, false, false};  // by CarmenLaserKind
};

/// True when `path` (plain or gz) is text whose first line that is not a comment or blank starts
/// with a CARMEN message word (PARAM, SYNC, ODOM, FLASER, RLASER, ROBOTLASER1, TRUEPOS, ...).
/// False for unreadable, empty or binary files; never throws.
bool looksLikeCarmen(const std::string& path);

/// A ScanSource over a CARMEN log. Auto and GroundTruth: the robot's pose of the laser line
/// (robotPoses); Odometry, with options.odometry LaserLines: its odometry (robotPoses), or the
/// latest ODOM line for ROBOTLASER1 (a scan with none before it is an InputError naming its line);
/// with OdomLines: the ODOM lines interpolated to each scan's time under options.odometry_track (a
/// scan with none near enough, or a log whose timestamps were degenerate, is an InputError naming
/// its line); Fixed: the line's pose (withFixedPose replaces it); Simplemap: InputError.
/// ScanRecord::index counts scans from 0. poseDetail() says which stream the poses are.
std::unique_ptr<ScanSource> openCarmenSource(const std::string& path, PoseSource source,
                                             const CarmenOptions& options);

}  // namespace dynamap
