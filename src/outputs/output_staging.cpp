#include "dynamap/outputs/output_staging.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "dynamap/outputs/map_outputs.h"

namespace dynamap {
namespace fs = std::filesystem;

namespace {

constexpr const char* kStagingPrefix = ".dynamap-run-";

[[noreturn]] void fail(const std::string& what, int err) {
  throw std::runtime_error(what + " (" + std::strerror(err) + ")");
}

// Staging directories of runs killed before they could clean up (SIGKILL, power loss), and the
// fixed-name temporaries of older versions: nobody else writes here while the lock is held.
void removeLeftovers(const std::string& dir) {
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    const bool staging = name.rfind(kStagingPrefix, 0) == 0;
    bool old_tmp = false;
    for (const auto& out : OutputStaging::runOutputs()) old_tmp |= name == ".tmp-" + out;
    if (staging || old_tmp) fs::remove_all(e.path(), ec);
  }
}

}  // namespace

const std::vector<std::string>& OutputStaging::runOutputs() {
  static const std::vector<std::string> names = {
      "static.png",  "dynamic.png", "overlay.png",    "mrpt_plain.png", "static.gridmap.gz",
      "dynamic.gridmap.gz", "static.pgm", "static.yaml", "config.ini", "objects.csv",
      "events.csv",  "tracks.csv",  "people.csv",     "poses.txt",      "graph.g2o",
      "timelapse.mp4", "frames",    "report.md",      "metrics.json",   "session.json",
      "changes.csv", "changes.png", "summary.json"};
  return names;
}

OutputStaging::OutputStaging(const std::string& out_dir) : out_dir_(out_dir) {
  prepareOutputDir(out_dir);
  lock_fd_ = ::open(out_dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (lock_fd_ < 0) fail(out_dir + ": cannot open output directory", errno);
  if (::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
    const int err = errno;
    ::close(lock_fd_);
    lock_fd_ = -1;
    if (err == EWOULDBLOCK) {
      throw std::runtime_error(out_dir + ": another dynamap run is writing into this directory");
    }
    fail(out_dir + ": cannot lock output directory", err);
  }
  removeLeftovers(out_dir);
  std::string tmpl = (fs::path(out_dir) / (std::string(kStagingPrefix) + "XXXXXX")).string();
  if (!::mkdtemp(tmpl.data())) {
    const int err = errno;
    ::close(lock_fd_);
    lock_fd_ = -1;
    fail(out_dir + ": cannot create a staging directory", err);
  }
  staging_ = tmpl;
}

OutputStaging::~OutputStaging() {
  if (!committed_ && !staging_.empty()) {
    std::error_code ec;
    fs::remove_all(staging_, ec);  // a failed or interrupted run leaves the directory as it was
  }
  if (lock_fd_ >= 0) ::close(lock_fd_);  // releases the lock
}

void OutputStaging::commit() {
  std::error_code ec;
  const fs::path out(out_dir_);
  // summary.json goes first and comes back last: while the set is being replaced, the directory
  // holds no summary claiming outputs that are not all there.
  fs::remove(out / "summary.json", ec);
  for (const auto& name : runOutputs()) {
    if (name == "summary.json") continue;
    fs::remove_all(out / name, ec);  // stale: this run's own comes next, or none at all
    const fs::path from = fs::path(staging_) / name;
    if (!fs::exists(from)) continue;
    if (::rename(from.c_str(), (out / name).c_str()) != 0) fail((out / name).string(), errno);
  }
  const fs::path summary = fs::path(staging_) / "summary.json";
  if (fs::exists(summary) &&
      ::rename(summary.c_str(), (out / "summary.json").c_str()) != 0) {
    fail((out / "summary.json").string(), errno);
  }
  committed_ = true;
  fs::remove_all(staging_, ec);  // empty now, but for a file of a name not in runOutputs()
}

}  // namespace dynamap
