#include "octarc/plot/Stamp.h"

#include <plplot/plplot.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <numbers>
#include <vector>

#include "PlplotMutex.h"
#include "octarc/core/Error.h"

namespace octarc {

namespace {

// cmap0 indices: 0 background, 1 text, 2 scale bar and arrows, 3.. the marks.
constexpr int kBackground = 0, kText = 1, kOverlay = 2, kFirstMark = 3;
constexpr int kMaxMarkColours = 12;
// Softness of the asinh stretch: the faint end is stretched about this much more than the top.
constexpr double kStretch = 12.0;

double stretched(double v, double lo, double hi) {
  if (!std::isfinite(v)) return 0.0;
  const double t = std::clamp((v - lo) / (hi - lo), 0.0, 1.0);
  return std::asinh(kStretch * t) / std::asinh(kStretch);
}

// An ellipse (or circle) as a closed polyline in image coordinates.
void drawEllipse(const StampMark& m) {
  constexpr int kPoints = 97;
  PLFLT x[kPoints], y[kPoints];
  const double b = m.ellipse ? m.semiAxis2Pix : m.semiAxis1Pix;
  const double c = std::cos(m.angleRad), s = std::sin(m.angleRad);
  for (int k = 0; k < kPoints; ++k) {
    const double t = 2.0 * std::numbers::pi * k / (kPoints - 1);
    const double u = m.semiAxis1Pix * std::cos(t), v = b * std::sin(t);
    x[k] = m.xFits + c * u - s * v;
    y[k] = m.yFits + s * u + c * v;
  }
  plline(kPoints, x, y);
}

// An arrow from (x0, y0) along (dx, dy), with a head and a label at its tip.
void drawArrow(double x0, double y0, double dx, double dy, const char* label) {
  PLFLT lx[2] = {x0, x0 + dx}, ly[2] = {y0, y0 + dy};
  plline(2, lx, ly);
  const double len = std::hypot(dx, dy);
  const double ux = dx / len, uy = dy / len;
  const double head = 0.25 * len;
  for (const double side : {1.0, -1.0}) {
    PLFLT hx[2] = {x0 + dx, x0 + dx - head * (ux * 0.87 - side * uy * 0.5)};
    PLFLT hy[2] = {y0 + dy, y0 + dy - head * (uy * 0.87 + side * ux * 0.5)};
    plline(2, hx, hy);
  }
  plptex(x0 + 1.3 * dx, y0 + 1.3 * dy, 1.0, 0.0, 0.5, label);
}

}  // namespace

void writeStampPng(const std::string& path, const Stamp& stamp) {
  const std::int64_t nx = stamp.pixels.width(), ny = stamp.pixels.height();
  if (nx <= 0 || ny <= 0) throw ConfigError("stamp " + stamp.title + ": empty cut-out");
  if (!(stamp.displayHighAdu > stamp.displayLowAdu)) {
    throw ConfigError("stamp " + stamp.title + ": the display range is not increasing");
  }
  // The grey levels, column-major as plimage takes them.
  std::vector<PLFLT> values(static_cast<std::size_t>(nx * ny));
  std::vector<const PLFLT*> columns(static_cast<std::size_t>(nx));
  for (std::int64_t i = 0; i < nx; ++i) {
    for (std::int64_t j = 0; j < ny; ++j) {
      values[std::size_t(i * ny + j)] =
          stretched(stamp.pixels(i, j), stamp.displayLowAdu, stamp.displayHighAdu);
    }
    columns[std::size_t(i)] = &values[std::size_t(i * ny)];
  }
  const double x0 = stamp.xFirstFits - 0.5, x1 = x0 + double(nx);
  const double y0 = stamp.yFirstFits - 0.5, y1 = y0 + double(ny);
  const double side = std::max(x1 - x0, y1 - y0);

  std::lock_guard<std::mutex> lock(detail::plplotMutex());
  PLINT stream = 0;
  plmkstrm(&stream);
  plsdev("pngcairo");
  plsfnam(path.c_str());
  plspage(0, 0, stamp.sizePix, stamp.sizePix, 0, 0);
  plscol0(kBackground, 24, 24, 24);
  plscol0(kText, 235, 235, 235);
  plscol0(kOverlay, 255, 220, 60);
  for (std::size_t k = 0; k < stamp.marks.size() && k < std::size_t(kMaxMarkColours); ++k) {
    const StampMark& m = stamp.marks[k];
    plscol0(kFirstMark + PLINT(k), m.red, m.green, m.blue);
  }
  plinit();
  pladv(0);
  plvpor(0.06, 0.94, 0.08, 0.92);
  plwind(x0, x0 + side, y0, y0 + side);
  const PLFLT level[2] = {0.0, 1.0}, grey[2] = {0.0, 1.0};
  plscmap1n(256);
  plscmap1l(1, 2, level, grey, grey, grey, nullptr);
  plimage(columns.data(), PLINT(nx), PLINT(ny), x0, x1, y0, y1, 0.0, 1.0, x0, x1, y0, y1);

  plwidth(1.5);
  for (std::size_t k = 0; k < stamp.marks.size(); ++k) {
    const StampMark& m = stamp.marks[k];
    plcol0(kFirstMark + PLINT(k % std::size_t(kMaxMarkColours)));
    drawEllipse(m);
    if (!m.label.empty()) {
      plschr(0, 0.8);
      plptex(m.xFits + m.semiAxis1Pix + 0.02 * side, m.yFits, 1.0, 0.0, 0.0, m.label.c_str());
      plschr(0, 1.0);
    }
  }
  plcol0(kOverlay);
  plschr(0, 0.9);
  if (stamp.hasSkyDirections) {
    // In the upper-left corner, 15% of the side long.
    const double len = 0.15 * side;
    const double ax = x0 + 0.82 * side, ay = y0 + 0.78 * side;
    drawArrow(ax, ay, len * stamp.northX, len * stamp.northY, "N");
    drawArrow(ax, ay, len * stamp.eastX, len * stamp.eastY, "E");
  }
  if (stamp.pixelScaleArcsec > 0 && stamp.scaleBarArcsec > 0) {
    const double bar = stamp.scaleBarArcsec / stamp.pixelScaleArcsec;
    const double bx = x0 + 0.06 * side, by = y0 + 0.06 * side;
    PLFLT lx[2] = {bx, bx + bar}, ly[2] = {by, by};
    plwidth(3.0);
    plline(2, lx, ly);
    plwidth(1.0);
    char label[32];
    std::snprintf(label, sizeof label, "%g\"", stamp.scaleBarArcsec);
    plptex(bx + 0.5 * bar, by + 0.03 * side, 1.0, 0.0, 0.5, label);
  }
  plcol0(kText);
  plschr(0, 1.0);
  if (!stamp.title.empty()) plmtex("t", 1.0, 0.5, 0.5, stamp.title.c_str());
  if (!stamp.subtitle.empty()) plmtex("b", 1.6, 0.5, 0.5, stamp.subtitle.c_str());
  plend1();
  std::error_code ec;
  if (!std::filesystem::exists(path, ec) || std::filesystem::file_size(path, ec) == 0) {
    throw IoError(path + ": PLplot did not write the stamp");
  }
}

}  // namespace octarc
