#pragma once
// Reading CARMEN logs (plain or .gz), the text format of the classic public 2D laser datasets.
//
// One message per line: `NAME [contents] ipc_timestamp ipc_hostname logger_timestamp`.
// Read here: FLASER/RLASER (old laser format), ROBOTLASER1 (new laser format), ODOM, and the PARAM
// lines that give a laser's field of view, angular step, maximum range and mounting offset. Every
// other line (SYNC, NEFF, TRUEPOS, sonar, other PARAMs, '#' comments, blank lines) is skipped and
// counted. docs/carmen.md states the format as read and every choice made.
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
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "dynamap/input/scan_source.h"

namespace dynamap {

/// How a CARMEN log is read.
struct CarmenOptions {
  /// Field of view [deg] of every laser line, overriding the PARAM lines and the ROBOTLASER1
  /// fields; the angular step then follows from the beam count. 0 = not overridden.
  double fov_deg = 0;
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
/// throws CarmenParseError when one that matters has a value that is not a number.
struct CarmenParams {
  CarmenLaserParams front, rear;
  bool applyParam(const std::string& name, const std::string& value);
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

/// The MRPT scan of a laser line: aperture and sensor yaw placing every beam at its angle,
/// rightToLeft, maxRange, validity (false for ranges <= 0, >= maxRange or not finite), sensorPose
/// (FLASER/RLASER: the PARAM offset along x, the rear laser facing backwards; ROBOTLASER1: laser
/// pose relative to robot pose), timestamp from `t`, sensorLabel "LASER".
mrpt::obs::CObservation2DRangeScan::Ptr makeScan(const CarmenLaser& laser,
                                                 const CarmenParams& params,
                                                 const CarmenOptions& options);

/// One thing read from a log, in log order.
struct CarmenEvent {
  enum class Kind { Scan, Odometry };
  Kind kind = Kind::Scan;
  std::size_t line = 0;  ///< 1-based line number in the file
  double t = 0;          ///< ipc_timestamp [s]
  // Kind::Scan:
  mrpt::obs::CObservation2DRangeScan::Ptr scan;
  mrpt::poses::CPose2D pose;                     ///< the line's (ground-truth) pose
  std::optional<mrpt::poses::CPose2D> odometry;  ///< odom fields, else the latest ODOM
  // Kind::Odometry: odometry holds the ODOM pose; tv/rv its velocities.
  double tv = 0, rv = 0;
};

/// Streams a CARMEN log (plain or gz, told by content) line by line; never holds the whole file.
/// stats(): records = lines read, scans = laser lines returned, skipped = lines skipped by reason
/// ("line type SYNC", "comment", "empty line", "PARAM not used", "bad line",
/// "ODOM with zero timestamp").
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

  const SourceStats& stats() const { return stats_; }
  const std::string& path() const { return path_; }
  /// Share of the file's (compressed) bytes consumed so far, in [0, 1]; negative if unknown.
  double fractionRead() const;

 private:
  struct LineInput;
  bool handleLine(const std::string& line, CarmenEvent& out);
  void skip(const std::string& reason) { ++stats_.skipped[reason]; }

  std::string path_;
  CarmenOptions options_;
  std::unique_ptr<LineInput> input_;
  double text_size_ = 0;  // bytes of text in the file, for fractionRead (0: unknown)
  CarmenParams params_;
  std::optional<mrpt::poses::CPose2D> last_odometry_;
  SourceStats stats_;
};

/// True when `path` (plain or gz) is text whose first line that is not a comment or blank starts
/// with a CARMEN message word (PARAM, SYNC, ODOM, FLASER, RLASER, ROBOTLASER1, TRUEPOS, ...).
/// False for unreadable, empty or binary files; never throws.
bool looksLikeCarmen(const std::string& path);

/// A ScanSource over a CARMEN log. Auto and GroundTruth: the laser line's pose; Odometry: the odom
/// fields of FLASER/RLASER, or the latest ODOM line for ROBOTLASER1 (a scan with none before it
/// is an InputError naming its line); Fixed: the line's pose (withFixedPose replaces it);
/// Simplemap: InputError. ScanRecord::index counts scans from 0.
std::unique_ptr<ScanSource> openCarmenSource(const std::string& path, PoseSource source,
                                             const CarmenOptions& options);

}  // namespace dynamap
