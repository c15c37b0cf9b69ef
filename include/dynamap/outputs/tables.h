#pragma once
// The object table and the poses as text files, in fixed formats (byte-identical between runs).

#include <fstream>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include "dynamap/objects/object_tracker.h"
#include "dynamap/pipeline/mapper.h"

namespace dynamap {

/// tracks.csv, streamed while the run goes: after every scan, one row per present object
/// (`scan_index,t,object_id,cx,cy,size_m,x_min,x_max,y_min,y_max`). Written under a temporary
/// name and renamed by finish(), so an interrupted run leaves no tracks.csv; rows are never
/// kept in memory.
class TrackLog {
 public:
  /// Opens the temporary file in `dir` (which must exist); throws std::runtime_error.
  explicit TrackLog(const std::string& dir);
  ~TrackLog();
  TrackLog(const TrackLog&) = delete;
  TrackLog& operator=(const TrackLog&) = delete;
  void append(std::size_t scan_index, double t, const ObjectTracker& tracker);
  /// Flushes and renames to tracks.csv; throws on I/O errors.
  void finish();

 private:
  std::string dir_, tmp_;
  std::unique_ptr<std::ofstream> out_;
};

/// poses.txt: `timestamp x y phi` per scan, the poses used (MRPT's .gt.txt format).
void writePosesTxt(std::ostream& out, const std::vector<UsedPose>& poses);

/// Writers of the object table, exact and fixed-format (byte-identical between runs).
void writeObjectsCsv(std::ostream& out, const ObjectTracker& tracker);
void writeEventsCsv(std::ostream& out, const ObjectTracker& tracker);

}  // namespace dynamap
