// A ROS 2 bag by content: an MCAP file, an SQLite (.db3) file, or a rosbag2 folder whose
// metadata.yaml lists its files (relative_file_paths) in the order they were recorded; a folder
// without one is read file by file in the order of the numbers in their names (bag_0.db3,
// bag_1.db3, ..., bag_10.db3).
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>

#include "dynamap/input/ros2_bag.h"
#include "dynamap/input/scan_source.h"

namespace dynamap::ros2 {
namespace {

namespace fs = std::filesystem;

std::string trimmed(std::string s) {
  const auto blank = [](unsigned char c) { return std::isspace(c) != 0; };
  while (!s.empty() && blank(static_cast<unsigned char>(s.back()))) s.pop_back();
  std::size_t b = 0;
  while (b < s.size() && blank(static_cast<unsigned char>(s[b]))) ++b;
  s = s.substr(b);
  if (s.size() >= 2 && (s[0] == '"' || s[0] == '\'') && s.back() == s[0]) {
    s = s.substr(1, s.size() - 2);
  }
  return s;
}

/// metadata.yaml's relative_file_paths (a block list, or a flow list on the key's line).
std::vector<std::string> metadataFiles(const std::string& yaml) {
  std::ifstream in(yaml);
  std::vector<std::string> out;
  bool in_list = false;
  for (std::string line; std::getline(in, line);) {
    const std::string t = trimmed(line);
    if (!in_list) {
      if (t.rfind("relative_file_paths:", 0) != 0) continue;
      std::string rest = trimmed(t.substr(20));
      if (rest.empty()) {
        in_list = true;
        continue;
      }
      if (rest.front() == '[' && rest.back() == ']') rest = rest.substr(1, rest.size() - 2);
      for (std::size_t at = 0; at <= rest.size();) {
        const std::size_t comma = std::min(rest.find(',', at), rest.size());
        const std::string item = trimmed(rest.substr(at, comma - at));
        if (!item.empty()) out.push_back(item);
        at = comma + 1;
      }
      break;
    }
    if (t.rfind("- ", 0) != 0) break;
    out.push_back(trimmed(t.substr(2)));
  }
  return out;
}

/// The number in a file name (bag_12.db3 -> 12) for ordering a folder without metadata.
std::pair<long long, std::string> orderKey(const fs::path& p) {
  const std::string stem = p.stem().string();
  std::size_t end = stem.size(), b = end;
  while (b > 0 && std::isdigit(static_cast<unsigned char>(stem[b - 1]))) --b;
  const long long n = b < end && end - b < 18 ? std::stoll(stem.substr(b)) : -1;
  return {n, p.filename().string()};
}

std::vector<std::string> folderFiles(const std::string& dir) {
  const fs::path yaml = fs::path(dir) / "metadata.yaml";
  std::vector<std::string> out;
  if (fs::exists(yaml)) {
    for (const std::string& f : metadataFiles(yaml.string())) {
      const fs::path p = fs::path(dir) / fs::path(f).filename();
      if (!fs::is_regular_file(p)) {
        throw InputError(yaml.string() + ": relative_file_paths names " + f +
                         ", which is not in the folder");
      }
      out.push_back(p.string());
    }
    if (out.empty()) throw InputError(yaml.string() + ": no relative_file_paths");
    return out;
  }
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.is_regular_file() && isRos2BagFile(e.path().string())) files.push_back(e.path());
  }
  std::sort(files.begin(), files.end(),
            [](const fs::path& a, const fs::path& b) { return orderKey(a) < orderKey(b); });
  for (const auto& f : files) out.push_back(f.string());
  if (out.empty()) throw InputError(dir + ": a folder with no metadata.yaml, .db3 or .mcap file");
  return out;
}

std::unique_ptr<MessageStream> openFile(const std::string& path,
                                        const std::vector<std::string>& topics) {
  switch (ros2FileKind(path)) {
    case Ros2File::kMcap:
      return openMcap(path, topics);
    case Ros2File::kSqlite:
      return openDb3(path, topics);
    default:
      throw InputError(path + ": neither an MCAP file nor a rosbag2 SQLite (.db3) file");
  }
}

/// The files of one bag, one after the other (a fault in one ends the bag).
class ChainStream : public MessageStream {
 public:
  ChainStream(std::vector<std::string> files, const std::vector<std::string>& topics)
      : files_(std::move(files)), topics_(topics), current_(openFile(files_[0], topics)) {}

  bool next() override {
    while (!current_->next()) {
      if (!current_->fault().empty() || at_ + 1 >= files_.size()) return false;
      current_ = openFile(files_[++at_], topics_);
    }
    return true;
  }
  const std::string& topic() const override { return current_->topic(); }
  const std::string& type() const override { return current_->type(); }
  std::uint64_t timeNs() const override { return current_->timeNs(); }
  const std::uint8_t* data() const override { return current_->data(); }
  std::size_t size() const override { return current_->size(); }
  std::string where() const override { return current_->where(); }
  std::string fault() const override { return current_->fault(); }
  double fractionRead() const override {
    return (double(at_) + current_->fractionRead()) / double(files_.size());
  }
  TopicList topics() override {
    TopicList all = current_->topics();
    for (std::size_t i = 0; i < files_.size(); ++i) {
      if (i == at_) continue;
      const TopicList more = openFile(files_[i], topics_)->topics();
      all.insert(all.end(), more.begin(), more.end());
    }
    std::sort(all.begin(), all.end());
    all.erase(std::unique(all.begin(), all.end()), all.end());
    return all;
  }

 private:
  std::vector<std::string> files_;
  std::vector<std::string> topics_;
  std::size_t at_ = 0;
  std::unique_ptr<MessageStream> current_;
};

}  // namespace

std::string ros1TypeName(const std::string& ros2_type) {
  const std::size_t at = ros2_type.find("/msg/");
  if (at == std::string::npos) return ros2_type;
  return ros2_type.substr(0, at) + "/" + ros2_type.substr(at + 5);
}

std::unique_ptr<MessageStream> openRos2Bag(const std::string& path,
                                           const std::vector<std::string>& topics) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    return std::make_unique<ChainStream>(folderFiles(path), topics);
  }
  return openFile(path, topics);
}

}  // namespace dynamap::ros2
