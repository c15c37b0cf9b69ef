#include "dynamap/evaluation/evaluation.h"
// The people level of the evaluation: CLEAR MOT against the truth's person rows.

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include "dynamap/base/hungarian.h"

namespace dynamap {

namespace {

struct MotFrame {
  std::vector<const TruthRow*> people;
  std::vector<const PersonTrackRow*> tracks;
};

// The track each person of the frame is matched to (-1: none): last scan's pairs first.
std::vector<int> matchFrame(const MotFrame& f, const std::map<int, int>& last, double gate) {
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<int> match(f.people.size(), -1);
  std::vector<char> taken(f.tracks.size(), 0);
  auto dist = [&](std::size_t i, std::size_t j) {
    return std::hypot(f.people[i]->x - f.tracks[j]->x, f.people[i]->y - f.tracks[j]->y);
  };
  for (std::size_t i = 0; i < f.people.size(); ++i) {
    const auto it = last.find(f.people[i]->id);
    if (it == last.end()) continue;
    for (std::size_t j = 0; j < f.tracks.size(); ++j) {
      if (!taken[j] && f.tracks[j]->person_id == it->second && dist(i, j) <= gate) {
        match[i] = static_cast<int>(j);
        taken[j] = 1;
      }
    }
  }
  Eigen::MatrixXd cost(static_cast<Eigen::Index>(f.people.size()),
                       static_cast<Eigen::Index>(f.tracks.size()));
  for (std::size_t i = 0; i < f.people.size(); ++i) {
    for (std::size_t j = 0; j < f.tracks.size(); ++j) {
      const bool open = match[i] < 0 && !taken[j] && dist(i, j) <= gate;
      cost(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = open ? dist(i, j) : inf;
    }
  }
  const std::vector<int> rest = solveAssignment(cost, inf);
  for (std::size_t i = 0; i < f.people.size(); ++i) {
    if (match[i] < 0) match[i] = rest[i];
  }
  return match;
}

/// When each person of the truth stood still: [first, last] time of each stop (MotOptions).
std::map<int, std::vector<std::pair<double, double>>> personStops(
    const std::vector<TruthRow>& truth, const MotOptions& o) {
  std::map<int, std::vector<const TruthRow*>> rows;
  for (const TruthRow& r : truth) {
    if (r.kind == sim::BodyKind::Person) rows[r.id].push_back(&r);
  }
  std::map<int, std::vector<std::pair<double, double>>> stops;
  for (auto& [id, v] : rows) {
    std::stable_sort(v.begin(), v.end(), [](const TruthRow* a, const TruthRow* b) {
      return a->scan_index < b->scan_index;
    });
    std::size_t first = 0;  // the run of rows within stop_radius_m of v[first]
    for (std::size_t i = 1; i <= v.size(); ++i) {
      if (i < v.size() &&
          std::hypot(v[i]->x - v[first]->x, v[i]->y - v[first]->y) <= o.stop_radius_m) {
        continue;
      }
      if (v[i - 1]->t - v[first]->t >= o.stop_min_s)
        stops[id].emplace_back(v[first]->t, v[i - 1]->t);
      first = i;
    }
  }
  return stops;
}

bool atStop(const std::vector<std::pair<double, double>>& stops, double t, const MotOptions& o) {
  return std::any_of(stops.begin(), stops.end(), [&](const std::pair<double, double>& s) {
    return t >= s.first && t <= s.second + o.after_stop_s;
  });
}

}  // namespace

MotScores evaluateClearMot(const std::vector<TruthRow>& truth,
                           const std::vector<PersonTrackRow>& tracks, const MotOptions& o) {
  std::map<std::size_t, MotFrame> frames;
  for (const TruthRow& r : truth) {
    if (r.kind == sim::BodyKind::Person) frames[r.scan_index].people.push_back(&r);
  }
  for (const PersonTrackRow& r : tracks) {
    auto it = frames.find(r.scan_index);
    if (it != frames.end()) it->second.tracks.push_back(&r);
  }
  MotScores s;
  const auto stops = personStops(truth, o);
  std::map<int, int> last;  // person -> the track it was last matched to
  std::set<int> people, ids;
  double sum = 0;
  for (const auto& [scan, f] : frames) {
    const std::vector<int> match = matchFrame(f, last, o.gate_m);
    std::vector<char> used(f.tracks.size(), 0);
    for (std::size_t i = 0; i < f.people.size(); ++i) {
      const TruthRow& p = *f.people[i];
      if (match[i] >= 0) used[static_cast<std::size_t>(match[i])] = 1;
      if (p.hits < o.min_visible_hits) continue;  // not counted either way
      ++s.ground_truth;
      people.insert(p.id);
      if (match[i] < 0) {
        ++s.misses;
        continue;
      }
      const PersonTrackRow& t = *f.tracks[static_cast<std::size_t>(match[i])];
      ++s.matches;
      sum += std::hypot(p.x - t.x, p.y - t.y);
      const auto it = last.find(p.id);
      if (it != last.end() && it->second != t.person_id) {
        ++s.id_switches;
        const auto st = stops.find(p.id);
        const bool at_stop = st != stops.end() && atStop(st->second, p.t, o);
        s.id_switches_at_stops += at_stop;
        s.switches.push_back({scan, p.t, p.id, it->second, t.person_id, at_stop});
      }
      last[p.id] = t.person_id;
    }
    for (std::size_t j = 0; j < f.tracks.size(); ++j) {
      ids.insert(f.tracks[j]->person_id);
      if (!used[j]) ++s.false_positives;
    }
  }
  s.people = people.size();
  s.track_ids = ids.size();
  s.motp_m = s.matches ? sum / static_cast<double>(s.matches) : std::nan("");
  s.mota = s.ground_truth
               ? 1.0 - static_cast<double>(s.misses + s.false_positives + s.id_switches) /
                           static_cast<double>(s.ground_truth)
               : std::nan("");
  return s;
}

}  // namespace dynamap
