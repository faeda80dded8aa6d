// The second band of `simulate lenses` (--band): injected colours measured back, reproducibility,
// the first band left as it was, the columns, and bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "EngineTestSetup.h"
#include "ExpectError.h"
#include "TestPaths.h"
#include "octarc/app/Commands.h"
#include "octarc/core/Error.h"
#include "octarc/selection/ColumnExpression.h"
#include "octarc/simulation/engine/LensCatalog.h"
#include "octarc/simulation/engine/LensSetup.h"
#include "octarc/simulation/engine/LensSimulation.h"

namespace octarc {
namespace {

namespace sim = octarc::simulation;

ImageF toFloat(const ImageD& image) {
  ImageF out(image.width(), image.height());
  for (std::int64_t i = 0; i < out.size(); ++i) out[i] = float(image[i]);
  return out;
}

double sumIn(const ImageD& image, const std::vector<PixelRun>& footprint) {
  double sum = 0.0;
  for (const PixelRun& run : footprint) {
    for (std::int32_t x = run.x0; x <= run.x1; ++x) sum += image(x, run.y);
  }
  return sum;
}

// The colour of a footprint holding S of source light and L of lens light in the measurement
// band, the source `sourceColour` and the lens `lensColour` bluer or redder in the other band.
double mixedColour(double s, double l, double sourceColour, double lensColour) {
  return -2.5 * std::log10((s * std::pow(10.0, -0.4 * sourceColour) +
                            l * std::pow(10.0, -0.4 * lensColour)) /
                           (s + l));
}

// A noise-free system with colours of no scatter: the arc gives back the source colour and the
// lens the lens colour. The geometry keeps them apart: b = 3", the source of 22.5 mag 2.7" from
// the centre (for a near-SIS the arc at b + beta = 5.7", the counter-image at b - beta = 0.3",
// magnified only b / beta - 1 = 0.11 times), a lens of 19.5 mag with r_e = 0.5". What remains
// of the other's light in a footprint shifts a colour by about 1.086 f (1 - 10^(-0.4 * 0.8)) =
// 0.57 f for a fraction f of foreign flux (here f is below 2 % in the arc rows and about 0.6 %
// in the lens, so the shifts stay near 0.01 mag): the 0.02 mag tolerance allows f up to 3.5 %.
// The footprints' exact fractions, from the source and the lens rendered apart, must then give
// the measured colours to float precision (1e-4 mag).
TEST(SecondBand, NoiselessColoursComeBack) {
  SimulationSetup setup = test::engineTestSetup();
  setup.observing.addNoise = false;
  setup.band = SecondBand{"g", {0.4, 0.0}, {1.2, 0.0}};
  const SourceDatabase sources = test::engineTestSources();
  sim::LensSystem sys;
  sys.mass = {3.0, 0.05, 0.0, 0.3};
  sys.light = {4.0, 0.5, 0.8, 0.3, 0.0};
  sys.lensMag = 19.5;
  sys.source.betaArcsec = {2.7, 0.0};
  sys.sourceMag = 22.5;
  const sim::SecondBandColours colours{0.4, 1.2, nullptr};
  std::mt19937_64 rng(7);
  const sim::RenderedLensSystem r =
      sim::renderLensSystem(sys, sources.stamp(1), setup.observing, rng, nullptr, &colours);
  ASSERT_EQ(r.bandImage.width(), r.image.width());
  const ImageF band = toFloat(r.bandImage);
  const DetectedSystem d = detectSystem(toFloat(r.image), setup, rng);
  ASSERT_TRUE(d.footprints.has_value());
  ASSERT_GE(d.arcs.chosenRow, 0);
  const SecondBandMagnitudes m = measureSecondBand(d, band, setup);
  ASSERT_EQ(m.arcs.size(), d.arcs.arcRows.size());

  // The components apart: the source alone (a lens 99 mag faint) and the lens alone.
  sim::LensSystem sourceOnly = sys, lensOnly = sys;
  sourceOnly.lensMag = 99.0;
  lensOnly.sourceMag = 99.0;
  const ImageD source =
      sim::renderLensSystem(sourceOnly, sources.stamp(1), setup.observing, rng).image;
  const ImageD lens = sim::renderLensSystem(lensOnly, sources.stamp(1), setup.observing, rng).image;

  const Table& t = d.objects;
  for (std::size_t a = 0; a < d.arcs.arcRows.size(); ++a) {
    const std::int64_t row = d.arcs.arcRows[a];
    const int level = int(t.value(row, t.findColumn("THRESH_LEVEL")));
    const auto number = std::int32_t(t.value(row, t.findColumn("NUMBER")));
    const std::vector<PixelRun> fp = d.footprints->footprints(level, {number}).front();
    const double arcColour = colourOf(m.arcs[a].band, m.arcs[a].measurement).value;
    EXPECT_NEAR(arcColour, 0.4, 0.02) << "arc row " << row;
    EXPECT_NEAR(arcColour, mixedColour(sumIn(source, fp), sumIn(lens, fp), 0.4, 1.2), 1e-4);
  }
  // The lens is detected apart at level 1 (the arc at 5.7" is well outside its isophote).
  ImageI32 levelOne;
  d.footprints->render(1, levelOne);
  const std::int32_t lensNumber = levelOne(50, 50);
  ASSERT_GT(lensNumber, 0);
  const std::vector<PixelRun> lensFp = d.footprints->footprints(1, {lensNumber}).front();
  const double lensColour = colourOf(m.levelOneLens.band, m.levelOneLens.measurement).value;
  EXPECT_NEAR(lensColour, 1.2, 0.02);
  EXPECT_NEAR(lensColour, mixedColour(sumIn(source, lensFp), sumIn(lens, lensFp), 0.4, 1.2), 1e-4);
  for (const BandPair& l : m.lenses) EXPECT_EQ(l.band.mag, m.levelOneLens.band.mag);
}

// The same seed gives the same second band; the first band is the same with or without it.
TEST(SecondBand, ReproducibleAndFirstBandUnchanged) {
  SimulationSetup one = test::engineTestSetup();
  one.population.sigmaMinKmPerS = 330.0;  // large Einstein radii: arcs in a few systems
  SimulationSetup two = one;
  two.band = SecondBand{};
  const SourceDatabase sources = test::engineTestSources();
  int measured = 0;
  std::vector<double> sourceColours;
  for (std::int64_t i = 0; i < 24; ++i) {
    const SimulatedSystem a = simulateSystem(one, sources, 99, i, true);
    const SimulatedSystem b = simulateSystem(two, sources, 99, i, true);
    const SimulatedSystem c = simulateSystem(two, sources, 99, i, true);
    EXPECT_TRUE(std::isnan(a.sourceColourMag));
    EXPECT_EQ(a.image.pixels(), b.image.pixels()) << "system " << i;
    ASSERT_EQ(a.objects.rows(), b.objects.rows());
    for (std::int64_t r = 0; r < a.objects.rows(); ++r) {
      for (int k = 0; k < a.objects.rowWidth(); ++k) {
        const double x = a.objects.row(r)[k], y = b.objects.row(r)[k];
        EXPECT_TRUE(x == y || (std::isnan(x) && std::isnan(y)));
      }
    }
    EXPECT_EQ(a.arcs.arcRows, b.arcs.arcRows);
    EXPECT_EQ(a.arcs.chosenRow, b.arcs.chosenRow);
    EXPECT_EQ(b.sourceColourMag, c.sourceColourMag);
    EXPECT_EQ(b.lensColourMag, c.lensColourMag);
    sourceColours.push_back(b.sourceColourMag);
    ASSERT_EQ(b.band.arcs.size(), c.band.arcs.size());
    for (std::size_t k = 0; k < b.band.arcs.size(); ++k) {
      EXPECT_EQ(b.band.arcs[k].band.mag, c.band.arcs[k].band.mag);
      EXPECT_EQ(b.band.lenses[k].band.mag, c.band.lenses[k].band.mag);
      ++measured;
    }
  }
  EXPECT_GT(measured, 0);
  // A scatter of 0.3 mag: the colours differ from system to system.
  EXPECT_NE(sourceColours.front(), sourceColours.back());
}

// The band's columns are scalar columns like any: an expression of the search's names works on
// both tables of a run.
TEST(SecondBand, ColumnsWorkInExpressions) {
  SimulationSetup setup = test::engineTestSetup();
  setup.band = SecondBand{};
  const SourceDatabase sources = test::engineTestSources();
  const LensRun run = runLensSimulation(setup, sources, 5, 16, 2, 0, {});
  for (const Table* t : {&run.systems, &run.arcs}) {
    const std::vector<double> v =
        ColumnExpression("ARC_COLOUR_g - LENS_COLOUR_g", "test").evaluate(*t);
    const int arc = t->requireColumn("ARC_COLOUR_g", "test");
    const int lens = t->requireColumn("LENS_COLOUR_g", "test");
    for (std::int64_t r = 0; r < t->rows(); ++r) {
      const double expected = t->value(r, arc) - t->value(r, lens);
      EXPECT_TRUE(v[std::size_t(r)] == expected ||
                  (std::isnan(v[std::size_t(r)]) && std::isnan(expected)));
    }
  }
  // The injected colours of every system; without a band the columns are not there.
  EXPECT_GE(run.systems.findColumn("SOURCE_COLOUR_TRUE_g"), 0);
  EXPECT_GE(run.systems.findColumn("LENS_COLOUR_TRUE_g"), 0);
  EXPECT_LT(Table(lensSystemColumns()).findColumn("MAG_g"), 0);
}

TEST(SecondBand, BadInputNamesTheOption) {
  EXPECT_EQ(parseColourDraw("0.4,0.3", "--source-colour").meanMag, 0.4);
  EXPECT_EQ(parseColourDraw("-0.5,0", "--lens-colour").scatterMag, 0.0);
  test::expectError<ConfigError>([] { parseColourDraw("0.4", "--source-colour"); },
                                 {"--source-colour", "MEAN,SCATTER"});
  test::expectError<ConfigError>([] { parseColourDraw("0.4,blue", "--lens-colour"); },
                                 {"--lens-colour"});
  test::expectError<ConfigError>([] { parseColourDraw("0.4,0.3,1", "--lens-colour"); },
                                 {"--lens-colour"});
  test::expectError<ConfigError>([] { parseColourDraw("1.2,-0.1", "--lens-colour"); },
                                 {"--lens-colour", ">= 0"});
  LensSetupOptions o;
  o.bandName = "g-r";
  test::expectError<ConfigError>([&] { makeSimulationSetup(o); }, {"--band", "'g-r'"});
  o.bandName.reset();
  o.sourceColour = ColourDraw{0.4, 0.3};
  test::expectError<ConfigError>([&] { makeSimulationSetup(o); }, {"--source-colour", "--band"});
  // Through the command: nothing written.
  const auto dir = test::scratchDir();
  const std::string out = (dir / "bad.fits").string();
  test::expectError<ConfigError>(
      [&] {
        runSimulateLenses({"-n", "5", "-o", out, "--band", "g r", "--quiet"});
      },
      {"--band"});
  test::expectError<ConfigError>(
      [&] {
        runSimulateLenses(
            {"-n", "5", "-o", out, "--band", "g", "--source-colour", "0.4;0.3", "--quiet"});
      },
      {"--source-colour"});
  test::expectError<ConfigError>(
      [&] {
        runSimulateLenses(
            {"-n", "5", "-o", out, "--band", "g", "--lens-colour", "1.2,-0.2", "--quiet"});
      },
      {"--lens-colour"});
  EXPECT_TRUE(std::filesystem::is_empty(dir));
}

}  // namespace
}  // namespace octarc
