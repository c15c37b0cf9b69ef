// Telling a ROS 1 bag by its first bytes needs no rosbag: a build without bag support can still
// name what it was given.
#include <filesystem>
#include <fstream>
#include <string>

#include "dynamap/input/bag_source.h"
#include "dynamap/input/ros2_bag.h"

namespace dynamap {

bool looksLikeRosBag(const std::string& path) {
  static const std::string kMagic = "#ROSBAG V2.0\n";
  std::ifstream in(path, std::ios::binary);
  std::string head(kMagic.size(), '\0');
  if (!in.read(head.data(), static_cast<std::streamsize>(head.size()))) return false;
  return head == kMagic;
}

namespace ros2 {

namespace fs = std::filesystem;

Ros2File ros2FileKind(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char head[16] = {};
  in.read(head, sizeof head);
  const std::string h(head, static_cast<std::size_t>(in.gcount()));
  if (h.compare(0, 8, std::string("\x89MCAP0\r\n", 8)) == 0) return Ros2File::kMcap;
  if (h == std::string("SQLite format 3\0", 16)) return Ros2File::kSqlite;
  return Ros2File::kNone;
}

bool isRos2BagFile(const std::string& name) {
  const fs::path p(name);
  return p.extension() == ".db3" || p.extension() == ".mcap";
}

bool looksLikeRos2Bag(const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    if (fs::exists(fs::path(path) / "metadata.yaml", ec)) return true;
    for (fs::directory_iterator it(path, ec), end; !ec && it != end; it.increment(ec)) {
      if (isRos2BagFile(it->path().string())) return true;
    }
    return false;
  }
  return fs::is_regular_file(path, ec) && ros2FileKind(path) != Ros2File::kNone;
}

}  // namespace ros2
}  // namespace dynamap
