#include "dynamap/outputs/run_outputs.h"

#include <iomanip>
#include <ostream>

#include "dynamap/outputs/format.h"
#include "dynamap/outputs/map_outputs.h"
#include "dynamap/outputs/render.h"
#include "dynamap/outputs/tables.h"

namespace dynamap {

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

// The people tracked: how many, for how long, how far each walked.
void writePeopleSummary(std::ostream& o, const PersonTracker& people) {
  const std::vector<PersonSummary> all = people.summaries();
  double duration = 0, path = 0;
  for (const PersonSummary& p : all) {
    duration += p.last_t - p.first_t;
    path += p.path_length;
  }
  o << "  \"people\": {\n"
    << "    \"enabled\": " << (people.options().enabled ? "true" : "false") << ",\n"
    << "    \"tracks\": " << all.size() << ",\n"
    << "    \"total_duration_s\": " << fmt("%.3f", duration) << ",\n"
    << "    \"total_path_m\": " << fmt("%.3f", path) << ",\n"
    << "    \"by_person\": [";
  for (std::size_t i = 0; i < all.size(); ++i) {
    const PersonSummary& p = all[i];
    o << (i ? ",\n      " : "\n      ") << "{\"id\": " << p.id << ", \"first_t\": "
      << fmt("%.6f", p.first_t) << ", \"last_t\": " << fmt("%.6f", p.last_t)
      << ", \"duration_s\": " << fmt("%.3f", p.last_t - p.first_t)
      << ", \"path_m\": " << fmt("%.3f", p.path_length) << "}";
  }
  o << (all.empty() ? "]\n" : "\n    ]\n") << "  },\n";
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

// Pass 1 of pose source slam: what the front end matched, the loop closures, the optimiser.
void writeSlamSummary(std::ostream& o, const SlamRun& run) {
  const SlamStats& s = run.slam->stats();
  o << "  \"slam\": {\n"
    << "    \"scans\": " << s.scans << ",\n"
    << "    \"front_end_matched\": " << s.matched << ",\n"
    << "    \"front_end_fallbacks\": " << s.fallbacks << ",\n"
    << "    \"submaps\": " << s.submaps << ",\n"
    << "    \"loop_searches\": " << s.loop_attempts << ",\n"
    << "    \"loop_closures\": {\"proposed\": " << s.loops_proposed
    << ", \"accepted\": " << s.loops_accepted << ", \"rejected\": " << s.loops_rejected
    << ", \"rejected_ambiguous\": " << s.loops_ambiguous << "},\n"
    << "    \"optimiser\": {\"runs\": " << s.optimisations << ", \"iterations\": " << s.iterations
    << ", \"final_error\": " << fmt("%.6g", s.final_error)
    << ", \"converged\": " << (s.converged ? "true" : "false") << "},\n"
    << "    \"poses\": "
    << jsonString(s.converged ? "optimised" : "front end (the optimiser did not converge)")
    << "\n  },\n";
}

// The only block that differs between identical runs: how long the passes took.
void writeTimingSummary(std::ostream& o, const RunCounts& c, const OutputInfo& info) {
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
  if (info.slam) {  // wall_s is pass 2's
    o << ",\n    \"slam_pass1_wall_s\": " << std::setprecision(3) << info.slam->wall_s;
  }
  o << "\n  }\n";
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
  writePeopleSummary(o, mapper.people());
  if (mapper.scanMatching()) writeScanMatchSummary(o, mapper.scanMatchCounts());
  if (info.slam) writeSlamSummary(o, *info.slam);
  if (info.baseline) writeBaselineSummary(o, m, *info.baseline);
  writeTimingSummary(o, c, info);
  o << "}\n";
}

}  // namespace

void writeMapOutputs(const std::string& dir, const Mapper& mapper, const ScanSource& source,
                     const OutputInfo& info) {
  const DynamicGridMap& m = mapper.map();
  saveImageAtomically(renderStatic(m), dir, "static.png");
  saveImageAtomically(renderDynamic(m), dir, "dynamic.png");
  const std::vector<PersonTrail> trails = mapper.people().trails();
  saveImageAtomically(renderOverlay(m, mapper.path(), &mapper.tracker().objects(), &trails), dir,
                      "overlay.png");
  writeGridmap(m, dir, "static.gridmap.gz");
  writeDynamicGridmap(m, dir, "dynamic.gridmap.gz");
  writeRosMap(m, dir, "static");
  writeFileAtomically(dir, "config.ini", [&](std::ostream& o) { mapper.config().writeIni(o); });
  writeFileAtomically(dir, "objects.csv",
                      [&](std::ostream& o) { writeObjectsCsv(o, mapper.tracker()); });
  writeFileAtomically(dir, "events.csv",
                      [&](std::ostream& o) { writeEventsCsv(o, mapper.tracker()); });
  if (info.baseline)
    saveImageAtomically(renderStaticOn(info.baseline->grid(), m), dir, "mrpt_plain.png");
  if (info.slam) {
    const std::string tmp = tempName(dir, "graph.g2o");
    info.slam->slam->graph().saveG2o(tmp);
    commit(tmp, dir, "graph.g2o");
  }
  writeFileAtomically(dir, "summary.json",
                      [&](std::ostream& o) { writeSummary(o, mapper, source, info); });
}

}  // namespace dynamap
