// Check-plots through PLplot's cairo driver: the files are what their format says (PNG
// signature and the asked size in the IHDR chunk; SVG text holding the title and the labels).
#include "octarc/plot/CheckPlot.h"

#include <cairo.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "TestPaths.h"
#include "octarc/core/Error.h"

namespace octarc {
namespace {

std::string readBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::uint32_t bigEndian32(const std::string& s, std::size_t at) {
  return std::uint32_t(std::uint8_t(s[at])) << 24 | std::uint32_t(std::uint8_t(s[at + 1])) << 16 |
         std::uint32_t(std::uint8_t(s[at + 2])) << 8 | std::uint32_t(std::uint8_t(s[at + 3]));
}

Plot histogram() {
  Plot p;
  p.title = "Arcness of simulated arcs";
  p.xLabel = "ARCNESS";
  p.yLabel = "fraction per bin";
  PlotSeries s;
  s.label = "simulated arcs";
  s.steps = true;
  s.x = {0.0, 0.05, 0.10, 0.15, 0.20};
  s.y = {0.5, 0.3, 0.15, 0.05};
  p.series.push_back(s);
  p.cuts.push_back({0.10, "a = 0.10"});
  return p;
}

TEST(CheckPlot, PngHasTheAskedSize) {
  const auto path = test::scratchDir() / "arcness.png";
  Plot p = histogram();
  p.widthPix = 640;
  p.heightPix = 480;
  writePlot(path.string(), PlotDevice::Png, p);
  const std::string png = readBytes(path);
  ASSERT_GT(png.size(), 1000u);
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_EQ(png.substr(12, 4), "IHDR");
  EXPECT_EQ(bigEndian32(png, 16), 640u);
  EXPECT_EQ(bigEndian32(png, 20), 480u);
}

TEST(CheckPlot, SvgHoldsTitleLabelsAndLegend) {
  const auto path = test::scratchDir() / "arcness.svg";
  writePlot(path.string(), PlotDevice::Svg, histogram());
  const std::string svg = readBytes(path);
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  // cairo draws text as glyph outlines: the strings are not in the file, but the drawing is.
  EXPECT_NE(svg.find("path"), std::string::npos);
}

// The pixels of a PNG check-plot, as cairo reads them (0xAARRGGBB).
std::vector<std::uint32_t> pngPixels(const std::filesystem::path& path) {
  cairo_surface_t* surface = cairo_image_surface_create_from_png(path.c_str());
  EXPECT_EQ(cairo_surface_status(surface), CAIRO_STATUS_SUCCESS) << path;
  std::vector<std::uint32_t> pixels;
  const int width = cairo_image_surface_get_width(surface);
  const int height = cairo_image_surface_get_height(surface);
  const int stride = cairo_image_surface_get_stride(surface);
  const unsigned char* data = cairo_image_surface_get_data(surface);
  for (int y = 0; y < height && data; ++y) {
    const auto* row = reinterpret_cast<const std::uint32_t*>(data + std::size_t(y) * stride);
    pixels.insert(pixels.end(), row, row + width);
  }
  cairo_surface_destroy(surface);
  return pixels;
}

// The pixels a cut's label adds: the plot drawn with and without the label's text.
long labelPixels(Plot p, double cutX, const std::filesystem::path& dir, const std::string& name) {
  p.cuts = {{cutX, "a = 0.10 cut"}};
  const auto with = dir / (name + "-with.png");
  writePlot(with.string(), PlotDevice::Png, p);
  p.cuts[0].label.clear();
  const auto without = dir / (name + "-without.png");
  writePlot(without.string(), PlotDevice::Png, p);
  const std::vector<std::uint32_t> a = pngPixels(with), b = pngPixels(without);
  EXPECT_EQ(a.size(), b.size());
  long differing = 0;
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) differing += a[i] != b[i];
  return differing;
}

// A cut under the legend's corner (top right) keeps its whole label in sight: the label adds as
// many pixels there as at the left, far from the legend (anti-aliasing at other sub-pixel
// offsets changes a few), where nothing can cover it. A legend over the label hides most of it.
TEST(CheckPlot, TheLegendNeverCoversACutLabel) {
  Plot p = histogram();
  p.series[0].label = "simulated arcs with a long legend entry";
  const std::filesystem::path dir = test::scratchDir();
  const long atLeft = labelPixels(p, 0.01, dir, "cut-left");
  const long underLegend = labelPixels(p, 0.14, dir, "cut-right");
  ASSERT_GT(atLeft, 100);  // the label is drawn at all
  EXPECT_NEAR(double(underLegend) / double(atLeft), 1.0, 0.1)
      << underLegend << " label pixels under the legend's corner, " << atLeft << " at the left";
}

TEST(CheckPlot, DevicesAreTheAstromaticNames) {
  EXPECT_EQ(parsePlotDevice("png"), PlotDevice::Png);
  EXPECT_EQ(parsePlotDevice("PDF"), PlotDevice::Pdf);
  EXPECT_EQ(parsePlotDevice("SVG"), PlotDevice::Svg);
  EXPECT_EQ(parsePlotDevice("PSC"), PlotDevice::Psc);
  EXPECT_STREQ(plotFileSuffix(PlotDevice::Psc), ".ps");
  EXPECT_THROW(parsePlotDevice("XWIN"), ConfigError);
}

TEST(CheckPlot, NothingToDrawIsAnError) {
  Plot p = histogram();
  p.series[0].y = {NAN, NAN, NAN, NAN};
  const auto path = test::scratchDir() / "empty.png";
  EXPECT_THROW(writePlot(path.string(), PlotDevice::Png, p), ConfigError);
  EXPECT_FALSE(std::filesystem::exists(path));
}

}  // namespace
}  // namespace octarc
