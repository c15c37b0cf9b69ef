#pragma once
// Pictures of the maps, rendered headlessly into MRPT images (north up: row 0 is the grid's
// largest y). static and dynamic pictures have one pixel per cell; the overlay is scaled up by
// an integer factor so that labels stay legible on small maps.

#include <mrpt/img/CImage.h>
#include <mrpt/img/TColor.h>

#include <vector>

#include "dynamap/mapping/dynamic_grid_map.h"
#include "dynamap/objects/object_tracker.h"
#include "dynamap/people/person_tracker.h"
#include "dynamap/pipeline/robot_path.h"
#include "dynamap/pipeline/session_changes.h"

namespace dynamap {

/// An occupancy grid (S, or a plain MRPT grid) in grey levels (white free, black occupied,
/// grey unknown), one pixel per cell, 1 channel.
mrpt::img::CImage renderStatic(const mrpt::maps::COccupancyGridMap2D& map);
/// D alone: white where D holds nothing, shades of red growing with D's P(occ) above 0.5, and
/// S's occupied cells in light grey for context. One pixel per cell.
mrpt::img::CImage renderDynamic(const DynamicGridMap& map);

/// The integer scale that makes a grid of `size_x` cells at least `min_width` pixels wide
/// (capped at 8; 1 for grids already that wide).
int overlayScale(unsigned size_x, unsigned min_width = 800);

/// The window of the grid a picture shows: cells [cx0, cx1) x [cy0, cy1), `scale` px per cell.
struct View {
  int cx0 = 0, cy0 = 0, cx1 = 0, cy1 = 0;
  int scale = 1;
};
/// The cells S has observed (any cell off the prior) with `margin` cells around them, clipped to
/// the grid, at the scale overlayScale gives its width; the whole grid if nothing is observed.
View observedView(const DynamicGridMap& map, int margin = 20);

/// `grid` in grey levels like renderStatic, on `geometry`'s cells (its size, origin and
/// resolution; the prior's grey where `grid` has no cell): pictures of two grids built from the
/// same scans that lie exactly over each other.
mrpt::img::CImage renderStaticOn(const mrpt::maps::COccupancyGridMap2D& grid,
                                 const mrpt::maps::COccupancyGridMap2D& geometry);

/// S in grey levels, D cells above object_threshold in red, the robot's path as a thin blue line,
/// and, given `objects`, each present object's box and circle with a label "<id>: <size> m".
/// Shows the observed part of the grid (observedView), not the unknown margins around it.
/// Given `people`, each person's trail as a line in their id's colour (six in turn, magenta
/// first) with a dot and "P<id>" at its last position (labels kept apart from each other).
mrpt::img::CImage renderOverlay(const DynamicGridMap& map, const std::vector<PathPoint>& path,
                                const std::vector<TrackedObject>* objects = nullptr,
                                const std::vector<PersonTrail>* people = nullptr);

/// changes.png: the prior session's S in grey (this session's S where the prior saw nothing),
/// structure removed in red and added in green, each moved object an arrow from its old place to
/// its new one, each new object a green ring and each gone object a red ring, labelled with its
/// id and size; a scale bar and a legend below. Shows the observed part of the grid.
mrpt::img::CImage renderChanges(const DynamicGridMap& map, const SessionChanges& changes,
                                const std::vector<ChangeRow>& rows);

/// Draws each trail of `people` (see renderOverlay).
void drawPeople(mrpt::img::CImage& img, const DynamicGridMap& map, const View& view,
                const std::vector<PersonTrail>& people);

/// Draws each present object of `objects` on an image of `map` in `view`: its box, its
/// estimated outline, and its label on a filled background, kept inside the image.
void drawObjects(mrpt::img::CImage& img, const DynamicGridMap& map, const View& view,
                 const std::vector<TrackedObject>& objects);

/// Pixel of a world point in an image of `map` drawn in `view` (north up).
struct Pixel {
  int x, y;
};
Pixel toPixel(const DynamicGridMap& map, const View& view, double x, double y);

}  // namespace dynamap
