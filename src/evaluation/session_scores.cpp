#include "dynamap/evaluation/session_scores.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <tuple>

namespace dynamap {
namespace {

constexpr double kFar = std::numeric_limits<double>::infinity();

bool isStructure(const std::string& kind) {
  return kind.rfind("structure_", 0) == 0;
}

double dist(const MaybePoint& a, const MaybePoint& b) {
  return a.known && b.known ? std::hypot(a.x - b.x, a.y - b.y) : kFar;
}

/// Where an object change is judged: the new place of a move or a new object, the old of a gone.
const MaybePoint& anchor(const ScoredRow& c) {
  return c.kind == "object_gone" ? c.from : c.to;
}

double segmentDistance(const MaybePoint& p, const ScoredRow& wall) {
  if (!p.known) return kFar;
  const double dx = wall.to.x - wall.from.x, dy = wall.to.y - wall.from.y;
  const double len2 = dx * dx + dy * dy;
  double u = len2 > 0 ? ((p.x - wall.from.x) * dx + (p.y - wall.from.y) * dy) / len2 : 0;
  u = std::clamp(u, 0.0, 1.0);
  return std::hypot(p.x - (wall.from.x + u * dx), p.y - (wall.from.y + u * dy));
}

/// The id the previous table gave the object at `place`, or -1.
int tableIdAt(const MaybePoint& place, const std::vector<TableRow>& table, double radius) {
  int id = -1;
  double best = radius;
  for (const TableRow& r : table) {
    const double d = dist(place, {true, r.cx, r.cy});
    if (d <= best) best = d, id = r.id;
  }
  return id;
}

struct Pair {
  int tier;  // 0 found, 1 wrong id, 2 misplaced
  double d;
  std::size_t truth, report;
};

/// The verdict of report row `r` for truth change `t`, or none (tier -1).
int tierOf(const ScoredChange& t, const ScoredRow& r, const std::set<int>& table_ids,
           double radius) {
  const ScoredRow& c = t.truth;
  if (r.kind != c.kind) return -1;
  const bool here = dist(anchor(c), anchor(r)) <= radius;
  const bool origin = c.kind != "object_moved" || dist(c.from, r.from) <= radius;
  const bool id_ok =
      c.kind == "object_new" ? !table_ids.count(r.id) : t.expected_id < 0 || r.id == t.expected_id;
  if (here && origin) return id_ok ? 0 : 1;
  const bool same_object = t.expected_id >= 0 && r.id == t.expected_id;
  if (same_object || (c.kind == "object_moved" && (here || origin))) return 2;
  return -1;
}

void matchObjects(SessionScore& score, const std::vector<ScoredRow>& report,
                  const std::set<int>& table_ids, std::vector<bool>& used, double radius) {
  std::vector<Pair> pairs;
  for (std::size_t i = 0; i < score.changes.size(); ++i) {
    if (isStructure(score.changes[i].truth.kind)) continue;
    for (std::size_t j = 0; j < report.size(); ++j) {
      const int tier = tierOf(score.changes[i], report[j], table_ids, radius);
      if (tier >= 0)
        pairs.push_back({tier, dist(anchor(score.changes[i].truth), anchor(report[j])), i, j});
    }
  }
  std::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) {
    return std::tie(a.tier, a.d, a.truth, a.report) < std::tie(b.tier, b.d, b.truth, b.report);
  });
  for (const Pair& p : pairs) {
    ScoredChange& c = score.changes[p.truth];
    if (used[p.report] || c.reported >= 0) continue;
    used[p.report] = true;
    c.reported = static_cast<int>(p.report);
    c.verdict = p.tier == 0 ? ChangeVerdict::Found
                            : (p.tier == 1 ? ChangeVerdict::WrongId : ChangeVerdict::Misplaced);
  }
}

/// A region's centre: where the report puts an added (to) or removed (from) region.
const MaybePoint& regionCentre(const ScoredRow& r) {
  return r.to.known ? r.to : r.from;
}

void matchStructure(SessionScore& score, const std::vector<ScoredRow>& report,
                    std::vector<bool>& used, double radius) {
  for (ScoredChange& c : score.changes) {
    if (!isStructure(c.truth.kind)) continue;
    double best = radius;
    for (std::size_t j = 0; j < report.size(); ++j) {
      const double d = segmentDistance(regionCentre(report[j]), c.truth);
      if (used[j] || report[j].kind != c.truth.kind || d > best) continue;
      best = d;
      c.reported = static_cast<int>(j);
    }
    if (c.reported < 0) continue;
    used[static_cast<std::size_t>(c.reported)] = true;
    c.verdict = ChangeVerdict::Found;
  }
  // Further regions along a found wall are parts of it (a wall cut in two by a doorway's view).
  for (std::size_t j = 0; j < report.size(); ++j) {
    for (const ScoredChange& c : score.changes) {
      if (used[j] || !isStructure(c.truth.kind) || c.verdict != ChangeVerdict::Found ||
          report[j].kind != c.truth.kind) {
        continue;
      }
      if (segmentDistance(regionCentre(report[j]), c.truth) <= radius) used[j] = true;
    }
  }
}

}  // namespace

const char* verdictName(ChangeVerdict v) {
  switch (v) {
    case ChangeVerdict::Found:
      return "found";
    case ChangeVerdict::WrongId:
      return "wrong id";
    case ChangeVerdict::Misplaced:
      return "misplaced";
    case ChangeVerdict::Missed:
      return "missed";
  }
  return "?";
}

int SessionScore::count(ChangeVerdict v) const {
  return static_cast<int>(std::count_if(changes.begin(), changes.end(),
                                        [&](const ScoredChange& c) { return c.verdict == v; }));
}

SessionScore scoreSession(int session, const std::vector<ScoredRow>& truth,
                          const std::vector<ScoredRow>& report,
                          const std::vector<TableRow>& previous_table,
                          const ChangeMatchOptions& options) {
  SessionScore score;
  score.session = session;
  std::set<int> table_ids;
  for (const TableRow& r : previous_table) table_ids.insert(r.id);
  for (const ScoredRow& t : truth) {
    if (t.session != session) continue;
    ScoredChange c;
    c.truth = t;
    if (t.kind == "object_moved" || t.kind == "object_gone") {
      c.expected_id = tableIdAt(t.from, previous_table, options.place_radius);
    }
    score.changes.push_back(c);
  }
  std::vector<bool> used(report.size(), false);
  matchObjects(score, report, table_ids, used, options.place_radius);
  matchStructure(score, report, used, options.place_radius);
  for (std::size_t j = 0; j < report.size(); ++j) {
    if (!used[j]) score.false_changes.push_back(static_cast<int>(j));
  }
  return score;
}

}  // namespace dynamap
