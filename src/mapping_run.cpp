#include "dynamap/mapping_run.h"

#include <cmath>
#include <iomanip>
#include <ostream>
#include <sstream>

#include "dynamap/config_check.h"
#include "dynamap/map_outputs.h"

namespace dynamap {

MapConfig MapConfig::load(const IniFile& ini) {
  ini.requireKnownSections({DynamicMapOptions::kSection, InsertionOptions::kSection, "input"});
  MapConfig c;
  c.map.load(ini);
  c.insertion.load(ini);
  ini.requireKnownKeys("input", {"poses"});
  const std::string poses = ini.getString("input", "poses", "auto");
  try {
    c.poses = parsePoseSource(poses);
  } catch (const std::invalid_argument& e) {
    ini.fail("input", "poses", e.what());
  }
  return c;
}

void MapConfig::writeIni(std::ostream& out) const {
  out << "; the effective configuration of this run (reload it with --config)\n\n";
  out << "[input]\n"
      << "poses = " << toString(poses)
      << "  ; auto | simplemap | ground_truth | odometry\n\n";
  map.writeIni(out);
  out << "\n";
  insertion.writeIni(out);
}

Mapper::Mapper(const MapConfig& config)
    : config_(config),
      map_(config.map, config.insertion),
      path_step_(std::max(0.05, config.map.resolution)) {}

bool Mapper::process(const ScanRecord& rec) {
  if (have_t_ && rec.t < counts_.last_t) ++counts_.time_backwards;
  if (!have_t_) counts_.first_t = rec.t;
  have_t_ = true;
  counts_.last_t = rec.t;

  const mrpt::poses::CPose3D pose(rec.pose);
  map_.insertObservation(*rec.scan, pose);
  const ScanInsertStats& st = map_.lastInsertStats();
  counts_.beams_bad += st.beams_bad;
  if (!st.inserted) {
    const bool planar = rec.scan->isPlanarScan(config_.insertion.horizontal_tolerance_deg * M_PI / 180.0);
    ++counts_.scans_skipped[planar ? "no usable beam" : "not horizontal"];
    return false;
  }
  ++counts_.scans_used;
  const PathPoint p{rec.pose.x(), rec.pose.y()};
  if (path_.empty() || std::hypot(p.x - path_.back().x, p.y - path_.back().y) >= path_step_) {
    path_.push_back(p);
  }
  return true;
}

InputOutcome runMapping(ScanSource& source, Mapper& mapper,
                        const std::function<void(const ScanRecord&)>& on_scan) {
  InputOutcome outcome;
  ScanRecord rec;
  while (true) {
    try {
      if (!source.next(rec)) break;
    } catch (const InputError& e) {
      outcome.fault = e.what();
      break;
    }
    mapper.process(rec);
    if (on_scan) on_scan(rec);
  }
  return outcome;
}

namespace {

void writeSummary(std::ostream& o, const Mapper& mapper, const ScanSource& source,
                  const OutputInfo& info) {
  const DynamicGridMap& m = mapper.map();
  const RunCounts& c = mapper.counts();
  const SourceStats& s = source.stats();
  const auto cells = m.countCells();
  std::size_t skipped = 0;
  for (const auto& kv : c.scans_skipped) skipped += kv.second;
  o << std::setprecision(10);
  o << "{\n"
    << "  \"input\": " << jsonString(info.input) << ",\n"
    << "  \"pose_source\": " << jsonString(toString(source.poseSource())) << ",\n"
    << "  \"complete_input\": " << (info.outcome.fault.empty() ? "true" : "false") << ",\n"
    << "  \"input_fault\": "
    << (info.outcome.fault.empty() ? "null" : jsonString(info.outcome.fault)) << ",\n"
    << "  \"records_read\": " << s.records << ",\n"
    << "  \"scans\": {\n"
    << "    \"read\": " << s.scans << ",\n"
    << "    \"used\": " << c.scans_used << ",\n"
    << "    \"skipped\": " << skipped << ",\n"
    << "    \"skipped_by_reason\": {";
  bool first = true;
  auto reasons = c.scans_skipped;
  for (const auto& kv : s.skipped) reasons[kv.first] += kv.second;
  for (const auto& kv : reasons) {
    o << (first ? "\n" : ",\n") << "      " << jsonString(kv.first) << ": " << kv.second;
    first = false;
  }
  o << (first ? "},\n" : "\n    },\n")
    << "    \"bad_beams\": " << c.beams_bad << ",\n"
    << "    \"timestamps_backwards\": " << c.time_backwards << ",\n"
    << "    \"first_t\": " << std::fixed << std::setprecision(6) << c.first_t << ",\n"
    << "    \"last_t\": " << c.last_t << std::defaultfloat << std::setprecision(10) << "\n"
    << "  },\n"
    << "  \"map\": {\n"
    << "    \"resolution_m\": " << m.getResolution() << ",\n"
    << "    \"size_cells\": [" << m.getSizeX() << ", " << m.getSizeY() << "],\n"
    << "    \"x_min\": " << m.getXMin() << ", \"x_max\": " << m.getXMax() << ",\n"
    << "    \"y_min\": " << m.getYMin() << ", \"y_max\": " << m.getYMax() << "\n"
    << "  },\n"
    << "  \"cells\": {\n"
    << "    \"static_occupied\": " << cells.static_occupied << ",\n"
    << "    \"static_free\": " << cells.static_free << ",\n"
    << "    \"dynamic_occupied\": " << cells.dynamic_occupied << "\n"
    << "  },\n"
    << "  \"timing\": {\n"
    << "    \"note\": \"the only part of the outputs that differs between identical runs\",\n"
    << "    \"wall_s\": " << std::fixed << std::setprecision(3) << info.wall_s << ",\n"
    << "    \"scans_per_s\": " << std::setprecision(1)
    << (info.wall_s > 0 ? c.scans_used / info.wall_s : 0.0) << "\n"
    << "  }\n"
    << "}\n";
}

}  // namespace

void writeMapOutputs(const std::string& dir, const Mapper& mapper, const ScanSource& source,
                     const OutputInfo& info) {
  const DynamicGridMap& m = mapper.map();
  saveImageAtomically(renderStatic(m), dir, "static.png");
  saveImageAtomically(renderDynamic(m), dir, "dynamic.png");
  saveImageAtomically(renderOverlay(m, mapper.path(), overlayScale(m.getSizeX())), dir,
                      "overlay.png");
  writeGridmap(m, dir, "static.gridmap.gz");
  writeDynamicGridmap(m, dir, "dynamic.gridmap.gz");
  writeRosMap(m, dir, "static");
  writeFileAtomically(dir, "config.ini", [&](std::ostream& o) { mapper.config().writeIni(o); });
  writeFileAtomically(dir, "summary.json",
                      [&](std::ostream& o) { writeSummary(o, mapper, source, info); });
}

}  // namespace dynamap
