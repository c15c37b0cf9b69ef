// The picture of a scenario at t = 0, for people to check a scenario by eye before trusting it.

#include <mrpt/img/CImage.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "dynamap/sim/simulator.h"

namespace dynamap::sim {
namespace {

using mrpt::img::TColor;

const TColor kBackground(255, 255, 255);
const TColor kGridLine(232, 232, 232);
const TColor kWall(20, 20, 20);
const TColor kImageWall(90, 90, 90);
const TColor kRoute(30, 90, 220);
const TColor kStart(0, 150, 60);
const TColor kObject(200, 40, 40);
const TColor kMove(150, 150, 150);
const TColor kPerson(240, 140, 0);
const TColor kText(0, 0, 0);

constexpr int kPad = 20;
constexpr int kTitleHeight = 34;
constexpr int kLegendHeight = 96;

struct Bounds {
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  void add(Vec2 p, double r = 0) {
    x0 = std::min(x0, p.x - r), y0 = std::min(y0, p.y - r);
    x1 = std::max(x1, p.x + r), y1 = std::max(y1, p.y + r);
  }
};

Bounds worldBounds(const Scenario& sc) {
  Bounds b;
  for (const auto& s : sc.world.segments) b.add(s.a), b.add(s.b);
  const WallGrid& g = sc.world.grid;
  if (g.width > 0) {
    b.add(g.origin);
    b.add({g.origin.x + g.width * g.resolution, g.origin.y + g.height * g.resolution});
  }
  for (const auto& w : sc.robot.waypoints) b.add(w);
  for (const auto& o : sc.objects) b.add(o.start, o.diameter / 2);
  for (const auto& m : sc.moves) b.add(m.to);
  for (const auto& p : sc.people) {
    for (const auto& q : p.path) b.add(q);
  }
  return b;
}

/// World metres to image pixels (y flipped: image rows run downwards).
struct View {
  Bounds b;
  double ppm = 50;  // pixels per metre
  int left = kPad, top = kTitleHeight;
  int px(double x) const { return left + static_cast<int>(std::lround((x - b.x0) * ppm)); }
  int py(double y) const { return top + static_cast<int>(std::lround((b.y1 - y) * ppm)); }
  int width() const { return static_cast<int>(std::ceil((b.x1 - b.x0) * ppm)); }
  int height() const { return static_cast<int>(std::ceil((b.y1 - b.y0) * ppm)); }
};

void fillDisc(mrpt::img::CImage& img, int cx, int cy, double r, const TColor& c) {
  const int ir = static_cast<int>(std::ceil(r));
  for (int y = cy - ir; y <= cy + ir; ++y) {
    for (int x = cx - ir; x <= cx + ir; ++x) {
      if (x < 0 || y < 0 || x >= static_cast<int>(img.getWidth()) ||
          y >= static_cast<int>(img.getHeight())) {
        continue;
      }
      if ((x - cx) * (x - cx) + (y - cy) * (y - cy) <= r * r) img.setPixel(x, y, c);
    }
  }
}

void drawGridLines(mrpt::img::CImage& img, const View& v) {
  for (double x = std::ceil(v.b.x0); x <= v.b.x1; x += 1) {
    img.line(v.px(x), v.py(v.b.y0), v.px(x), v.py(v.b.y1), kGridLine);
  }
  for (double y = std::ceil(v.b.y0); y <= v.b.y1; y += 1) {
    img.line(v.px(v.b.x0), v.py(y), v.px(v.b.x1), v.py(y), kGridLine);
  }
}

void drawWalls(mrpt::img::CImage& img, const View& v, const StaticWorld& w) {
  const WallGrid& g = w.grid;
  for (int iy = 0; iy < g.height; ++iy) {
    for (int ix = 0; ix < g.width; ++ix) {
      if (!g.isWall(ix, iy)) continue;
      const double x = g.origin.x + ix * g.resolution, y = g.origin.y + iy * g.resolution;
      img.filledRectangle(v.px(x), v.py(y + g.resolution), v.px(x + g.resolution), v.py(y),
                          kImageWall);
    }
  }
  for (const auto& s : w.segments)
    img.line(v.px(s.a.x), v.py(s.a.y), v.px(s.b.x), v.py(s.b.y), kWall, 3);
}

void drawRoute(mrpt::img::CImage& img, const View& v, const RobotSpec& r) {
  const auto& w = r.waypoints;
  const std::size_t legs = w.size() < 2 ? 0 : (r.loop ? w.size() : w.size() - 1);
  for (std::size_t i = 0; i < legs; ++i) {
    const Vec2 a = w[i], b = w[(i + 1) % w.size()];
    img.line(v.px(a.x), v.py(a.y), v.px(b.x), v.py(b.y), kRoute, 2);
  }
  for (const auto& p : w) fillDisc(img, v.px(p.x), v.py(p.y), 3, kRoute);
  const Pose2 start = RobotPath(r).at(0);
  fillDisc(img, v.px(start.x), v.py(start.y), 7, kStart);
  const double l = 0.6;
  img.line(v.px(start.x), v.py(start.y), v.px(start.x + l * std::cos(start.phi)),
           v.py(start.y + l * std::sin(start.phi)), kStart, 3);
}

void drawMovesAndObjects(mrpt::img::CImage& img, const View& v, const Scenario& sc) {
  // A glide is drawn as its path; a jump (duration 0: carried while nobody looked) only as its
  // target, since a line would cross walls the object never crossed.
  img.selectTextFont("6x13");
  for (const auto& m : sc.moves) {
    const Vec2 a = moveOrigin(sc, m);
    if (m.duration > 0) {
      img.line(v.px(a.x), v.py(a.y), v.px(m.to.x), v.py(m.to.y), kMove, 1,
               mrpt::img::CCanvas::psDash);
    }
    for (const auto& o : sc.objects) {
      if (o.id != m.object_id) continue;
      const int r = std::max(2, static_cast<int>(std::lround(o.diameter / 2 * v.ppm)));
      img.drawCircle(v.px(m.to.x), v.py(m.to.y), r, kMove);
      img.textOut(v.px(m.to.x) + r + 2, v.py(m.to.y) - 6, std::to_string(o.id), kMove);
    }
  }
  img.selectTextFont("9x15B");
  for (const auto& o : sc.objects) {
    const int cx = v.px(o.start.x), cy = v.py(o.start.y);
    const double r = std::max(2.0, o.diameter / 2 * v.ppm);
    fillDisc(img, cx, cy, r, kObject);
    img.textOut(cx + static_cast<int>(r) + 2, cy - 7, std::to_string(o.id), kObject);
  }
}

void drawPeople(mrpt::img::CImage& img, const View& v, const Scenario& sc) {
  img.selectTextFont("9x15B");
  for (const auto& p : sc.people) {
    for (std::size_t i = 1; i < p.path.size(); ++i) {
      img.line(v.px(p.path[i - 1].x), v.py(p.path[i - 1].y), v.px(p.path[i].x), v.py(p.path[i].y),
               kPerson, 1, mrpt::img::CCanvas::psDot);
    }
    const Vec2 c = personPositionAt(p, 0);
    const double r = std::max(3.0, p.diameter / 2 * v.ppm);
    fillDisc(img, v.px(c.x), v.py(c.y), r, kPerson);
    img.textOut(v.px(c.x) + static_cast<int>(r) + 2, v.py(c.y) - 7, "P" + std::to_string(p.id),
                kPerson);
  }
}

void drawLegend(mrpt::img::CImage& img, const View& v, const Scenario& sc) {
  const int y0 = v.top + v.height() + 16;
  img.selectTextFont("9x15");
  int x = kPad;
  auto item = [&](const std::string& label, auto&& swatch) {
    swatch(x, y0 + 7);
    img.textOut(x + 30, y0, label, kText);
    x += 30 + 9 * static_cast<int>(label.size()) + 24;
  };
  item("wall", [&](int sx, int sy) { img.line(sx, sy, sx + 22, sy, kWall, 3); });
  item("robot route, start", [&](int sx, int sy) {
    img.line(sx, sy, sx + 22, sy, kRoute, 2);
    fillDisc(img, sx + 11, sy, 6, kStart);
  });
  item("object at t=0 (id)", [&](int sx, int sy) { fillDisc(img, sx + 11, sy, 7, kObject); });
  const int y1 = y0 + 26;
  x = kPad;
  auto item2 = [&](const std::string& label, auto&& swatch) {
    swatch(x, y1 + 7);
    img.textOut(x + 30, y1, label, kText);
    x += 30 + 9 * static_cast<int>(label.size()) + 24;
  };
  item2("glide: path, target (id)", [&](int sx, int sy) {
    img.line(sx, sy, sx + 16, sy, kMove, 1, mrpt::img::CCanvas::psDash);
    img.drawCircle(sx + 19, sy, 5, kMove);
  });
  item2("jump target (id)", [&](int sx, int sy) { img.drawCircle(sx + 11, sy, 6, kMove); });
  item2("person at t=0, walk path", [&](int sx, int sy) {
    img.line(sx, sy, sx + 22, sy, kPerson, 1, mrpt::img::CCanvas::psDot);
    fillDisc(img, sx + 11, sy, 6, kPerson);
  });
  // Scale bar: one metre.
  const int sy = y1 + 38, sx = kPad, len = static_cast<int>(std::lround(v.ppm));
  img.line(sx, sy, sx + len, sy, kText, 2);
  img.line(sx, sy - 5, sx, sy + 5, kText, 2);
  img.line(sx + len, sy - 5, sx + len, sy + 5, kText, 2);
  img.textOut(sx + len + 10, sy - 7, "1 m   (grid lines every metre)", kText);
  (void)sc;
}

void drawTitle(mrpt::img::CImage& img, const Scenario& sc, const View& v) {
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "%s: world at t = 0  (%.1f x %.1f m, %zu objects, %zu moves, %zu people, %.0f s)",
                sc.name.c_str(), v.b.x1 - v.b.x0 - 1.0, v.b.y1 - v.b.y0 - 1.0, sc.objects.size(),
                sc.moves.size(), sc.people.size(), sc.duration_s);
  img.selectTextFont("9x15B");
  img.textOut(kPad, 10, buf, kText);
}

}  // namespace

void renderWorldImage(const Scenario& sc, const std::string& path) {
  View v;
  v.b = worldBounds(sc);
  const double margin = 0.5;
  v.b.x0 -= margin, v.b.y0 -= margin, v.b.x1 += margin, v.b.y1 += margin;
  const double extent = std::max(v.b.x1 - v.b.x0, v.b.y1 - v.b.y0);
  v.ppm = std::clamp(std::floor(1000 / extent), 20.0, 150.0);
  const int w = std::max(v.width() + 2 * kPad, 760);
  const int h = v.top + v.height() + kLegendHeight;
  mrpt::img::CImage img(w, h, mrpt::img::CH_RGB);
  img.filledRectangle(0, 0, w - 1, h - 1, kBackground);
  drawTitle(img, sc, v);
  drawGridLines(img, v);
  drawWalls(img, v, sc.world);
  drawRoute(img, v, sc.robot);
  drawMovesAndObjects(img, v, sc);
  drawPeople(img, v, sc);
  drawLegend(img, v, sc);
  if (!img.saveToFile(path)) throw std::runtime_error(path + ": cannot write image");
}

}  // namespace dynamap::sim
