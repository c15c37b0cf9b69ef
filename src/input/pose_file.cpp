#include "dynamap/input/pose_file.h"

#include <sstream>

#include "dynamap/base/ini.h"
#include "dynamap/input/line_reader.h"
#include "dynamap/input/scan_source.h"

namespace dynamap {
namespace {

std::string stripRawlogExtension(std::string p) {
  for (const char* ext : {".gz", ".rawlog"}) {
    const std::string e = ext;
    if (p.size() > e.size() && p.compare(p.size() - e.size(), e.size(), e) == 0) {
      p.resize(p.size() - e.size());
    }
  }
  return p;
}

}  // namespace

std::string companionGroundTruth(const std::string& path) {
  return stripRawlogExtension(path) + ".gt.txt";
}

std::vector<TimedPose> readPoseFile(const std::string& path) {
  LineReader in(path);  // every line capped: a pose file of /dev/zero is an error, not 13 GB
  std::vector<TimedPose> poses;
  std::string line;
  while (in.next(line)) {
    const std::size_t line_no = in.lineNumber();
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
    poses.push_back({v[0], v[1], v[2], v[3]});
  }
  return poses;
}

}  // namespace dynamap
