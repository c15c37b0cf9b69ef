#include "dynamap/people/person_tracker.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

#include "dynamap/base/hungarian.h"

namespace dynamap {

// --- the filter --------------------------------------------------------------------------------

ConstantVelocityFilter::ConstantVelocityFilter(double x, double y, double position_std,
                                               double velocity_std) {
  s_ << x, y, 0, 0;
  p_.setZero();
  p_(0, 0) = p_(1, 1) = position_std * position_std;
  p_(2, 2) = p_(3, 3) = velocity_std * velocity_std;
}

void ConstantVelocityFilter::predict(double dt, double accel_std) {
  if (!(dt > 0)) return;
  Eigen::Matrix4d f = Eigen::Matrix4d::Identity();
  f(0, 2) = f(1, 3) = dt;
  // White acceleration, integrated over the step (the discrete Wiener process model).
  const double q = accel_std * accel_std, dt2 = dt * dt;
  Eigen::Matrix4d qm = Eigen::Matrix4d::Zero();
  qm(0, 0) = qm(1, 1) = q * dt2 * dt2 / 4;
  qm(0, 2) = qm(2, 0) = qm(1, 3) = qm(3, 1) = q * dt2 * dt / 2;
  qm(2, 2) = qm(3, 3) = q * dt2;
  s_ = f * s_;
  p_ = f * p_ * f.transpose() + qm;
}

void ConstantVelocityFilter::update(double x, double y, double measurement_std) {
  const Eigen::Vector2d innovation(x - s_(0), y - s_(1));
  Eigen::Matrix2d s = p_.topLeftCorner<2, 2>();
  s(0, 0) += measurement_std * measurement_std;
  s(1, 1) += measurement_std * measurement_std;
  const Eigen::Matrix<double, 4, 2> k = p_.leftCols<2>() * s.inverse();
  s_ += k * innovation;
  p_ -= k * p_.topRows<2>();
  p_ = 0.5 * (p_ + p_.transpose());  // keep it symmetric against rounding
}

void ConstantVelocityFilter::stop(double velocity_std) {
  s_(2) = s_(3) = 0;
  p_.block<2, 2>(2, 0).setZero();
  p_.block<2, 2>(0, 2).setZero();
  p_.block<2, 2>(2, 2) = Eigen::Matrix2d::Identity() * velocity_std * velocity_std;
}

const char* toString(PersonState s) {
  switch (s) {
    case PersonState::Tentative: return "tentative";
    case PersonState::Confirmed: return "confirmed";
    case PersonState::Coasting: return "coasting";
    case PersonState::Lost: return "lost";
    case PersonState::Ended: return "ended";
  }
  return "?";
}

DiscView viewDisc(const ScanHits& h, double x, double y, double r) {
  constexpr double kMargin = 0.05;  // [m] range noise and the body's own depth
  int occupied = 0, crossed = 0;
  const bool cached = h.cosines.size() == h.angles.size() && h.sines.size() == h.angles.size();
  const double dx = x - h.sensor_x, dy = y - h.sensor_y;
  // Evenly spaced beams: only those within the disc's angular span (and one more on each side)
  // can reach it; the rest of the loop's test would skip them.
  std::size_t first = 0, last = h.angles.size();
  const double dist = std::hypot(dx, dy);
  if (h.angles.size() > 1 && dist > r) {
    const double d = std::remainder(h.angles[1] - h.angles[0], 2 * M_PI);
    if (std::abs(d) > 1e-9) {
      const double centre = std::remainder(std::atan2(dy, dx) - h.angles[0], 2 * M_PI) / d;
      const double span = std::asin(r / dist) / std::abs(d) + 1;
      const double n = static_cast<double>(h.angles.size());
      first = static_cast<std::size_t>(std::clamp(std::floor(centre - span), 0.0, n));
      last = static_cast<std::size_t>(std::clamp(std::ceil(centre + span) + 1, 0.0, n));
    }
  }
  for (std::size_t i = first; i < last; ++i) {
    const double c = cached ? h.cosines[i] : std::cos(h.angles[i]);
    const double s = cached ? h.sines[i] : std::sin(h.angles[i]);
    const double along = dx * c + dy * s, perp = std::abs(dx * s - dy * c);
    if (along <= 0 || perp >= r) continue;
    const double half = std::sqrt(r * r - perp * perp);
    const double range = h.ranges[i] < 0 ? h.max_range : h.ranges[i];
    if (range < along - half - kMargin) continue;  // hidden behind something nearer
    if (range <= along + half + kMargin) {
      ++occupied;
    } else {
      ++crossed;
    }
  }
  if (occupied > 0) return DiscView::Occupied;
  return crossed > 0 ? DiscView::Empty : DiscView::Unseen;
}

// --- the tracker -------------------------------------------------------------------------------

namespace {
constexpr double kInitialVelocityStd = 1.0;  // [m/s] a new track could walk any way
constexpr double kStoppedVelocityStd = 0.1;  // [m/s] a person seen standing
// A track that appears this many gates from where someone stood unseen is them walking off: out
// of the laser's view they may have taken a step or two before it saw them.
constexpr double kTakeBackGates = 3;
double speedOf(const ConstantVelocityFilter& f) { return std::hypot(f.vx(), f.vy()); }
}  // namespace

PersonTracker::PersonTracker(const PeopleOptions& options) : options_(options) {}

void PersonTracker::predictAll(double t) {
  const double dt = have_t_ ? t - last_t_ : 0.0;
  for (PersonTrack& tr : tracks_) {
    if (tr.kind() != PersonState::Lost) tr.filter.predict(dt, options_.accel_std);
  }
  have_t_ = true;
  last_t_ = t;
}

std::vector<int> PersonTracker::associate(const std::vector<PersonDetection>& dets) const {
  const double inf = std::numeric_limits<double>::infinity();
  Eigen::MatrixXd cost(static_cast<Eigen::Index>(tracks_.size()),
                       static_cast<Eigen::Index>(dets.size()));
  for (std::size_t i = 0; i < tracks_.size(); ++i) {
    if (tracks_[i].kind() == PersonState::Lost) {  // only a new track can take a lost id back
      cost.row(static_cast<Eigen::Index>(i)).setConstant(inf);
      continue;
    }
    // A person lost for a while may have turned: the gate widens with the time unseen, at
    // walking pace (1 m/s), up to three times its size.
    const double unseen = std::max(0.0, last_t_ - tracks_[i].last_detected_t);
    const double gate =
        tracks_[i].id != 0 ? std::min(3 * options_.gate, options_.gate + unseen) : options_.gate;
    for (std::size_t j = 0; j < dets.size(); ++j) {
      const double d =
          std::hypot(tracks_[i].filter.x() - dets[j].x, tracks_[i].filter.y() - dets[j].y);
      cost(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = d <= gate ? d : inf;
    }
  }
  return solveAssignment(cost, inf);
}

void PersonTracker::advanceTentative(PersonTrack& tr, double t) {
  auto& st = std::get<TentativeState>(tr.state);
  // Legs by their shape, most of the time, over shape_confirm_scans: a person whether or not
  // they move in the map's frame, whose motion odometry drift (or a robot without poses) hides.
  // Even beside an object: an object moving off is one cluster, never a pair of legs.
  if (options_.shape_confirm_scans > 0 && st.shaped >= options_.shape_confirm_scans &&
      2 * st.shaped > st.detections) {
    confirm(tr, t);
    return;
  }
  if (!mapSteady()) return;  // motion in a map that does not hold still says nothing
  if (speedOf(tr.filter) < options_.moving_speed) {  // a pause: the clock starts again
    st.moving_since_t = t;
    st.from_x = tr.filter.x();
    st.from_y = tr.filter.y();
    st.pair_seen = false;
    return;
  }
  const double moving = t - st.moving_since_t;
  const double travel = std::hypot(tr.filter.x() - st.from_x, tr.filter.y() - st.from_y);
  // A person back in view is known sooner (never what appeared near an object: an object
  // moving off must not take a person's id; nor what stands still, whose velocity is noise).
  if (!st.near_static && moving >= options_.reacquire_s && travel >= options_.reacquire_travel &&
      backInView(st, reidentify(tr.filter.x(), tr.filter.y(), t))) {
    confirm(tr, t);
    return;
  }
  // Two legs, most of the time, and the pair itself walking: a person walking off from where
  // they stood, not an object moved (one cluster). (Legs seen one at a time, or two small
  // objects side by side, make a track that stands jump about within the pair's span.)
  const bool legs = st.mostlyLegs() && st.pair_seen &&
                    std::hypot(st.pair_x - st.pair_from_x, st.pair_y - st.pair_from_y) >=
                        options_.confirm_travel;
  const double needed = st.near_static && !legs ? options_.confirm_static_s : options_.confirm_s;
  if (moving < needed || travel < options_.confirm_travel) return;
  confirm(tr, t);
}

bool PersonTracker::backInView(const TentativeState& st, const PersonTrack* lost) const {
  if (lost == nullptr) return false;
  if (st.in_view_before) return true;
  // The view came to it: a cylinder the robot turns to jumps 0.3 m while more of its outline
  // comes into view, and someone lost 4-16 m away could have walked there unseen. Only someone
  // who stood or lingered out of view is expected so near where they were last detected.
  const double unseen = std::max(0.0, st.born_t - lost->last_detected_t);
  return std::hypot(lost->detected_x - st.born_x, lost->detected_y - st.born_y) <=
         options_.gate + options_.reacquire_unseen_speed * unseen;
}

PersonTrack* PersonTracker::reidentify(double x, double y, double t) {
  PersonTrack* best = nullptr;
  double best_d = options_.reid_distance;
  for (PersonTrack& tr : tracks_) {
    // Lost, or coasting unseen: a prediction can run on through a wall while the person turned.
    const auto* lost = std::get_if<LostState>(&tr.state);
    const auto* coast = std::get_if<CoastingState>(&tr.state);
    if (tr.id == 0 || (lost == nullptr && (coast == nullptr || coast->held))) continue;
    if (lost != nullptr && t - lost->since_t > options_.lost_s) continue;
    // Measured from their last detection, not a prediction: people turn where they cannot be
    // seen. Nobody walks faster than max_speed.
    const double d = std::hypot(tr.detected_x - x, tr.detected_y - y);
    if (d > options_.gate + options_.max_speed * (t - tr.last_detected_t)) continue;
    if (d <= best_d && (best == nullptr || d < best_d)) {  // ties: the earlier track
      best = &tr;
      best_d = d;
    }
  }
  return best;
}

bool PersonTracker::takeBack(PersonTrack& tr, const PersonTrack* lost, double t) {
  const auto& tent = std::get<TentativeState>(tr.state);  // only tentative tracks are confirmed
  // Where they walked off from, not how far they came since.
  const double x = tent.born_x, y = tent.born_y;
  const double beaten = lost ? std::hypot(lost->detected_x - x, lost->detected_y - y)
                             : std::numeric_limits<double>::infinity();
  auto place = stood_unseen_.end();
  double best = kTakeBackGates * options_.gate;
  for (auto it = stood_unseen_.begin(); it != stood_unseen_.end(); ++it) {
    const double d = std::hypot(it->x - x, it->y - y);
    if (d <= best && d < beaten) place = it, best = d;
  }
  if (place == stood_unseen_.end()) return false;
  const auto holder = std::find_if(tracks_.begin(), tracks_.end(), [&](const PersonTrack& o) {
    return &o != &tr && o.id == place->id && o.isPerson();
  });
  if (holder == tracks_.end()) return false;  // the id is lost again: re-identification's
  tr.id = place->id;
  stood_unseen_.erase(place);
  tr.first_reported_t = holder->first_reported_t;
  tr.path_length = holder->path_length;
  breakTrail(tr.id);  // no line from the other person
  newId(*holder, t);  // whoever had it is someone else, from now on
  return true;
}

void PersonTracker::breakTrail(int id) {
  auto& pts = trails_[static_cast<std::size_t>(id - 1)].points;
  if (!pts.empty() && trail_points_ < kMaxTrailPoints) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    pts.emplace_back(nan, nan);
    ++trail_points_;
  }
}

void PersonTracker::newId(PersonTrack& tr, double t) {
  tr.id = next_id_++;
  trails_.push_back({tr.id, {}});
  tr.first_reported_t = t;
  tr.path_length = 0;
}

void PersonTracker::confirm(PersonTrack& tr, double t) {
  if (const auto* tent = std::get_if<TentativeState>(&tr.state); tent && tent->near_static) {
    walk_offs_.push_back({tent->born_x, tent->born_y, tent->from_x, tent->from_y, tent->born_t});
  }
  PersonTrack* lost = reidentify(tr.filter.x(), tr.filter.y(), t);
  if (takeBack(tr, lost, t)) {
    // someone who stood out of view, walking off: their id back from whoever had it
  } else if (lost != nullptr) {  // a person back in view: their id, their figures so far
    if (const auto* c = std::get_if<CoastingState>(&lost->state); c && c->unseen_standing) {
      stood_unseen_.push_back(
          {lost->id, lost->detected_x, lost->detected_y, lost->last_detected_t});
    }
    tr.id = lost->id;
    breakTrail(tr.id);  // no line across where they were unseen
    tr.first_reported_t = lost->first_reported_t;
    tr.path_length = lost->path_length;
    lost->id = 0;  // ends without a summary of its own
    lost->state = EndedState{t};
  } else {
    newId(tr, t);
  }
  tr.state = ConfirmedState{};
  tr.last_x = tr.filter.x();
  tr.last_y = tr.filter.y();
}

void PersonTracker::correct(PersonTrack& tr, const PersonDetection& d, double t) {
  // Its id went to a new track earlier in this scan (it was unseen): that track is the person.
  if (tr.kind() == PersonState::Ended) return;
  // One leg alone lies off the person's centre by up to half a stride: trusted less.
  const double std = d.legs == 1 ? 2 * options_.measurement_std : options_.measurement_std;
  tr.filter.update(d.x, d.y, std);
  tr.last_detected_t = t;
  tr.detected_x = tr.filter.x();
  tr.detected_y = tr.filter.y();
  if (auto* tent = std::get_if<TentativeState>(&tr.state)) {
    // Seen leaving a place S held: an object moving off, unless it walks off as legs.
    if (d.static_left) tent->near_static = true;
    ++tent->detections;
    tent->shaped += d.leg_shaped ? 1 : 0;
    if (d.legs == 2) {
      ++tent->leg_pairs;
      if (!tent->pair_seen) tent->pair_from_x = d.x, tent->pair_from_y = d.y;
      tent->pair_seen = true;
      tent->pair_x = d.x;
      tent->pair_y = d.y;
    }
    advanceTentative(tr, t);
  } else {
    tr.state = ConfirmedState{};
  }
}

void PersonTracker::miss(PersonTrack& tr, const ScanHits& hits, double t) {
  if (tr.kind() == PersonState::Ended) return;  // its id was given back to a new track
  if (tr.kind() == PersonState::Tentative) {
    if (t - tr.last_detected_t > options_.tentative_miss_s) endTrack(tr, t);
    return;
  }
  if (const auto* lost = std::get_if<LostState>(&tr.state)) {
    if (t - lost->since_t > options_.lost_s) endTrack(tr, t);
    return;
  }
  if (tr.kind() == PersonState::Confirmed) tr.state = CoastingState{tr.last_detected_t, 0, false, false};
  auto& st = std::get<CoastingState>(tr.state);
  switch (viewDisc(hits, tr.filter.x(), tr.filter.y(), options_.hold_radius)) {
    case DiscView::Occupied:  // still there, no longer in S's free space: standing?
      // Not if they were last seen walking: a beam ending on the prediction is no sign of them
      // (a wall it runs into, someone else; held, such a track walked on through walls). Nor if
      // they stood out of view: only a detection says the one standing there is them.
      if (st.unseen_standing || speedOf(tr.filter) >= options_.moving_speed) {
        coastUnseen(tr, st, t);
        return;
      }
      st = {t, 0, true, false};
      tr.filter.stop(kStoppedVelocityStd);
      return;
    case DiscView::Empty:
      st.held = false;
      if (++st.empty_scans >= options_.empty_scans) loseTrack(tr, t);
      return;
    case DiscView::Unseen:
      coastUnseen(tr, st, t);
      return;
  }
}

void PersonTracker::coastUnseen(PersonTrack& tr, CoastingState& st, double t) {
  // Standing when they went out of view: nobody has seen the place empty since, so they still
  // stand there, unseen, until lost_s (a walking person's prediction is a guess after coast_s).
  if (!st.unseen_standing && speedOf(tr.filter) < options_.moving_speed) {
    st.unseen_standing = true;
    tr.filter.stop(kStoppedVelocityStd);
  }
  st.held = false;
  st.empty_scans = 0;
  if (t - st.since_t > (st.unseen_standing ? options_.lost_s : options_.coast_s)) loseTrack(tr, t);
}

void PersonTracker::endTrack(PersonTrack& tr, double t) {
  const auto* tent = std::get_if<TentativeState>(&tr.state);
  if (tent != nullptr && tent->near_static) static_ends_.push_back({tr.filter.x(), tr.filter.y(), t});
  if (tr.id != 0) ended_.push_back({tr.id, tr.first_reported_t, tr.last_reported_t, tr.path_length});
  tr.state = EndedState{t};
}

void PersonTracker::loseTrack(PersonTrack& tr, double t) {
  if (options_.lost_s > 0) {
    tr.state = LostState{t};
  } else {
    endTrack(tr, t);
  }
}

void PersonTracker::record(PersonTrack& tr, double t) {
  tr.path_length += std::hypot(tr.filter.x() - tr.last_x, tr.filter.y() - tr.last_y);
  tr.last_x = tr.filter.x();
  tr.last_y = tr.filter.y();
  tr.last_reported_t = t;
  auto& pts = trails_[static_cast<std::size_t>(tr.id - 1)].points;
  const bool far = pts.empty() || std::isnan(pts.back().first) || std::hypot(tr.filter.x() - pts.back().first,
                                             tr.filter.y() - pts.back().second) >= kTrailStep;
  if (far && trail_points_ < kMaxTrailPoints) {
    pts.emplace_back(tr.filter.x(), tr.filter.y());
    ++trail_points_;
  }
}

namespace {
bool isReported(const PersonTrack& tr) {
  if (tr.id == 0) return false;
  if (tr.kind() == PersonState::Confirmed) return true;
  const auto* c = std::get_if<CoastingState>(&tr.state);
  return c != nullptr && c->held;
}
}  // namespace

void PersonTracker::update(const std::vector<PersonDetection>& dets, const ScanHits& hits,
                           double t, double free_share) {
  walk_offs_.clear();
  free_share_.add(free_share);
  // A place seen empty is left: whoever stood there walked off unseen.
  stood_unseen_.erase(std::remove_if(stood_unseen_.begin(), stood_unseen_.end(),
                                     [&](const StoodUnseen& p) {
                                       return t - p.t > options_.lost_s ||
                                              viewDisc(hits, p.x, p.y, options_.hold_radius) ==
                                                  DiscView::Empty;
                                     }),
                      stood_unseen_.end());
  predictAll(t);
  const std::vector<int> match = associate(dets);
  std::vector<char> used(dets.size(), 0);
  for (std::size_t i = 0; i < tracks_.size(); ++i) {
    if (match[i] >= 0) {
      used[static_cast<std::size_t>(match[i])] = 1;
      correct(tracks_[i], dets[static_cast<std::size_t>(match[i])], t);
    } else {
      miss(tracks_[i], hits, t);
    }
  }
  tracks_.erase(std::remove_if(tracks_.begin(), tracks_.end(),
                               [](const PersonTrack& tr) { return tr.kind() == PersonState::Ended; }),
                tracks_.end());
  // Where objects' tracks ended long ago no longer matters.
  static_ends_.erase(std::remove_if(static_ends_.begin(), static_ends_.end(),
                                    [&](const StaticEnd& e) {
                                      return t - e.t > options_.confirm_static_s;
                                    }),
                     static_ends_.end());
  for (std::size_t j = 0; j < dets.size(); ++j) {
    if (!used[j] && !legOfPerson(dets[j], t)) startTrack(dets[j], t);
  }
  for (PersonTrack& tr : tracks_) {
    if (isReported(tr)) record(tr, t);
  }
  last_hits_ = hits;  // the vectors keep their capacity: nothing allocated once warm
}

bool PersonTracker::legOfPerson(const PersonDetection& d, double t) const {
  if (d.legs != 1) return false;
  const double reach = options_.leg_pair_distance / 2;
  for (const PersonTrack& tr : tracks_) {
    if (tr.kind() == PersonState::Confirmed && tr.last_detected_t == t &&
        std::hypot(tr.filter.x() - d.x, tr.filter.y() - d.y) < reach)
      return true;
  }
  return false;
}

bool PersonTracker::nearStaticTrack(double x, double y, double t) const {
  const double reach = options_.gate;
  for (const StaticEnd& e : static_ends_) {
    if (std::hypot(e.x - x, e.y - y) <= reach && t - e.t <= options_.confirm_static_s) return true;
  }
  for (const PersonTrack& tr : tracks_) {
    const auto* tent = std::get_if<TentativeState>(&tr.state);
    if (tent != nullptr && tent->near_static &&
        std::hypot(tr.filter.x() - x, tr.filter.y() - y) <= reach)
      return true;
  }
  return false;
}

void PersonTracker::startTrack(const PersonDetection& d, double t) {
  const bool near_static = d.near_static || d.static_left || nearStaticTrack(d.x, d.y, t);
  PersonTrack tr{next_key_++, 0,
                 ConstantVelocityFilter(d.x, d.y, options_.measurement_std, kInitialVelocityStd),
                 TentativeState{t, d.x, d.y, near_static, t, d.x, d.y, 1,
                                d.legs == 2 ? 1 : 0}};
  std::get<TentativeState>(tr.state).in_view_before =
      viewDisc(last_hits_, d.x, d.y, options_.hold_radius) != DiscView::Unseen;
  tr.last_detected_t = t;
  tr.detected_x = d.x;
  tr.detected_y = d.y;
  tracks_.push_back(tr);
}

std::vector<PersonRow> PersonTracker::reported() const {
  std::vector<PersonRow> out;
  for (const PersonTrack& tr : tracks_) {
    if (isReported(tr)) {
      out.push_back({tr.id, tr.filter.x(), tr.filter.y(), tr.filter.vx(), tr.filter.vy()});
    }
  }
  std::sort(out.begin(), out.end(),
            [](const PersonRow& a, const PersonRow& b) { return a.person_id < b.person_id; });
  return out;
}

std::vector<PersonSummary> PersonTracker::summaries() const {
  std::vector<PersonSummary> out = ended_;
  for (const PersonTrack& tr : tracks_) {
    if (tr.id != 0 && tr.kind() != PersonState::Ended) out.push_back({tr.id, tr.first_reported_t, tr.last_reported_t, tr.path_length});
  }
  std::sort(out.begin(), out.end(),
            [](const PersonSummary& a, const PersonSummary& b) { return a.id < b.id; });
  return out;
}

std::vector<PersonTrail> PersonTracker::trails() const { return trails_; }

std::vector<std::pair<double, double>> PersonTracker::standingLegs() const {
  std::vector<std::pair<double, double>> out;
  for (const PersonTrack& tr : tracks_) {
    const auto* tent = std::get_if<TentativeState>(&tr.state);
    if (tent && tr.last_detected_t == last_t_ && tent->mostlyLegs())
      out.emplace_back(tr.filter.x(), tr.filter.y());
  }
  return out;
}

std::vector<std::pair<double, double>> PersonTracker::personPositions() const {
  std::vector<std::pair<double, double>> out;
  for (const PersonTrack& tr : tracks_) {
    if (tr.isPerson()) out.emplace_back(tr.filter.x(), tr.filter.y());
  }
  return out;
}

}  // namespace dynamap
