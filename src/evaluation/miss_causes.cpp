#include "dynamap/evaluation/evaluation.h"
// Why a move was not detected: what the result shows at the object's new place in its window.

#include <map>

#include "by_scan.h"

namespace dynamap {
namespace {

/// What the result shows around one missed move, scan by scan over its window.
struct PlaceCounts {
  std::size_t views = 0;          ///< scans with min_visible_hits beams on the object
  std::size_t person_on = 0;      ///< scans with a person track on its place
  std::size_t people_near = 0;    ///< scans with a person track within kNearRadius
  std::size_t reported_near = 0;  ///< object rows within kNearRadius
};

/// People rows by scan.
std::map<std::size_t, std::vector<const PersonTrackRow*>> peopleByScan(
    const std::vector<PersonTrackRow>& people) {
  std::map<std::size_t, std::vector<const PersonTrackRow*>> out;
  for (const PersonTrackRow& p : people) out[p.scan_index].push_back(&p);
  return out;
}

/// One scan of a missed move's window, the object's row `b` there (its new place `to`): a view,
/// the people on and near its place, the objects reported near it.
void countScan(const TruthRow& b, sim::Vec2 to, const std::vector<const PersonTrackRow*>& people,
               const std::vector<const TrackRow*>& objects, const EvalOptions& options,
               PlaceCounts& c) {
  const auto near = [&](double x, double y, double within) {
    return sim::distance({x, y}, to) <= within;
  };
  c.views += b.hits >= options.min_visible_hits;
  bool on = false, close = false;
  for (const PersonTrackRow* p : people) {
    on = on || near(p->x, p->y, b.diameter / 2 + kOnPlaceMargin);
    close = close || near(p->x, p->y, kNearRadius);
  }
  c.person_on += on, c.people_near += close;
  for (const TrackRow* o : objects) c.reported_near += near(o->cx, o->cy, kNearRadius);
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
    {MissCause::PersonOnPlace, "person_on_place", "a person track on its place",
     "a person on its place"},
    {MissCause::PeopleNear, "people_near", "people within 1 m", "people within 1 m"},
    {MissCause::ReportedOffPlace, "reported_off_place", "an object reported near, off its place",
     "reported off its place"},
    {MissCause::FewViews, "few_views", "seen in few scans", "seen in few scans"},
    {MissCause::Unreported, "unreported", "nothing reported near", "nothing reported near"},
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
  const ByScan g = groupByScan(rows, tracks);
  const auto persons = peopleByScan(people);
  std::map<int, const TruthMove*> move_of;
  for (const TruthMove& m : moves) move_of[m.move_id] = &m;
  for (MoveResult& r : scores.moves) {
    const auto m = move_of.find(r.move_id);
    if (!r.notDetected() || m == move_of.end()) continue;
    PlaceCounts c;
    forEachWindowScan(
        g, *m->second, r, options,
        [&](std::size_t scan, double, const TruthRow& b, const std::vector<const TruthRow*>&) {
          countScan(b, m->second->to, rowsAt(persons, scan), rowsAt(g.tracks, scan), options, c);
        });
    r.missed_because = causeOf(c, options);
  }
}

}  // namespace dynamap
