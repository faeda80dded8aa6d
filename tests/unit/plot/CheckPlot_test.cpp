// Check-plots through PLplot's cairo driver: the files are what their format says (PNG
// signature and the asked size in the IHDR chunk; SVG text holding the title and the labels).
#include "octarc/plot/CheckPlot.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <string>

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
