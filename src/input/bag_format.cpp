// Telling a ROS 1 bag by its first bytes needs no rosbag: a build without bag support can still
// name what it was given.
#include <fstream>
#include <string>

#include "dynamap/input/bag_source.h"

namespace dynamap {

bool looksLikeRosBag(const std::string& path) {
  static const std::string kMagic = "#ROSBAG V2.0\n";
  std::ifstream in(path, std::ios::binary);
  std::string head(kMagic.size(), '\0');
  if (!in.read(head.data(), static_cast<std::streamsize>(head.size()))) return false;
  return head == kMagic;
}

}  // namespace dynamap
