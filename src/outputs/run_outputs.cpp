#include "dynamap/outputs/run_outputs.h"

#include <cmath>
#include <future>
#include <iomanip>
#include <ostream>

#include "dynamap/outputs/format.h"
#include "dynamap/outputs/json.h"
#include "dynamap/outputs/map_outputs.h"
#include "dynamap/outputs/render.h"
#include "dynamap/outputs/tables.h"

namespace dynamap {

namespace {

Json objectSummary(const ObjectTracker& tracker) {
  std::map<std::string, std::size_t> by_state{
      {"present", 0}, {"absent", 0}, {"withdrawn", 0}, {"relabeled", 0}, {"retracted", 0}};
  for (const TrackedObject& ob : tracker.objects()) ++by_state[toString(ob.state)];
  // The events as events.csv holds them.
  std::map<std::string, std::size_t> by_event{{"new", 0},         {"moved", 0},
                                              {"disappeared", 0}, {"reappeared", 0},
                                              {"relabeled", 0},   {"retracted", 0}};
  for (const EventRecord& e : tracker.events()) {
    if (eventsListed(tracker, e.object_id)) ++by_event[toString(e.event)];
  }
  const std::size_t present = by_state["present"], absent = by_state["absent"];
  Json events = Json::object();
  for (const auto& kv : by_event) events[kv.first] = kv.second;
  return {{"enabled", tracker.options().enabled},
          {"total", present + absent},
          {"by_state", {{"present", present}, {"absent", absent}}},
          {"withdrawn_as_people", by_state["withdrawn"]},
          {"provisional_relabeled", by_state["relabeled"]},
          {"provisional_retracted", by_state["retracted"]},
          {"events", events}};
}

// The people tracked: how many, for how long, how far each walked.
Json peopleSummary(const PersonTracker& people) {
  const std::vector<PersonSummary> all = people.summaries();
  double duration = 0, path = 0;
  Json by_person = Json::array();
  for (const PersonSummary& p : all) {
    duration += p.last_t - p.first_t;
    path += p.path_length;
    by_person.push_back({{"id", p.id},
                         {"first_t", jsonNumber("%.6f", p.first_t)},
                         {"last_t", jsonNumber("%.6f", p.last_t)},
                         {"duration_s", jsonNumber("%.3f", p.last_t - p.first_t)},
                         {"path_m", jsonNumber("%.3f", p.path_length)}});
  }
  return {{"enabled", people.options().enabled},
          {"tracks", all.size()},
          {"total_duration_s", jsonNumber("%.3f", duration)},
          {"total_path_m", jsonNumber("%.3f", path)},
          {"by_person", by_person}};
}

// What a plain MRPT grid of the same scans holds that S does not, and the other way round.
Json baselineSummary(const PlainComparison& c) {
  return {{"note", "cells, each S cell against a plain MRPT grid built from the same scans"},
          {"plain_occupied_static_free", c.plain_occupied_static_free},
          {"static_occupied_plain_not", c.static_occupied_plain_not},
          {"both_occupied", c.both_occupied}};
}

// How many scans scan matching placed, and why the others kept their odometry pose.
Json scanMatchSummary(const ScanMatchCounts& c) {
  Json reasons = Json::object();
  for (const auto& kv : c.fallbacks) reasons[kv.first] = kv.second;
  return {
      {"matched", c.matched},
      {"fallbacks", c.fallbackTotal()},
      {"fallbacks_by_reason", reasons},
      {"mean_correction_m",
       jsonNumber("%.4f", c.matched ? c.sum_correction_m / static_cast<double>(c.matched) : 0.0)},
      {"max_correction_m", jsonNumber("%.4f", c.max_correction_m)}};
}

// keep_better_odometry: both trajectories' global consistency, and which one pass 2 used.
Json odometryCheckSummary(const SlamRun& run) {
  if (run.layout_full) return "not made: the log has more points to score than the check keeps";
  if (!run.checked) return "not made (keep_better_odometry = false, or no scan to score)";
  auto mm = [](double m) { return std::isfinite(m) ? jsonNumber("%.2f", m * 1000) : Json(); };
  return {{"scans_scored", run.slam_consistency.scans},
          {"odometry_global_mm", mm(run.odometry_consistency.global_m)},
          {"slam_global_mm", mm(run.slam_consistency.global_m)},
          {"kept", run.kept_odometry ? "odometry" : "slam"}};
}

// Pass 1 of pose source slam: what the front end matched, the loop closures, the optimiser.
Json slamSummary(const SlamRun& run) {
  const SlamStats& s = run.slam->stats();
  Json j = {{"scans", s.scans},
          {"front_end_matched", s.matched},
          {"front_end_fallbacks", s.fallbacks},
          {"scans_matched_to_the_scan_before", s.scan_to_scan},
          {"submaps", s.submaps},
          {"loop_searches", s.loop_attempts},
          {"loop_closures",
           {{"proposed", s.loops_proposed},
            {"accepted", s.loops_accepted},
            {"rejected", s.loops_rejected},
            {"rejected_ambiguous", s.loops_ambiguous}}},
          {"optimiser",
           {{"runs", s.optimisations},
            {"iterations", s.iterations},
            {"final_error", jsonNumber("%.6g", s.final_error)},
            {"converged", s.converged}}},
          {"odometry_check", odometryCheckSummary(run)},
          {"poses", run.kept_odometry ? "odometry (it lays the scans onto each other better)"
                    : s.converged     ? "optimised"
                                      : "front end (the optimiser did not converge)"}};
  if (s.ties_attempted > 0) {  // a session tied to its prior's map
    j["prior_map_ties"] = {{"searches", s.ties_attempted},
                           {"proposed", s.ties_proposed},
                           {"accepted", s.ties_accepted},
                           {"rejected", s.ties_proposed - s.ties_accepted},
                           {"rejected_ambiguous", s.ties_ambiguous}};
  }
  return j;
}

// The only block that differs between identical runs: how long the passes took.
Json timingSummary(const RunCounts& c, const OutputInfo& info) {
  Json t = {
      {"note", "the only part of the outputs that differs between identical runs"},
      {"wall_s", jsonNumber("%.3f", info.wall_s)},
      {"scans_per_s", jsonNumber("%.1f", info.wall_s > 0 ? c.scans_used / info.wall_s : 0.0)}};
  if (info.baseline) {
    t["mrpt_baseline_wall_s"] = jsonNumber("%.3f", info.baseline_wall_s);
    t["mrpt_baseline_scans_per_s"] =
        jsonNumber("%.1f", info.baseline_wall_s > 0 ? c.scans_used / info.baseline_wall_s : 0.0);
  }
  if (info.slam) t["slam_pass1_wall_s"] = jsonNumber("%.3f", info.slam->wall_s);  // wall_s: pass 2
  return t;
}

Json scanSummary(const RunCounts& c, const SourceStats& s) {
  std::size_t skipped = 0;
  for (const auto& kv : c.scans_skipped) skipped += kv.second;
  Json by_reason = Json::object();
  for (const auto& kv : c.scans_skipped) by_reason[kv.first] = kv.second;
  return {{"read", s.scans},
          {"used", c.scans_used},
          {"skipped", skipped},
          {"skipped_by_reason", by_reason},
          {"bad_beams", c.beams_bad},
          {"timestamps_backwards", c.time_backwards},
          {"first_t", jsonNumber("%.6f", c.first_t)},
          {"last_t", jsonNumber("%.6f", c.last_t)}};
}

/// The records (lines, messages) of the input that were not scans: a CARMEN comment line is a
/// line skipped, never a scan skipped.
Json recordsSkipped(const SourceStats& s) {
  std::size_t total = 0;
  Json by_reason = Json::object();
  for (const auto& kv : s.skipped) {
    total += kv.second;
    by_reason[kv.first] = kv.second;
  }
  return {{"unit", s.record_unit}, {"total", total}, {"by_reason", by_reason}};
}

/// The change report's counts by kind, and which session this is (2: the first continued).
Json changeSummary(const std::vector<ChangeRow>& rows, int session) {
  Json by_kind = Json::object();
  for (const char* k :
       {"object_moved", "object_new", "object_gone", "structure_added", "structure_removed"}) {
    by_kind[k] = 0;
  }
  for (const ChangeRow& r : rows) by_kind[r.kind] = by_kind[r.kind].get<int>() + 1;
  return {{"session", session}, {"total", rows.size()}, {"by_kind", by_kind}};
}

Json summary(const Mapper& mapper, const ScanSource& source, const OutputInfo& info) {
  const DynamicGridMap& m = mapper.map();
  const RunCounts& c = mapper.counts();
  const auto cells = m.countCells();
  Json j = {{"input", info.input},
            {"pose_source", mapper.poseSourceName(source)},
            {"complete_input", info.outcome.fault.empty()},
            {"input_fault", info.outcome.fault.empty() ? Json(nullptr) : Json(info.outcome.fault)},
            {"pose_detail", source.poseDetail()},
            {"input_warnings", source.stats().warnings},
            {"records_read", source.stats().records},
            {"records_skipped", recordsSkipped(source.stats())},
            {"scans", scanSummary(c, source.stats())},
            {"map",
             {{"resolution_m", jsonNumber("%.6g", m.getResolution())},
              {"size_cells", {m.getSizeX(), m.getSizeY()}},
              {"x_min", jsonNumber("%.6g", m.getXMin())},
              {"x_max", jsonNumber("%.6g", m.getXMax())},
              {"y_min", jsonNumber("%.6g", m.getYMin())},
              {"y_max", jsonNumber("%.6g", m.getYMax())}}},
            {"cells",
             {{"static_occupied", cells.static_occupied},
              {"static_free", cells.static_free},
              {"dynamic_occupied", cells.dynamic_occupied}}},
            {"objects", objectSummary(mapper.tracker())},
            {"people", peopleSummary(mapper.people())}};
  if (mapper.scanMatching()) j["scan_matching"] = scanMatchSummary(mapper.scanMatchCounts());
  if (info.slam) j["slam"] = slamSummary(*info.slam);
  if (info.baseline) j["mrpt_baseline"] = baselineSummary(info.baseline_cells);
  j["timing"] = timingSummary(c, info);
  return j;
}

}  // namespace

void writeMapOutputs(const std::string& dir, const Mapper& mapper, const ScanSource& source,
                     const OutputInfo& info) {
  const DynamicGridMap& m = mapper.map();
  // The overlay, the costliest picture, is drawn and encoded on a second core meanwhile; all
  // of them only read the mapper. get() below passes on its error, if any.
  std::future<void> overlay = std::async(std::launch::async, [&] {
    const std::vector<PersonTrail> trails = mapper.people().trails();
    saveImageAtomically(renderOverlay(m, mapper.path(), &mapper.tracker().objects(), &trails), dir,
                        "overlay.png");
  });
  saveImageAtomically(renderStatic(m), dir, "static.png");
  saveImageAtomically(renderDynamic(m), dir, "dynamic.png");
  overlay.get();
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
  writeFileAtomically(dir, "session.json",
                      [&](std::ostream& o) { writeSessionState(mapper.sessionState(), o); });
  Json j = summary(mapper, source, info);
  if (const SessionChanges* changes = mapper.changes()) {
    const std::vector<ChangeRow> rows = mapper.changeReport();
    writeFileAtomically(dir, "changes.csv", [&](std::ostream& o) { writeChangesCsv(o, rows); });
    saveImageAtomically(renderChanges(m, *changes, rows), dir, "changes.png");
    j["changes"] = changeSummary(rows, mapper.sessions());
  }
  writeFileAtomically(dir, "summary.json", [&](std::ostream& o) { writeJson(o, j); });
}

}  // namespace dynamap
