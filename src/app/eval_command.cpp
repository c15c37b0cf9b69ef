// dynamap eval: a mapping result scored against the simulator's ground truth.
// The metric definitions live in src/evaluation.cpp and docs/evaluation.md; this file reads the
// files, runs the mapper and the plain MRPT baseline when needed, and writes the reports.

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <set>
#include <sstream>

#include "cli.h"
#include "dynamap/base/ini.h"
#include "dynamap/localization/consistency.h"
#include "dynamap/evaluation/evaluation.h"
#ifdef DYNAMAP_HAVE_ROSBAG
#include "dynamap/evaluation/bag_people_truth.h"
#endif
#include "dynamap/input/line_reader.h"
#include "dynamap/input/open_source.h"
#include "dynamap/input/pose_file.h"
#include "dynamap/mapping/dynamic_map_options.h"
#include "dynamap/outputs/map_job.h"
#include "dynamap/outputs/json.h"
#include "dynamap/outputs/map_outputs.h"
#include "dynamap/pipeline/mapper.h"
#include "dynamap/sim/scenario.h"

namespace dynamap::app {
namespace {

namespace fs = std::filesystem;

const char* const kUsage =
    "usage: dynamap eval [--scenario FILE] --truth PREFIX --result DIR [--config FILE]\n"
    "       dynamap eval --summary DIR...\n"
    "       dynamap eval --truth PREFIX --trajectory FILE\n"
    "       dynamap eval --input LOG --trajectory FILE [--truth PREFIX]\n"
    "       dynamap eval --people-bag BAG --result DIR [--scan-topic T] [--person-topic T]\n\n"
    "Scores a `dynamap map` result against the simulator's ground truth: per object move\n"
    "(the paper's Table 3: correctly detected, not detected, size estimation errors, static\n"
    "parts detected as objects, latency) and per cell (SA, DA, AA, HA of the static map, and\n"
    "of a plain MRPT grid built from the same scans; precision and recall of S u D).\n"
    "PREFIX is the simulator's file prefix (rawlogs/arena/arena) or its directory\n"
    "(rawlogs/arena). When DIR has no summary.json the mapper runs first (ground-truth\n"
    "poses, --config). Prints a table and writes DIR/report.md and DIR/metrics.json.\n"
    "Without --scenario (real scans with objects added by `dynamap perturb --add-objects`) the\n"
    "walls are unknown: the object figures are scored, the cell figures know the objects only.\n"
    "--summary prints one table of several evaluated results beside the paper's Table 3.\n"
    "The poses the result was mapped at (DIR/poses.txt) and the log's raw odometry are scored\n"
    "against the truth's poses (PREFIX.gt.txt): absolute trajectory error, RMSE of position and\n"
    "heading. --trajectory scores any `timestamp x y phi` file (e.g. another SLAM's) that way.\n"
    "--input LOG with --trajectory lays the log's scans out at the file's poses and says how\n"
    "well they lie on each other, no truth needed: the mean distance of their points to those\n"
    "of scans more than 50 scans away (global) and of the scan before (local).\n"
    "Definitions: docs/evaluation.md.";

// ---- reading the truth and the tracks ------------------------------------------------------

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
  static std::string trim(const std::string& s) {
    const auto b = s.find_first_not_of(" \t\r");
    const auto e = s.find_last_not_of(" \t\r");
    return b == std::string::npos ? "" : s.substr(b, e - b + 1);
  }
  std::string path_;
  LineReader in_;  // lines capped in length
  std::size_t line_ = 0;
  std::size_t columns_ = 0;
};

std::vector<TruthRow> readTruthRows(const std::string& path) {
  CsvReader csv(path, "scan_index,t,kind,id,x,y,diameter,hits");
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
  CsvReader csv(path, "move_id,object_id,t_start,t_end,from_x,from_y,to_x,to_y");
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
  CsvReader csv(path, "scan_index,t,object_id,cx,cy,size_m,x_min,x_max,y_min,y_max");
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

/// The ids of the final object table (objects.csv).
std::set<int> readTableIds(const std::string& path) {
  CsvReader csv(path,
                "id,label,size_m,cx,cy,x_min,x_max,y_min,y_max,state,first_seen_t,last_seen_t,"
                "n_moves");
  std::set<int> ids;
  for (std::vector<std::string> f; csv.next(f);) {
    ids.insert(static_cast<int>(csv.integer(f[0], "id")));
  }
  return ids;
}

/// Drops the rows of objects the final table does not hold (withdrawn: a person who stood
/// and walked off) and says how many there were.
void keepTableRows(const fs::path& objects_csv, std::vector<TrackRow>& rows,
                   std::vector<std::string>& notes) {
  if (!fs::exists(objects_csv)) return;
  const std::set<int> table = readTableIds(objects_csv.string());
  std::set<int> dropped;
  rows.erase(std::remove_if(rows.begin(), rows.end(),
                            [&](const TrackRow& r) {
                              if (table.count(r.object_id)) return false;
                              dropped.insert(r.object_id);
                              return true;
                            }),
             rows.end());
  if (!dropped.empty()) {
    notes.push_back(std::to_string(dropped.size()) +
                    " object(s) of tracks.csv not in objects.csv (withdrawn as people, or provisional "
                    "reports relabeled or retracted): ignored");
  }
}

/// perturb --add-objects' NAME.own.csv: the unedited log's object rows.
std::vector<OwnRow> readOwn(const std::string& path) {
  CsvReader csv(path, "scan_index,cx,cy");
  std::vector<OwnRow> rows;
  for (std::vector<std::string> f; csv.next(f);) {
    rows.push_back({static_cast<std::size_t>(csv.integer(f[0], "scan_index")),
                    csv.number(f[1], "cx"), csv.number(f[2], "cy")});
  }
  return rows;
}

std::vector<PersonTrackRow> readPeople(const std::string& path) {
  CsvReader csv(path, "scan_index,t,person_id,x,y,vx,vy");
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

/// `timestamp x y phi` lines (poses.txt, <name>.gt.txt), sorted by time.
std::vector<TimedPose> readPoses(const std::string& path) {
  std::vector<TimedPose> poses = readPoseFile(path);
  std::stable_sort(poses.begin(), poses.end(),
                   [](const TimedPose& a, const TimedPose& b) { return a.t < b.t; });
  return poses;
}

/// The raw odometry pose of every scan of a rawlog.
std::vector<TimedPose> odometryPoses(const std::string& rawlog) {
  auto source = openScanSource(rawlog, PoseSource::Odometry);
  std::vector<TimedPose> poses;
  ScanRecord rec;
  while (source->next(rec)) poses.push_back({rec.t, rec.pose.x(), rec.pose.y(), rec.pose.phi()});
  return poses;
}

/// "rawlogs/arena" (a directory) stands for "rawlogs/arena/arena".
std::string truthPrefix(const std::string& given) {
  const fs::path p(given);
  if (fs::is_directory(p)) return (p / p.filename()).string();
  return given;
}

// ---- the mapping result -------------------------------------------------------------------

/// Maps the rawlog with ground-truth poses into `dir`, as `dynamap map` would (no baseline).
void runMapper(const std::string& rawlog, MapConfig config, const std::string& dir) {
  config.poses = PoseSource::GroundTruth;
  MapJob job;
  job.input = rawlog;
  job.out_dir = dir;
  job.config = config;
  job.baseline = false;
  const MapJobResult r = runMapJob(job);
  if (!r.outcome.fault.empty()) throw InputError(r.outcome.fault);
}

mrpt::maps::COccupancyGridMap2D loadGrid(const std::string& path) {
  if (!fs::exists(path)) throw InputError(path + ": missing (not a dynamap map result?)");
  mrpt::maps::COccupancyGridMap2D grid;
  try {
    mrpt::io::CFileGZInputStream in(path);
    auto arch = mrpt::serialization::archiveFrom(in);
    arch >> grid;
  } catch (const std::exception& e) {
    throw InputError(path + ": not a readable MRPT gridmap (" +
                     std::string(e.what()).substr(0, 200) + ")");
  }
  return grid;
}

GridGeometry geometryOf(const mrpt::maps::COccupancyGridMap2D& grid) {
  return {grid.getXMin(), grid.getYMin(), grid.getResolution(), static_cast<int>(grid.getSizeX()),
          static_cast<int>(grid.getSizeY())};
}

/// P(occupied) of `grid` at the centre of every cell of `g` (0.5 outside `grid`): grids of
/// slightly different extents are compared cell for cell.
std::vector<float> occupancyOn(const mrpt::maps::COccupancyGridMap2D& grid, const GridGeometry& g) {
  std::vector<float> out(g.cells(), 0.5f);
  for (int iy = 0; iy < g.size_y; ++iy) {
    const int gy = grid.y2idx(g.y_min + (iy + 0.5) * g.resolution);
    if (gy < 0 || gy >= static_cast<int>(grid.getSizeY())) continue;
    for (int ix = 0; ix < g.size_x; ++ix) {
      const int gx = grid.x2idx(g.x_min + (ix + 0.5) * g.resolution);
      if (gx < 0 || gx >= static_cast<int>(grid.getSizeX())) continue;
      out[g.index(ix, iy)] = 1.0f - grid.getCell(gx, gy);
    }
  }
  return out;
}

/// What a user gets without dynamap: MRPT's grid, default insertion options, the same scans and
/// poses, the resolution and extent of S.
std::vector<float> plainMrptOccupancy(const std::string& rawlog, const GridGeometry& g,
                                      const MapConfig& config) {
  PlainGrid plain(config.map, config.insertion, static_cast<float>(g.x_min),
                  static_cast<float>(g.x_min + g.size_x * g.resolution),
                  static_cast<float>(g.y_min),
                  static_cast<float>(g.y_min + g.size_y * g.resolution));
  auto source = openScanSource(rawlog, PoseSource::GroundTruth);
  for (ScanRecord rec; source->next(rec);) plain.insert(*rec.scan, rec.pose);
  return occupancyOn(plain.grid(), g);
}

// ---- the evaluation -----------------------------------------------------------------------

struct Evaluation {
  std::string scenario, truth, result;
  bool have_tracks = false;
  bool real_scans = false;  // no scenario: objects added to a real log
  bool have_own = false;    // real scans: the unedited log's own object rows (PREFIX.own.csv)
  std::size_t moves = 0;
  ObjectScores objects;
  std::size_t observed = 0;
  CellScores dynamap, plain;
  PrecisionRecall union_pr;
  double object_threshold = 0.85;
  std::vector<std::string> notes;
  bool have_people = false;              // the result has people.csv
  MotScores mot;                         // its CLEAR MOT against the person truth
  bool have_poses = false;               // the result has poses.txt
  TrajectoryError trajectory, odometry;  // of poses.txt and of the log's raw odometry
};

double objectThreshold(const std::string& result) {
  const std::string path = (fs::path(result) / "config.ini").string();
  if (!fs::exists(path)) return DynamicMapOptions{}.object_threshold;
  return IniFile::fromFile(path).getDouble("dynamic_map", "object_threshold", 0.85);
}

void evaluateCells(const sim::Scenario& scenario, const std::vector<TruthRow>& rows,
                   const std::vector<TruthMove>& moves, const std::string& rawlog,
                   const MapConfig& config, Evaluation& ev) {
  const auto s_grid = loadGrid((fs::path(ev.result) / "static.gridmap.gz").string());
  const auto d_grid = loadGrid((fs::path(ev.result) / "dynamic.gridmap.gz").string());
  const GridGeometry g = geometryOf(s_grid);
  const auto s_occ = occupancyOn(s_grid, g);
  const auto d_occ = occupancyOn(d_grid, g);
  const auto plain = plainMrptOccupancy(rawlog, g, config);
  // One set of observed cells for both maps, so their figures share a denominator.
  const CellMask observed = observedCells({&s_occ, &d_occ, &plain});
  for (auto o : observed) ev.observed += o;
  const CellTruth truth = cellTruth(scenario.world, rows, moves, g);
  ev.dynamap = scoreStaticMap(s_occ, truth, observed, g);
  ev.plain = scoreStaticMap(plain, truth, observed, g);
  ev.object_threshold = objectThreshold(ev.result);
  ev.union_pr = scoreOccupied(unionOccupied(s_occ, d_occ, ev.object_threshold), truth.world_at_end,
                              observed, g);
}

// ---- output -------------------------------------------------------------------------------

/// A fixed-format number; NaN prints as `nan_text`.
std::string num(double v, int decimals, const std::string& nan_text = "null") {
  if (std::isnan(v)) return nan_text;
  std::ostringstream s;
  s << std::fixed << std::setprecision(decimals) << v;
  return s.str();
}
std::string pct(double v) {
  return num(v, 2, "n/a");
}

/// The paper's Table 3 column that matches a scenario, or -1.
int paperColumn(const std::string& scenario) {
  if (scenario.find("corridor") != std::string::npos) return 2;
  if (scenario.find("arena") != std::string::npos) return 3;
  return -1;
}
const char* const kPaperNames[4] = {"real corridors", "real arena", "sim corridors", "sim arena"};
const char* const kPaperShortNames[4] = {"real corr.", "real arena", "sim corr.", "sim arena"};
const int kPaperMoves[4] = {20, 20, 20, 20};
const int kPaperDetected[4] = {19, 19, 20, 20};
const int kPaperNotDetected[4] = {1, 1, 0, 0};
const int kPaperStatic[4] = {3, 0, 0, 0};
const int kPaperSize[4] = {6, 5, 4, 4};

std::string moveStatus(const MoveResult& m) {
  if (!m.visible) return "never visible";
  if (!m.matched) return "not detected";
  std::string s = m.correct ? "correct" : "";
  if (m.sizeError()) {
    const std::string why = m.wrong_id && m.double_match ? "wrong id, double match"
                            : m.wrong_id                 ? "wrong id"
                                                         : "double match";
    s += (s.empty() ? "" : " + ") + std::string("size error (") + why + ")";
  }
  return s;
}

void printTable(std::ostream& o, const Evaluation& ev) {
  const auto& ob = ev.objects;
  const int pc = paperColumn(ev.scenario);
  o << "dynamap eval " << ev.scenario << ": " << ev.moves << " moves, " << ob.visible
    << " became visible, " << ob.ids.size() << " tracker ids"
    << (ev.have_tracks ? "" : " (no tracks.csv in the result)") << "\n\n";
  o << "  object level                    ours"
    << (pc >= 0 ? std::string("   paper (") + kPaperNames[pc] + ")" : "") << "\n";
  auto line = [&](const char* what, std::size_t ours, const int* paper) {
    o << "  " << std::left << std::setw(30) << what << std::right << std::setw(6) << ours;
    if (pc >= 0 && paper != nullptr) o << std::setw(10) << paper[pc];
    o << "\n";
  };
  line("correctly detected", ob.correct, kPaperDetected);
  line("not detected", ob.not_detected, kPaperNotDetected);
  line("static detected as objects", ob.static_as_objects, kPaperStatic);
  line("people detected as objects", ob.people_as_objects, nullptr);  // not in the paper
  if (ev.have_own) line("the log's own (unlabeled)", ob.log_own_objects, nullptr);
  if (ev.real_scans) line("left where it stood, unseen", ob.left_behind_objects, nullptr);
  line("size estimation errors", ob.size_errors, kPaperSize);
  o << "  latency median / max            " << num(ob.latency.median_s, 2, "n/a") << " / "
    << num(ob.latency.max_s, 2, "n/a") << " s  (" << num(ob.latency.median_scans, 1, "n/a") << " / "
    << num(ob.latency.max_scans, 0, "n/a") << " scans)\n\n";
  o << "  cell level (" << ev.observed << " observed cells; " << ev.dynamap.static_cells
    << " static truth, " << ev.dynamap.dynamic_cells << " dynamic truth)\n"
    << "  map              SA %     DA %     AA %     HA %\n";
  for (const auto& [name, c] :
       {std::pair<const char*, const CellScores&>{"dynamap S  ", ev.dynamap},
        {"plain MRPT ", ev.plain}}) {
    o << "  " << name << std::setw(9) << pct(c.sa) << std::setw(9) << pct(c.da) << std::setw(9)
      << pct(c.aa) << std::setw(9) << pct(c.ha) << "\n";
  }
  o << "  S u D at the last scan: precision " << pct(ev.union_pr.precision) << " %, recall "
    << pct(ev.union_pr.recall) << " %\n";
  if (ev.have_poses) {
    o << "\n  trajectory (ATE RMSE)     position m   heading deg\n";
    for (const auto& [name, e] :
         {std::pair<const char*, const TrajectoryError&>{"poses mapped at ", ev.trajectory},
          {"raw odometry    ", ev.odometry}}) {
      o << "  " << name << std::setw(19) << num(e.rmse_xy_m, 4, "n/a") << std::setw(14)
        << num(e.rmse_phi_rad * 180.0 / M_PI, 3, "n/a") << "\n";
    }
  }
  const MotScores& m = ev.mot;
  o << "\n  people (CLEAR MOT, gate 0.75 m, persons with >= 3 beams)"
    << (ev.have_people ? "" : "  (no people.csv in the result)") << "\n"
    << "  MOTA " << num(m.mota, 3, "n/a") << "   MOTP " << num(m.motp_m, 3, "n/a") << " m   "
    << m.ground_truth << " person-scans: " << m.matches << " matched, " << m.misses << " missed, "
    << m.false_positives << " false positives, " << m.id_switches << " identity switches ("
    << m.id_switches_at_stops << " at a stop); "
    << m.people << " persons, " << m.track_ids << " track ids\n";
  for (const IdSwitch& w : m.switches) {
    o << "    identity switch at scan " << w.scan_index << " (t " << num(w.t, 1, "n/a")
      << " s): person " << w.person << " from track " << w.from_id << " to " << w.to_id
      << (w.at_stop ? ", at a stop" : "") << "\n";
  }
  for (const auto& n : ev.notes) o << "  note: " << n << "\n";
}

/// `v` with `decimals` fixed decimals as a JSON number; null when it is not a number.
Json jnum(double v, int decimals) {
  if (std::isnan(v)) return nullptr;
  const std::string format = "%." + std::to_string(decimals) + "f";
  return jsonNumber(format.c_str(), v);
}

Json cellJson(const CellScores& c) {
  return {{"static_cells", c.static_cells}, {"static_kept", c.static_kept},
          {"dynamic_cells", c.dynamic_cells}, {"dynamic_clear", c.dynamic_clear},
          {"sa", jnum(c.sa, 3)}, {"da", jnum(c.da, 3)}, {"aa", jnum(c.aa, 3)},
          {"ha", jnum(c.ha, 3)}};
}

Json movesJson(const ObjectScores& ob) {
  Json moves = Json::array();
  for (const auto& m : ob.moves) {
    moves.push_back({{"move_id", m.move_id},
                     {"object_id", m.object_id},
                     {"visible", m.visible},
                     {"visible_scan", m.visible ? Json(m.visible_scan) : Json(nullptr)},
                     {"visible_t", m.visible ? jnum(m.visible_t, 3) : Json(nullptr)},
                     {"matched", m.matched},
                     {"correct", m.correct},
                     {"wrong_id", m.wrong_id},
                     {"double_match", m.double_match},
                     {"latency_s", m.correct ? jnum(m.latency_s, 3) : Json(nullptr)},
                     {"latency_scans", m.correct ? Json(m.latency_scans) : Json(nullptr)}});
  }
  return moves;
}

Json idsJson(const ObjectScores& ob) {
  Json ids = Json::array();
  for (const auto& a : ob.ids) {
    const char* kind = a.body.kind == sim::BodyKind::Object ? "object" : "person";
    ids.push_back({{"id", a.track_id},
                   {"rows", a.rows},
                   {"assigned_kind", a.matches == 0 ? Json(nullptr) : Json(kind)},
                   {"assigned_id", a.matches == 0 ? Json(nullptr) : Json(a.body.id)},
                   {"matches", a.matches},
                   {"far_rows", a.far_rows},
                   {"static_object", a.static_object}});
  }
  return ids;
}

/// The figures of the summary table, each key unique in the file (--summary reads them).
Json tableFiguresJson(const Evaluation& ev) {
  const auto& ob = ev.objects;
  return {{"moves_total", ev.moves},
          {"moves_visible", ob.visible},
          {"correctly_detected", ob.correct},
          {"not_detected", ob.not_detected},
          {"static_detected_as_objects", ob.static_as_objects},
          {"people_detected_as_objects", ob.people_as_objects},
          {"size_estimation_errors", ob.size_errors},
          {"latency_median_s", jnum(ob.latency.median_s, 3)},
          {"latency_max_s", jnum(ob.latency.max_s, 3)},
          {"latency_median_scans", jnum(ob.latency.median_scans, 1)},
          {"latency_max_scans", jnum(ob.latency.max_scans, 0)},
          {"dynamap_sa", jnum(ev.dynamap.sa, 3)},
          {"dynamap_da", jnum(ev.dynamap.da, 3)},
          {"dynamap_aa", jnum(ev.dynamap.aa, 3)},
          {"dynamap_ha", jnum(ev.dynamap.ha, 3)},
          {"mrpt_sa", jnum(ev.plain.sa, 3)},
          {"mrpt_da", jnum(ev.plain.da, 3)},
          {"mrpt_aa", jnum(ev.plain.aa, 3)},
          {"mrpt_ha", jnum(ev.plain.ha, 3)},
          {"union_precision", jnum(ev.union_pr.precision, 3)},
          {"union_recall", jnum(ev.union_pr.recall, 3)},
          {"tracker_id_count", ob.ids.size()}};
}

/// People and trajectory figures (null where the result has none).
Json peopleAndPosesJson(const Evaluation& ev) {
  const double deg = 180.0 / M_PI;
  const auto pose = [&](double v, int d) { return ev.have_poses ? jnum(v, d) : Json(nullptr); };
  return {{"people_present", ev.have_people},
          {"mota", jnum(ev.mot.mota, 3)},
          {"motp_m", jnum(ev.mot.motp_m, 3)},
          {"mot_person_scans", ev.mot.ground_truth},
          {"mot_matches", ev.mot.matches},
          {"mot_misses", ev.mot.misses},
          {"mot_false_positives", ev.mot.false_positives},
          {"mot_id_switches", ev.mot.id_switches},
          {"mot_id_switches_at_stops", ev.mot.id_switches_at_stops},
          {"mot_track_ids", ev.mot.track_ids},
          {"ate_rmse_xy_m", pose(ev.trajectory.rmse_xy_m, 4)},
          {"ate_rmse_phi_deg", pose(ev.trajectory.rmse_phi_rad * deg, 3)},
          {"odometry_ate_rmse_xy_m", pose(ev.odometry.rmse_xy_m, 4)},
          {"odometry_ate_rmse_phi_deg", pose(ev.odometry.rmse_phi_rad * deg, 3)}};
}

/// Fixed key order and number formats: the same inputs give the same bytes.
void writeMetricsJson(std::ostream& o, const Evaluation& ev) {
  Json j = {{"scenario", ev.scenario},
            {"truth", ev.truth},
            {"result", ev.result},
            {"tracks_present", ev.have_tracks}};
  j.update(tableFiguresJson(ev));
  if (ev.have_own) j["log_own_objects"] = ev.objects.log_own_objects;
  if (ev.real_scans) j["left_behind_objects"] = ev.objects.left_behind_objects;
  j.update(peopleAndPosesJson(ev));
  j["cells"] = {{"observed", ev.observed},
                {"object_threshold", jnum(ev.object_threshold, 3)},
                {"union",
                 {{"predicted", ev.union_pr.predicted},
                  {"predicted_right", ev.union_pr.predicted_right},
                  {"truth", ev.union_pr.truth},
                  {"truth_found", ev.union_pr.truth_found}}},
                {"dynamap", cellJson(ev.dynamap)},
                {"plain_mrpt", cellJson(ev.plain)}};
  j["moves"] = movesJson(ev.objects);
  j["tracker_ids"] = idsJson(ev.objects);
  writeJson(o, j);
}

void writeReport(std::ostream& o, const Evaluation& ev) {
  o << "# dynamap eval: " << ev.scenario << "\n\n"
    << "Truth `" << ev.truth << "`, result `" << ev.result
    << "`. Definitions: docs/evaluation.md in the dynamap sources.\n\n"
    << "```\n";
  printTable(o, ev);
  o << "```\n\n## Moves\n\n"
    << "| move | object | visible at (s, scan) | outcome | latency (s, scans) |\n"
    << "|-----:|-------:|---------------------|---------|--------------------|\n";
  for (const auto& m : ev.objects.moves) {
    o << "| " << m.move_id << " | " << m.object_id << " | "
      << (m.visible ? num(m.visible_t, 1) + ", " + std::to_string(m.visible_scan) : "–") << " | "
      << moveStatus(m) << " | "
      << (m.correct ? num(m.latency_s, 2) + ", " + std::to_string(m.latency_scans) : "–") << " |\n";
  }
  o << "\n## Tracker ids\n\n| id | rows | assigned to | matches | rows far from every body |\n"
    << "|---:|-----:|-------------|--------:|-------------------------:|\n";
  for (const auto& a : ev.objects.ids) {
    o << "| " << a.track_id << " | " << a.rows << " | "
      << (a.matches == 0 ? std::string("–")
                         : (a.body.kind == sim::BodyKind::Object ? "object " : "person ") +
                               std::to_string(a.body.id))
      << " | " << a.matches << " | " << a.far_rows
      << (a.static_object ? " (static)"
          : a.log_own     ? " (the log's own)"
          : a.left_behind ? " (left where it stood)"
                          : "")
      << " |\n";
  }
  o << "\n## Pictures\n\n";
  for (const char* p : {"overlay.png", "static.png", "dynamic.png"}) {
    if (fs::exists(fs::path(ev.result) / p)) o << "![" << p << "](" << p << ")\n\n";
  }
}

// ---- --summary ----------------------------------------------------------------------------

/// A figure of a metrics.json written above, as the table shows it ("n/a" for null): integers
/// as they are, other numbers with the decimals they were written with.
std::string metric(const Json& metrics, const std::string& key, const std::string& file) {
  const auto it = metrics.find(key);
  // Figures eval gained in a later release: a result evaluated before has none ("n/a").
  static const std::set<std::string> kAddedLater = {"people_detected_as_objects"};
  if (it == metrics.end() && kAddedLater.count(key)) return "n/a";
  if (it == metrics.end()) {
    throw InputError(file + ": no \"" + key + "\" (not written by dynamap eval?)");
  }
  if (it->is_null()) return "n/a";
  if (it->is_number_integer()) return std::to_string(it->get<long long>());
  if (!it->is_number()) throw InputError(file + ": \"" + key + "\" is not a number");
  const int decimals = key == "ate_rmse_xy_m" ? 4 : key == "latency_median_scans" ? 1 : 3;
  return num(it->get<double>(), decimals);
}

/// An evaluated result directory's metrics.json, and the name its column gets.
struct EvaluatedResult {
  std::string name, path;
  Json metrics;
};

constexpr std::size_t kMaxMetricsBytes = std::size_t{16} << 20;

std::vector<EvaluatedResult> readEvaluated(const std::vector<std::string>& dirs) {
  std::vector<EvaluatedResult> results;
  for (const auto& d : dirs) {
    const std::string path = (fs::path(d) / "metrics.json").string();
    std::ifstream in(path);
    if (!in) throw InputError(path + ": cannot open (run dynamap eval on " + d + " first)");
    // metrics.json is small; a file of gigabytes named so is not one.
    std::string text(kMaxMetricsBytes + 1, '\0');
    in.read(text.data(), static_cast<std::streamsize>(text.size()));
    text.resize(static_cast<std::size_t>(in.gcount()));
    if (text.size() > kMaxMetricsBytes) throw InputError(path + ": too large for a metrics.json");
    fs::path name = fs::path(d).lexically_normal();
    if (name.filename().empty()) name = name.parent_path();  // "out/arena/"
    Json metrics = parseJson(text, path);
    if (!metrics.is_object()) throw InputError(path + ": not a metrics.json (not an object)");
    results.push_back({name.filename().string(), path, std::move(metrics)});
  }
  return results;
}

// The rows of the summary table: a label, its key in metrics.json, the paper's figures.
struct SummaryRow {
  const char* label;
  const char* key;
  const int* paper;
};
const SummaryRow kSummaryRows[] = {
    {"moves", "moves_total", kPaperMoves},
    {"moves visible", "moves_visible", nullptr},
    {"correctly detected", "correctly_detected", kPaperDetected},
    {"not detected", "not_detected", kPaperNotDetected},
    {"static detected as objects", "static_detected_as_objects", kPaperStatic},
    {"people detected as objects", "people_detected_as_objects", nullptr},
    {"size estimation errors", "size_estimation_errors", kPaperSize},
    {"latency median (s)", "latency_median_s", nullptr},
    {"latency max (s)", "latency_max_s", nullptr},
    {"SA % dynamap", "dynamap_sa", nullptr},
    {"SA % plain MRPT", "mrpt_sa", nullptr},
    {"DA % dynamap", "dynamap_da", nullptr},
    {"DA % plain MRPT", "mrpt_da", nullptr},
    {"AA % dynamap", "dynamap_aa", nullptr},
    {"AA % plain MRPT", "mrpt_aa", nullptr},
    {"HA % dynamap", "dynamap_ha", nullptr},
    {"HA % plain MRPT", "mrpt_ha", nullptr},
    {"S u D precision %", "union_precision", nullptr},
    {"S u D recall %", "union_recall", nullptr},
    {"ATE position RMSE (m)", "ate_rmse_xy_m", nullptr},
    {"ATE heading RMSE (deg)", "ate_rmse_phi_deg", nullptr},
    {"people MOTA", "mota", nullptr},
    {"people MOTP (m)", "motp_m", nullptr},
    {"people identity switches", "mot_id_switches", nullptr},
    {"people switches at a stop", "mot_id_switches_at_stops", nullptr},
    {"people misses", "mot_misses", nullptr},
    {"people false positives", "mot_false_positives", nullptr},
};
int runSummary(const std::vector<std::string>& dirs, std::ostream& o) {
  const std::vector<EvaluatedResult> results = readEvaluated(dirs);
  constexpr int kLabel = 28, kColumn = 11;
  o << std::left << std::setw(kLabel) << "" << std::setw(4 * kColumn)
    << "paper (Wolf & Sukhatme, Table 3)"
    << "| dynamap\n"
    << std::setw(kLabel) << "";
  // One blank at least between columns, however long a result's name.
  for (const auto* n : kPaperShortNames) o << std::setw(kColumn - 1) << n << ' ';
  o << "| ";
  for (const auto& r : results) o << std::setw(kColumn - 1) << r.name << ' ';
  o << "\n";

  for (const auto& row : kSummaryRows) {
    o << std::setw(kLabel) << row.label;
    for (int c = 0; c < 4; ++c) {
      // The paper gives its latency only as "1-2 s from the change to the table update".
      const std::string p = row.paper ? std::to_string(row.paper[c])
                                      : (std::string(row.key) == "latency_max_s" ? "2" : "");
      o << std::setw(kColumn - 1) << p << ' ';
    }
    o << "| ";
    for (const auto& r : results) {
      o << std::setw(kColumn - 1) << metric(r.metrics, row.key, r.path) << ' ';
    }
    o << "\n";
  }
  o << std::right;
  return kExitOk;
}

// ---- a real bag's people -------------------------------------------------------------------

/// --people-bag BAG --result DIR: CLEAR MOT of DIR/people.csv against the bag's Person messages
/// (scored on the scans they annotate), printed and written to DIR/people_metrics.json.
int scorePeopleBag(const po::variables_map& vm) {
#ifdef DYNAMAP_HAVE_ROSBAG
  const std::string bag = vm["people-bag"].as<std::string>(), result = vm["result"].as<std::string>();
  const fs::path people = fs::path(result) / "people.csv", poses = fs::path(result) / "poses.txt";
  for (const fs::path& f : {people, poses}) {
    if (!fs::exists(f)) throw InputError(f.string() + ": missing (map the bag into " + result + " first)");
  }
  const BagPeopleTruth truth = bagPeopleTruth(bag, bagOptions(vm), vm["person-topic"].as<std::string>(),
                                              readPoses(poses.string()));
  const MotScores m = evaluateClearMot(truth.rows, readPeople(people.string()));
  std::cout << "dynamap eval: " << result << " against " << bag << " (" << truth.messages
            << " annotations, " << truth.unplaced << " on scans without a pose)\n"
            << "  people (CLEAR MOT, gate 0.75 m)\n  MOTA " << num(m.mota, 3, "n/a") << "   MOTP "
            << num(m.motp_m, 3, "n/a") << " m   matches " << m.matches << ", misses " << m.misses
            << ", false positives " << m.false_positives << ", identity switches " << m.id_switches
            << "\n  " << m.people << " persons, " << m.track_ids << " track ids\n";
  const Json j = {{"people_bag", bag},          {"annotations", truth.messages},
                  {"unplaced", truth.unplaced},  {"mota", jnum(m.mota, 3)},
                  {"motp_m", jnum(m.motp_m, 3)}, {"mot_person_scans", m.ground_truth},
                  {"mot_matches", m.matches},    {"mot_misses", m.misses},
                  {"mot_false_positives", m.false_positives}, {"mot_id_switches", m.id_switches},
                  {"mot_track_ids", m.track_ids}};
  writeFileAtomically(result, "people_metrics.json", [&](std::ostream& o) { o << j.dump(2) << "\n"; });
  return kExitOk;
#else
  (void)vm;
  throw std::runtime_error("this dynamap was built without ROS bag support (DYNAMAP_ROSBAG=OFF)");
#endif
}

// ---- the command --------------------------------------------------------------------------

Evaluation evaluate(const std::string& scenario_path, const std::string& truth_given,
                    const std::string& result, const MapConfig& config) {
  const std::string prefix = truthPrefix(truth_given);
  // No scenario: a real log with added objects (perturb --add-objects), whose walls nobody knows.
  sim::Scenario scenario;
  if (!scenario_path.empty()) {
    scenario = sim::loadScenario(scenario_path);
  } else {
    scenario.name = fs::path(prefix).filename().string();
  }
  const std::string rawlog = prefix + ".rawlog";
  const auto rows = readTruthRows(prefix + ".objects.csv");
  const auto moves = readMoves(prefix + ".moves.csv");

  Evaluation ev;
  ev.scenario = scenario.name;
  if (scenario_path.empty()) {
    ev.notes.push_back("no scenario: the walls are unknown, so the cell figures know the added "
                       "objects only (SA, AA, HA undefined)");
  }
  ev.truth = prefix;
  ev.result = result;
  ev.moves = moves.size();
  if (!fs::exists(fs::path(result) / "summary.json")) {
    std::cerr << "dynamap eval: no mapping result in " << result << ", mapping " << rawlog << "\n";
    runMapper(rawlog, config, result);
  }
  const fs::path tracks = fs::path(result) / "tracks.csv";
  ev.have_tracks = fs::exists(tracks);
  std::vector<TrackRow> track_rows;
  if (ev.have_tracks) {
    track_rows = readTracks(tracks.string());
    keepTableRows(fs::path(result) / "objects.csv", track_rows, ev.notes);
  } else
    ev.notes.push_back("the result has no tracks.csv: no object was reported");
  try {
    ev.objects = evaluateObjects(rows, moves, track_rows);
  } catch (const std::invalid_argument& e) {
    throw InputError(tracks.string() + ": " + e.what());
  }
  // Real scans (no scenario): the log's own changes and objects left where the robot never
  // looked again are no static parts; the simulator's robots see every place again.
  ev.real_scans = scenario_path.empty();
  ev.have_own = ev.real_scans && fs::exists(prefix + ".own.csv");
  if (ev.have_own) setAsideLogOwn(ev.objects, track_rows, readOwn(prefix + ".own.csv"));
  if (ev.real_scans) setAsideLeftBehind(ev.objects, track_rows, rows);
  evaluateCells(scenario, rows, moves, rawlog, config, ev);
  const fs::path people = fs::path(result) / "people.csv";
  ev.have_people = fs::exists(people);
  ev.mot = evaluateClearMot(
      rows, ev.have_people ? readPeople(people.string()) : std::vector<PersonTrackRow>{});
  const fs::path poses = fs::path(result) / "poses.txt";
  ev.have_poses = fs::exists(poses);
  if (ev.have_poses) {
    const auto truth = readPoses(prefix + ".gt.txt");
    ev.trajectory = trajectoryError(readPoses(poses.string()), truth);
    ev.odometry = trajectoryError(odometryPoses(rawlog), truth);
  }
  return ev;
}

/// --trajectory: `file` against the truth `given` (a pose file such as dynamap perturb's
/// gt.txt, or the simulator's prefix): the anchored ATE, then the errors that do not depend on
/// where the estimate starts.
void scoreTrajectory(const std::string& file, const std::string& given) {
  const std::string truth = std::filesystem::is_regular_file(given) && given.size() > 4 &&
                                    given.compare(given.size() - 4, 4, ".txt") == 0
                                ? given
                                : truthPrefix(given) + ".gt.txt";
  const std::vector<TimedPose> estimate = readPoses(file), reference = readPoses(truth);
  // Nothing to score is an error, not a table of n/a with exit status 0.
  if (estimate.empty()) throw InputError(file + ": no pose (expected 'timestamp x y phi' lines)");
  if (reference.empty()) throw InputError(truth + ": no pose (expected 'timestamp x y phi' lines)");
  const TrajectoryError e = trajectoryError(estimate, reference);
  std::cout << "dynamap eval: " << file << " against " << truth << ": " << e.matched
            << " poses scored, " << e.unmatched << " without truth; ATE RMSE position "
            << num(e.rmse_xy_m, 4, "n/a") << " m, heading "
            << num(e.rmse_phi_rad * 180.0 / M_PI, 3, "n/a") << " deg, max position error "
            << num(e.max_xy_m, 3, "n/a") << " m\n";
  const AlignedTrajectoryError a = alignedTrajectoryError(estimate, reference);
  std::cout << "dynamap eval: after the best rigid alignment: position RMSE "
            << num(a.aligned_rmse_xy_m, 4, "n/a") << " m; relative error over 1 m of path "
            << num(a.rel_1m_xy_m, 4, "n/a") << " m, "
            << num(a.rel_1m_phi_rad * 180.0 / M_PI, 3, "n/a") << " deg; over 10 m "
            << num(a.rel_10m_xy_m, 4, "n/a") << " m, "
            << num(a.rel_10m_phi_rad * 180.0 / M_PI, 3, "n/a") << " deg\n";
}

/// --input LOG with --trajectory FILE: the log's scans (the hits the mapper inserts, at the
/// default insertion range) laid out at the pose of FILE at each scan's timestamp, scored by
/// mapConsistency (no truth needed). Scans without a (finite) pose there are counted, not scored.
void scoreConsistency(const std::string& log, const std::string& file) {
  const std::vector<TimedPose> poses = readPoses(file);
  if (poses.empty()) throw InputError(file + ": no pose (expected 'timestamp x y phi' lines)");
  auto source = openScanSource(log, PoseSource::Fixed);
  const InsertionOptions insertion;
  const ConsistencyOptions o;
  ScanLayout layout(o);
  std::vector<mrpt::poses::CPose2D> at;
  std::size_t without_pose = 0;
  ScanRecord rec;
  while (!layout.full() && source->next(rec)) {
    const TimedPose* p = poseAtTime(poses, rec.t, 1e-3);
    if (p == nullptr || !std::isfinite(p->x) || !std::isfinite(p->y) || !std::isfinite(p->phi)) {
      ++without_pose;
      continue;
    }
    if (layout.addScan(*rec.scan, insertion)) at.emplace_back(p->x, p->y, p->phi);
  }
  if (at.empty()) throw InputError(file + ": no pose at the time of any scan of " + log);
  const Consistency c = layout.score(at);
  std::cout << "dynamap eval: " << log << " laid out at " << file << ": " << at.size()
            << " scans scored, " << without_pose << " without a pose"
            << (layout.full() ? " (the rest not read: the points kept reached their bound)" : "")
            << "; consistency: global "
            << num(c.global_m * 1000, 2, "n/a") << " mm (" << c.global_points
            << " points, against scans more than " << o.neighbour_scans << " away), local "
            << num(c.local_m * 1000, 2, "n/a") << " mm (" << c.local_points
            << " points, against the scan before)\n";
}

}  // namespace

static po::options_description evalOptions() {
  po::options_description opts("options");
  opts.add_options()("help,h", "explain the options")(
      "scenario,s", po::value<std::string>(), "the scenario file the truth was simulated from")(
      "truth,t", po::value<std::string>(),
      "the simulator's file prefix (rawlogs/arena/arena) or its directory")(
      "result,r", po::value<std::string>(), "a dynamap map output directory (mapped if empty)")(
      "config,c", po::value<std::string>(),
      "the mapper's configuration (default: the built-in defaults = config/default.ini), for\n"
      "mapping the result when it is not there yet and for the plain MRPT grid")(
      "summary", po::value<std::vector<std::string>>()->multitoken(),
      "print one table of these evaluated result directories beside the paper's Table 3")(
      "trajectory", po::value<std::string>(),
      "only score this `timestamp x y phi` file against the truth's poses (--truth), and/or\n"
      "lay out the scans of --input at it (consistency)")(
      "input,i", po::value<std::string>(), "with --trajectory: the log the poses are of")(
      "people-bag", po::value<std::string>(),
      "score --result's people against this ROS bag's leg_tracker/Person messages")(
      "person-topic", po::value<std::string>()->default_value("/ground_truth_people_tracks"),
      "with --people-bag: the topic of the Person messages");
  addBagOptions(opts, "with --people-bag, as the bag was mapped: ");
  return opts;
}

int runEval(const Args& args) {
  const po::options_description opts = evalOptions();
  po::positional_options_description positional;
  po::variables_map vm;
  if (!parseArgs(args, opts, positional, vm, kUsage)) return kExitOk;

  if (vm.count("summary")) {
    if (vm.count("scenario") || vm.count("truth") || vm.count("result")) {
      throw UsageError("--summary takes only result directories");
    }
    return runSummary(vm["summary"].as<std::vector<std::string>>(), std::cout);
  }
  if (vm.count("people-bag")) {
    if (!vm.count("result") || vm.count("scenario") || vm.count("truth") || vm.count("trajectory"))
      throw UsageError("--people-bag takes --result (and --scan-topic, --person-topic) only");
    return scorePeopleBag(vm);
  }
  if (vm.count("trajectory")) {
    if ((!vm.count("truth") && !vm.count("input")) || vm.count("scenario") || vm.count("result")) {
      throw UsageError("--trajectory takes --truth, --input or both");
    }
    const std::string file = vm["trajectory"].as<std::string>();
    if (vm.count("truth")) scoreTrajectory(file, vm["truth"].as<std::string>());
    if (vm.count("input")) scoreConsistency(vm["input"].as<std::string>(), file);
    return kExitOk;
  }
  if (vm.count("input")) throw UsageError("--input goes with --trajectory");
  for (const char* k : {"truth", "result"}) {
    if (!vm.count(k)) throw UsageError(std::string("--") + k + " is required");
  }
  const std::string result = vm["result"].as<std::string>();
  MapConfig config;
  if (vm.count("config"))
    config = MapConfig::load(IniFile::fromFile(vm["config"].as<std::string>()));
  const Evaluation ev =
      evaluate(vm.count("scenario") ? vm["scenario"].as<std::string>() : std::string(),
               vm["truth"].as<std::string>(), result, config);
  printTable(std::cout, ev);
  writeFileAtomically(result, "metrics.json", [&](std::ostream& o) { writeMetricsJson(o, ev); });
  writeFileAtomically(result, "report.md", [&](std::ostream& o) { writeReport(o, ev); });
  return kExitOk;
}

}  // namespace dynamap::app
