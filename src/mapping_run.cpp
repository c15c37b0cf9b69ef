#include "dynamap/mapping_run.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <ostream>
#include <sstream>

#include "dynamap/config_check.h"
#include "dynamap/map_outputs.h"

namespace dynamap {

MapConfig MapConfig::load(const IniFile& ini) {
  ini.requireKnownSections({DynamicMapOptions::kSection, InsertionOptions::kSection,
                            ObjectOptions::kSection, ScanMatchOptions::kSection, "input"});
  MapConfig c;
  c.map.load(ini);
  c.insertion.load(ini);
  c.objects.load(ini);
  c.scan_matching.load(ini);
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
      << "  ; auto | simplemap | ground_truth | odometry | scan_matching\n\n";
  map.writeIni(out);
  out << "\n";
  insertion.writeIni(out);
  out << "\n";
  objects.writeIni(out);
  out << "\n";
  scan_matching.writeIni(out);
}

std::size_t ScanMatchCounts::fallbackTotal() const {
  std::size_t n = 0;
  for (const auto& kv : fallbacks) n += kv.second;
  return n;
}

Mapper::Mapper(const MapConfig& config)
    : config_(config),
      map_(config.map, config.insertion),
      tracker_(config.objects),
      path_step_(std::max(0.05, config.map.resolution)) {
  if (config.poses == PoseSource::ScanMatching) {
    matcher_ = std::make_unique<ScanMatcher>(config.scan_matching,
                                             config.insertion.max_distance_insertion);
  }
}

std::string Mapper::poseSourceName(const ScanSource& source) const {
  return toString(matcher_ ? PoseSource::ScanMatching : source.poseSource());
}

mrpt::poses::CPose2D Mapper::correctPose(const ScanRecord& rec) {
  // The odometry increment since the last scan, applied to the last pose used, is the guess.
  const mrpt::poses::CPose2D guess =
      have_pose_ ? last_pose_ + (rec.pose - last_odometry_) : rec.pose;
  // Matched against S only: D's people and moved objects cannot pull the pose.
  const ScanMatchResult r = matcher_->match(map_, *rec.scan, guess);
  if (r.matched) {
    ++match_counts_.matched;
    match_counts_.sum_correction_m += r.correction_m;
    match_counts_.max_correction_m = std::max(match_counts_.max_correction_m, r.correction_m);
  } else {
    ++match_counts_.fallbacks[r.fallback_reason];
  }
  have_pose_ = true;
  last_odometry_ = rec.pose;
  last_pose_ = r.pose;
  return r.pose;
}

bool Mapper::process(const ScanRecord& rec) {
  if (have_t_ && rec.t < counts_.last_t) ++counts_.time_backwards;
  if (!have_t_) counts_.first_t = rec.t;
  have_t_ = true;
  counts_.last_t = rec.t;

  const mrpt::poses::CPose2D pose2 = matcher_ ? correctPose(rec) : rec.pose;
  used_poses_.push_back({rec.t, pose2});
  map_.insertObservation(*rec.scan, mrpt::poses::CPose3D(pose2));
  const ScanInsertStats& st = map_.lastInsertStats();
  counts_.beams_bad += st.beams_bad;
  if (!st.inserted) {
    ++counts_.scans_skipped[st.skip_reason ? st.skip_reason : "no usable beam"];
    return false;
  }
  ++counts_.scans_used;
  // Objects, from the D cells this scan changed and the scan's view of known places.
  tracker_.update(map_, makeScanView(*rec.scan, pose2, config_.insertion.max_distance_insertion),
                  rec.t, rec.index);
  const PathPoint p{pose2.x(), pose2.y()};
  if (path_.empty() || std::hypot(p.x - path_.back().x, p.y - path_.back().y) >= path_step_) {
    path_.push_back(p);
    // Hours of driving must not grow memory without bound: past kMaxPathPoints, every other
    // point goes and the step doubles (at 5 cm, the first halving comes after 3.3 km).
    if (path_.size() > kMaxPathPoints) {
      std::size_t kept = 0;
      for (std::size_t i = 0; i < path_.size(); i += 2) path_[kept++] = path_[i];
      path_.resize(kept);
      path_step_ *= 2;
    }
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
    rec.pose = mapper.usedPoses().back().pose;  // scan matching may have corrected it
    if (on_scan) on_scan(rec);
  }
  return outcome;
}

namespace {

// Fixed formats: outputs are byte-identical between runs of the same input.
std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

}  // namespace

TrackLog::TrackLog(const std::string& dir) : dir_(dir), tmp_(tempName(dir, "tracks.csv")) {
  out_ = std::make_unique<std::ofstream>(tmp_, std::ios::binary | std::ios::trunc);
  if (!*out_) throw std::runtime_error(dir + "/tracks.csv: cannot write");
  *out_ << "scan_index,t,object_id,cx,cy,size_m,x_min,x_max,y_min,y_max\n";
}

TrackLog::~TrackLog() {
  if (!out_) return;
  out_.reset();
  std::error_code ec;
  std::filesystem::remove(tmp_, ec);  // not finished: leave no half-written file
}

void TrackLog::append(std::size_t scan_index, double t, const ObjectTracker& tracker) {
  for (const TrackedObject& o : tracker.objects()) {
    if (o.state != ObjectState::Present) continue;
    const ShapeEstimate& s = o.shape;
    *out_ << scan_index << ',' << fmt("%.6f", t) << ',' << o.id << ',' << fmt("%.3f", s.cx) << ','
          << fmt("%.3f", s.cy) << ',' << fmt("%.3f", s.size) << ',' << fmt("%.3f", s.x_min) << ','
          << fmt("%.3f", s.x_max) << ',' << fmt("%.3f", s.y_min) << ',' << fmt("%.3f", s.y_max)
          << '\n';
  }
}

void TrackLog::finish() {
  out_->flush();
  const bool ok = static_cast<bool>(*out_);
  out_.reset();
  if (!ok) {
    std::error_code ec;
    std::filesystem::remove(tmp_, ec);
    throw std::runtime_error(dir_ + "/tracks.csv: cannot write");
  }
  commit(tmp_, dir_, "tracks.csv");
}

void writePosesTxt(std::ostream& o, const std::vector<UsedPose>& poses) {
  o << "% timestamp x y phi (the pose each scan was mapped at)\n";
  char buf[128];
  for (const UsedPose& p : poses) {
    std::snprintf(buf, sizeof buf, "%.6f %.6f %.6f %.6f\n", p.t, p.pose.x(), p.pose.y(),
                  p.pose.phi());
    o << buf;
  }
}

void writeObjectsCsv(std::ostream& o, const ObjectTracker& tracker) {
  o << "id,label,size_m,cx,cy,x_min,x_max,y_min,y_max,state,first_seen_t,last_seen_t,n_moves\n";
  for (const TrackedObject& ob : tracker.objects()) {
    const ShapeEstimate& s = ob.shape;
    o << ob.id << ',' << ob.label << ',' << fmt("%.3f", s.size) << ',' << fmt("%.3f", s.cx) << ','
      << fmt("%.3f", s.cy) << ',' << fmt("%.3f", s.x_min) << ',' << fmt("%.3f", s.x_max) << ','
      << fmt("%.3f", s.y_min) << ',' << fmt("%.3f", s.y_max) << ',' << toString(ob.state) << ','
      << fmt("%.6f", ob.first_seen_t) << ',' << fmt("%.6f", ob.last_seen_t) << ',' << ob.n_moves
      << '\n';
  }
}

void writeEventsCsv(std::ostream& o, const ObjectTracker& tracker) {
  o << "t,scan_index,object_id,event,cx,cy,size_m\n";
  for (const EventRecord& e : tracker.events()) {
    o << fmt("%.6f", e.t) << ',' << e.scan_index << ',' << e.object_id << ',' << toString(e.event)
      << ',' << fmt("%.3f", e.cx) << ',' << fmt("%.3f", e.cy) << ',' << fmt("%.3f", e.size) << '\n';
  }
}

namespace {

void writeObjectSummary(std::ostream& o, const ObjectTracker& tracker) {
  std::size_t present = 0, absent = 0;
  for (const TrackedObject& ob : tracker.objects()) {
    (ob.state == ObjectState::Present ? present : absent) += 1;
  }
  std::map<std::string, std::size_t> by_event{
      {"new", 0}, {"moved", 0}, {"disappeared", 0}, {"reappeared", 0}};
  for (const EventRecord& e : tracker.events()) ++by_event[toString(e.event)];
  o << "  \"objects\": {\n"
    << "    \"enabled\": " << (tracker.options().enabled ? "true" : "false") << ",\n"
    << "    \"total\": " << tracker.objects().size() << ",\n"
    << "    \"by_state\": {\"present\": " << present << ", \"absent\": " << absent << "},\n"
    << "    \"events\": {";
  bool first = true;
  for (const auto& kv : by_event) {
    o << (first ? "" : ", ") << jsonString(kv.first) << ": " << kv.second;
    first = false;
  }
  o << "}\n  },\n";
}

// What a plain MRPT grid of the same scans holds that S does not, and the other way round.
void writeBaselineSummary(std::ostream& o, const DynamicGridMap& m, const PlainGrid& plain) {
  const PlainComparison c = comparePlain(m, plain.grid());
  o << "  \"mrpt_baseline\": {\n"
    << "    \"note\": \"cells, each S cell against a plain MRPT grid built from the same scans\",\n"
    << "    \"plain_occupied_static_free\": " << c.plain_occupied_static_free << ",\n"
    << "    \"static_occupied_plain_not\": " << c.static_occupied_plain_not << ",\n"
    << "    \"both_occupied\": " << c.both_occupied << "\n"
    << "  },\n";
}

// How many scans scan matching placed, and why the others kept their odometry pose.
void writeScanMatchSummary(std::ostream& o, const ScanMatchCounts& c) {
  o << "  \"scan_matching\": {\n"
    << "    \"matched\": " << c.matched << ",\n"
    << "    \"fallbacks\": " << c.fallbackTotal() << ",\n"
    << "    \"fallbacks_by_reason\": {";
  bool first = true;
  for (const auto& kv : c.fallbacks) {
    o << (first ? "" : ", ") << jsonString(kv.first) << ": " << kv.second;
    first = false;
  }
  o << "},\n"
    << "    \"mean_correction_m\": "
    << fmt("%.4f", c.matched ? c.sum_correction_m / static_cast<double>(c.matched) : 0.0) << ",\n"
    << "    \"max_correction_m\": " << fmt("%.4f", c.max_correction_m) << "\n"
    << "  },\n";
}

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
    << "  \"pose_source\": " << jsonString(mapper.poseSourceName(source)) << ",\n"
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
  o << (first ? "},\n" : "\n    },\n") << "    \"bad_beams\": " << c.beams_bad << ",\n"
    << "    \"timestamps_backwards\": " << c.time_backwards << ",\n"
    << "    \"first_t\": " << std::fixed << std::setprecision(6) << c.first_t << ",\n"
    << "    \"last_t\": " << c.last_t << std::defaultfloat << std::setprecision(10) << "\n"
    << "  },\n"
    << "  \"map\": {\n"
    << std::setprecision(6) << "    \"resolution_m\": " << m.getResolution() << ",\n"
    << "    \"size_cells\": [" << m.getSizeX() << ", " << m.getSizeY() << "],\n"
    << "    \"x_min\": " << m.getXMin() << ", \"x_max\": " << m.getXMax() << ",\n"
    << "    \"y_min\": " << m.getYMin() << ", \"y_max\": " << m.getYMax() << "\n"
    << "  },\n"
    << "  \"cells\": {\n"
    << "    \"static_occupied\": " << cells.static_occupied << ",\n"
    << "    \"static_free\": " << cells.static_free << ",\n"
    << "    \"dynamic_occupied\": " << cells.dynamic_occupied << "\n"
    << "  },\n";
  writeObjectSummary(o, mapper.tracker());
  if (mapper.scanMatching()) writeScanMatchSummary(o, mapper.scanMatchCounts());
  if (info.baseline) writeBaselineSummary(o, m, *info.baseline);
  o << "  \"timing\": {\n"
    << "    \"note\": \"the only part of the outputs that differs between identical runs\",\n"
    << "    \"wall_s\": " << std::fixed << std::setprecision(3) << info.wall_s << ",\n"
    << "    \"scans_per_s\": " << std::setprecision(1)
    << (info.wall_s > 0 ? c.scans_used / info.wall_s : 0.0);
  if (info.baseline) {
    o << ",\n    \"mrpt_baseline_wall_s\": " << std::setprecision(3) << info.baseline_wall_s
      << ",\n    \"mrpt_baseline_scans_per_s\": " << std::setprecision(1)
      << (info.baseline_wall_s > 0 ? c.scans_used / info.baseline_wall_s : 0.0);
  }
  o << "\n  }\n"
    << "}\n";
}

}  // namespace

void writeMapOutputs(const std::string& dir, const Mapper& mapper, const ScanSource& source,
                     const OutputInfo& info) {
  const DynamicGridMap& m = mapper.map();
  saveImageAtomically(renderStatic(m), dir, "static.png");
  saveImageAtomically(renderDynamic(m), dir, "dynamic.png");
  saveImageAtomically(renderOverlay(m, mapper.path(), &mapper.tracker().objects()), dir,
                      "overlay.png");
  writeGridmap(m, dir, "static.gridmap.gz");
  writeDynamicGridmap(m, dir, "dynamic.gridmap.gz");
  writeRosMap(m, dir, "static");
  writeFileAtomically(dir, "config.ini", [&](std::ostream& o) { mapper.config().writeIni(o); });
  writeFileAtomically(dir, "objects.csv",
                      [&](std::ostream& o) { writeObjectsCsv(o, mapper.tracker()); });
  writeFileAtomically(dir, "events.csv",
                      [&](std::ostream& o) { writeEventsCsv(o, mapper.tracker()); });
  writeFileAtomically(dir, "poses.txt",
                      [&](std::ostream& o) { writePosesTxt(o, mapper.usedPoses()); });
  if (info.baseline)
    saveImageAtomically(renderStatic(info.baseline->grid()), dir, "mrpt_plain.png");
  writeFileAtomically(dir, "summary.json",
                      [&](std::ostream& o) { writeSummary(o, mapper, source, info); });
}

}  // namespace dynamap
