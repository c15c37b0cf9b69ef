#include "dynamap/evaluation/evaluation.h"
// Why a move was not detected: what the result shows at the object's new place in its window.

#include <map>

namespace dynamap {
namespace {

/// What the result shows around one missed move, scan by scan over its window.
struct PlaceCounts {
  std::size_t views = 0;          ///< scans with min_visible_hits beams on the object
  std::size_t person_on = 0;      ///< scans with a person track on its place
  std::size_t people_near = 0;    ///< scans with a person track within kNearRadius
  std::size_t reported_near = 0;  ///< object rows within kNearRadius
};

template <typename Row>
std::map<std::size_t, std::vector<const Row*>> byScan(const std::vector<Row>& rows) {
  std::map<std::size_t, std::vector<const Row*>> out;
  for (const Row& r : rows) out[r.scan_index].push_back(&r);
  return out;
}

MissCause causeOf(const PlaceCounts& c, const EvalOptions& options) {
  if (c.person_on >= kPeopleScans) return MissCause::PersonOnPlace;
  if (c.people_near >= kPeopleScans) return MissCause::PeopleNear;
  if (c.reported_near > 0) return MissCause::ReportedOffPlace;
  if (c.views < options.few_views_scans) return MissCause::FewViews;
  return MissCause::Unreported;
}

}  // namespace

const MissCauseName kMissCauses[5] = {
    {MissCause::PersonOnPlace, "person_on_place", "a person track on its place"},
    {MissCause::PeopleNear, "people_near", "people within 1 m"},
    {MissCause::ReportedOffPlace, "reported_off_place", "an object reported near, off its place"},
    {MissCause::FewViews, "few_views", "seen in few scans"},
    {MissCause::Unreported, "unreported", "nothing reported near"},
};

const char* toString(MissCause c) {
  for (const MissCauseName& n : kMissCauses) {
    if (n.cause == c) return n.key;
  }
  return nullptr;
}

const char* describe(MissCause c) {
  for (const MissCauseName& n : kMissCauses) {
    if (n.cause == c) return n.text;
  }
  return "";
}

void explainMisses(ObjectScores& scores, const std::vector<TruthRow>& rows,
                   const std::vector<TruthMove>& moves, const std::vector<TrackRow>& tracks,
                   const std::vector<PersonTrackRow>& people, const EvalOptions& options) {
  const auto truth = byScan(rows);
  const auto objects = byScan(tracks);
  const auto persons = byScan(people);
  std::map<int, const TruthMove*> move_of;
  for (const TruthMove& m : moves) move_of[m.move_id] = &m;
  for (MoveResult& r : scores.moves) {
    const auto m = move_of.find(r.move_id);
    if (!r.notDetected() || m == move_of.end()) continue;
    const sim::Vec2 to = m->second->to;
    const auto near = [&](double x, double y, double within) {
      return sim::distance({x, y}, to) <= within;
    };
    PlaceCounts c;
    for (auto it = truth.find(r.visible_scan); it != truth.end(); ++it) {
      if (it->second.empty() || !inDetectWindow(r, it->first, it->second[0]->t, options)) break;
      const TruthRow* b = nullptr;
      for (const TruthRow* row : it->second) {
        if (row->kind == sim::BodyKind::Object && row->id == r.object_id) b = row;
      }
      if (b == nullptr || sim::distance({b->x, b->y}, to) > options.place_tolerance_m) continue;
      c.views += b->hits >= options.min_visible_hits;
      const auto ps = persons.find(it->first);
      if (ps != persons.end()) {
        bool on = false, close = false;
        for (const PersonTrackRow* p : ps->second) {
          on = on || near(p->x, p->y, b->diameter / 2 + kOnPlaceMargin);
          close = close || near(p->x, p->y, kNearRadius);
        }
        c.person_on += on, c.people_near += close;
      }
      const auto os = objects.find(it->first);
      if (os == objects.end()) continue;
      for (const TrackRow* o : os->second) c.reported_near += near(o->cx, o->cy, kNearRadius);
    }
    r.missed_because = causeOf(c, options);
  }
}

}  // namespace dynamap
