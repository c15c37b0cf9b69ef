#pragma once
// OutputStaging: one run's outputs as one consistent set in the output directory.
//
// A run writes every output into a staging directory of its own inside the output directory
// (.dynamap-run-XXXXXX, unique per process). commit() then removes every output a previous run
// left there (the fixed names of kRunOutputs, frames/ included, and an evaluation's report.md
// and metrics.json, which describe that earlier map) and moves the new ones in, summary.json
// last: a directory holding a summary.json holds the complete outputs of the run it describes.
// A run that fails or is interrupted before commit() leaves the directory as it was: its staging
// directory is removed when the OutputStaging is destroyed. While a run lives it holds an
// exclusive lock on the output directory: a second run into it is refused, never spliced in.
// Files of other names in the directory are never touched.

#include <string>
#include <vector>

namespace dynamap {

class OutputStaging {
 public:
  /// Every name a run may write into its output directory (or an evaluation into it).
  static const std::vector<std::string>& runOutputs();

  /// Creates `out_dir` if needed, locks it and creates the staging directory. Throws
  /// std::runtime_error naming the directory (and errno's reason) when it cannot be created or
  /// written, or when another run holds it.
  explicit OutputStaging(const std::string& out_dir);
  ~OutputStaging();
  OutputStaging(const OutputStaging&) = delete;
  OutputStaging& operator=(const OutputStaging&) = delete;

  /// Where this run writes its outputs until commit().
  const std::string& path() const { return staging_; }
  /// Replaces the previous run's outputs with this one's (see above). Throws std::runtime_error
  /// naming the file and errno's reason if a rename fails.
  void commit();

 private:
  std::string out_dir_, staging_;
  int lock_fd_ = -1;
  bool committed_ = false;
};

}  // namespace dynamap
