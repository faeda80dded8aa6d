// Check-plots, as SCAMP and PSFEx make them: line and step plots drawn with PLplot (its cairo
// driver), wrapped here once. Each plot has axes with units, a title, a legend and, where a
// study has them, the cut lines of the search spaces.
//
// CHECKPLOT_DEV names the device as the astromatic tools do: PNG, PDF, SVG, PSC (colour
// PostScript) or EPSC. PLplot keeps global state: plots are drawn one at a time (a mutex).
#pragma once

#include <string>
#include <vector>

namespace octarc {

enum class PlotDevice { Png, Pdf, Svg, Psc, Epsc };

// CHECKPLOT_DEV value (any case) to a device; ConfigError listing the values otherwise.
PlotDevice parsePlotDevice(const std::string& name);
// The file name suffix of a device: ".png", ".pdf", ".svg", ".ps", ".eps".
const char* plotFileSuffix(PlotDevice device);

struct PlotSeries {
  std::string label;      // legend text
  std::vector<double> x;  // data coordinates
  std::vector<double> y;
  bool steps = false;  // a histogram: x holds the n + 1 bin edges, y the n bin values
  // Optional error bars (same length as y): drawn from yLow to yHigh at each point (bin centre).
  std::vector<double> yLow, yHigh;
};

// A vertical line at x, e.g. a search space's cut ("a = 0.10").
struct CutLine {
  double x = 0.0;
  std::string label;
};

struct Plot {
  std::string title;
  std::string xLabel;  // with its unit, e.g. "S/N (ISO)" or "#gh#dE#u [arcsec]" (PLplot escapes)
  std::string yLabel;
  std::vector<PlotSeries> series;
  std::vector<CutLine> cuts;
  bool logX = false;  // axes in log10 (the data must then be > 0)
  bool logY = false;
  int widthPix = 800, heightPix = 600;  // raster devices
};

// Draws `plot` into `path` (written by PLplot itself: give a temporary name of an OutputFiles
// entry). ConfigError for a plot without a finite point; IoError naming the file when it
// cannot be written.
void writePlot(const std::string& path, PlotDevice device, const Plot& plot);

}  // namespace octarc
