#pragma once
// Runs a child process for the benchmark programs and measures it.

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

namespace dynamap::bench {

struct ChildSample {
  double wall_s = 0;  ///< fork to exit
  double cpu_s = 0;   ///< user + system CPU time of the child
  long peak_kb = 0;   ///< the kernel's ru_maxrss: peak resident memory
};

/// Runs `args` (args[0] a path) with stdout and stderr to /dev/null; false when it could not be
/// started or did not exit with 0.
inline bool runChild(const std::vector<std::string>& args, ChildSample& out) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  if (pid < 0) return false;
  if (pid == 0) {
    if (std::freopen("/dev/null", "w", stdout) == nullptr ||
        std::freopen("/dev/null", "w", stderr) == nullptr) {
      _exit(126);
    }
    execv(argv[0], argv.data());
    _exit(127);
  }
  int status = 0;
  rusage usage{};
  if (wait4(pid, &status, 0, &usage) != pid) return false;
  out.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  auto seconds = [](const timeval& tv) {
    return static_cast<double>(tv.tv_sec) + tv.tv_usec * 1e-6;
  };
  out.cpu_s = seconds(usage.ru_utime) + seconds(usage.ru_stime);
  out.peak_kb = usage.ru_maxrss;
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

}  // namespace dynamap::bench
