#include "dynamap/outputs/render.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>

namespace dynamap {
namespace {

using mrpt::img::CImage;

// BGR, as MRPT's OpenCV-backed images store them.
struct Bgr {
  std::uint8_t b, g, r;
};

inline void put(CImage& img, int x, int y, Bgr c) {
  auto* p = img.ptrLine<std::uint8_t>(static_cast<unsigned>(y)) + 3 * x;
  p[0] = c.b;
  p[1] = c.g;
  p[2] = c.r;
}

inline std::uint8_t grey(const mrpt::maps::COccupancyGridMap2D& map, std::size_t i) {
  return DynamicGridMap::l2p_255(map.getRawMap()[i]);
}

// Fills an image of the cells in `view`, colour from a cell's linear index.
template <typename ColourOf>
CImage paintCells(const DynamicGridMap& map, const View& view, ColourOf colour) {
  const std::size_t sx = map.getSizeX();
  const int scale = view.scale, w = view.cx1 - view.cx0, h = view.cy1 - view.cy0;
  CImage img(w * scale, h * scale, mrpt::img::CH_RGB);
  for (int cy = view.cy0; cy < view.cy1; ++cy) {
    const int row0 = (view.cy1 - 1 - cy) * scale;
    for (int cx = view.cx0; cx < view.cx1; ++cx) {
      const Bgr c = colour(cx + static_cast<std::size_t>(cy) * sx);
      const int col0 = (cx - view.cx0) * scale;
      for (int dy = 0; dy < scale; ++dy) {
        for (int dx = 0; dx < scale; ++dx) put(img, col0 + dx, row0 + dy, c);
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

CImage renderDynamic(const DynamicGridMap& map) {
  const auto& d = map.dynamicRaw();
  return paintCells(map, wholeGrid(map), [&](std::size_t i) {
    const float p = 1.0f - DynamicGridMap::l2p(d[i]);
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
  if (people) drawPeople(img, map, view, *people);
  if (objects) drawObjects(img, map, view, *objects);
  return img;
}

namespace {

// A box or a label on a picture, in pixels (inclusive).
struct Rect {
  int x0, y0, x1, y1;
  bool overlaps(const Rect& o) const { return x0 <= o.x1 && o.x0 <= x1 && y0 <= o.y1 && o.y0 <= y1; }
};

// Beside the end point: right, left, above, below, then the same one and two label sizes
// further out; the first place that covers no label of `labels` (else the first place).
std::array<int, 4> placeLabel(Pixel end, int lw, int lh, int w, int h,
                              const std::vector<std::array<int, 4>>& labels) {
  auto clamped = [&](int x, int y) {
    return std::array<int, 4>{std::clamp(x, 0, std::max(0, w - lw - 1)),
                              std::clamp(y, 0, std::max(0, h - lh - 1)), 0, 0};
  };
  for (int ring = 0; ring < 3; ++ring) {
    const int dx = 4 + ring * lw, dy = lh / 2 + ring * (lh + 1);
    for (const auto& c : {clamped(end.x + dx, end.y - lh / 2),
                          clamped(end.x - dx - lw, end.y - lh / 2),
                          clamped(end.x - lw / 2, end.y - dy - lh),
                          clamped(end.x - lw / 2, end.y + dy)}) {
      bool clear = true;
      for (const auto& l : labels) {
        clear = clear && !(c[0] <= l[2] && l[0] <= c[0] + lw && c[1] <= l[3] && l[1] <= c[1] + lh);
      }
      if (clear) return c;
    }
  }
  return clamped(end.x + 4, end.y - lh / 2);
}

}  // namespace

void drawPeople(CImage& img, const DynamicGridMap& map, const View& view,
                const std::vector<PersonTrail>& people) {
  // Magenta: apart from the red of D, the green of object boxes and the blue of the robot.
  const mrpt::img::TColor trail(200, 0, 200), text(255, 255, 255);
  const bool big = img.getWidth() >= 1000;
  img.selectTextFont(big ? "9x15B" : "6x13B");
  const int char_w = big ? 9 : 6, char_h = big ? 15 : 13;
  const int w = static_cast<int>(img.getWidth()), h = static_cast<int>(img.getHeight());
  std::vector<std::array<int, 4>> labels;  // x0 y0 x1 y1
  for (const PersonTrail& p : people) {
    if (p.points.empty()) continue;
    for (std::size_t k = 1; k < p.points.size(); ++k) {
      const Pixel a = toPixel(map, view, p.points[k - 1].first, p.points[k - 1].second);
      const Pixel b = toPixel(map, view, p.points[k].first, p.points[k].second);
      img.line(a.x, a.y, b.x, b.y, trail, 1);
    }
    const Pixel end = toPixel(map, view, p.points.back().first, p.points.back().second);
    img.filledRectangle(end.x - 2, end.y - 2, end.x + 2, end.y + 2, trail);
    const std::string label = "P" + std::to_string(p.id);
    const int lw = static_cast<int>(label.size()) * char_w + 4, lh = char_h + 2;
    const auto at = placeLabel(end, lw, lh, w, h, labels);
    const int x = at[0], y = at[1];
    labels.push_back({x, y, x + lw, y + lh});
    img.filledRectangle(x, y, x + lw, y + lh, trail);
    img.textOut(x + 2, y + 1, label, text);
  }
}

void drawObjects(CImage& img, const DynamicGridMap& map, const View& view,
                 const std::vector<TrackedObject>& objects) {
  const int scale = view.scale;
  const mrpt::img::TColor box(0, 150, 0), text(0, 0, 0), label_bg(255, 240, 120);
  // Big pictures get the bigger font; 6x13 keeps labels readable on small maps.
  const bool big = img.getWidth() >= 1000;
  img.selectTextFont(big ? "9x15B" : "6x13B");
  const int char_w = big ? 9 : 6, char_h = big ? 15 : 13;
  const int w = static_cast<int>(img.getWidth()), h = static_cast<int>(img.getHeight());
  // Boxes first, then each label beside its box where it covers no other box and no label:
  // above, below, then the same on the right edge, then further up.
  std::vector<Rect> boxes;
  std::vector<const TrackedObject*> shown;
  for (const TrackedObject& o : objects) {
    if (o.state != ObjectState::Present) continue;
    const ShapeEstimate& s = o.shape;
    const Pixel p0 = toPixel(map, view, s.x_min, s.y_max);
    const Pixel p1 = toPixel(map, view, s.x_max, s.y_min);
    // At least a few pixels around the object, so that small ones stay visible.
    const int pad = std::max(2, scale / 2);
    boxes.push_back({p0.x - pad, p0.y - pad, p1.x + pad, p1.y + pad});
    shown.push_back(&o);
    img.rectangle(boxes.back().x0, boxes.back().y0, boxes.back().x1, boxes.back().y1, box, 2);
  }
  std::vector<Rect> labels;
  for (std::size_t k = 0; k < shown.size(); ++k) {
    const Rect& b = boxes[k];
    char buf[48];
    std::snprintf(buf, sizeof buf, "%d: %.2f m", shown[k]->id, shown[k]->shape.size);
    const std::string label = buf;
    const int lw = static_cast<int>(label.size()) * char_w + 4, lh = char_h + 2;
    auto place = [&](int x, int y) {
      x = std::clamp(x, 0, std::max(0, w - lw - 1));
      y = std::clamp(y, 0, std::max(0, h - lh - 1));
      return Rect{x, y, x + lw, y + lh};
    };
    std::vector<Rect> tries;
    for (const int x : {b.x0, b.x1 - lw}) {
      tries.push_back(place(x, b.y0 - lh - 1));  // above
      tries.push_back(place(x, b.y1 + 2));       // below
    }
    for (int up = 2; up <= 4; ++up) tries.push_back(place(b.x0, b.y0 - up * (lh + 1)));
    Rect at = tries.front();
    for (const Rect& r : tries) {
      bool clear = true;
      for (const Rect& l : labels) clear = clear && !r.overlaps(l);
      for (std::size_t j = 0; j < boxes.size(); ++j)
        clear = clear && (j == k || !r.overlaps(boxes[j]));
      if (clear) {
        at = r;
        break;
      }
    }
    labels.push_back(at);
    img.filledRectangle(at.x0, at.y0, at.x1, at.y1, label_bg);
    img.rectangle(at.x0, at.y0, at.x1, at.y1, box, 1);
    img.textOut(at.x0 + 2, at.y0 + 1, label, text);
  }
}

}  // namespace dynamap
