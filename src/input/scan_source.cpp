#include "dynamap/input/scan_source.h"

#include <fstream>
#include <stdexcept>

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
  if (name == "fixed") return PoseSource::Fixed;
  if (name == "slam") return PoseSource::Slam;
  throw std::invalid_argument("unknown pose source '" + name +
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
