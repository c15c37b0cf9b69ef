#include "dynamap/input/carmen_reader.h"

#include <mrpt/core/Clock.h>
#include <mrpt/io/CFileGZInputStream.h>

#include <algorithm>
#include <deque>
#include <exception>
#include <filesystem>
#include <memory>
#include <set>
#include <string>

#include "carmen_text.h"
#include "dynamap/input/line_reader.h"

namespace dynamap {

namespace {

constexpr std::size_t kReadBlock = 64 * 1024;

const std::set<std::string>& knownMessageWords() {
  static const std::set<std::string> kWords = {
      "PARAM",     "SYNC",      "ODOM",         "FLASER",      "RLASER",      "LASER3",
      "LASER4",    "TRUEPOS",   "NEFF",         "ROBOTLASER1", "ROBOTLASER2", "RAWLASER1",
      "RAWLASER2", "RAWLASER3", "RAWLASER4",    "GPSNMEA",     "GPSNMEAGGA",  "SONAR",
      "BUMPER",    "SCANMARK",  "POSITIONLASER"};
  return kWords;
}

/// The skip reason of a line type, its name cut short so garbage cannot flood the summary.
std::string typeReason(const std::string& type) {
  return "line type " + (type.size() > 32 ? type.substr(0, 32) + "..." : type);
}

}  // namespace

using carmen::formatDeg;

// --- streaming -------------------------------------------------------------------------------

/// Lines of a plain or gz file, read in blocks, each capped in length (LineReader).
struct CarmenReader::LineInput : LineReader {
  using LineReader::LineReader;
};

CarmenReader::CarmenReader(const std::string& path, const CarmenOptions& options)
    : path_(path), options_(options) {
  stats_.record_unit = "lines";
  // A missing file is said plainly (not MRPT's backtrace); a fifo or device is not a log file.
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path + ": no such file");
  input_ = std::make_unique<LineInput>(path, options.max_line_length);
  text_size_ = static_cast<double>(uncompressedSize(path));
}

CarmenReader::~CarmenReader() = default;

double CarmenReader::fractionRead() const {
  if (text_size_ == 0) return -1.0;
  return std::min(1.0, static_cast<double>(input_->position()) / text_size_);
}

bool CarmenReader::next(CarmenEvent& out) {
  if (!probed_) probeTimes();
  if (!ahead_.empty()) {
    out = std::move(ahead_.front());
    ahead_.pop_front();
  } else if (probe_fault_) {
    // A fault met while reading ahead comes after every event read before it.
    std::exception_ptr fault = probe_fault_;
    probe_fault_ = nullptr;
    std::rethrow_exception(fault);
  } else if (!readEvent(out)) {
    return false;
  }
  if (retime_) retime(out);
  return true;
}

bool CarmenReader::readEvent(CarmenEvent& out) {
  std::string line;
  while (true) {
    if (const std::size_t empty = input_->skipEmptyLines()) {
      stats_.records += empty;
      stats_.skipped["empty line"] += empty;
    }
    if (!input_->next(line)) break;
    ++stats_.records;
    try {
      if (line.find('\0') != std::string::npos) {
        throw CarmenParseError("a NUL byte: not a line of text");
      }
      if (handleLine(line, out)) return true;
    } catch (const CarmenSubnormalNumber&) {
      skip("line with a subnormal number");
    } catch (const CarmenParseError& e) {
      if (!options_.skip_bad_lines) {
        throw InputError(path_ + ":" + std::to_string(input_->lineNumber()) + ": " + e.what());
      }
      skip("bad line");
    }
  }
  return false;
}

void CarmenReader::probeTimes() {
  probed_ = true;
  std::set<double> times;
  std::size_t scans = 0;
  try {
    CarmenEvent e;
    while (scans < kTimeProbeScans && ahead_.size() < kTimeProbeEvents && readEvent(e)) {
      if (e.kind == CarmenEvent::Kind::Scan) {
        ++scans;
        times.insert(e.t);
      }
      ahead_.push_back(std::move(e));
    }
  } catch (const InputError&) {
    probe_fault_ = std::current_exception();
  }
  if (times.size() > 2 || times.size() >= scans) return;
  retime_ = true;
  const bool zero = times.size() == 1 && *times.begin() == 0;
  warn("its first " + std::to_string(scans) + " laser lines carry " +
       (zero ? std::string("timestamp 0 only")
             : "only " + std::to_string(times.size()) + " distinct timestamps") +
       ": time cannot order them, so each scan is timed by its place in the log at a nominal " +
       formatDeg(kNominalRate) + " Hz (scan k at k/" + formatDeg(kNominalRate) +
       " s) and each ODOM line at the scan before it");
}

void CarmenReader::retime(CarmenEvent& e) {
  if (e.kind == CarmenEvent::Kind::Scan) {
    retimed_t_ = static_cast<double>(retimed_scans_++) / kNominalRate;
    e.scan->timestamp = mrpt::Clock::fromDouble(retimed_t_);
  }
  e.t = retimed_t_;
}

void CarmenReader::applyParam(const std::string& name, const std::string& value) {
  std::string note;
  if (!params_.applyParam(name, value, &note)) {
    skip("PARAM not used");
  } else if (!note.empty()) {
    warn("line " + std::to_string(input_->lineNumber()) + ": " + note);
  }
}

void CarmenReader::checkGeometry(const CarmenLaser& laser) {
  bool& checked = geometry_checked_[static_cast<int>(laser.kind)];
  if (checked || laser.kind == CarmenLaserKind::Robot) return;
  checked = true;
  const CarmenLaserParams& lp = params_.of(laser.kind);
  const std::string what = geometryDisagreement(laser.ranges.size(), lp, options_);
  if (!what.empty()) warn("line " + std::to_string(input_->lineNumber()) + ": " + what);
}

bool CarmenReader::handleLine(const std::string& line, CarmenEvent& out) {
  CarmenLine parsed = parseCarmenLine(line);
  if (parsed.param) {
    applyParam(parsed.param->first, parsed.param->second);
    return false;
  }
  if (parsed.odometry) {
    // The corrected logs hold an ODOM line stamped 0 after each scan: no time, so no odometry.
    if (parsed.odometry->t == 0) {
      skip("ODOM with zero timestamp");
      return false;
    }
    last_odometry_ = mrpt::poses::CPose2D(parsed.odometry->pose);
    out = CarmenEvent{};
    out.kind = CarmenEvent::Kind::Odometry;
    out.line = input_->lineNumber();
    out.t = parsed.odometry->t;
    out.odometry = last_odometry_;
    out.tv = parsed.odometry->tv;
    out.rv = parsed.odometry->rv;
    return true;
  }
  if (parsed.laser) {
    const CarmenLaser& laser = *parsed.laser;
    out = CarmenEvent{};
    out.kind = CarmenEvent::Kind::Scan;
    out.line = input_->lineNumber();
    out.t = laser.t;
    checkGeometry(laser);
    out.scan = makeScan(laser, params_, options_);
    const CarmenRobotPoses robot = robotPoses(laser, params_);
    out.pose = robot.pose;
    out.odometry = robot.odometry ? *robot.odometry : last_odometry_;
    ++stats_.scans;
    return true;
  }
  if (parsed.type.empty()) {
    skip("empty line");
  } else if (parsed.type == "#") {
    skip("comment");
  } else {
    skip(typeReason(parsed.type));
  }
  return false;
}

// --- detection and the ScanSource --------------------------------------------------------------

bool looksLikeCarmen(const std::string& path) {
  std::string head(kReadBlock, '\0');
  try {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) return false;
    mrpt::io::CFileGZInputStream in;
    if (!in.open(path)) return false;
    head.resize(in.Read(head.data(), head.size()));
  } catch (const std::exception&) {
    return false;
  }
  if (head.empty()) return false;
  // Told by the first line that is not blank or a comment; a NUL byte later in the file is a
  // fault of that line (CarmenReader), wherever it is.
  std::size_t pos = 0;
  while (pos < head.size()) {
    std::size_t end = head.find('\n', pos);
    const bool complete = end != std::string::npos;
    if (!complete) end = head.size();
    const std::string line = head.substr(pos, end - pos);
    pos = end + 1;
    if (line.find('\0') != std::string::npos) return false;  // binary from its start
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    const auto word_end = line.find_first_of(" \t\r", first);
    if (word_end == std::string::npos && !complete) return false;  // word cut by the buffer
    return knownMessageWords().count(line.substr(first, word_end - first)) > 0;
  }
  return false;
}

namespace {

class CarmenSource : public ScanSource {
 public:
  CarmenSource(const std::string& path, PoseSource source, const CarmenOptions& options)
      : reader_(path, options),
        source_(source),
        odom_lines_(source == PoseSource::Odometry &&
                    options.odometry == CarmenOdometrySource::OdomLines),
        odom_(options.odometry_track) {}

  bool next(ScanRecord& out) override {
    if (odom_lines_) return nextOnOdomLines(out);
    CarmenEvent e;
    while (reader_.next(e)) {
      if (e.kind != CarmenEvent::Kind::Scan) continue;
      out = record(e);
      if (source_ == PoseSource::Odometry) {
        if (!e.odometry) {
          throw InputError(where(e, out.index) + " has no odometry (no ODOM line before it)");
        }
        out.pose = *e.odometry;
      }
      return true;
    }
    return false;
  }
  PoseSource poseSource() const override { return source_; }
  const SourceStats& stats() const override { return reader_.stats(); }
  const std::string& path() const override { return reader_.path(); }
  double fractionRead() const override { return reader_.fractionRead(); }
  std::string poseDetail() const override {
    if (source_ != PoseSource::Odometry) return "each laser line's own pose";
    return odom_lines_ ? "the ODOM lines, interpolated to each scan's time"
                       : "the odometry fields of each laser line";
  }

 private:
  struct Pending {
    std::size_t line;
    ScanRecord rec;
  };
  static constexpr std::size_t kMaxPending = 10000;
  static constexpr double kOdomHistory_s = 10.0;

  ScanRecord record(const CarmenEvent& e) {
    ScanRecord r;
    r.index = next_index_++;
    r.t = e.t;
    r.scan = e.scan;
    r.pose = e.pose;
    return r;
  }
  std::string where(const CarmenEvent& e, std::size_t index) const {
    return path() + ":" + std::to_string(e.line) + ": scan " + std::to_string(index);
  }

  /// Scans wait until the ODOM lines around their time have been read.
  bool nextOnOdomLines(ScanRecord& out) {
    CarmenEvent e;
    while (true) {
      if (resolveFront(eof_, out)) return true;
      if (eof_) return false;
      if (!reader_.next(e)) {
        eof_ = true;
        continue;
      }
      if (reader_.retimed()) {
        throw InputError(path() +
                         ": the ODOM lines cannot be interpolated to the scans' times: "
                         "the log's timestamps are degenerate (use the laser lines' "
                         "odometry: --carmen-odometry laser)");
      }
      if (e.kind == CarmenEvent::Kind::Odometry) {
        odom_.add(e.t, *e.odometry);
        continue;
      }
      pending_.push_back({e.line, record(e)});
      if (pending_.size() > kMaxPending) {
        throw InputError(where(e, pending_.front().rec.index) + " has no ODOM line within " +
                         std::to_string(kMaxPending) + " scans after it");
      }
    }
  }

  bool resolveFront(bool complete, ScanRecord& out) {
    if (pending_.empty()) return false;
    Pending& p = pending_.front();
    const PoseTrack::Lookup r = odom_.at(p.rec.t, p.rec.pose, complete);
    if (r == PoseTrack::Lookup::kLater) return false;
    if (r != PoseTrack::Lookup::kFound) {
      throw InputError(path() + ":" + std::to_string(p.line) + ": scan " +
                       std::to_string(p.rec.index) + " (t=" + std::to_string(p.rec.t) +
                       ") has no ODOM line within " + std::to_string(odom_.maxGap()) +
                       " s around it (see [input] pose_max_gap)");
    }
    out = std::move(p.rec);
    pending_.pop_front();
    odom_.forgetBefore(out.t - kOdomHistory_s);
    return true;
  }

  CarmenReader reader_;
  PoseSource source_;
  bool odom_lines_;
  PoseTrack odom_;
  std::deque<Pending> pending_;
  bool eof_ = false;
  std::size_t next_index_ = 0;
};

}  // namespace

std::unique_ptr<ScanSource> openCarmenSource(const std::string& path, PoseSource source,
                                             const CarmenOptions& options) {
  if (source == PoseSource::Simplemap) {
    throw InputError(path + ": a CARMEN log has no simplemap poses (use ground_truth or odometry)");
  }
  if (source == PoseSource::Auto) source = PoseSource::GroundTruth;
  return std::make_unique<CarmenSource>(path, source, options);
}

}  // namespace dynamap
