#pragma once
// The size and place of an object from what the laser saw of it: from its grid cells, or from
// the hit points themselves. Plain data in, plain data out: testable without a map.

#include <cstddef>
#include <vector>

#include "dynamap/objects/clustering.h"
#include "dynamap/objects/object_options.h"

namespace dynamap {

/// What a cluster of cells says about the object it belongs to.
struct ShapeEstimate {
  double cx = 0, cy = 0;                              ///< [m] centre
  double size = 0;                                    ///< [m] diameter
  double x_min = 0, x_max = 0, y_min = 0, y_max = 0;  ///< [m] the object's box
  bool circle = false;   ///< true: from a circle fit; false: from the cells' width
  double thickness = 0;  ///< [m] std of the cell centres across their main axis (0: a row)
  double length = 0;     ///< [m] widest distance between cell centres
  std::size_t cells = 0;
};

/// A circle through points: algebraic (Kasa) fit refined by a few Gauss-Newton steps on the
/// geometric distance. False when degenerate (fewer than 3 points, collinear points).
struct Circle {
  double cx, cy, r;
};
bool fitCircle(const std::vector<double>& xs, const std::vector<double>& ys, Circle& out);

/// The shape of the object seen as the centres of `cells` (global cells of `resolution` m).
/// A circle fit when there are enough cells and the fit is sane (radius at least half the
/// cells' width minus a cell, at most max_size/2, centre not among the cells); otherwise the
/// widest extent of the cells plus one cell, centred on their box. A cylinder seen from one
/// side shows an arc whose fit gives the whole cylinder; a half-seen object keeps its width.
ShapeEstimate estimateShape(const std::vector<CellXY>& cells, double resolution,
                            const ObjectOptions& options);

/// The shape of an object from the laser's own hit points on it (not the cells they fell in):
/// centimetre-precise where cells are 5 cm. A circle fit when the points show a sane arc (as wide
/// as the points at least, at most max_size, little residual, its centre beyond the points as
/// seen from (sensor_x, sensor_y)); otherwise the widest distance between points plus `gap`
/// (the beams' spacing there: each edge lies somewhere between the last beam that hit and the
/// first that missed), the visible outline of a convex object, centred on their box. False
/// with fewer than min_fit_cells points.
bool estimatePointShape(const std::vector<double>& xs, const std::vector<double>& ys, double gap,
                        double sensor_x, double sensor_y, const ObjectOptions& options,
                        ShapeEstimate& out);

}  // namespace dynamap
