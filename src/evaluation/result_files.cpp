#include "dynamap/evaluation/result_files.h"
// The readers of the truth (the simulator's and perturb's files) and of a map result's tables.
// Each table's header is its schema (dynamap/base/csv_schema.h), the same the writers write.

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>

#include "dynamap/base/csv_schema.h"
#include "dynamap/base/ini.h"
#include "dynamap/input/line_reader.h"
#include "dynamap/input/open_source.h"
#include "dynamap/input/pose_file.h"

namespace dynamap {

namespace fs = std::filesystem;

namespace {

/// Lines of a CSV file with a fixed header; every error names file:line.
class CsvReader {
 public:
  CsvReader(const std::string& path, const std::string& header) : path_(path), in_(path) {
    std::string line;
    if (!in_.next(line) || trim(line) != header) {
      throw InputError(path + ":1: expected the header \"" + header + "\"");
    }
    line_ = 1;
    columns_ = static_cast<std::size_t>(std::count(header.begin(), header.end(), ',')) + 1;
  }
  /// The next non-empty line's fields, false at the end.
  bool next(std::vector<std::string>& fields) {
    std::string line;
    while (in_.next(line)) {
      line_ = in_.lineNumber();
      line = trim(line);
      if (line.empty()) continue;
      fields.clear();
      std::stringstream s(line);
      for (std::string f; std::getline(s, f, ',');) fields.push_back(f);
      if (line.back() == ',') fields.emplace_back();
      if (fields.size() != columns_) {
        fail("expected " + std::to_string(columns_) + " fields, got " +
             std::to_string(fields.size()));
      }
      return true;
    }
    return false;
  }
  double number(const std::string& f, const char* name) const {
    double v = 0;
    if (!parseDouble(f, v) || !std::isfinite(v))
      fail(std::string(name) + ": not a number: '" + f + "'");
    return v;
  }
  long integer(const std::string& f, const char* name) const {
    long v = 0;
    if (!parseLong(f, v) || v < 0) fail(std::string(name) + ": not an integer >= 0: '" + f + "'");
    return v;
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(path_ + ":" + std::to_string(line_) + ": " + what);
  }

 private:
  std::string path_;
  LineReader in_;  // lines capped in length
  std::size_t line_ = 0;
  std::size_t columns_ = 0;
};

}  // namespace

std::vector<TruthRow> readTruthRows(const std::string& path) {
  CsvReader csv(path, csv::kTruthRows);
  std::vector<TruthRow> rows;
  for (std::vector<std::string> f; csv.next(f);) {
    TruthRow r;
    r.scan_index = static_cast<std::size_t>(csv.integer(f[0], "scan_index"));
    r.t = csv.number(f[1], "t");
    if (f[2] == "object")
      r.kind = sim::BodyKind::Object;
    else if (f[2] == "person")
      r.kind = sim::BodyKind::Person;
    else
      csv.fail("kind: expected object or person, got '" + f[2] + "'");
    r.id = static_cast<int>(csv.integer(f[3], "id"));
    r.x = csv.number(f[4], "x");
    r.y = csv.number(f[5], "y");
    r.diameter = csv.number(f[6], "diameter");
    r.hits = static_cast<int>(csv.integer(f[7], "hits"));
    rows.push_back(r);
  }
  return rows;
}

std::vector<TruthMove> readMoves(const std::string& path) {
  CsvReader csv(path, csv::kMoves);
  std::vector<TruthMove> moves;
  for (std::vector<std::string> f; csv.next(f);) {
    TruthMove m;
    m.move_id = static_cast<int>(csv.integer(f[0], "move_id"));
    m.object_id = static_cast<int>(csv.integer(f[1], "object_id"));
    m.t_start = csv.number(f[2], "t_start");
    m.t_end = csv.number(f[3], "t_end");
    m.from = {csv.number(f[4], "from_x"), csv.number(f[5], "from_y")};
    m.to = {csv.number(f[6], "to_x"), csv.number(f[7], "to_y")};
    if (m.t_end < m.t_start) csv.fail("t_end before t_start");
    moves.push_back(m);
  }
  return moves;
}

std::vector<TrackRow> readTracks(const std::string& path) {
  CsvReader csv(path, csv::kTracks);
  std::vector<TrackRow> rows;
  for (std::vector<std::string> f; csv.next(f);) {
    TrackRow r;
    r.scan_index = static_cast<std::size_t>(csv.integer(f[0], "scan_index"));
    r.t = csv.number(f[1], "t");
    r.object_id = static_cast<int>(csv.integer(f[2], "object_id"));
    r.cx = csv.number(f[3], "cx");
    r.cy = csv.number(f[4], "cy");
    r.size_m = csv.number(f[5], "size_m");
    r.x_min = csv.number(f[6], "x_min");
    r.x_max = csv.number(f[7], "x_max");
    r.y_min = csv.number(f[8], "y_min");
    r.y_max = csv.number(f[9], "y_max");
    rows.push_back(r);
  }
  return rows;
}

std::set<int> readTableIds(const std::string& path) {
  CsvReader csv(path, csv::kObjects);
  std::set<int> ids;
  for (std::vector<std::string> f; csv.next(f);) {
    ids.insert(static_cast<int>(csv.integer(f[0], "id")));
  }
  return ids;
}

std::vector<TableRow> readTable(const std::string& path) {
  CsvReader csv(path, csv::kObjects);
  std::vector<TableRow> rows;
  for (std::vector<std::string> f; csv.next(f);) {
    rows.push_back({static_cast<int>(csv.integer(f[0], "id")), csv.number(f[2], "size_m"),
                    csv.number(f[3], "cx"), csv.number(f[4], "cy")});
  }
  return rows;
}

namespace {

const std::set<std::string> kChangeKinds = {"object_moved", "object_new", "object_gone",
                                            "structure_added", "structure_removed"};

/// Two fields x, y: both empty (unknown) or both numbers.
MaybePoint maybePoint(const CsvReader& csv, const std::string& x, const std::string& y,
                      const char* name) {
  if (x.empty() && y.empty()) return {};
  return {true, csv.number(x, name), csv.number(y, name)};
}

/// The fields kind,id,size_m,from_x,from_y,to_x,to_y starting at f[first].
ScoredRow changeFields(const CsvReader& csv, const std::vector<std::string>& f, std::size_t first) {
  ScoredRow c;
  c.kind = f[first];
  if (!kChangeKinds.count(c.kind)) csv.fail("kind: unknown change '" + c.kind + "'");
  c.id = static_cast<int>(csv.integer(f[first + 1], "id"));
  c.size = csv.number(f[first + 2], "size_m");
  c.from = maybePoint(csv, f[first + 3], f[first + 4], "from");
  c.to = maybePoint(csv, f[first + 5], f[first + 6], "to");
  return c;
}

}  // namespace

std::vector<ScoredRow> readChangeTruth(const std::string& path) {
  CsvReader csv(path, csv::kSessionChanges);
  std::vector<ScoredRow> rows;
  for (std::vector<std::string> f; csv.next(f);) {
    const long session = csv.integer(f[0], "session");
    if (session < 2) csv.fail("session: changes are seen from session 2 on");
    rows.push_back(changeFields(csv, f, 1));
    rows.back().session = static_cast<int>(session);
  }
  return rows;
}

std::vector<ScoredRow> readChangeReport(const std::string& path) {
  CsvReader csv(path, csv::kChanges);
  std::vector<ScoredRow> rows;
  for (std::vector<std::string> f; csv.next(f);) rows.push_back(changeFields(csv, f, 0));
  return rows;
}

void keepTableRows(const std::string& objects_csv, std::vector<TrackRow>& rows,
                   std::vector<std::string>& notes) {
  if (!fs::exists(objects_csv)) return;
  const std::set<int> table = readTableIds(objects_csv);
  std::set<int> dropped;
  rows.erase(std::remove_if(rows.begin(), rows.end(),
                            [&](const TrackRow& r) {
                              if (table.count(r.object_id)) return false;
                              dropped.insert(r.object_id);
                              return true;
                            }),
             rows.end());
  if (!dropped.empty()) {
    notes.push_back(
        std::to_string(dropped.size()) +
        " object(s) of tracks.csv not in objects.csv (withdrawn as people, or provisional "
        "reports relabeled or retracted): ignored");
  }
}

std::vector<OwnRow> readOwn(const std::string& path) {
  CsvReader csv(path, csv::kOwn);
  std::vector<OwnRow> rows;
  for (std::vector<std::string> f; csv.next(f);) {
    rows.push_back({static_cast<std::size_t>(csv.integer(f[0], "scan_index")),
                    csv.number(f[1], "cx"), csv.number(f[2], "cy")});
  }
  return rows;
}

std::vector<PersonTrackRow> readPeople(const std::string& path) {
  CsvReader csv(path, csv::kPeople);
  std::vector<PersonTrackRow> rows;
  for (std::vector<std::string> f; csv.next(f);) {
    PersonTrackRow r;
    r.scan_index = static_cast<std::size_t>(csv.integer(f[0], "scan_index"));
    csv.number(f[1], "t");
    r.person_id = static_cast<int>(csv.integer(f[2], "person_id"));
    r.x = csv.number(f[3], "x");
    r.y = csv.number(f[4], "y");
    csv.number(f[5], "vx");
    csv.number(f[6], "vy");
    rows.push_back(r);
  }
  return rows;
}

std::vector<TimedPose> readPoses(const std::string& path) {
  std::vector<TimedPose> poses = readPoseFile(path);
  std::stable_sort(poses.begin(), poses.end(),
                   [](const TimedPose& a, const TimedPose& b) { return a.t < b.t; });
  return poses;
}

std::vector<TimedPose> odometryPoses(const std::string& log) {
  auto source = openScanSource(log, PoseSource::Odometry);
  std::vector<TimedPose> poses;
  ScanRecord rec;
  while (source->next(rec)) poses.push_back({rec.t, rec.pose.x(), rec.pose.y(), rec.pose.phi()});
  return poses;
}

std::string truthPrefix(const std::string& given) {
  const fs::path p(given);
  if (fs::is_directory(p)) return (p / p.filename()).string();
  return given;
}
}  // namespace dynamap
