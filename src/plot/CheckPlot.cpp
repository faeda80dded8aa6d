#include "octarc/plot/CheckPlot.h"

#include <plplot/plplot.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <limits>
#include <mutex>

#include "octarc/core/Error.h"
#include "octarc/core/Format.h"

namespace octarc {

namespace {

std::mutex& plplotMutex() {
  static std::mutex m;
  return m;
}

const char* driverName(PlotDevice d) {
  switch (d) {
    case PlotDevice::Png:
      return "pngcairo";
    case PlotDevice::Pdf:
      return "pdfcairo";
    case PlotDevice::Svg:
      return "svgcairo";
    case PlotDevice::Psc:
      return "pscairo";
    case PlotDevice::Epsc:
      return "epscairo";
  }
  return "pngcairo";
}

// Colours of the series (cmap0 indices after setColours): blue, red, green, orange, purple.
constexpr int kSeriesColours[] = {9, 1, 3, 8, 13};
constexpr int kCutColour = 15;

void setColours() {
  plscol0(0, 255, 255, 255);  // background: white
  plscol0(15, 0, 0, 0);       // axes and text: black (set below with plcol0)
  plscol0(9, 31, 119, 180);
  plscol0(1, 214, 39, 40);
  plscol0(3, 44, 160, 44);
  plscol0(8, 255, 127, 14);
  plscol0(13, 148, 103, 189);
  plscol0(7, 120, 120, 120);
}

double axisValue(double v, bool log) {
  if (!log) return v;
  return v > 0 ? std::log10(v) : std::numeric_limits<double>::quiet_NaN();
}

// The points of one series as drawn: steps become a polyline along the bin edges.
void seriesLine(const PlotSeries& s, const Plot& p, std::vector<PLFLT>& x, std::vector<PLFLT>& y) {
  x.clear();
  y.clear();
  if (s.steps) {
    for (std::size_t k = 0; k < s.y.size() && k + 1 < s.x.size(); ++k) {
      const double v = axisValue(s.y[k], p.logY);
      x.push_back(axisValue(s.x[k], p.logX));
      y.push_back(v);
      x.push_back(axisValue(s.x[k + 1], p.logX));
      y.push_back(v);
    }
  } else {
    for (std::size_t k = 0; k < s.x.size() && k < s.y.size(); ++k) {
      x.push_back(axisValue(s.x[k], p.logX));
      y.push_back(axisValue(s.y[k], p.logY));
    }
  }
}

struct Range {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
  void add(double v) {
    if (!std::isfinite(v)) return;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  bool valid() const { return lo <= hi; }
  // A little room on both sides; a single value gets a unit-wide range.
  void pad(double fraction) {
    const double w = hi > lo ? hi - lo : std::max(1.0, std::abs(lo));
    lo -= fraction * w;
    hi += fraction * w;
  }
};

}  // namespace

PlotDevice parsePlotDevice(const std::string& name) {
  std::string u = name;
  for (char& c : u) c = char(std::toupper(static_cast<unsigned char>(c)));
  if (u == "PNG") return PlotDevice::Png;
  if (u == "PDF") return PlotDevice::Pdf;
  if (u == "SVG") return PlotDevice::Svg;
  if (u == "PSC") return PlotDevice::Psc;
  if (u == "EPSC") return PlotDevice::Epsc;
  throw ConfigError("CHECKPLOT_DEV " + quoteForMessage(name) +
                    " is not supported (PNG, PDF, SVG, PSC or EPSC)");
}

const char* plotFileSuffix(PlotDevice device) {
  switch (device) {
    case PlotDevice::Png:
      return ".png";
    case PlotDevice::Pdf:
      return ".pdf";
    case PlotDevice::Svg:
      return ".svg";
    case PlotDevice::Psc:
      return ".ps";
    case PlotDevice::Epsc:
      return ".eps";
  }
  return ".png";
}

void writePlot(const std::string& path, PlotDevice device, const Plot& plot) {
  Range xr, yr;
  std::vector<PLFLT> x, y;
  for (const PlotSeries& s : plot.series) {
    seriesLine(s, plot, x, y);
    for (std::size_t k = 0; k < x.size(); ++k) {
      if (std::isfinite(x[k]) && std::isfinite(y[k])) {
        xr.add(x[k]);
        yr.add(y[k]);
      }
    }
    for (double v : s.yLow) yr.add(axisValue(v, plot.logY));
    for (double v : s.yHigh) yr.add(axisValue(v, plot.logY));
  }
  if (!xr.valid() || !yr.valid()) {
    throw ConfigError("check-plot " + quoteForMessage(plot.title) + ": nothing to draw");
  }
  for (const CutLine& c : plot.cuts) xr.add(axisValue(c.x, plot.logX));
  xr.pad(0.02);
  if (!plot.logY && yr.lo >= 0) {
    yr.lo = 0;
    yr.hi = yr.hi > 0 ? yr.hi * 1.08 : 1.0;
  } else {
    yr.pad(0.05);
  }

  std::lock_guard<std::mutex> lock(plplotMutex());
  PLINT stream = 0;
  plmkstrm(&stream);
  plsdev(driverName(device));
  plsfnam(path.c_str());
  plspage(0, 0, plot.widthPix, plot.heightPix, 0, 0);
  setColours();
  plinit();
  plcol0(15);
  const PLINT axisFlags = (plot.logX ? 10 : 0) + (plot.logY ? 20 : 0);
  plenv(xr.lo, xr.hi, yr.lo, yr.hi, 0, axisFlags);
  pllab(plot.xLabel.c_str(), plot.yLabel.c_str(), plot.title.c_str());

  std::vector<PLINT> legendOpts, lineColours, lineStyles, textColours;
  std::vector<PLFLT> lineWidths;
  std::vector<const char*> texts;
  for (std::size_t i = 0; i < plot.series.size(); ++i) {
    const PlotSeries& s = plot.series[i];
    const int colour = kSeriesColours[i % (sizeof kSeriesColours / sizeof kSeriesColours[0])];
    plcol0(colour);
    plwidth(2.0);
    seriesLine(s, plot, x, y);
    // Break the line at undefined points.
    std::size_t start = 0;
    for (std::size_t k = 0; k <= x.size(); ++k) {
      if (k == x.size() || !std::isfinite(x[k]) || !std::isfinite(y[k])) {
        if (k > start + 1) plline(PLINT(k - start), &x[start], &y[start]);
        start = k + 1;
      }
    }
    for (std::size_t k = 0; k < s.yLow.size() && k < s.yHigh.size() && k < s.y.size(); ++k) {
      const double xc = s.steps && k + 1 < s.x.size() ? 0.5 * (s.x[k] + s.x[k + 1]) : s.x[k];
      PLFLT ex[2] = {axisValue(xc, plot.logX), axisValue(xc, plot.logX)};
      PLFLT ey[2] = {axisValue(s.yLow[k], plot.logY), axisValue(s.yHigh[k], plot.logY)};
      if (std::isfinite(ex[0]) && std::isfinite(ey[0]) && std::isfinite(ey[1])) plline(2, ex, ey);
    }
    legendOpts.push_back(PL_LEGEND_LINE);
    lineColours.push_back(colour);
    lineStyles.push_back(1);
    lineWidths.push_back(2.0);
    textColours.push_back(15);
    texts.push_back(s.label.c_str());
  }
  // The legend sits in the top right corner; the cut labels go in a row just below it, so that
  // it never covers one. It is drawn once to learn its height (normalised viewport units), and
  // again after the cut lines so that none crosses it.
  const auto drawLegend = [&] {
    PLFLT legendWidth = 0, legendHeight = 0;
    pllegend(&legendWidth, &legendHeight, PL_LEGEND_BACKGROUND | PL_LEGEND_BOUNDING_BOX,
             PL_POSITION_TOP | PL_POSITION_RIGHT | PL_POSITION_INSIDE, 0.02, 0.02, 0.08, 0, 15, 1,
             0, 0, PLINT(legendOpts.size()), legendOpts.data(), 1.0, 0.8, 2.0, 0.0,
             textColours.data(), texts.data(), nullptr, nullptr, nullptr, nullptr,
             lineColours.data(), lineStyles.data(), lineWidths.data(), nullptr, nullptr, nullptr,
             nullptr);
    return legendHeight;
  };
  double labelRowFraction = 0.95;
  if (!plot.series.empty()) {
    const PLFLT legendHeight = drawLegend();
    PLFLT defaultMm = 0, charMm = 0, pageX0 = 0, pageX1 = 0, pageY0 = 0, pageY1 = 0;
    PLFLT vpX0 = 0, vpX1 = 0, vpY0 = 0, vpY1 = 0;
    plgchr(&defaultMm, &charMm);
    plgspa(&pageX0, &pageX1, &pageY0, &pageY1);
    plgvpd(&vpX0, &vpX1, &vpY0, &vpY1);
    const double viewportMm = (vpY1 - vpY0) * (pageY1 - pageY0);
    const double charFraction = viewportMm > 0 ? charMm / viewportMm : 0.03;
    labelRowFraction = std::max(0.05, 1.0 - 0.02 - legendHeight - 1.5 * charFraction);
  }
  for (const CutLine& c : plot.cuts) {
    const double cx = axisValue(c.x, plot.logX);
    if (!std::isfinite(cx)) continue;
    plcol0(kCutColour);
    plwidth(1.0);
    pllsty(2);
    PLFLT lx[2] = {cx, cx}, ly[2] = {yr.lo, yr.hi};
    plline(2, lx, ly);
    pllsty(1);
    plptex(cx, yr.lo + labelRowFraction * (yr.hi - yr.lo), 1.0, 0.0, -0.05, c.label.c_str());
  }
  if (!plot.series.empty() && !plot.cuts.empty()) drawLegend();
  plend1();
  std::error_code ec;
  if (!std::filesystem::exists(path, ec) || std::filesystem::file_size(path, ec) == 0) {
    throw IoError(path + ": PLplot did not write the check-plot");
  }
}

}  // namespace octarc
