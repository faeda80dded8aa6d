// Lens-light subtraction over an image: which catalog rows are fitted, the model and residual
// images of two galaxies drawn by the lens simulator's renderer, a fit that fails leaving its
// galaxy in the image, and which residual rows belong to which galaxy (hand-placed rows).
#include "octarc/lenslight/LensSubtraction.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "octarc/core/Error.h"
#include "octarc/simulation/LensLight.h"
#include "octarc/simulation/Psf.h"

namespace octarc::lenslight {
namespace {

constexpr double kScaleArcsec = 0.25;
constexpr double kSeeingArcsec = 0.9;  // 3.6 px FWHM

// A galaxy drawn by the lens simulator (adaptive integration, simulation/LensLight.h) at a
// 1-based position, added to `image`.
void addGalaxy(ImageD& image, double xPix, double yPix, double fluxAdu, double rePix, double n,
               double q, double thetaRad) {
  simulation::SurveyGrid grid;
  grid.width = int(image.width());
  grid.height = int(image.height());
  grid.pixelScaleArcsec = 1.0;
  grid.lensXPix = xPix - 1.0;  // 0-based
  grid.lensYPix = yPix - 1.0;
  simulation::SersicLightParams light;
  light.sersicIndex = n;
  light.halfLightRadiusArcsec = rePix;
  light.axisRatio = q;
  light.positionAngleRad = thetaRad;
  light.totalFlux = fluxAdu;
  simulation::addSersicLight(image, grid, light);
}

ColumnSpec spec(const char* name) {
  ColumnSpec s;
  s.name = name;
  s.type = ColumnType::Float64;
  return s;
}

// A catalog of level-1 rows (NUMBER, THRESH_LEVEL, X_IMAGE, Y_IMAGE, MAG_ISO) and one level-2
// row, as a detection would give for the galaxies.
Table catalogOf(const std::vector<std::array<double, 4>>& rows) {
  Table t(
      {spec("NUMBER"), spec("THRESH_LEVEL"), spec("X_IMAGE"), spec("Y_IMAGE"), spec("MAG_ISO")});
  for (const auto& r : rows) {
    double* row = t.appendRow();
    row[0] = r[0];
    row[1] = r[1];
    row[2] = r[2];
    row[3] = r[3];
    row[4] = r[0] == 1 ? 18.0 : 23.0;  // NUMBER 1 is the bright one
  }
  return t;
}

ImageF toFloat(const ImageD& image) {
  ImageF out(image.width(), image.height());
  for (std::int64_t i = 0; i < image.size(); ++i) out[i] = float(image[i]);
  return out;
}

SubtractionSettings settings() {
  SubtractionSettings s;
  s.mode = SubtractionMode::Local;
  s.selectExpression = "MAG_ISO < 20";
  s.cutoutArcsec = 24.0;
  s.pixelScaleArcsec = kScaleArcsec;
  s.seeingFwhmArcsec = kSeeingArcsec;
  return s;
}

TEST(LensSubtraction, ParsesTheModes) {
  EXPECT_EQ(parseSubtractionMode("n"), SubtractionMode::Off);
  EXPECT_EQ(parseSubtractionMode("Local"), SubtractionMode::Local);
  EXPECT_EQ(parseSubtractionMode("IMAGE"), SubtractionMode::Image);
  EXPECT_THROW(parseSubtractionMode("ALL"), ConfigError);
}

TEST(LensSubtraction, FitsTheChosenGalaxyAndLeavesTheNoise) {
  // A bright de Vaucouleurs galaxy (chosen) and a faint exponential one (not), with noise.
  const double sigmaAdu = 4.0, fluxAdu = 1.5e5;
  ImageD sky(160, 140, 0.0);
  addGalaxy(sky, 60.4, 70.2, fluxAdu, 7.0, 4.0, 0.75, 0.4);
  addGalaxy(sky, 130.0, 40.0, 3000.0, 3.0, 1.0, 0.5, 1.0);
  const double fwhmPix = kSeeingArcsec / kScaleArcsec;
  ImageD image = simulation::applyGaussianSeeing(sky, fwhmPix, 1.0);
  ImageD noiseless = image;
  std::mt19937_64 rng(3);
  std::normal_distribution<double> noise(0.0, sigmaAdu);
  for (double& v : image.pixels()) v += noise(rng);
  const Table catalog = catalogOf({{1, 1, 60.5, 70.0}, {2, 1, 130.0, 40.0}, {1, 2, 60.4, 70.1}});

  const Subtraction sub =
      subtractLensLight(toFloat(image), ImageF(), sigmaAdu, catalog, settings());
  ASSERT_EQ(sub.galaxies.size(), 1u);  // the bright level-1 row only
  const FittedGalaxy& g = sub.galaxies[0];
  EXPECT_EQ(g.row, 0u);
  EXPECT_EQ(g.number, 1);
  ASSERT_TRUE(g.subtracted()) << g.fit.message;
  EXPECT_EQ(sub.subtractedCount(), 1);
  // The cut-out: 24" = 96 px, so 48 px either side of the pixel nearest the centroid: X_IMAGE
  // 60.5 is 0-based 59.5, rounded to 60.
  EXPECT_EQ(g.x0, 12);
  EXPECT_EQ(g.width, 97);
  EXPECT_NEAR(g.fittedXPix(), 60.4, 0.05);
  EXPECT_NEAR(g.fittedYPix(), 70.2, 0.05);
  EXPECT_NEAR(g.fit.params.sersicIndex, 4.0, 0.3);

  // The model holds the galaxy's flux within its cut-out, and nothing outside it.
  double modelSum = 0.0, truthInCutout = 0.0;
  for (std::int64_t y = 0; y < 140; ++y) {
    for (std::int64_t x = 0; x < 160; ++x) {
      const bool inside = x >= g.x0 && x < g.x0 + g.width && y >= g.y0 && y < g.y0 + g.height;
      if (!inside) {
        EXPECT_EQ(sub.model(x, y), 0.0f);
        continue;
      }
      modelSum += sub.model(x, y);
      if (x < 100) truthInCutout += noiseless(x, y);  // the faint galaxy lies beyond x = 107
    }
  }
  EXPECT_NEAR(modelSum / truthInCutout, 1.0, 0.01);
  // The residual is the noise: its RMS over the galaxy's inner 21 x 21 pixels is sigma.
  double sumSq = 0.0;
  int count = 0;
  for (std::int64_t y = 60; y <= 80; ++y) {
    for (std::int64_t x = 50; x <= 70; ++x) {
      sumSq += double(sub.residual(x, y)) * sub.residual(x, y);
      ++count;
    }
  }
  EXPECT_NEAR(std::sqrt(sumSq / count), sigmaAdu, 0.15 * sigmaAdu);
}

TEST(LensSubtraction, AFailedFitLeavesItsGalaxyInTheImage) {
  const double sigmaAdu = 4.0;
  ImageD sky(100, 100, 0.0);
  addGalaxy(sky, 50.0, 50.0, 1e5, 6.0, 4.0, 0.8, 0.0);
  const ImageF image = toFloat(simulation::applyGaussianSeeing(sky, 3.6, 1.0));
  const Table catalog = catalogOf({{1, 1, 50.0, 50.0}});

  // One iteration: the solver stops before it converges.
  SubtractionSettings s = settings();
  s.fit.fit.maxIterations = 1;
  const Subtraction stopped = subtractLensLight(image, ImageF(), sigmaAdu, catalog, s);
  ASSERT_EQ(stopped.galaxies.size(), 1u);
  EXPECT_EQ(stopped.galaxies[0].failure & kFitNotConverged, kFitNotConverged);
  EXPECT_EQ(stopped.subtractedCount(), 0);
  for (std::int64_t i = 0; i < image.size(); ++i) {
    ASSERT_EQ(stopped.model[i], 0.0f);
    ASSERT_EQ(stopped.residual[i], image[i]);
  }

  // Every weight rejected (infinite variance): no pixel to fit.
  const ImageF rejected(100, 100, std::numeric_limits<float>::infinity());
  const Subtraction empty = subtractLensLight(image, rejected, sigmaAdu, catalog, settings());
  EXPECT_EQ(empty.galaxies[0].failure, kFitTooFewPixels);
  EXPECT_EQ(empty.subtractedCount(), 0);

  SubtractionSettings bad = settings();
  bad.selectExpression = "MAG_ISO <";
  EXPECT_THROW(subtractLensLight(image, ImageF(), sigmaAdu, catalog, bad), ConfigError);
  bad.selectExpression = "FLUX_AUTO > 1";  // no such column
  EXPECT_THROW(subtractLensLight(image, ImageF(), sigmaAdu, catalog, bad), ConfigError);
}

// An arc in the halo: a ridge of Gaussian width 1.2 px along +-40 degrees of a circle of
// `radiusPix` about (xPix, yPix) (1-based), towards +x, holding `fluxAdu` before the seeing.
void addArc(ImageD& image, double xPix, double yPix, double radiusPix, double fluxAdu) {
  ImageD arc(image.width(), image.height(), 0.0);
  double total = 0;
  for (std::int64_t y = 0; y < arc.height(); ++y) {
    for (std::int64_t x = 0; x < arc.width(); ++x) {
      const double dx = double(x) - (xPix - 1.0), dy = double(y) - (yPix - 1.0);
      if (std::abs(std::atan2(dy, dx)) > 40.0 * std::numbers::pi / 180.0) continue;
      arc(x, y) = std::exp(-0.5 * std::pow((std::hypot(dx, dy) - radiusPix) / 1.2, 2));
      total += arc(x, y);
    }
  }
  for (std::int64_t i = 0; i < arc.size(); ++i) image[i] += arc[i] * fluxAdu / total;
}

// The pre-screen: a bright galaxy alone is not fitted; with an arc in its halo it is; with a
// neighbour it is unless the catalog already holds the neighbour as an object of its own.
TEST(LensSubtraction, ThePrescreenFitsOnlyGalaxiesWithSomethingInTheirResidual) {
  const double sigmaAdu = 4.0;
  auto image = [&](bool arc, bool neighbour) {
    ImageD sky(120, 120, 0.0);
    addGalaxy(sky, 60.4, 60.2, 1.5e5, 7.0, 4.0, 0.75, 0.4);
    if (arc) addArc(sky, 60.4, 60.2, 12.0, 4000.0);  // 3" from the centre, S/N about 100
    if (neighbour) addGalaxy(sky, 60.0, 76.0, 4000.0, 1.5, 1.0, 0.8, 0.0);  // 4" away
    ImageD seen = simulation::applyGaussianSeeing(sky, kSeeingArcsec / kScaleArcsec, 1.0);
    std::mt19937_64 rng(8);
    std::normal_distribution<double> noise(0.0, sigmaAdu);
    for (double& v : seen.pixels()) v += noise(rng);
    return toFloat(seen);
  };
  // The galaxy's row; the neighbour's own row (with most of its flux) when `separated`.
  auto catalog = [](bool separated) {
    Table t({spec("NUMBER"), spec("THRESH_LEVEL"), spec("X_IMAGE"), spec("Y_IMAGE"),
             spec("MAG_ISO"), spec("FLUX_ISO")});
    double* row = t.appendRow();
    row[0] = 1, row[1] = 1, row[2] = 60.4, row[3] = 60.2, row[4] = 17.6, row[5] = 1.4e5;
    if (separated) {
      row = t.appendRow();
      row[0] = 2, row[1] = 3, row[2] = 60.1, row[3] = 75.8, row[4] = 21.2, row[5] = 3500.0;
    }
    return t;
  };
  SubtractionSettings s = settings();
  // As a search with SNR_MIN 40, RESOLVED_MIN 1" and LENS_RADIUS 6" sets them.
  s.prescreenMinSnr = 20.0;
  s.prescreenMinSizeArcsec = 0.75;
  s.searchRadiusArcsec = 6.0;

  const Subtraction alone =
      subtractLensLight(image(false, false), ImageF(), sigmaAdu, catalog(false), s);
  ASSERT_EQ(alone.galaxies.size(), 1u);
  EXPECT_EQ(alone.galaxies[0].failure, kFitSkipped);
  EXPECT_FALSE(alone.galaxies[0].fitted());
  EXPECT_FALSE(alone.galaxies[0].subtracted());
  EXPECT_TRUE(std::isnan(alone.galaxies[0].quickResidualSnr)) << alone.galaxies[0].quickResidualSnr;
  EXPECT_EQ(alone.fittedCount(), 0);
  for (float v : alone.model.pixels()) ASSERT_EQ(v, 0.0f);

  const Subtraction withArc =
      subtractLensLight(image(true, false), ImageF(), sigmaAdu, catalog(false), s);
  ASSERT_TRUE(withArc.galaxies[0].subtracted()) << withArc.galaxies[0].failure;
  EXPECT_GT(withArc.galaxies[0].quickResidualSnr, 50.0);
  EXPECT_NEAR(withArc.galaxies[0].fit.params.sersicIndex, 4.0, 0.3);

  const ImageF crowded = image(false, true);
  EXPECT_TRUE(
      subtractLensLight(crowded, ImageF(), sigmaAdu, catalog(false), s).galaxies[0].subtracted());
  EXPECT_EQ(subtractLensLight(crowded, ImageF(), sigmaAdu, catalog(true), s).galaxies[0].failure,
            kFitSkipped);

  // Without the pre-screen every chosen galaxy is fitted.
  s.prescreenMinSnr = 0.0;
  EXPECT_TRUE(subtractLensLight(image(false, false), ImageF(), sigmaAdu, catalog(false), s)
                  .galaxies[0]
                  .subtracted());
}

TEST(LensSubtraction, AFitOnABoundIsFlaggedAndSubtracted) {
  const double sigmaAdu = 4.0;
  ImageD sky(100, 100, 0.0);
  addGalaxy(sky, 50.0, 50.0, 1e5, 6.0, 4.0, 0.8, 0.0);
  const ImageF image = toFloat(simulation::applyGaussianSeeing(sky, 3.6, 1.0));
  SubtractionSettings s = settings();
  s.fit.fit.maxIndex = 2.5;  // below the galaxy's 4
  const Subtraction sub =
      subtractLensLight(image, ImageF(), sigmaAdu, catalogOf({{1, 1, 50, 50}}), s);
  EXPECT_EQ(sub.galaxies[0].failure, kFitAtBound);
  EXPECT_TRUE(sub.galaxies[0].subtracted());
  EXPECT_EQ(sub.subtractedCount(), 1);
}

TEST(LensSubtraction, ResidualRowsBelongToTheNearestSubtractedGalaxy) {
  Subtraction sub;
  FittedGalaxy a, b, failed;
  a.x0 = 0;  // fitted centres (1-based): a at (11, 11), b at (41, 11)
  a.fit.params.xPix = 10.0;
  a.fit.params.yPix = 10.0;
  b.x0 = 30;
  b.fit.params.xPix = 10.0;
  b.fit.params.yPix = 10.0;
  failed = a;
  failed.failure = kFitNotConverged;
  failed.x0 = 10;  // at (21, 11), between them, but left in the image
  sub.galaxies = {a, failed, b};
  // 4 px = 1" at 0.25"/px; radius 3" = 12 px.
  Table rows({spec("X_IMAGE"), spec("Y_IMAGE")});
  const std::vector<std::array<double, 2>> xy = {
      {11.0, 13.0},  // 2 px from a: its own core, left out
      {11.0, 15.0},  // 4 px from a: exactly 1", kept for a
      {20.0, 11.0},  // 9 px from a, 21 from b: a (the failed galaxy does not count)
      {33.0, 11.0},  // 8 px from b: b
      {41.0, 24.0},  // 13 px from b: beyond 3"
  };
  for (const auto& p : xy) {
    double* r = rows.appendRow();
    r[0] = p[0];
    r[1] = p[1];
  }
  const ResidualRows near = residualRowsNearLenses(rows, sub, 3.0, 0.25);
  EXPECT_EQ(near.rows, (std::vector<std::int64_t>{1, 2, 3}));
  EXPECT_EQ(near.galaxy, (std::vector<std::size_t>{0, 0, 2}));
}

}  // namespace
}  // namespace octarc::lenslight
