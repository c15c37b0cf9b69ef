#pragma once
// Geometry of a simulated world and exact 2D ray casting against it. Pure functions over plain
// data: no I/O, no randomness, so every result can be checked against hand-computed values.
//
// A ray is o + t·d with |d| = 1 and t >= 0; every range returned is that t, exact to the
// rounding of double arithmetic. "No hit" is +infinity.

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace dynamap::sim {

constexpr double kNoHit = std::numeric_limits<double>::infinity();

struct Vec2 {
  double x = 0;
  double y = 0;
};

/// A straight wall from a to b (zero thickness).
struct Segment {
  Vec2 a;
  Vec2 b;
};

/// Walls given as an image: a cell is a wall when its pixel is dark. Cell (ix, iy) covers
/// [origin.x + ix·res, origin.x + (ix+1)·res) × [origin.y + iy·res, ...); iy = 0 is the bottom
/// row (the image's last row).
struct WallGrid {
  double resolution = 0.05;        ///< metres per cell
  Vec2 origin;                     ///< world x y of the lower-left corner
  int width = 0;                   ///< cells along x
  int height = 0;                  ///< cells along y
  std::vector<std::uint8_t> wall;  ///< width·height flags, index iy·width + ix

  bool isWall(int ix, int iy) const {
    return ix >= 0 && iy >= 0 && ix < width && iy < height && wall[iy * width + ix] != 0;
  }
};

/// Everything that does not move.
struct StaticWorld {
  std::vector<Segment> segments;
  WallGrid grid;  ///< empty (width 0) when the scenario has no map image
};

/// What a circle stands for; the simulator reports hits per body.
enum class BodyKind { Object, Person };

/// A cylinder seen by the laser: a movable object or a walking person.
struct Body {
  Vec2 centre;
  double radius = 0;
  BodyKind kind = BodyKind::Object;
  int id = 0;  ///< the scenario's object or person number
};

/// What a beam met first.
struct RayHit {
  double range = kNoHit;  ///< kNoHit when nothing was met within the max range
  int body = -1;          ///< index into the bodies passed, or -1 for a wall or nothing
  bool hit() const { return range != kNoHit; }
};

/// Distance along the ray to segment s, or kNoHit. A ray along a collinear segment misses.
double raySegment(Vec2 o, Vec2 d, const Segment& s);
/// Distance along the ray to the circle's boundary, or kNoHit. A circle containing o is not
/// seen (a sensor inside a person sees out of it), so the result is kNoHit.
double rayCircle(Vec2 o, Vec2 d, Vec2 centre, double radius);
/// Distance along the ray to the first wall cell it enters within max_range, or kNoHit.
/// Starting inside a wall cell gives 0.
double rayGrid(Vec2 o, Vec2 d, double max_range, const WallGrid& grid);

/// The first surface met by the beam from o at `angle` (rad, world frame) within max_range
/// (a surface at exactly max_range is met).
RayHit castRay(const StaticWorld& world, const std::vector<Body>& bodies, Vec2 o, double angle,
               double max_range);

double distance(Vec2 a, Vec2 b);
/// Shortest distance from p to the segment.
double pointSegmentDistance(Vec2 p, const Segment& s);
/// True when the closed segments share a point.
bool segmentsIntersect(const Segment& s, const Segment& t);
/// True when the disc (open) overlaps the segment.
bool discOverlapsSegment(Vec2 centre, double radius, const Segment& s);
/// True when the disc (open) overlaps a wall cell.
bool discOverlapsGrid(Vec2 centre, double radius, const WallGrid& grid);
/// True when the segment passes through a wall cell.
bool segmentCrossesGrid(const Segment& s, const WallGrid& grid);

}  // namespace dynamap::sim
