#include "dynamap/input/scan_source.h"

#include <fstream>
#include <stdexcept>

namespace dynamap {

namespace {

/// A file's size, whether it is gzip, and for gzip the trailer's ISIZE (the uncompressed size
/// modulo 4 GiB of its last member).
struct StoredSize {
  std::uint64_t file = 0;
  bool gz = false;
  std::uint64_t isize = 0;
};

StoredSize storedSize(const std::string& path) {
  StoredSize s;
  std::ifstream f(path, std::ios::binary | std::ios::ate);
  if (!f) return s;
  s.file = static_cast<std::uint64_t>(static_cast<std::streamoff>(f.tellg()));
  unsigned char head[2] = {0, 0};
  f.seekg(0);
  f.read(reinterpret_cast<char*>(head), 2);
  s.gz = head[0] == 0x1f && head[1] == 0x8b;
  if (!s.gz || s.file < 18) return s;
  unsigned char tail[4];
  f.seekg(static_cast<std::streamoff>(s.file - 4));
  f.read(reinterpret_cast<char*>(tail), 4);
  if (f) {
    s.isize =
        tail[0] | (tail[1] << 8) | (tail[2] << 16) | (static_cast<std::uint64_t>(tail[3]) << 24);
  }
  return s;
}

}  // namespace

std::uint64_t uncompressedSize(const std::string& path) {
  const StoredSize s = storedSize(path);
  return s.gz ? s.isize : s.file;
}

std::uint64_t uncompressedSizeBound(const std::string& path) {
  const StoredSize s = storedSize(path);
  if (!s.gz) return s.file;
  // Deflate inflates at most 1032:1: a smaller file cannot hold 4 GiB, so ISIZE is exact.
  constexpr std::uint64_t kMaxDeflateRatio = 1032;
  return s.file * kMaxDeflateRatio < (std::uint64_t{1} << 32) ? s.isize : 0;
}

PoseSource parsePoseSource(const std::string& name) {
  if (name == "auto") return PoseSource::Auto;
  if (name == "simplemap") return PoseSource::Simplemap;
  if (name == "ground_truth") return PoseSource::GroundTruth;
  if (name == "odometry") return PoseSource::Odometry;
  if (name == "scan_matching") return PoseSource::ScanMatching;
  if (name == "fixed") return PoseSource::Fixed;
  if (name == "slam") return PoseSource::Slam;
  throw std::invalid_argument(
      "unknown pose source '" + name +
      "' (auto, simplemap, ground_truth, odometry, scan_matching, fixed, slam)");
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
    case PoseSource::Fixed:
      return "fixed";
    case PoseSource::Slam:
      return "slam";
  }
  return "?";
}

}  // namespace dynamap
