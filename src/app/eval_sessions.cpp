// dynamap eval --sessions: the change reports of a run of sessions scored against the
// simulator's truth of the changes (session_scores.h). Session k's report is DIR_k/changes.csv,
// the table its ids are judged by DIR_{k-1}/objects.csv.

#include <filesystem>
#include <iostream>

#include "commands.h"
#include "dynamap/base/ini.h"
#include "dynamap/evaluation/result_files.h"
#include "dynamap/outputs/map_outputs.h"
#include "eval_report.h"

namespace dynamap::app {
namespace {

namespace fs = std::filesystem;

std::string place(const MaybePoint& p) {
  return p.known ? "(" + num(p.x, 2) + " " + num(p.y, 2) + ")" : "-";
}

std::string describe(const ScoredRow& c) {
  std::string s = c.kind + " " + std::to_string(c.id) + " " + num(c.size, 2) + " m";
  if (c.from.known) s += " from " + place(c.from);
  if (c.to.known) s += " to " + place(c.to);
  return s;
}

Json scoreJson(const SessionScore& score, const std::vector<ScoredRow>& report) {
  Json j;
  j["session"] = score.session;
  j["changes"] = score.changes.size();
  for (auto v : {ChangeVerdict::Found, ChangeVerdict::WrongId, ChangeVerdict::Misplaced,
                 ChangeVerdict::Missed}) {
    j[verdictName(v)] = score.count(v);
  }
  j["false"] = score.false_changes.size();
  Json rows = Json::array();
  for (const ScoredChange& c : score.changes) {
    Json r;
    r["truth"] = describe(c.truth);
    r["verdict"] = verdictName(c.verdict);
    r["expected_id"] = c.expected_id;
    r["reported"] = c.reported < 0 ? "" : describe(report[static_cast<std::size_t>(c.reported)]);
    rows.push_back(r);
  }
  j["scored"] = rows;
  Json wrong = Json::array();
  for (int k : score.false_changes) wrong.push_back(describe(report[static_cast<std::size_t>(k)]));
  j["false_changes"] = wrong;
  return j;
}

void printScore(std::ostream& o, const SessionScore& s, const std::vector<ScoredRow>& report) {
  o << "session " << s.session << ": " << s.changes.size() << " changes, "
    << s.count(ChangeVerdict::Found) << " found, " << s.count(ChangeVerdict::WrongId)
    << " under a wrong id, " << s.count(ChangeVerdict::Misplaced) << " misplaced, "
    << s.count(ChangeVerdict::Missed) << " missed; " << s.false_changes.size()
    << " false changes\n";
  for (const ScoredChange& c : s.changes) {
    if (c.verdict == ChangeVerdict::Found) continue;
    o << "  " << verdictName(c.verdict) << ": " << describe(c.truth);
    if (c.expected_id >= 0) o << " (id " << c.expected_id << " expected)";
    if (c.reported >= 0)
      o << "; reported " << describe(report[static_cast<std::size_t>(c.reported)]);
    o << "\n";
  }
  for (int k : s.false_changes) {
    o << "  false: " << describe(report[static_cast<std::size_t>(k)]) << "\n";
  }
}

}  // namespace

int scoreSessions(const std::vector<std::string>& dirs, const std::string& truth_prefix,
                  std::ostream& o) {
  if (dirs.size() < 2)
    throw UsageError("--sessions takes the result of every session, in order (two at least)");
  const std::vector<ScoredRow> truth = readChangeTruth(truthPrefix(truth_prefix) + ".changes.csv");
  for (std::size_t k = 1; k < dirs.size(); ++k) {
    const int session = static_cast<int>(k) + 1;
    const auto report = readChangeReport((fs::path(dirs[k]) / "changes.csv").string());
    const auto table = readTable((fs::path(dirs[k - 1]) / "objects.csv").string());
    const SessionScore score = scoreSession(session, truth, report, table);
    printScore(o, score, report);
    writeFileAtomically(dirs[k], "changes_score.json",
                        [&](std::ostream& out) { writeJson(out, scoreJson(score, report)); });
  }
  return kExitOk;
}

}  // namespace dynamap::app
