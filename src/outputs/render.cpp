#include "dynamap/outputs/render.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>

namespace dynamap {
namespace {

using mrpt::img::CImage;

// BGR, as MRPT's OpenCV-backed images store them.
struct Bgr {
  std::uint8_t b, g, r;
};

inline std::uint8_t grey(const mrpt::maps::COccupancyGridMap2D& map, std::size_t i) {
  return DynamicGridMap::cellGrey(map.getRawMap()[i]);
}

// Fills an image of the cells in `view`, colour from a cell's linear index.
template <typename ColourOf>
CImage paintCells(const DynamicGridMap& map, const View& view, ColourOf colour) {
  const std::size_t sx = map.getSizeX();
  const int scale = view.scale, w = view.cx1 - view.cx0, h = view.cy1 - view.cy0;
  CImage img(w * scale, h * scale, mrpt::img::CH_RGB);
  std::vector<Bgr> cells(static_cast<std::size_t>(std::max(w, 0)));
  for (int cy = view.cy0; cy < view.cy1; ++cy) {
    for (int cx = view.cx0; cx < view.cx1; ++cx)
      cells[cx - view.cx0] = colour(cx + static_cast<std::size_t>(cy) * sx);
    // Each image row through one pointer: MRPT checks the image on every ptrLine call.
    const int row0 = (view.cy1 - 1 - cy) * scale;
    for (int dy = 0; dy < scale; ++dy) {
      std::uint8_t* p = img.ptrLine<std::uint8_t>(static_cast<unsigned>(row0 + dy));
      for (const Bgr& c : cells) {
        for (int dx = 0; dx < scale; ++dx, p += 3) {
          p[0] = c.b;
          p[1] = c.g;
          p[2] = c.r;
        }
      }
    }
  }
  return img;
}

View wholeGrid(const DynamicGridMap& map) {
  return {0, 0, static_cast<int>(map.getSizeX()), static_cast<int>(map.getSizeY()), 1};
}

}  // namespace

CImage renderStatic(const mrpt::maps::COccupancyGridMap2D& map) {
  const unsigned sx = map.getSizeX(), sy = map.getSizeY();
  CImage img(sx, sy, mrpt::img::CH_GRAY);
  for (unsigned cy = 0; cy < sy; ++cy) {
    auto* row = img.ptrLine<std::uint8_t>(sy - 1 - cy);
    for (unsigned cx = 0; cx < sx; ++cx)
      row[cx] = grey(map, cx + static_cast<std::size_t>(cy) * sx);
  }
  return img;
}

CImage renderStaticOn(const mrpt::maps::COccupancyGridMap2D& grid,
                      const mrpt::maps::COccupancyGridMap2D& geometry) {
  const unsigned sx = geometry.getSizeX(), sy = geometry.getSizeY();
  const int gx = static_cast<int>(grid.getSizeX()), gy = static_cast<int>(grid.getSizeY());
  CImage img(sx, sy, mrpt::img::CH_GRAY);
  for (unsigned cy = 0; cy < sy; ++cy) {
    auto* row = img.ptrLine<std::uint8_t>(sy - 1 - cy);
    const int ty = grid.y2idx(geometry.idx2y(cy));
    for (unsigned cx = 0; cx < sx; ++cx) {
      const int tx = grid.x2idx(geometry.idx2x(cx));
      // Outside `grid`: never observed there, the prior's grey.
      row[cx] = tx < 0 || ty < 0 || tx >= gx || ty >= gy
                    ? DynamicGridMap::l2p_255(0)
                    : grey(grid, static_cast<std::size_t>(tx) +
                                     static_cast<std::size_t>(ty) * grid.getSizeX());
    }
  }
  return img;
}

CImage renderDynamic(const DynamicGridMap& map) {
  const auto& d = map.dynamicRaw();
  return paintCells(map, wholeGrid(map), [&](std::size_t i) {
    const float p = 1.0f - DynamicGridMap::cellProbability(d[i]);
    if (p > 0.5f) {
      // White at 0.5 to deep red at 1.
      const float f = std::min(1.0f, (p - 0.5f) * 2.0f);
      const auto fade = static_cast<std::uint8_t>(255.0f * (1.0f - f));
      return Bgr{fade, fade, static_cast<std::uint8_t>(255 - 75.0f * f)};
    }
    if (map.getRawMap()[i] < 0) return Bgr{200, 200, 200};  // S occupied, for context
    return Bgr{255, 255, 255};
  });
}

int overlayScale(unsigned size_x, unsigned min_width) {
  if (size_x == 0) return 1;
  const unsigned s = (min_width + size_x - 1) / size_x;
  return static_cast<int>(std::clamp(s, 1u, 8u));
}

View observedView(const DynamicGridMap& map, int margin) {
  const auto& cells = map.getRawMap();
  const int sx = static_cast<int>(map.getSizeX()), sy = static_cast<int>(map.getSizeY());
  int x0 = sx, y0 = sy, x1 = -1, y1 = -1;
  for (int cy = 0; cy < sy; ++cy) {
    const auto* row = &cells[static_cast<std::size_t>(cy) * sx];
    for (int cx = 0; cx < sx; ++cx) {
      if (row[cx] == 0) continue;
      x0 = std::min(x0, cx);
      x1 = std::max(x1, cx);
      y0 = std::min(y0, cy);
      y1 = std::max(y1, cy);
    }
  }
  View v = wholeGrid(map);
  if (x1 >= 0) {
    v = {std::max(0, x0 - margin), std::max(0, y0 - margin), std::min(sx, x1 + 1 + margin),
         std::min(sy, y1 + 1 + margin), 1};
  }
  v.scale = overlayScale(static_cast<unsigned>(v.cx1 - v.cx0));
  return v;
}

Pixel toPixel(const DynamicGridMap& map, const View& view, double x, double y) {
  const double fx = (x - map.getXMin()) / map.getResolution() - view.cx0;
  const double fy = (y - map.getYMin()) / map.getResolution();
  return {static_cast<int>(std::floor(fx * view.scale)),
          static_cast<int>(std::floor((view.cy1 - fy) * view.scale))};
}

namespace {

// A box or a label on a picture, in pixels (inclusive).
struct Rect {
  int x0, y0, x1, y1;
  bool overlaps(const Rect& o) const {
    return x0 <= o.x1 && o.x0 <= x1 && y0 <= o.y1 && o.y0 <= y1;
  }
};

// What is drawn on a picture that no label may cover: object boxes and the labels placed so far.
struct LabelBoard {
  std::vector<Rect> taken;
  // A place for a label of lw x lh pixels beside `anchor` (a box or a dot) inside a w x h
  // picture that covers nothing taken: above, below, right, left, then the same further out.
  // False when there is none: the label is left out rather than drawn over another.
  bool place(const Rect& anchor, int lw, int lh, int w, int h, Rect& out) const {
    constexpr int kRings = 6;
    for (int ring = 0; ring < kRings; ++ring) {
      const int gy = ring * (lh + 2), gx = ring * (lw / 2 + 2);
      const int cx = (anchor.x0 + anchor.x1) / 2 - lw / 2;
      const int cy = (anchor.y0 + anchor.y1) / 2 - lh / 2;
      for (const auto& [x, y] : {std::pair<int, int>{anchor.x0, anchor.y0 - lh - 2 - gy},
                                 {anchor.x0, anchor.y1 + 2 + gy},
                                 {anchor.x1 + 3 + gx, cy},
                                 {anchor.x0 - lw - 3 - gx, cy},
                                 {cx, anchor.y0 - lh - 2 - gy},
                                 {cx, anchor.y1 + 2 + gy}}) {
        const Rect r{x, y, x + lw, y + lh};
        if (r.x0 < 0 || r.y0 < 0 || r.x1 >= w || r.y1 >= h) continue;
        bool clear = true;
        for (const Rect& t : taken) clear = clear && !r.overlaps(t);
        if (clear) {
          out = r;
          return true;
        }
      }
    }
    return false;
  }
};

void selectFont(CImage& img, int& char_w, int& char_h) {
  // Big pictures get the bigger font; 6x13 keeps labels readable on small maps.
  const bool big = img.getWidth() >= 1000;
  img.selectTextFont(big ? "9x15B" : "6x13B");
  char_w = big ? 9 : 6;
  char_h = big ? 15 : 13;
}

// The last point of a trail that is not a break, or nullptr.
const std::pair<double, double>* trailEnd(const PersonTrail& p) {
  for (auto it = p.points.rbegin(); it != p.points.rend(); ++it) {
    if (!std::isnan(it->first)) return &*it;
  }
  return nullptr;
}

// A colour per person, so that crossing trails can be told apart: none near the red of D, the
// green of object boxes, the blue of the robot or the yellow of object labels, each dark enough
// for a white label. Person k takes colour (k - 1) mod 6; magenta first.
const mrpt::img::TColor kTrails[] = {{200, 0, 200}, {220, 100, 0},  {0, 130, 150},
                                     {140, 70, 20}, {100, 30, 170}, {230, 50, 130}};
const mrpt::img::TColor& trailColour(int id) {
  constexpr int n = static_cast<int>(sizeof(kTrails) / sizeof(kTrails[0]));
  return kTrails[((id - 1) % n + n) % n];
}

void drawTrailLines(CImage& img, const DynamicGridMap& map, const View& view,
                    const std::vector<PersonTrail>& people) {
  for (const PersonTrail& p : people) {
    for (std::size_t k = 1; k < p.points.size(); ++k) {
      // A NaN point breaks the trail: the person was out of sight in between.
      if (std::isnan(p.points[k - 1].first) || std::isnan(p.points[k].first)) continue;
      const Pixel a = toPixel(map, view, p.points[k - 1].first, p.points[k - 1].second);
      const Pixel b = toPixel(map, view, p.points[k].first, p.points[k].second);
      img.line(a.x, a.y, b.x, b.y, trailColour(p.id), 1);
    }
  }
}

void drawTrailLabels(CImage& img, const DynamicGridMap& map, const View& view,
                     const std::vector<PersonTrail>& people, LabelBoard& board) {
  const mrpt::img::TColor text(255, 255, 255);
  int char_w = 0, char_h = 0;
  selectFont(img, char_w, char_h);
  const int w = static_cast<int>(img.getWidth()), h = static_cast<int>(img.getHeight());
  for (const PersonTrail& p : people) {  // one label per person, at the trail's end
    const auto* last = trailEnd(p);
    if (last == nullptr) continue;
    const Pixel end = toPixel(map, view, last->first, last->second);
    const mrpt::img::TColor& trail = trailColour(p.id);
    img.filledRectangle(end.x - 2, end.y - 2, end.x + 2, end.y + 2, trail);
    const std::string label = "P" + std::to_string(p.id);
    const int lw = static_cast<int>(label.size()) * char_w + 4, lh = char_h + 2;
    Rect at{};
    if (!board.place({end.x - 2, end.y - 2, end.x + 2, end.y + 2}, lw, lh, w, h, at)) continue;
    board.taken.push_back(at);
    img.filledRectangle(at.x0, at.y0, at.x1, at.y1, trail);
    img.textOut(at.x0 + 2, at.y0 + 1, label, text);
  }
}

void drawObjectBoxes(CImage& img, const DynamicGridMap& map, const View& view,
                     const std::vector<TrackedObject>& objects, LabelBoard& board) {
  const mrpt::img::TColor box(0, 150, 0), text(0, 0, 0), label_bg(255, 240, 120);
  int char_w = 0, char_h = 0;
  selectFont(img, char_w, char_h);
  const int w = static_cast<int>(img.getWidth()), h = static_cast<int>(img.getHeight());
  std::vector<std::pair<Rect, const TrackedObject*>> shown;
  for (const TrackedObject& o : objects) {  // boxes first: no label may cover one
    if (o.state != ObjectState::Present) continue;
    const Pixel p0 = toPixel(map, view, o.shape.x_min, o.shape.y_max);
    const Pixel p1 = toPixel(map, view, o.shape.x_max, o.shape.y_min);
    // At least a few pixels around the object, so that small ones stay visible.
    const int pad = std::max(2, view.scale / 2);
    const Rect b{p0.x - pad, p0.y - pad, p1.x + pad, p1.y + pad};
    img.rectangle(b.x0, b.y0, b.x1, b.y1, box, 2);
    board.taken.push_back(b);
    shown.emplace_back(b, &o);
  }
  for (const auto& [b, o] : shown) {
    char buf[48];
    std::snprintf(buf, sizeof buf, "%d: %.2f m", o->id, o->shape.size);
    const std::string label = buf;
    const int lw = static_cast<int>(label.size()) * char_w + 4, lh = char_h + 2;
    Rect at{};
    if (!board.place(b, lw, lh, w, h, at)) continue;
    board.taken.push_back(at);
    // A label away from its box points at it.
    if (!(at.y1 + 3 >= b.y0 && at.y0 <= b.y1 + 3 && at.x1 + 4 >= b.x0 && at.x0 <= b.x1 + 4)) {
      img.line((at.x0 + at.x1) / 2, (at.y0 + at.y1) / 2, (b.x0 + b.x1) / 2, (b.y0 + b.y1) / 2, box,
               1);
    }
    img.filledRectangle(at.x0, at.y0, at.x1, at.y1, label_bg);
    img.rectangle(at.x0, at.y0, at.x1, at.y1, box, 1);
    img.textOut(at.x0 + 2, at.y0 + 1, label, text);
  }
}

// 1, 2 or 5 times a power of ten metres, the longest such that fits in `max_px` pixels.
double scaleBarMetres(double metres_per_px, int max_px) {
  double best = 0;
  for (double decade = 0.01; decade <= 1e5; decade *= 10) {
    for (const double f : {1.0, 2.0, 5.0}) {
      if (f * decade / metres_per_px <= max_px) best = f * decade;
    }
  }
  return best;
}

// One entry of a legend: its words and the sample drawn before them at (x0, y).
struct LegendItem {
  std::string what;
  std::function<void(CImage& img, int x0, int y, int char_h)> draw;
};

// The picture with a strip below it: a scale bar and what each colour means.
CImage withLegend(const CImage& map_img, double metres_per_px,
                  const std::vector<LegendItem>& items) {
  int char_w = 0, char_h = 0;
  CImage probe(map_img.getWidth(), 1, mrpt::img::CH_RGB);
  selectFont(probe, char_w, char_h);
  const int w = static_cast<int>(map_img.getWidth()), strip = 2 * char_h + 14;
  const int h = static_cast<int>(map_img.getHeight());
  CImage img(w, h + strip + (h + strip) % 2, mrpt::img::CH_RGB);  // even: video frames
  img.filledRectangle(0, 0, w - 1, static_cast<int>(img.getHeight()) - 1,
                      mrpt::img::TColor(255, 255, 255));
  img.drawImage(0, 0, map_img);
  selectFont(img, char_w, char_h);
  const mrpt::img::TColor black(0, 0, 0);
  const int y0 = h + 4, y1 = y0 + char_h + 6;
  // Scale bar: at most a third of the width.
  const double metres = scaleBarMetres(metres_per_px, std::max(10, w / 3));
  const int bar = static_cast<int>(std::lround(metres / metres_per_px));
  img.filledRectangle(6, y0 + char_h / 2, 6 + bar, y0 + char_h / 2 + 3, black);
  img.line(6, y0, 6, y0 + char_h, black, 1);
  img.line(6 + bar, y0, 6 + bar, y0 + char_h, black, 1);
  char buf[32];
  std::snprintf(buf, sizeof buf, metres >= 1 ? "%.0f m" : "%.2f m", metres);
  img.textOut(12 + bar, y0, buf, black);
  // Legend, on the second line.
  int x = 6;
  for (const LegendItem& item : items) {
    item.draw(img, x, y1, char_h);
    img.textOut(x + 22, y1, item.what, black);
    x += 22 + static_cast<int>(item.what.size()) * char_w + 14;
  }
  return img;
}

LegendItem lineItem(const std::string& what, mrpt::img::TColor colour) {
  return {what, [colour](CImage& img, int x0, int y, int char_h) {
            img.line(x0, y + char_h / 2, x0 + 16, y + char_h / 2, colour, 2);
          }};
}

LegendItem patchItem(const std::string& what, mrpt::img::TColor colour) {
  return {what, [colour](CImage& img, int x0, int y, int char_h) {
            img.filledRectangle(x0 + 4, y + 2, x0 + 12, y + char_h - 2, colour);
          }};
}

LegendItem boxItem(const std::string& what, mrpt::img::TColor colour) {
  return {what, [colour](CImage& img, int x0, int y, int char_h) {
            img.rectangle(x0 + 2, y + 1, x0 + 14, y + char_h - 1, colour, 2);
          }};
}

LegendItem ringItem(const std::string& what, mrpt::img::TColor colour) {
  return {what, [colour](CImage& img, int x0, int y, int char_h) {
            img.drawCircle(x0 + 8, y + char_h / 2, char_h / 2 - 1, colour, 2);
          }};
}

// The overlay's legend: the path, D, and the objects and people when drawn.
std::vector<LegendItem> overlayLegend(bool people, bool objects) {
  std::vector<LegendItem> items = {lineItem("robot path", mrpt::img::TColor(40, 90, 255)),
                                   patchItem("object cells (D)", mrpt::img::TColor(230, 0, 0))};
  if (objects) items.push_back(boxItem("object: id, size", mrpt::img::TColor(0, 150, 0)));
  if (people) {
    items.push_back({"person trails (a colour each), P<id> at the end",
                     [](CImage& img, int x0, int y, int char_h) {
                       for (int k = 0; k < 3; ++k) {
                         img.line(x0 + 6 * k, y + char_h / 2, x0 + 6 * k + 4, y + char_h / 2,
                                  kTrails[k], 2);
                       }
                     }});
  }
  return items;
}

}  // namespace

CImage renderOverlay(const DynamicGridMap& map, const std::vector<PathPoint>& path,
                     const std::vector<TrackedObject>* objects,
                     const std::vector<PersonTrail>* people) {
  const View view = observedView(map);
  CImage img = paintCells(map, view, [&](std::size_t i) {
    if (map.isObjectIndex(i)) return Bgr{0, 0, 230};
    const std::uint8_t g = grey(map, i);
    return Bgr{g, g, g};
  });
  const mrpt::img::TColor blue(40, 90, 255);
  for (std::size_t k = 1; k < path.size(); ++k) {
    const Pixel a = toPixel(map, view, path[k - 1].x, path[k - 1].y);
    const Pixel b = toPixel(map, view, path[k].x, path[k].y);
    img.line(a.x, a.y, b.x, b.y, blue, 1);
  }
  // Trails under the boxes; no label covers a box or another label.
  LabelBoard board;
  if (people) drawTrailLines(img, map, view, *people);
  if (objects) drawObjectBoxes(img, map, view, *objects, board);
  if (people) drawTrailLabels(img, map, view, *people, board);
  return withLegend(img, map.getResolution() / view.scale,
                    overlayLegend(people != nullptr, objects != nullptr));
}

namespace {

const mrpt::img::TColor kRemoved(220, 0, 0), kAdded(0, 160, 0), kMoved(30, 80, 255);

// A cell's grey in three tones: a wall (P(occ) above 0.65) black, free space (below 0.35)
// white, the rest the grey of the unknown. Under a change report the shading of free space is
// noise that hides the changes' colours (and makes a picture of a campus ten times larger).
std::uint8_t plainGrey(std::uint8_t g) {
  return g < 89 ? 0 : g > 166 ? 255 : 127;
}

// The map under a change report, in plain tones: the prior's S, this session's where the prior
// saw nothing, the structure changes' cells in their colours.
CImage paintChangeCells(const DynamicGridMap& map, const View& view, const SessionChanges& changes,
                        const std::vector<ChangeRow>& rows) {
  std::vector<std::uint8_t> tag(map.getRawMap().size(), 0);  // 1 removed or left, 2 added
  for (const ChangeRow& r : rows) {
    const std::uint8_t t = r.kind == "structure_added" ? 2 : 1;  // else: a place vacated
    for (const auto& [x, y] : r.region) tag[x + static_cast<std::size_t>(y) * map.getSizeX()] = t;
  }
  const auto colour = [](const mrpt::img::TColor& c) { return Bgr{c.B, c.G, c.R}; };
  const std::vector<std::int8_t> on_grid = changes.priorOnGrid(map);
  return paintCells(map, view, [&](std::size_t i) {
    if (tag[i] == 1) return colour(kRemoved);
    if (tag[i] == 2) return colour(kAdded);
    const std::int8_t prior = on_grid[i];
    const std::uint8_t g = plainGrey(prior != 0 ? DynamicGridMap::cellGrey(prior) : grey(map, i));
    return Bgr{g, g, g};
  });
}

// An object change: a ring at its place (new, gone) or an arrow to it (moved), and its label.
void drawObjectChange(CImage& img, const DynamicGridMap& map, const View& view, const ChangeRow& r,
                      LabelBoard& board) {
  const bool moved = r.kind == "object_moved", gone = r.kind == "object_gone";
  const mrpt::img::TColor c = moved ? kMoved : gone ? kRemoved : kAdded;
  const double x = gone ? r.from_x : r.to_x, y = gone ? r.from_y : r.to_y;
  const Pixel at = toPixel(map, view, x, y);
  const int radius = std::max(4, static_cast<int>(0.5 * r.size / map.getResolution() * view.scale));
  if (moved) {
    const Pixel from = toPixel(map, view, r.from_x, r.from_y);
    img.line(from.x, from.y, at.x, at.y, c, 2);
    const double a = std::atan2(at.y - from.y, at.x - from.x);
    for (const double side : {-0.5, 0.5}) {  // the head
      img.line(at.x, at.y, at.x - static_cast<int>(9 * std::cos(a + side)),
               at.y - static_cast<int>(9 * std::sin(a + side)), c, 2);
    }
  }
  img.drawCircle(at.x, at.y, radius, c, 2);
  int char_w = 0, char_h = 0;
  selectFont(img, char_w, char_h);
  char buf[48];  // an object of the prior's S has no id
  if (r.id > 0) std::snprintf(buf, sizeof buf, "%d: %.2f m", r.id, r.size);
  if (r.id <= 0) std::snprintf(buf, sizeof buf, "%.2f m", r.size);
  const std::string label = buf;
  const int lw = static_cast<int>(label.size()) * char_w + 4, lh = char_h + 2;
  const Rect anchor{at.x - radius, at.y - radius, at.x + radius, at.y + radius};
  Rect where{};
  if (!board.place(anchor, lw, lh, static_cast<int>(img.getWidth()),
                   static_cast<int>(img.getHeight()), where)) {
    return;
  }
  board.taken.push_back(where);
  img.filledRectangle(where.x0, where.y0, where.x1, where.y1, mrpt::img::TColor(255, 255, 255));
  img.rectangle(where.x0, where.y0, where.x1, where.y1, c, 1);
  img.textOut(where.x0 + 2, where.y0 + 1, label, mrpt::img::TColor(0, 0, 0));
}

}  // namespace

CImage renderChanges(const DynamicGridMap& map, const SessionChanges& changes,
                     const std::vector<ChangeRow>& rows) {
  const View view = observedView(map);
  CImage img = paintChangeCells(map, view, changes, rows);
  LabelBoard board;
  for (const ChangeRow& r : rows) {
    if (r.kind.rfind("object_", 0) == 0) drawObjectChange(img, map, view, r, board);
  }
  const std::vector<LegendItem> legend = {
      patchItem("structure removed", kRemoved), patchItem("structure added", kAdded),
      lineItem("object moved: id, size", kMoved), ringItem("new object", kAdded),
      ringItem("object gone", kRemoved)};
  return withLegend(img, map.getResolution() / view.scale, legend);
}

void drawPeople(CImage& img, const DynamicGridMap& map, const View& view,
                const std::vector<PersonTrail>& people) {
  LabelBoard board;
  drawTrailLines(img, map, view, people);
  drawTrailLabels(img, map, view, people, board);
}

void drawObjects(CImage& img, const DynamicGridMap& map, const View& view,
                 const std::vector<TrackedObject>& objects) {
  LabelBoard board;
  drawObjectBoxes(img, map, view, objects, board);
}

}  // namespace dynamap
