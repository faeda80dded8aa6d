// Lens-light subtraction over an image: which catalog rows are fitted, the model and residual
// images of two galaxies drawn by the lens simulator's renderer, a fit that fails leaving its
// galaxy in the image, and which residual rows belong to which galaxy (hand-placed rows).
#include "octarc/lenslight/LensSubtraction.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <utility>

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

// The flux ratio in the core, against sums done by hand: the inverse-variance weighted
// least-squares amplitude over the pixels within the radius, nothing beyond it.
TEST(LensSubtraction, CoreFluxRatioIsTheModelsAmplitudeInTheCore) {
  ImageD model(9, 9, 2.0), stamp(9, 9, 6.0), variance(9, 9, 1.0);
  // Beyond 1.5 px of (4, 4): an arc ten times brighter, which must not count.
  for (std::int64_t y = 0; y < 9; ++y) {
    for (std::int64_t x = 0; x < 9; ++x) {
      if (std::hypot(double(x) - 4.0, double(y) - 4.0) > 1.5) stamp(x, y) = 60.0;
    }
  }
  EXPECT_DOUBLE_EQ(coreFluxRatio(stamp, variance, model, 4.0, 4.0, 1.5), 3.0);
  // Two pixels of the core with other values and variances: within 1 px of (4, 4) are the
  // centre and its four neighbours; (4, 4) holds d = 10, m = 4, v = 4 and (5, 4) d = 1, m = 1,
  // v = 0.5, the other three d = 6, m = 2, v = 1:
  // sum(d m / v) = 10 + 2 + 36 = 48, sum(m^2 / v) = 4 + 2 + 12 = 18, ratio 8/3.
  stamp(4, 4) = 10.0;
  model(4, 4) = 4.0;
  variance(4, 4) = 4.0;
  stamp(5, 4) = 1.0;
  model(5, 4) = 1.0;
  variance(5, 4) = 0.5;
  EXPECT_NEAR(coreFluxRatio(stamp, variance, model, 4.0, 4.0, 1.0), 8.0 / 3.0, 1e-14);
  // A rejected pixel (infinite variance) is left out: the same sums without (5, 4).
  variance(5, 4) = std::numeric_limits<double>::infinity();
  EXPECT_NEAR(coreFluxRatio(stamp, variance, model, 4.0, 4.0, 1.0), 46.0 / 16.0, 1e-14);
  // No model light in the core: no ratio.
  EXPECT_TRUE(std::isnan(coreFluxRatio(stamp, variance, ImageD(9, 9, 0.0), 4.0, 4.0, 1.5)));
  EXPECT_THROW(coreFluxRatio(stamp, variance, ImageD(8, 9, 1.0), 4.0, 4.0, 1.5), ConfigError);
}

// A circular Gaussian of `sigmaPix` and `fluxAdu` about (xPix, yPix) (0-based) integrated over
// each pixel exactly (a product of two differences of error functions).
ImageD pixelGaussian(int width, int height, double xPix, double yPix, double sigmaPix,
                     double fluxAdu) {
  auto along = [&](int i, double centre) {
    const double k = 1.0 / (std::sqrt(2.0) * sigmaPix);
    return 0.5 * (std::erf((i + 0.5 - centre) * k) - std::erf((i - 0.5 - centre) * k));
  };
  ImageD out(width, height, 0.0);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) out(x, y) = fluxAdu * along(x, xPix) * along(y, yPix);
  }
  return out;
}

struct Moments {
  double flux = 0, x = 0, y = 0, xx = 0, yy = 0;
};
Moments momentsOf(const ImageF& image) {
  Moments m;
  double sx = 0, sy = 0, sxx = 0, syy = 0;
  for (std::int64_t y = 0; y < image.height(); ++y) {
    for (std::int64_t x = 0; x < image.width(); ++x) {
      const double v = image(x, y);
      m.flux += v;
      sx += v * double(x);
      sy += v * double(y);
      sxx += v * double(x) * double(x);
      syy += v * double(y) * double(y);
    }
  }
  m.x = sx / m.flux;
  m.y = sy / m.flux;
  m.xx = sxx / m.flux - m.x * m.x;
  m.yy = syy / m.flux - m.y * m.y;
  return m;
}

// A Sersic profile of index 0.5 is a Gaussian (half-light radius sigma sqrt(2 ln 2)), so a galaxy
// fitted in another band must come back, drawn for this image, as a Gaussian whose variance is
// the galaxy's plus this image's PSF's (Gaussians convolved add their variances: the model is
// PSF-matched whether this image's seeing is broader or sharper) and whose flux is this image's
// (the band's times the flux ratio).
TEST(LensSubtraction, AGalaxyFittedInAnotherBandIsScaledAndPsfMatched) {
  const int side = 81;
  const double x0 = 40.3, y0 = 39.8;  // 0-based
  const double galaxySigmaPix = 3.0, bandFluxAdu = 2.0e5, ratio = 0.4;
  // The images hold no noise, but the fits are told of some, as a real image's would be: told
  // of almost none, they leave out (as an arc) the pixels where the model's quadrature is off
  // by a thousandth of the peak.
  const double kNoiseAdu = 20.0;
  const Table catalog = catalogOf({{1, 1, x0 + 1.0, y0 + 1.0}});
  for (const auto& [searchedPsfPix, bandPsfPix] : {std::pair{2.0, 1.2}, std::pair{1.0, 2.0}}) {
    SCOPED_TRACE(searchedPsfPix);
    const double searchedVariance =
        galaxySigmaPix * galaxySigmaPix + searchedPsfPix * searchedPsfPix;
    const double bandVariance = galaxySigmaPix * galaxySigmaPix + bandPsfPix * bandPsfPix;
    const ImageF searched = toFloat(
        pixelGaussian(side, side, x0, y0, std::sqrt(searchedVariance), ratio * bandFluxAdu));
    const ImageF band =
        toFloat(pixelGaussian(side, side, x0, y0, std::sqrt(bandVariance), bandFluxAdu));
    SubtractionSettings s = settings();
    s.cutoutArcsec = 80 * kScaleArcsec;  // the whole image
    s.seeingFwhmArcsec = searchedPsfPix * kScaleArcsec * 2.3548200450309493;
    FitBandImage fitBand;
    fitBand.pixels = &band;
    fitBand.sigmaAdu = kNoiseAdu;
    fitBand.seeingFwhmArcsec = bandPsfPix * kScaleArcsec * 2.3548200450309493;
    const Subtraction sub =
        subtractLensLight(searched, ImageF(), kNoiseAdu, catalog, s, {}, &fitBand);
    ASSERT_EQ(sub.galaxies.size(), 1u);
    const FittedGalaxy& g = sub.galaxies[0];
    EXPECT_EQ(g.failure, kFitOtherBand) << g.fit.message;
    EXPECT_NEAR(g.bandFluxRatio, ratio, 1e-3);
    EXPECT_NEAR(g.fit.params.sersicIndex, 0.5, 0.01);
    // The galaxy's own size: the band's PSF taken out.
    EXPECT_NEAR(g.fit.params.halfLightRadiusPix, galaxySigmaPix * std::sqrt(2.0 * std::log(2.0)),
                0.01);
    EXPECT_NEAR(g.fit.params.totalFluxAdu, ratio * bandFluxAdu, 1e-3 * ratio * bandFluxAdu);
    // The model: this image's flux (conserved), centre, and the variances added (plus the
    // pixel's 1/12, which the exact pixel integral holds too).
    const Moments m = momentsOf(sub.model);
    EXPECT_NEAR(m.flux / (ratio * bandFluxAdu), 1.0, 1e-3);
    EXPECT_NEAR(m.x, x0, 0.01);
    EXPECT_NEAR(m.y, y0, 0.01);
    EXPECT_NEAR(m.xx, searchedVariance + 1.0 / 12.0, 0.02 * searchedVariance);
    EXPECT_NEAR(m.yy, searchedVariance + 1.0 / 12.0, 0.02 * searchedVariance);
    // And the residual is nothing: at most a thousandth of the peak.
    double peak = 0, worst = 0;
    for (std::int64_t i = 0; i < searched.size(); ++i) {
      peak = std::max(peak, double(searched[i]));
      worst = std::max(worst, std::abs(double(sub.residual[i])));
    }
    EXPECT_LT(worst, 1e-3 * peak);
  }
}

TEST(LensSubtraction, AGalaxyWithoutLightInTheSearchedBandIsLeftAlone) {
  const int side = 61;
  const Table catalog = catalogOf({{1, 1, 31.0, 31.0}});
  const ImageF band = toFloat(pixelGaussian(side, side, 30.0, 30.0, 3.0, 1e5));
  FitBandImage fitBand;
  fitBand.pixels = &band;
  fitBand.sigmaAdu = 1.0;
  const ImageF empty(side, side, 0.0f);
  SubtractionSettings s = settings();
  s.seeingFwhmArcsec = 0.0;
  const Subtraction sub = subtractLensLight(empty, ImageF(), 1.0, catalog, s, {}, &fitBand);
  ASSERT_EQ(sub.galaxies.size(), 1u);
  EXPECT_EQ(sub.galaxies[0].failure, kFitOtherBand | kFitNoBandRatio);
  EXPECT_EQ(sub.subtractedCount(), 0);
  // Another band of another size is refused.
  const ImageF small(side - 1, side, 0.0f);
  fitBand.pixels = &small;
  EXPECT_THROW(subtractLensLight(empty, ImageF(), 1.0, catalog, s, {}, &fitBand), ConfigError);
}

}  // namespace
}  // namespace octarc::lenslight
