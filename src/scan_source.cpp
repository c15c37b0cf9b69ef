#include "dynamap/scan_source.h"

#include <mrpt/core/aligned_allocator.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <fstream>
#include <new>
#include <sstream>

#include "dynamap/carmen_reader.h"
#include "dynamap/config_check.h"
#include "dynamap/pose_track.h"

// --- a bound on what one record may make MRPT allocate ------------------------------------------
// MRPT's deserializers trust the sizes a file states: a scan "of 2^31 beams" is resized, and zero
// filled, before its data are read. While a record is read (RecordAllocationLimit in scope), no
// single allocation may exceed kMaxRecordAllocation: operator new throws std::bad_alloc instead,
// and the record is reported as corrupt. Everywhere else allocation is as usual. These are the
// program's replacements of the global operator new and delete (malloc and free underneath).
namespace {
thread_local std::size_t t_allocation_limit = 0;  // 0: no limit
}  // namespace

// The operator delete below frees what the operator new below took from malloc; GCC cannot see
// that the two are replaced together and warns about every call it inlines.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif

void* operator new(std::size_t n) {
  if (t_allocation_limit != 0 && n > t_allocation_limit) throw std::bad_alloc();
  if (void* p = std::malloc(n != 0 ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) {
  return ::operator new(n);
}
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  try {
    return ::operator new(n);
  } catch (const std::bad_alloc&) {
    return nullptr;
  }
}
void* operator new[](std::size_t n, const std::nothrow_t& tag) noexcept {
  return ::operator new(n, tag);
}
void operator delete(void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}
void operator delete[](void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete[](void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  std::free(p);
}

namespace mrpt {
// MRPT's scans keep their beams in vectors of mrpt::aligned_allocator_cpp11, which allocate
// through this libmrpt-core function rather than operator new; this definition takes its place
// (same behaviour: C++17 aligned_alloc, released by mrpt::aligned_free's free()) and applies the
// record limit. Its callers do not check for null: a refusal throws.
void* aligned_malloc(std::size_t size, std::size_t alignment) {
  if (t_allocation_limit != 0 && size > t_allocation_limit) throw std::bad_alloc();
  if (alignment != 0 && size % alignment != 0) size = (size / alignment + 1) * alignment;
  return ::aligned_alloc(alignment, size);
}
}  // namespace mrpt

namespace dynamap {

std::uint64_t uncompressedSize(const std::string& path) {
  std::ifstream f(path, std::ios::binary | std::ios::ate);
  if (!f) return 0;
  const auto size = static_cast<std::streamoff>(f.tellg());
  unsigned char head[2] = {0, 0};
  f.seekg(0);
  f.read(reinterpret_cast<char*>(head), 2);
  if (!(head[0] == 0x1f && head[1] == 0x8b)) return static_cast<std::uint64_t>(size);
  if (size < 18) return 0;
  unsigned char tail[4];
  f.seekg(size - 4);
  f.read(reinterpret_cast<char*>(tail), 4);
  if (!f) return 0;
  return tail[0] | (tail[1] << 8) | (tail[2] << 16) | (static_cast<std::uint64_t>(tail[3]) << 24);
}

PoseSource parsePoseSource(const std::string& name) {
  if (name == "auto") return PoseSource::Auto;
  if (name == "simplemap") return PoseSource::Simplemap;
  if (name == "ground_truth") return PoseSource::GroundTruth;
  if (name == "odometry") return PoseSource::Odometry;
  if (name == "scan_matching") return PoseSource::ScanMatching;
  throw std::invalid_argument("unknown pose source '" + name +
                              "' (auto, simplemap, ground_truth, odometry, scan_matching)");
}

std::string toString(PoseSource source) {
  switch (source) {
    case PoseSource::Auto:
      return "auto";
    case PoseSource::Simplemap:
      return "simplemap";
    case PoseSource::GroundTruth:
      return "ground_truth";
    case PoseSource::Odometry:
      return "odometry";
    case PoseSource::ScanMatching:
      return "scan_matching";
  }
  return "?";
}

namespace {

using mrpt::obs::CObservation2DRangeScan;

/// MRPT copies a scan's rightToLeft byte from the file as it is: any byte but 0 or 1 is no valid
/// bool (reading it is undefined behaviour). Makes it one.
void normalizeFlags(CObservation2DRangeScan& scan) {
  unsigned char raw = 0;
  std::memcpy(&raw, &scan.rightToLeft, 1);
  scan.rightToLeft = raw != 0;
}

/// Far above any real record's largest buffer (a laser scan of a million beams takes 4 MB).
constexpr std::size_t kMaxRecordAllocation = std::size_t{256} << 20;

/// Bounds single allocations while a record is deserialized (see operator new above).
class RecordAllocationLimit {
 public:
  RecordAllocationLimit() : saved_(t_allocation_limit) {
    t_allocation_limit = kMaxRecordAllocation;
  }
  ~RecordAllocationLimit() { t_allocation_limit = saved_; }
  RecordAllocationLimit(const RecordAllocationLimit&) = delete;
  RecordAllocationLimit& operator=(const RecordAllocationLimit&) = delete;

 private:
  std::size_t saved_;
};

/// Reads one top-level object; a size in it beyond any real record throws std::bad_alloc.
mrpt::serialization::CSerializable::Ptr readBoundedObject(mrpt::io::CStream& in) {
  const RecordAllocationLimit limit;
  return mrpt::serialization::archiveFrom(in).ReadObject();
}

std::string stripRawlogExtension(std::string p) {
  for (const char* ext : {".gz", ".rawlog"}) {
    const std::string e = ext;
    if (p.size() > e.size() && p.compare(p.size() - e.size(), e.size(), e) == 0) {
      p.resize(p.size() - e.size());
    }
  }
  return p;
}

/// MRPT's companion ground-truth file: <log without .rawlog[.gz]>.gt.txt.
std::string companionGroundTruth(const std::string& path) {
  return stripRawlogExtension(path) + ".gt.txt";
}

bool fileExists(const std::string& p) {
  return std::ifstream(p).good();
}

/// The first decompressed bytes of a file (gz or plain).
std::string fileHead(const std::string& path, std::size_t n) {
  mrpt::io::CFileGZInputStream in;
  if (!in.open(path)) throw InputError(path + ": cannot open");
  std::string head(n, '\0');
  const std::size_t got = in.Read(head.data(), n);
  head.resize(got);
  return head;
}

/// Reads `timestamp x y phi` lines (MRPT's .gt.txt) into a pose track.
void loadGroundTruthText(const std::string& path, PoseTrack& track) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open ground-truth file");
  std::string line;
  std::size_t line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#' || line[first] == '%') continue;
    std::istringstream fields(line);
    std::string tok[4];
    double v[4];
    for (int k = 0; k < 4; ++k) {
      if (!(fields >> tok[k]) || !parseDouble(tok[k], v[k])) {
        throw InputError(path + ":" + std::to_string(line_no) +
                         ": expected 'timestamp x y phi' (numbers)");
      }
    }
    track.add(v[0], mrpt::poses::CPose2D(v[1], v[2], v[3]));
  }
}

double toSeconds(const mrpt::Clock::time_point& t) {
  return mrpt::Clock::toDouble(t);
}

/// Streams an MRPT rawlog (either format), one record at a time, resolving each scan's pose by
/// time from the chosen pose source.
class RawlogSource : public ScanSource {
 public:
  RawlogSource(const std::string& path, PoseSource source)
      : path_(path), source_(source), bytes_(static_cast<double>(uncompressedSize(path))) {
    if (!in_.open(path)) throw InputError(path + ": cannot open");
    if (source_ == PoseSource::GroundTruth && !hasGroundTruthInLog(path)) {
      const std::string gt = companionGroundTruth(path);
      if (!fileExists(gt)) {
        throw InputError(path +
                         ": no ground-truth poses (no CObservationRobotPose in the log, "
                         "no companion file " +
                         gt + ")");
      }
      loadGroundTruthText(gt, poses_);
      poses_from_file_ = true;
    }
  }

  static bool hasGroundTruthInLog(const std::string& path);

  bool next(ScanRecord& out) override {
    while (true) {
      if (!ready_.empty()) {
        out = std::move(ready_.front());
        ready_.pop_front();
        return true;
      }
      if (eof_) return flushPending(out);
      readRecord();
      resolvePending(false);
    }
  }

  PoseSource poseSource() const override { return source_; }
  const SourceStats& stats() const override { return stats_; }
  const std::string& path() const override { return path_; }
  double fractionRead() const override {
    return bytes_ > 0 ? std::min(1.0, static_cast<double>(in_.getPosition()) / bytes_) : -1.0;
  }

 private:
  struct Pending {
    std::size_t index;
    double t;
    CObservation2DRangeScan::Ptr scan;
  };

  void readRecord() {
    const uint64_t start = in_.getPosition();
    mrpt::serialization::CSerializable::Ptr obj;
    try {
      obj = readBoundedObject(in_);
    } catch (const mrpt::serialization::CExceptionEOF&) {
      eof_ = true;
      if (in_.getPosition() != start) {
        fault_ = "record " + std::to_string(stats_.records) + " at byte " + std::to_string(start) +
                 " is cut off (truncated file)";
      }
      return;
    } catch (const std::exception& e) {
      // MRPT reports a record cut short as an error reading it, not as CExceptionEOF.
      eof_ = true;
      const std::string msg = innermostMessage(e.what());
      const std::string where =
          "record " + std::to_string(stats_.records) + " at byte " + std::to_string(start);
      if (msg.find("(EOF?)") != std::string::npos || in_.checkEOF()) {
        fault_ = where + " is cut off (truncated file)";
      } else if (msg.find("bad_alloc") != std::string::npos) {
        fault_ = where + " is corrupt: it states a size no real record has";
      } else {
        fault_ = where + " is corrupt: " + msg;
      }
      return;
    }
    ++stats_.records;
    if (!obj) return;
    if (auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(obj)) {
      for (const auto& o : *sf) take(o);
      if (!odometry_observed_) {
        // Action / sensory-frame format: the odometry integrated so far (the origin before the
        // first action) is the pose of this frame's observations.
        const double t = frameTime(*sf);
        if (std::isfinite(t) && source_ == PoseSource::Odometry) poses_.add(t, odometry_);
      }
    } else if (auto acts = std::dynamic_pointer_cast<mrpt::obs::CActionCollection>(obj)) {
      if (auto mv = acts->getBestMovementEstimation()) {
        odometry_ = odometry_ + mv->poseChange->getMeanVal();
      }
    } else if (auto o = std::dynamic_pointer_cast<mrpt::obs::CObservation>(obj)) {
      take(o);
    } else {
      ++stats_.skipped[std::string("record of class ") + obj->GetRuntimeClass()->className];
    }
  }

  /// MRPT's exceptions nest reports with call stacks; the innermost "Message:" says what failed.
  static std::string innermostMessage(const std::string& what) {
    std::string msg;
    for (std::size_t pos = what.find("Message:"); pos != std::string::npos;
         pos = what.find("Message:", pos + 1)) {
      msg = what.substr(pos + 8, what.find('\n', pos) - pos - 8);
    }
    if (msg.empty()) msg = what.substr(0, what.find('\n'));
    const auto first = msg.find_first_not_of(' ');
    return first == std::string::npos ? std::string() : msg.substr(first);
  }

  static double frameTime(const mrpt::obs::CSensoryFrame& sf) {
    for (const auto& o : sf) {
      if (o && o->timestamp != INVALID_TIMESTAMP) return toSeconds(o->timestamp);
    }
    return NAN;
  }

  void take(const mrpt::obs::CObservation::Ptr& o) {
    if (!o) return;
    const double t = o->timestamp == INVALID_TIMESTAMP ? NAN : toSeconds(o->timestamp);
    if (auto scan = std::dynamic_pointer_cast<CObservation2DRangeScan>(o)) {
      normalizeFlags(*scan);
      const std::size_t index = stats_.scans++;
      if (!std::isfinite(t)) {
        throw InputError(path_ + ": scan " + std::to_string(index) + " has no timestamp");
      }
      pending_.push_back({index, t, scan});
      if (pending_.size() > kMaxPending) {
        throw InputError(path_ + ": scan " + std::to_string(pending_.front().index) + " has no " +
                         toString(source_) + " pose within " + std::to_string(kMaxPending) +
                         " scans after it");
      }
    } else if (auto odo = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(o)) {
      odometry_observed_ = true;
      if (source_ == PoseSource::Odometry && std::isfinite(t)) poses_.add(t, odo->odometry);
    } else if (auto gt = std::dynamic_pointer_cast<mrpt::obs::CObservationRobotPose>(o)) {
      if (source_ == PoseSource::GroundTruth && !poses_from_file_ && std::isfinite(t)) {
        poses_.add(t, mrpt::poses::CPose2D(gt->pose.mean));
      }
    }
  }

  /// Moves pending scans whose pose is now known to ready_. At the end of input (`final`), a
  /// scan past the last pose can only take it if close enough in time.
  void resolvePending(bool final) {
    while (!pending_.empty()) {
      Pending& p = pending_.front();
      mrpt::poses::CPose2D pose;
      const PoseTrack::Lookup r = poses_.at(p.t, pose, final);
      if (r == PoseTrack::Lookup::kLater) return;  // wait for a later pose
      if (r != PoseTrack::Lookup::kFound) {
        if (final && !fault_.empty()) {  // the fault, not the pose, is what went wrong
          pending_.clear();
          return;
        }
        throw InputError(path_ + ": scan " + std::to_string(p.index) +
                         " (t=" + std::to_string(p.t) + ") has no " + toString(source_) + " pose");
      }
      const double t = p.t;
      ready_.push_back({p.index, t, pose, std::move(p.scan)});
      pending_.pop_front();  // p is gone from here on
      // Poses from a little before it stay: a later scan stamped earlier (a clock stepping back)
      // still finds its pose.
      poses_.forgetBefore(t - kPoseHistory_s);
    }
  }

  bool flushPending(ScanRecord& out) {
    resolvePending(true);
    if (!ready_.empty()) {
      out = std::move(ready_.front());
      ready_.pop_front();
      return true;
    }
    if (!fault_.empty()) {
      const std::string f = fault_;
      fault_.clear();
      throw InputError(path_ + ": " + f);
    }
    return false;
  }

  static constexpr std::size_t kMaxPending = 10000;
  static constexpr double kPoseHistory_s = 10.0;

  std::string path_;
  PoseSource source_;
  double bytes_;  // uncompressed size, for fractionRead (0: unknown)
  mrpt::io::CFileGZInputStream in_;
  SourceStats stats_;
  PoseTrack poses_;
  bool poses_from_file_ = false;
  mrpt::poses::CPose2D odometry_;
  bool odometry_observed_ = false;  // CObservationOdometry seen: frames carry no pose of their own
  std::deque<Pending> pending_;
  std::deque<ScanRecord> ready_;
  bool eof_ = false;
  std::string fault_;
};

/// What pose sources a rawlog offers, from its first records.
struct RawlogPeek {
  bool ground_truth = false;
  bool odometry = false;
};

RawlogPeek peekRawlog(const std::string& path) {
  RawlogPeek peek;
  mrpt::io::CFileGZInputStream in;
  if (!in.open(path)) throw InputError(path + ": cannot open");
  auto see = [&](const mrpt::obs::CObservation::Ptr& o) {
    if (std::dynamic_pointer_cast<mrpt::obs::CObservationRobotPose>(o)) peek.ground_truth = true;
    if (std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(o)) peek.odometry = true;
  };
  // A few hundred records tell which kinds of pose the log carries.
  for (int i = 0; i < 300; ++i) {
    mrpt::serialization::CSerializable::Ptr obj;
    try {
      obj = readBoundedObject(in);
    } catch (const std::exception&) {
      break;  // faults are reported by the real pass, at their record
    }
    if (auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(obj)) {
      for (const auto& o : *sf) see(o);
    } else if (std::dynamic_pointer_cast<mrpt::obs::CActionCollection>(obj)) {
      peek.odometry = true;
    } else if (auto o = std::dynamic_pointer_cast<mrpt::obs::CObservation>(obj)) {
      see(o);
    }
  }
  return peek;
}

bool RawlogSource::hasGroundTruthInLog(const std::string& path) {
  return peekRawlog(path).ground_truth;
}

/// A simplemap's keyframes: each sensory frame's scans at the keyframe's mean pose.
class SimplemapSource : public ScanSource {
 public:
  explicit SimplemapSource(const std::string& path) : path_(path) {
    bool loaded = false;
    try {
      const RecordAllocationLimit limit;
      loaded = map_.loadFromFile(path);
    } catch (const std::exception& e) {
      throw InputError(path + ": cannot read simplemap: " + std::string(e.what()).substr(0, 200));
    }
    if (!loaded) throw InputError(path + ": cannot read simplemap");
    stats_.records = map_.size();
    it_ = map_.begin();
  }

  bool next(ScanRecord& out) override {
    while (it_ != map_.end()) {
      if (obs_index_ < it_->sf->size()) {
        auto o = it_->sf->getObservationByIndex(obs_index_++);
        auto scan = std::dynamic_pointer_cast<CObservation2DRangeScan>(o);
        if (!scan) continue;
        normalizeFlags(*scan);
        out.index = stats_.scans++;
        out.t = scan->timestamp == INVALID_TIMESTAMP ? 0.0 : toSeconds(scan->timestamp);
        out.pose = mrpt::poses::CPose2D(it_->pose->getMeanVal());
        out.scan = scan;
        return true;
      }
      ++it_;
      obs_index_ = 0;
    }
    return false;
  }

  PoseSource poseSource() const override { return PoseSource::Simplemap; }
  double fractionRead() const override {
    return map_.size() ? static_cast<double>(it_ - map_.begin()) / map_.size() : 1.0;
  }
  const SourceStats& stats() const override { return stats_; }
  const std::string& path() const override { return path_; }

 private:
  std::string path_;
  mrpt::maps::CSimpleMap map_;
  mrpt::maps::CSimpleMap::const_iterator it_;
  std::size_t obs_index_ = 0;
  SourceStats stats_;
};

}  // namespace

std::unique_ptr<ScanSource> openScanSource(const std::string& path, PoseSource source,
                                           const CarmenOptions* carmen) {
  if (!fileExists(path)) throw InputError(path + ": no such file");
  if (source == PoseSource::ScanMatching) source = PoseSource::Odometry;  // corrected by Mapper
  if (looksLikeCarmen(path))
    return openCarmenSource(path, source, carmen ? *carmen : CarmenOptions{});
  const std::string head = fileHead(path, 256);
  if (head.empty()) throw InputError(path + ": empty file");
  if (head.find("CSimpleMap") != std::string::npos) {
    if (source != PoseSource::Auto && source != PoseSource::Simplemap) {
      throw InputError(path + ": a simplemap only carries simplemap poses (asked for " +
                       toString(source) + ")");
    }
    return std::make_unique<SimplemapSource>(path);
  }
  if (head.find("CSensoryFrame") == std::string::npos &&
      head.find("CActionCollection") == std::string::npos &&
      head.find("CObservation") == std::string::npos) {
    throw InputError(path + ": not an MRPT rawlog, simplemap or CARMEN log");
  }
  if (source == PoseSource::Simplemap) {
    throw InputError(path + ": pose source simplemap needs a .simplemap file");
  }
  if (source == PoseSource::Auto) {
    const RawlogPeek peek = peekRawlog(path);
    if (peek.ground_truth || fileExists(companionGroundTruth(path))) {
      source = PoseSource::GroundTruth;
    } else if (peek.odometry) {
      source = PoseSource::Odometry;
    } else {
      throw InputError(path + ": no poses found (no ground truth, no odometry)");
    }
  }
  return std::make_unique<RawlogSource>(path, source);
}

}  // namespace dynamap
