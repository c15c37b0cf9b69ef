#pragma once
// The object table and the poses as text files, in fixed formats (byte-identical between runs).

#include <fstream>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include <mrpt/poses/CPose2D.h>

#include "dynamap/objects/object_tracker.h"
#include "dynamap/people/person_tracker.h"
#include "dynamap/pipeline/session_changes.h"

namespace dynamap {

/// A text file written while the run goes, row by row, never held in memory: under a temporary
/// name in `dir` until finish() renames it, so an interrupted run leaves no half-written file
/// under the final name (the destructor of an unfinished one removes it).
class StreamedFile {
 public:
  /// Opens the temporary file in `dir` (which must exist) and writes `header`; throws
  /// std::runtime_error naming the final file.
  StreamedFile(const std::string& dir, const std::string& name, const std::string& header);
  ~StreamedFile();
  StreamedFile(const StreamedFile&) = delete;
  StreamedFile& operator=(const StreamedFile&) = delete;
  std::ostream& out() { return *out_; }
  /// Flushes and renames to the final name; throws on I/O errors.
  void finish();

 private:
  std::string dir_, name_, tmp_;
  std::unique_ptr<std::ofstream> out_;
};

/// tracks.csv: after every scan, one row per present object
/// (`scan_index,t,object_id,cx,cy,size_m,x_min,x_max,y_min,y_max`).
class TrackLog {
 public:
  explicit TrackLog(const std::string& dir);
  void append(std::size_t scan_index, double t, const ObjectTracker& tracker);
  void finish() { file_.finish(); }

 private:
  StreamedFile file_;
  std::string rows_;  // a scan's rows, the buffer kept for its capacity
};

/// people.csv: after every scan, one row per person the tracker reports
/// (`scan_index,t,person_id,x,y,vx,vy`, map frame, metres and m/s).
class PeopleLog {
 public:
  explicit PeopleLog(const std::string& dir);
  void append(std::size_t scan_index, double t, const PersonTracker& people);
  void finish() { file_.finish(); }

 private:
  StreamedFile file_;
};

/// poses.txt: `timestamp x y phi` per scan, the pose each scan was mapped at (MRPT's .gt.txt
/// format), skipped scans included.
class PoseLog {
 public:
  explicit PoseLog(const std::string& dir);
  void append(double t, const mrpt::poses::CPose2D& pose);
  void finish() { file_.finish(); }

 private:
  StreamedFile file_;
};

/// Whether events.csv lists the events of object `id`: every object's but a withdrawn one's (a
/// person standing, who walked off). A relabeled or retracted provisional report keeps its
/// events, so a user can follow it; objects.csv lists neither.
bool eventsListed(const ObjectTracker& tracker, int id);
/// Writers of the object table, exact and fixed-format (byte-identical between runs): the
/// table's objects (present or absent) and the events (see eventsListed). A withdrawn,
/// relabeled or retracted object is not in objects.csv, only in tracks.csv, which was streamed
/// while it was reported.
void writeObjectsCsv(std::ostream& out, const ObjectTracker& tracker);
void writeEventsCsv(std::ostream& out, const ObjectTracker& tracker);
/// changes.csv: one row per change (csv::kChanges); a place or time not known is left empty.
void writeChangesCsv(std::ostream& out, const std::vector<ChangeRow>& rows);

}  // namespace dynamap
