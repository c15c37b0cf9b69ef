// dynamap perturb --add-objects: cylinders added to a real log's scans, moved while the robot
// looks elsewhere (jumps) or in view (glides), with the truth in the simulator's format so that
// `dynamap eval --truth DIR/NAME --result ...` scores the object table on real scans.

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/serialization/CArchive.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <stdexcept>

#include "cli.h"
#include "commands.h"
#include "dynamap/base/csv_schema.h"
#include "dynamap/input/open_source.h"
#include "dynamap/outputs/map_outputs.h"
#include "dynamap/pipeline/mapper.h"
#include "dynamap/sim/added_objects.h"

namespace dynamap::app {
namespace {

/// Clearances are worked out to this distance [m]: more than any cylinder and margin needs.
constexpr double kClearanceCap = 3.0;

std::vector<ScanRecord> readAll(const std::string& input) {
  auto source = openScanSource(input, PoseSource::Auto);
  if (source->poseSource() == PoseSource::Odometry || source->poseSource() == PoseSource::Slam) {
    throw InputError(input + ": no known poses (ground truth or simplemap) to add objects to");
  }
  std::vector<ScanRecord> records;
  for (ScanRecord rec; source->next(rec);) records.push_back(rec);
  if (records.empty()) throw InputError(input + ": no scans");
  return records;
}

/// S of `map` as Free cells (below the mapper's free_threshold: where a new object raises D).
sim::FreeSpace freeSpaceOf(const DynamicGridMap& map, const std::vector<sim::Vec2>& robot,
                           double t) {
  sim::FreeSpace free;
  free.t = t;
  free.x_min = map.getXMin();
  free.y_min = map.getYMin();
  free.resolution = map.getResolution();
  free.size_x = static_cast<int>(map.getSizeX());
  free.size_y = static_cast<int>(map.getSizeY());
  std::vector<std::uint8_t> flags(static_cast<std::size_t>(free.size_x) * free.size_y);
  for (int y = 0; y < free.size_y; ++y) {
    for (int x = 0; x < free.size_x; ++x) {
      flags[static_cast<std::size_t>(y) * free.size_x + x] = map.isStaticFree(x, y);
    }
  }
  free.build(flags, robot, kClearanceCap);
  return free;
}

/// S of the unedited log, as `dynamap map` makes it with `config`, at each of `times` (seconds
/// since the first scan) and at the end; `own` gets the objects that run reports (own.csv rows).
std::vector<sim::FreeSpace> freeSpaces(const std::vector<ScanRecord>& records, MapConfig config,
                                       const std::vector<double>& times, std::string& own) {
  config.poses = PoseSource::GroundTruth;
  Mapper mapper(config);
  std::vector<sim::Vec2> robot;
  for (const ScanRecord& rec : records) robot.push_back({rec.pose.x(), rec.pose.y()});
  std::vector<sim::FreeSpace> free;
  for (const ScanRecord& rec : records) {
    while (free.size() + 1 < times.size() && rec.t - records.front().t >= times[free.size()]) {
      free.push_back(freeSpaceOf(mapper.map(), robot, times[free.size()]));
    }
    mapper.process(rec);
    for (const TrackedObject& o : mapper.tracker().objects()) {
      if (o.state != ObjectState::Present) continue;
      char row[96];
      std::snprintf(row, sizeof row, "%zu,%.3f,%.3f\n", &rec - records.data(), o.shape.cx,
                    o.shape.cy);
      own += row;
    }
  }
  while (free.size() < times.size())
    free.push_back(freeSpaceOf(mapper.map(), robot, times[free.size()]));
  return free;
}

sim::ScanGeometry geometryOf(const ScanRecord& rec, double t0) {
  const auto& scan = *rec.scan;
  sim::ScanGeometry g;
  g.t = rec.t - t0;
  g.robot = {rec.pose.x(), rec.pose.y()};
  const mrpt::poses::CPose2D sensor = rec.pose + mrpt::poses::CPose2D(scan.sensorPose);
  g.sensor = {sensor.x(), sensor.y()};
  g.sensor_phi = sensor.phi();
  const std::size_t n = scan.getScanSize();
  g.first_angle = n > 0 ? scan.getScanAngle(0) : 0;
  g.step = n > 1 ? (scan.getScanAngle(n - 1) - g.first_angle) / static_cast<double>(n - 1) : 0;
  if (g.step < 0) {
    throw InputError("scan " + std::to_string(rec.index) + ": clockwise scans are not supported");
  }
  g.max_range = scan.maxRange;
  g.ranges.resize(n);
  g.valid.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    g.valid[i] = scan.getScanRangeValidity(i) ? 1 : 0;
    const float r = scan.getScanRange(i);
    g.ranges[i] = g.valid[i] && std::isfinite(r) && r > 0 ? std::min(r, g.max_range) : g.max_range;
  }
  return g;
}

std::FILE* openOut(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) throw std::runtime_error(path + ": cannot write");
  return f;
}

void closeOut(std::FILE* f, const std::string& path) {
  if (std::fclose(f) != 0) throw std::runtime_error(path + ": write error");
}

/// The edited log and its truth, each under a temporary name until all are written.
struct Outputs {
  std::string dir, name;
  std::string tmp(const char* ext) const { return tempName(dir, name + ext); }
  void commitAll() const {
    for (const char* ext : {".rawlog", ".gt.txt", ".objects.csv", ".moves.csv", ".added.txt"}) {
      commit(tmp(ext), dir, name + ext);
    }
  }
};

/// The log's scan with the beams a cylinder shortened (`g`, edited) set to their new ranges.
mrpt::obs::CObservation2DRangeScan editedScan(const ScanRecord& rec, const sim::ScanGeometry& g) {
  auto scan = *rec.scan;
  scan.timestamp = mrpt::Clock::fromDouble(rec.t);
  for (std::size_t i = 0; i < g.ranges.size(); ++i) {
    // Only the beams a cylinder shortened change; every other stays as the log has it.
    if (!g.valid[i] || (scan.getScanRangeValidity(i) && g.ranges[i] >= scan.getScanRange(i)))
      continue;
    scan.setScanRange(i, g.ranges[i]);
    scan.setScanRangeValidity(i, true);
  }
  return scan;
}

void writeRecord(mrpt::serialization::CArchive& ar, const ScanRecord& rec,
                 const sim::ScanGeometry& g) {
  const auto stamp = mrpt::Clock::fromDouble(rec.t);
  mrpt::obs::CObservationOdometry odo;  // the known pose: odometry that does not drift
  odo.sensorLabel = "ODOMETRY";
  odo.timestamp = stamp;
  odo.odometry = rec.pose;
  const auto scan = editedScan(rec, g);
  mrpt::obs::CObservationRobotPose gt;
  gt.sensorLabel = "GT";
  gt.timestamp = stamp;
  gt.pose.mean = mrpt::poses::CPose3D(rec.pose);
  ar << odo << scan << gt;
}

/// S as `dynamap map` makes it from the edited scans, with `config` on the log's known poses.
class MappedEdits : public sim::EditedMap {
 public:
  MappedEdits(const std::vector<ScanRecord>& records, MapConfig config)
      : records_(records), mapper_([&] {
          config.poses = PoseSource::GroundTruth;
          return config;
        }()) {}

  bool heldFree(sim::Vec2 p, double radius) const override {
    const DynamicGridMap& map = mapper_.map();
    const double res = map.getResolution();
    // Cell indices by floor, not x2idx's truncation: a disc just below the grid's lower edge
    // must come out off the grid (never seen: isStaticFree is false there), not on its first
    // cell. The grid is at most max_map_size_m wide: its indices fit in an int.
    const auto cell = [res](double v, double min) {
      return static_cast<int>(std::floor((v - min) / res));
    };
    const int x0 = cell(p.x - radius, map.getXMin()), x1 = cell(p.x + radius, map.getXMin());
    const int y0 = cell(p.y - radius, map.getYMin()), y1 = cell(p.y + radius, map.getYMin());
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const double dx = map.getXMin() + (x + 0.5) * res - p.x;
        const double dy = map.getYMin() + (y + 0.5) * res - p.y;
        if (std::hypot(dx, dy) <= radius && !map.isStaticFree(x, y)) return false;
      }
    }
    return true;
  }

  void insert(std::size_t index, const sim::ScanGeometry& edited) override {
    ScanRecord rec = records_[index];
    rec.scan = std::make_shared<mrpt::obs::CObservation2DRangeScan>(editedScan(rec, edited));
    mapper_.process(rec);
  }

 private:
  const std::vector<ScanRecord>& records_;
  Mapper mapper_;
};

/// Edits every scan and writes the rawlog, gt.txt and objects.csv.
void writeScans(const Outputs& out, const std::vector<ScanRecord>& records,
                std::vector<sim::ScanGeometry>& geometry, const sim::AddedPlan& plan,
                const sim::AddObjectsSpec& spec) {
  mrpt::io::CFileGZOutputStream rawlog;
  if (!rawlog.open(out.tmp(".rawlog")))
    throw std::runtime_error(out.tmp(".rawlog") + ": cannot write");
  auto ar = mrpt::serialization::archiveFrom(rawlog);
  std::FILE* gt = openOut(out.tmp(".gt.txt"));
  std::FILE* objects = openOut(out.tmp(".objects.csv"));
  std::fprintf(objects, "%s\n", csv::kTruthRows);
  for (std::size_t s = 0; s < records.size(); ++s) {
    sim::ScanGeometry& g = geometry[s];
    const std::vector<int> hits =
        sim::applyAddedObjects(plan, g, spec, sim::addedNoiseStream(spec, s));
    writeRecord(ar, records[s], g);
    const auto& p = records[s].pose;
    std::fprintf(gt, "%.6f %.6f %.6f %.6f\n", records[s].t, p.x(), p.y(), p.phi());
    for (std::size_t k = 0; k < plan.objects.size(); ++k) {
      const sim::Vec2 c = sim::addedPositionAt(plan, k, g.t);
      std::fprintf(objects, "%zu,%.3f,object,%d,%.4f,%.4f,%.3f,%d\n", s, g.t, plan.objects[k].id,
                   c.x, c.y, plan.objects[k].diameter, hits[k]);
    }
  }
  rawlog.close();
  closeOut(gt, out.tmp(".gt.txt"));
  closeOut(objects, out.tmp(".objects.csv"));
}

void writePlan(const Outputs& out, const sim::AddedPlan& plan, const std::string& input,
               const std::string& spec_text, std::size_t planned) {
  std::FILE* moves = openOut(out.tmp(".moves.csv"));
  std::fprintf(moves, "%s\n", csv::kMoves);
  for (const auto& m : plan.moves) {
    std::fprintf(moves, "%d,%d,%.3f,%.3f,%.4f,%.4f,%.4f,%.4f\n", m.id, m.object_id, m.t_start,
                 m.t_end, m.from.x, m.from.y, m.to.x, m.to.y);
  }
  closeOut(moves, out.tmp(".moves.csv"));
  std::FILE* note = openOut(out.tmp(".added.txt"));
  std::fprintf(note,
               "input: %s\nspec: %s\nobjects: %zu\nmoves planned: %zu, kept: %zu, dropped: %zu\n",
               input.c_str(), spec_text.c_str(), plan.objects.size(), planned, plan.moves.size(),
               plan.dropped.size());
  for (const auto& o : plan.objects) {
    std::fprintf(note, "object %d: diameter %.3f m, starts at %.4f %.4f\n", o.id, o.diameter,
                 o.start.x, o.start.y);
  }
  for (const auto& d : plan.dropped) std::fprintf(note, "dropped: %s\n", d.c_str());
  closeOut(note, out.tmp(".added.txt"));
}

std::string defaultName(const std::string& input) {
  std::string stem = std::filesystem::path(input).filename().string();
  for (const char* ext : {".gz", ".log", ".rawlog", ".simplemap"}) {
    const std::string e(ext);
    if (stem.size() > e.size() && stem.compare(stem.size() - e.size(), e.size(), e) == 0) {
      stem.resize(stem.size() - e.size());
    }
  }
  return stem.empty() ? "added" : stem;
}

}  // namespace

int runAddObjects(const std::string& input, const std::string& dir, const std::string& spec_text,
                  std::string name, const MapConfig& config) {
  sim::AddObjectsSpec spec;
  try {
    spec = sim::parseAddObjectsSpec(spec_text);
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("--add-objects: ") + e.what());
  }
  if (name.empty()) name = defaultName(input);
  const std::vector<ScanRecord> records = readAll(input);
  spec.counted_range_m = config.insertion.max_distance_insertion;
  std::vector<sim::ScanGeometry> geometry;
  for (const ScanRecord& rec : records) geometry.push_back(geometryOf(rec, records.front().t));
  std::string own = std::string(csv::kOwn) + "\n";
  const auto free = freeSpaces(records, config, sim::addedSlotTimes(geometry.back().t, spec), own);
  for (sim::ScanGeometry& g : geometry) sim::limitBeamsWithoutReturn(g, free.back());
  sim::AddedPlan plan;
  try {
    plan = sim::planAddedObjects(geometry, free, spec);
  } catch (const std::invalid_argument& e) {
    throw InputError(input + ": " + e.what());
  }
  sim::dropUnseenMoves(geometry, spec, plan);
  // Each drop changes the later scans: what S holds at the later moves' places and how often
  // they are seen. The pass over S takes its own drops in as it goes; one for too few views
  // means another pass.
  for (;;) {
    MappedEdits map(records, config);
    sim::dropMovesIntoHeldPlaces(geometry, spec, plan, map);
    const std::size_t kept = plan.moves.size();
    sim::dropUnseenMoves(geometry, spec, plan);
    if (plan.moves.size() == kept) break;
  }
  prepareOutputDir(dir);
  const Outputs out{dir, name};
  writeScans(out, records, geometry, plan, spec);
  writeFileAtomically(dir, name + ".own.csv", [&](std::ostream& o) { o << own; });
  writePlan(out, plan, input, spec_text, static_cast<std::size_t>(spec.moves));
  out.commitAll();
  std::cout << "dynamap perturb: " << plan.objects.size() << " cylinders added to the "
            << records.size() << " scans of " << input << "; " << plan.moves.size()
            << " moves kept, " << plan.dropped.size() << " dropped (" << dir << "/" << name
            << ".added.txt says why); truth prefix " << dir << "/" << name << "\n";
  for (const auto& d : plan.dropped) std::cout << "  dropped: " << d << "\n";
  return kExitOk;
}

}  // namespace dynamap::app
