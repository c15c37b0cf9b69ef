#include "eval_report.h"
// What `dynamap eval` prints and writes: the table on the terminal, report.md, metrics.json,
// and the --summary table of several evaluated results beside the paper's Table 3.

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <set>
#include <sstream>

#include "cli.h"
#include "dynamap/input/scan_source.h"

namespace dynamap::app {

namespace fs = std::filesystem;

namespace {

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
  if (!m.matched) return std::string("not detected (") + describe(m.missed_because) + ")";
  std::string s = m.correct ? "correct" : "";
  if (m.sizeError()) {
    const std::string why = m.wrong_id && m.double_match ? "wrong id, double match"
                            : m.wrong_id                 ? "wrong id"
                                                         : "double match";
    s += (s.empty() ? "" : " + ") + std::string("size error (") + why + ")";
  }
  return s;
}

Json cellJson(const CellScores& c) {
  return {{"static_cells", c.static_cells},
          {"static_kept", c.static_kept},
          {"dynamic_cells", c.dynamic_cells},
          {"dynamic_clear", c.dynamic_clear},
          {"sa", jnum(c.sa, 3)},
          {"da", jnum(c.da, 3)},
          {"aa", jnum(c.aa, 3)},
          {"ha", jnum(c.ha, 3)}};
}

Json movesJson(const ObjectScores& ob) {
  Json moves = Json::array();
  for (const auto& m : ob.moves) {
    moves.push_back(
        {{"move_id", m.move_id},
         {"object_id", m.object_id},
         {"visible", m.visible},
         {"visible_scan", m.visible ? Json(m.visible_scan) : Json(nullptr)},
         {"visible_t", m.visible ? jnum(m.visible_t, 3) : Json(nullptr)},
         {"matched", m.matched},
         {"correct", m.correct},
         {"wrong_id", m.wrong_id},
         {"double_match", m.double_match},
         {"latency_s", m.correct ? jnum(m.latency_s, 3) : Json(nullptr)},
         {"latency_scans", m.correct ? Json(m.latency_scans) : Json(nullptr)},
         {"missed_because", m.notDetected() ? Json(toString(m.missed_because)) : Json(nullptr)}});
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

/// The undetected moves by cause, every cause (kMissCauses' order) with its count, 0 included.
std::vector<std::pair<const MissCauseName*, std::size_t>> missCounts(const ObjectScores& ob) {
  std::vector<std::pair<const MissCauseName*, std::size_t>> n;
  for (const MissCauseName& c : kMissCauses) {
    std::size_t count = 0;
    for (const auto& m : ob.moves) count += m.notDetected() && m.missed_because == c.cause;
    n.emplace_back(&c, count);
  }
  return n;
}

/// A cause's count in metrics.json: missed_<its key>.
std::string missKey(const MissCauseName& c) {
  return std::string("missed_") + c.key;
}

/// missed_<cause> for each cause.
Json missCausesJson(const ObjectScores& ob) {
  Json j = Json::object();
  for (const auto& [cause, count] : missCounts(ob)) j[missKey(*cause)] = count;
  return j;
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

/// A figure of a metrics.json written above, as the table shows it ("n/a" for null): integers
/// as they are, other numbers with the decimals they were written with.
std::string metric(const Json& metrics, const std::string& key, const std::string& file) {
  const auto it = metrics.find(key);
  // Figures eval gained in a later release: a result evaluated before has none ("n/a").
  static const std::set<std::string> kAddedLater = [] {
    std::set<std::string> keys = {"people_detected_as_objects"};
    for (const MissCauseName& c : kMissCauses) keys.insert(missKey(c));
    return keys;
  }();
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
  std::string label;
  std::string key;
  const int* paper;
};

/// The rows: Table 3's first, then each miss cause's under "not detected", then the rest.
std::vector<SummaryRow> summaryRows() {
  std::vector<SummaryRow> rows = {{"moves", "moves_total", kPaperMoves},
                                  {"moves visible", "moves_visible", nullptr},
                                  {"correctly detected", "correctly_detected", kPaperDetected},
                                  {"not detected", "not_detected", kPaperNotDetected}};
  for (const MissCauseName& c : kMissCauses) {
    rows.push_back({std::string("  ") + c.row, missKey(c), nullptr});
  }
  const std::vector<SummaryRow> rest = {
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
  rows.insert(rows.end(), rest.begin(), rest.end());
  return rows;
}

}  // namespace

std::string num(double v, int decimals, const std::string& nan_text) {
  if (std::isnan(v)) return nan_text;
  std::ostringstream s;
  s << std::fixed << std::setprecision(decimals) << v;
  return s.str();
}

/// "    of them: 2 a person track on its place, 1 seen in few scans" (nothing when none missed).
void printMissCauses(std::ostream& o, const ObjectScores& ob) {
  std::string text;
  for (const auto& [cause, count] : missCounts(ob)) {
    if (count == 0) continue;
    text += (text.empty() ? "" : ", ") + std::to_string(count) + " " + cause->text;
  }
  if (!text.empty()) o << "    of them: " << text << "\n";
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
  printMissCauses(o, ob);
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
    << m.id_switches_at_stops << " at a stop); " << m.people << " persons, " << m.track_ids
    << " track ids\n";
  for (const IdSwitch& w : m.switches) {
    o << "    identity switch at scan " << w.scan_index << " (t " << num(w.t, 1, "n/a")
      << " s): person " << w.person << " from track " << w.from_id << " to " << w.to_id
      << (w.at_stop ? ", at a stop" : "") << "\n";
  }
  for (const auto& n : ev.notes) o << "  note: " << n << "\n";
}

Json jnum(double v, int decimals) {
  if (std::isnan(v)) return nullptr;
  const std::string format = "%." + std::to_string(decimals) + "f";
  return jsonNumber(format.c_str(), v);
}

void writeMetricsJson(std::ostream& o, const Evaluation& ev) {
  Json j = {{"scenario", ev.scenario},
            {"truth", ev.truth},
            {"result", ev.result},
            {"tracks_present", ev.have_tracks}};
  j.update(tableFiguresJson(ev));
  j.update(missCausesJson(ev.objects));
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

  for (const auto& row : summaryRows()) {
    o << std::setw(kLabel) << row.label;
    for (int c = 0; c < 4; ++c) {
      // The paper gives its latency only as "1-2 s from the change to the table update".
      const std::string p =
          row.paper ? std::to_string(row.paper[c]) : (row.key == "latency_max_s" ? "2" : "");
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

}  // namespace dynamap::app
