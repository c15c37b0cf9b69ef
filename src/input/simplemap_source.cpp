#include "dynamap/input/simplemap_source.h"

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose3DPDF.h>
#include <mrpt/poses/CPosePDF.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <cstdint>

#include "dynamap/input/mrpt_records.h"

namespace dynamap {
namespace {

using mrpt::obs::CObservation2DRangeScan;

/// Streams a simplemap keyframe by keyframe instead of letting MRPT load it whole, so that a
/// file cut or damaged at keyframe k still gives the scans of keyframes 0 … k-1 (and then the
/// fault, naming the keyframe and its byte) and memory holds one keyframe at a time.
///
/// The file is one serialized object: a header (class name and version), a uint32 keyframe
/// count, then that many (pose PDF, sensory frame) pairs, each an object of its own. Both
/// headers MRPT ever wrote are read: the current one (a length byte with bit 7 set, the name,
/// a uint8 version; the name with or without "mrpt::maps::") and the one before MRPT 1.0 (a uint32
/// length, the name, a uint32 version), whose class was CSensFrameProbSequence and whose poses are
/// 2D PDFs.
class SimplemapSource : public ScanSource {
 public:
  explicit SimplemapSource(const std::string& path)
      : path_(path), size_bound_(uncompressedSizeBound(path)) {
    if (!in_.open(path)) throw InputError(path + ": cannot open");
    try {
      readHeader();
    } catch (const std::exception& e) {
      throw InputError(path +
                       ": cannot read simplemap: " + describeRecordFault(e, in_, "header", 0));
    }
  }

  bool next(ScanRecord& out) override {
    while (true) {
      if (frame_ && obs_index_ < frame_->size()) {
        auto scan = std::dynamic_pointer_cast<CObservation2DRangeScan>(
            frame_->getObservationByIndex(obs_index_++));
        if (!scan) continue;
        normalizeFlags(*scan);
        out.index = stats_.scans++;
        out.t = scan->timestamp == INVALID_TIMESTAMP ? 0.0 : toSeconds(scan->timestamp);
        out.pose = pose_;
        out.scan = scan;
        return true;
      }
      if (stats_.records == keyframes_) return false;
      readKeyframe();
    }
  }

  PoseSource poseSource() const override { return PoseSource::Simplemap; }
  double fractionRead() const override {
    return keyframes_ ? static_cast<double>(stats_.records) / keyframes_ : 1.0;
  }
  const SourceStats& stats() const override { return stats_; }
  const std::string& path() const override { return path_; }

 private:
  void readHeader() {
    const uint8_t first = readInt<uint8_t>();
    std::string name;
    if (first & 0x80) {
      name = readBytes(first & 0x7f);
      readInt<uint8_t>();  // the version: every one MRPT wrote has the layout read below
    } else {
      const uint32_t length =
          first | uint32_t{readInt<uint8_t>()} << 8 | uint32_t{readInt<uint16_t>()} << 16;
      name = readBytes(std::min<uint32_t>(length, 64));
      readInt<uint32_t>();
    }
    const std::string kNamespace = "mrpt::maps::";  // written since MRPT 2.0
    if (name.rfind(kNamespace, 0) == 0) name.erase(0, kNamespace.size());
    if (name != "CSimpleMap" && name != "CSensFrameProbSequence") {
      throw std::runtime_error("Message: its object is a " + name + ", not a simplemap");
    }
    keyframes_ = readInt<uint32_t>();
    stats_.record_unit = "keyframes";
  }

  /// `n` bytes of the file; MRPT's archive accepts a short read, which here is the file's end.
  std::string readBytes(std::size_t n) {
    std::string bytes(n, '\0');
    if (n && in_.Read(bytes.data(), n) != n) {
      throw mrpt::serialization::CExceptionEOF("the file ends inside the simplemap's header");
    }
    return bytes;
  }

  /// A little-endian integer of the file.
  template <typename T>
  T readInt() {
    const std::string bytes = readBytes(sizeof(T));
    T v = 0;
    for (std::size_t i = sizeof(T); i-- > 0;) v = static_cast<T>(v << 8 | uint8_t(bytes[i]));
    return v;
  }

  /// Reads the next (pose, frame) pair; throws InputError naming the keyframe on a fault.
  void readKeyframe() {
    const uint64_t start = in_.getPosition();
    const std::string what =
        "keyframe " + std::to_string(stats_.records) + " of " + std::to_string(keyframes_);
    try {
      const auto pose = readBoundedObject(in_, recordAllocationBound(size_bound_, start));
      frame_ = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(
          readBoundedObject(in_, recordAllocationBound(size_bound_, in_.getPosition())));
      if (auto p3 = std::dynamic_pointer_cast<mrpt::poses::CPose3DPDF>(pose)) {
        pose_ = mrpt::poses::CPose2D(p3->getMeanVal());
      } else if (auto p2 = std::dynamic_pointer_cast<mrpt::poses::CPosePDF>(pose)) {
        pose_ = p2->getMeanVal();
      } else {
        throw std::runtime_error("Message: its pose is no pose PDF");
      }
      if (!frame_) throw std::runtime_error("Message: its observations are no sensory frame");
    } catch (const std::exception& e) {
      frame_.reset();
      keyframes_ = stats_.records;  // nothing after a fault is read
      throw InputError(path_ + ": " + describeRecordFault(e, in_, what, start));
    }
    ++stats_.records;
    obs_index_ = 0;
  }

  std::string path_;
  std::uint64_t size_bound_;  // what the file can hold at most, bounding a keyframe's allocations
  mrpt::io::CFileGZInputStream in_;
  uint32_t keyframes_ = 0;  // as the file states it: never allocated, only counted up to
  mrpt::obs::CSensoryFrame::Ptr frame_;
  mrpt::poses::CPose2D pose_;
  std::size_t obs_index_ = 0;
  SourceStats stats_;
};

}  // namespace

std::unique_ptr<ScanSource> openSimplemapSource(const std::string& path) {
  return std::make_unique<SimplemapSource>(path);
}

}  // namespace dynamap
