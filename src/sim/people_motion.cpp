#include "dynamap/sim/scenario.h"
// Where each scripted person is at time t: along their waypoints at their speed, with their pauses,
// and the bodies (two legs, or one disc) the laser sees of them.

#include <algorithm>
#include <cmath>

namespace dynamap::sim {

namespace {

double pauseAt(const PersonSpec& p, std::size_t point) {
  for (const auto& q : p.pauses) {
    if (q.point == point) return q.duration;
  }
  return 0;
}

}  // namespace

PersonPose personPoseAt(const PersonSpec& person, double t) {
  // One cycle: the pause at the start point (also before the first walk: a walker can wait
  // there for the robot to see the floor), the legs to the end, each followed by the pause at
  // the point it arrives at, then the legs back likewise.
  const auto& pts = person.path;
  const std::size_t k = pts.size();
  std::vector<std::size_t> order;  // the points in the order they are walked to
  for (std::size_t i = 1; i < k; ++i) order.push_back(i);
  for (std::size_t i = k - 1; i-- > 0;) order.push_back(i);
  double length = 0, cycle = 0;
  for (std::size_t i = 1; i < k; ++i) length += distance(pts[i - 1], pts[i]);
  cycle = 2 * length / person.speed_mps;
  for (const std::size_t i : order) cycle += pauseAt(person, i);
  const double cycles = std::floor(t / cycle);
  double rest = t - cycles * cycle;
  PersonPose pose;
  pose.walked = cycles * 2 * length;
  pose.centre = pts[0];
  if (rest < pauseAt(person, 0)) {
    pose.standing = true;
    return pose;
  }
  rest -= pauseAt(person, 0);
  std::size_t from = 0;
  for (const std::size_t to : order) {
    const Vec2 a = pts[from], b = pts[to];
    const double leg = distance(a, b), walk = leg / person.speed_mps;
    if (leg > 0) pose.heading = {(b.x - a.x) / leg, (b.y - a.y) / leg};
    if (rest < walk) {
      const double f = rest / walk;
      pose.centre = {a.x + (b.x - a.x) * f, a.y + (b.y - a.y) * f};
      pose.walked += leg * f;
      return pose;
    }
    rest -= walk;
    pose.walked += leg;
    const double stand = to == 0 ? 0.0 : pauseAt(person, to);  // the start's opens the cycle
    if (rest < stand) {
      pose.centre = b;
      pose.standing = true;
      return pose;
    }
    rest -= stand;
    from = to;
  }
  pose.centre = pts[0];  // rounding at the very end of a cycle
  pose.standing = false;
  return pose;
}

Vec2 personPositionAt(const PersonSpec& person, double t) {
  if (person.pauses.empty()) {
    // Without pauses the walk is the plain back-and-forth of the original format, computed as
    // it always was so that the bundled rawlogs stay byte-identical.
    double length = 0;
    for (std::size_t i = 1; i < person.path.size(); ++i) {
      length += distance(person.path[i - 1], person.path[i]);
    }
    double s = std::fmod(person.speed_mps * t, 2 * length);
    if (s > length) s = 2 * length - s;  // on the way back
    for (std::size_t i = 1; i < person.path.size(); ++i) {
      const Vec2 a = person.path[i - 1], b = person.path[i];
      const double leg = distance(a, b);
      if (s <= leg && leg > 0) return {a.x + (b.x - a.x) * s / leg, a.y + (b.y - a.y) * s / leg};
      s -= leg;
    }
    return person.path.back();
  }
  return personPoseAt(person, t).centre;
}

std::vector<Body> personBodies(const PersonSpec& p, double t) {
  const Vec2 c = personPositionAt(p, t);
  if (p.leg_diameter <= 0) return {{c, p.diameter / 2, BodyKind::Person, p.id}};
  const PersonPose pose = personPoseAt(p, t);
  const double r = p.leg_diameter / 2, side = p.diameter / 2 - r;
  const double swing =
      pose.standing || p.stride <= 0 ? 0.0 : p.stride * std::sin(M_PI * pose.walked / p.stride);
  const Vec2 h = pose.heading, n{-h.y, h.x};
  return {
      {{c.x + n.x * side + h.x * swing, c.y + n.y * side + h.y * swing}, r, BodyKind::Person, p.id},
      {{c.x - n.x * side - h.x * swing, c.y - n.y * side - h.y * swing},
       r,
       BodyKind::Person,
       p.id}};
}

std::vector<Body> bodiesAt(const Scenario& sc, double t) {
  std::vector<Body> out;
  for (std::size_t i = 0; i < sc.objects.size(); ++i) {
    out.push_back({objectPositionAt(sc, i, t), sc.objects[i].diameter / 2, BodyKind::Object,
                   sc.objects[i].id});
  }
  for (const auto& p : sc.people) {
    for (const Body& b : personBodies(p, t)) out.push_back(b);
  }
  return out;
}

}  // namespace dynamap::sim
