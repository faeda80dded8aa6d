// The lens-light model and its fit: the rendered model against the analytic total flux and the
// lens simulator's independent renderer (adaptive integration), the fit of a simulated Sersic
// galaxy without and with noise, and the residual of a lens with an arc in its halo against the
// arc alone.
#include "octarc/lenslight/SersicFit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "octarc/core/Error.h"
#include "octarc/lenslight/SersicModel.h"
#include "octarc/measure/Registry.h"
#include "octarc/run/ImageRun.h"
#include "octarc/run/Levels.h"
#include "octarc/simulation/LensLight.h"
#include "octarc/simulation/Psf.h"

namespace octarc::lenslight {
namespace {

constexpr double kPsfFwhmPix = 3.5;
const double kPsfSigmaPix = kPsfFwhmPix / (2.0 * std::sqrt(2.0 * std::log(2.0)));

// The galaxy as the lens simulator draws it (simulation/LensLight.h, adaptive integration over
// each pixel) and its seeing: a renderer independent of the fitted model's.
ImageD simulatedGalaxy(const SersicParams& p, int size) {
  simulation::SurveyGrid grid;
  grid.width = grid.height = size;
  grid.pixelScaleArcsec = 1.0;  // in pixels
  grid.lensXPix = p.xPix;
  grid.lensYPix = p.yPix;
  simulation::SersicLightParams light;
  light.sersicIndex = p.sersicIndex;
  light.halfLightRadiusArcsec = p.halfLightRadiusPix;
  light.axisRatio = p.axisRatio;
  light.positionAngleRad = p.positionAngleRad;
  light.totalFlux = p.totalFluxAdu;
  ImageD image(size, size, 0.0);
  simulation::addSersicLight(image, grid, light);
  return simulation::applyGaussianSeeing(image, kPsfFwhmPix, 1.0);
}

SersicParams truth() {
  SersicParams p;
  p.xPix = 40.3;
  p.yPix = 39.6;
  p.totalFluxAdu = 2.0e5;
  p.halfLightRadiusPix = 6.0;
  p.sersicIndex = 4.0;
  p.axisRatio = 0.7;
  p.positionAngleRad = 0.5;
  return p;
}

double sum(const ImageD& image) {
  double s = 0;
  for (double v : image.pixels()) s += v;
  return s;
}

TEST(SersicModel, ExponentialHoldsItsTotalFlux) {
  // n = 1, r_e = 4 px: beyond the 201^2 stamp lies e^-42 of the flux; the sum is the total but
  // for the pixels beyond 10 px, taken at their centres (a convex profile's midpoint is low by
  // f''/24 of the pixel: 3e-4 of the total here).
  SersicParams p;
  p.xPix = p.yPix = 100.2;
  p.totalFluxAdu = 1000.0;
  p.halfLightRadiusPix = 4.0;
  p.sersicIndex = 1.0;
  p.axisRatio = 0.6;
  p.positionAngleRad = 1.0;
  EXPECT_NEAR(sum(renderSersic(p, 201, 201, 0.0)), 1000.0, 0.4);
  EXPECT_NEAR(sum(renderSersic(p, 201, 201, 2.0)), sum(renderSersic(p, 201, 201, 0.0)),
              1e-6);  // the PSF keeps the flux
  // I_e of the analytic normalisation: exp(-b_1 (r/r_e - 1)) integrates to 2 pi q r_e^2 e^b/b^2.
  const double b1 = simulation::sersicBn(1.0);
  EXPECT_NEAR(
      sersicIntensityAtRe(p) * 2.0 * std::numbers::pi * 0.6 * 16.0 * std::exp(b1) / (b1 * b1),
      1000.0, 1e-9);
}

TEST(SersicModel, AgreesWithTheSimulatorsAdaptiveIntegration) {
  // De Vaucouleurs, cusp included: every pixel within 0.2 % of the brightest pixel.
  const SersicParams p = truth();
  const ImageD ours = renderSersic(p, 81, 81, kPsfSigmaPix);
  const ImageD reference = simulatedGalaxy(p, 81);
  double peak = 0, worst = 0;
  for (double v : reference.pixels()) peak = std::max(peak, v);
  for (std::int64_t i = 0; i < ours.size(); ++i)
    worst = std::max(worst, std::abs(ours[i] - reference[i]));
  EXPECT_LT(worst, 2e-3 * peak);
  EXPECT_THROW(renderSersic(SersicParams{0, 0, 1, 1, 4, 1.5, 0}, 5, 5, 0), ConfigError);
}

TEST(SersicFit, RecoversANoiselessGalaxy) {
  const SersicParams p = truth();
  const ImageD stamp = simulatedGalaxy(p, 81);
  const ImageD variance(81, 81, 1.0);
  SersicFitSettings settings;
  settings.psfSigmaPix = kPsfSigmaPix;
  const SersicFitResult fit = fitSersic(stamp, variance, {}, momentsStart(stamp), settings);
  ASSERT_TRUE(fit.converged) << fit.message;
  // Only the two renderers differ (0.2 % of the peak at most): the parameters come back to a
  // few parts in a thousand.
  EXPECT_NEAR(fit.params.xPix, p.xPix, 2e-3);
  EXPECT_NEAR(fit.params.yPix, p.yPix, 2e-3);
  EXPECT_NEAR(fit.params.totalFluxAdu / p.totalFluxAdu, 1.0, 3e-3);
  EXPECT_NEAR(fit.params.halfLightRadiusPix / p.halfLightRadiusPix, 1.0, 5e-3);
  EXPECT_NEAR(fit.params.sersicIndex, p.sersicIndex, 0.02);
  EXPECT_NEAR(fit.params.axisRatio, p.axisRatio, 1e-3);
  EXPECT_NEAR(fit.params.positionAngleRad, p.positionAngleRad, 1e-3);
}

TEST(SersicFit, RecoversANoisyGalaxyWithinItsErrors) {
  const SersicParams p = truth();
  ImageD stamp = simulatedGalaxy(p, 81);
  const double sigmaAdu = 5.0;  // peak S/N about 150, a bright (R ~ 19) lens at DLS depth
  std::mt19937_64 rng(11);
  std::normal_distribution<double> noise(0.0, sigmaAdu);
  for (double& v : stamp.pixels()) v += noise(rng);
  const ImageD variance(81, 81, sigmaAdu * sigmaAdu);
  SersicFitSettings settings;
  settings.psfSigmaPix = kPsfSigmaPix;
  const SersicFitResult fit = fitSersic(stamp, variance, {}, momentsStart(stamp), settings);
  ASSERT_TRUE(fit.converged) << fit.message;
  // chi^2 per degree of freedom near 1: the model is the galaxy.
  EXPECT_NEAR(fit.chi2 / double(fit.degreesOfFreedom), 1.0, 0.05);
  // Each parameter within 3.5 sigma of its error, the errors themselves small.
  auto within = [](double got, double want, double error, const char* name) {
    EXPECT_TRUE(std::isfinite(error) && error > 0) << name;
    EXPECT_LT(std::abs(got - want), 3.5 * error) << name << ": " << got << " +- " << error;
  };
  within(fit.params.xPix, p.xPix, fit.errors.xPix, "x");
  within(fit.params.yPix, p.yPix, fit.errors.yPix, "y");
  within(fit.params.totalFluxAdu, p.totalFluxAdu, fit.errors.totalFluxAdu, "flux");
  within(fit.params.halfLightRadiusPix, p.halfLightRadiusPix, fit.errors.halfLightRadiusPix, "r_e");
  within(fit.params.sersicIndex, p.sersicIndex, fit.errors.sersicIndex, "n");
  within(fit.params.axisRatio, p.axisRatio, fit.errors.axisRatio, "q");
  within(fit.params.positionAngleRad, p.positionAngleRad, fit.errors.positionAngleRad, "theta");
  EXPECT_LT(fit.errors.halfLightRadiusPix / p.halfLightRadiusPix, 0.05);
  EXPECT_LT(fit.errors.sersicIndex, 0.3);
}

// A round galaxy sits where an axis ratio bounded by 1 would put the fit on its bound; the fit
// must still converge, from a round start, without and with noise, and give the radius and flux.
TEST(SersicFit, RecoversARoundGalaxy) {
  SersicParams p = truth();
  p.axisRatio = 1.0;
  const ImageD clean = simulatedGalaxy(p, 81);
  const ImageD variance(81, 81, 25.0);
  SersicFitSettings settings;
  settings.psfSigmaPix = kPsfSigmaPix;
  SersicParams roundStart = momentsStart(clean);
  roundStart.axisRatio = 1.0;
  const SersicFitResult noiseless = fitSersic(clean, variance, {}, roundStart, settings);
  ASSERT_TRUE(noiseless.converged) << noiseless.message;
  EXPECT_NEAR(noiseless.params.xPix, p.xPix, 2e-3);
  EXPECT_NEAR(noiseless.params.totalFluxAdu / p.totalFluxAdu, 1.0, 3e-3);
  EXPECT_NEAR(noiseless.params.halfLightRadiusPix / p.halfLightRadiusPix, 1.0, 5e-3);
  EXPECT_NEAR(noiseless.params.sersicIndex, p.sersicIndex, 0.02);
  EXPECT_GT(noiseless.params.axisRatio, 0.998);

  // Noisy, over several noise draws (a fit near q = 1 steps to either side of it).
  for (int seed = 1; seed <= 5; ++seed) {
    ImageD stamp = clean;
    std::mt19937_64 rng{std::uint64_t(seed)};
    std::normal_distribution<double> noise(0.0, 5.0);
    for (double& v : stamp.pixels()) v += noise(rng);
    const SersicFitResult fit = fitSersic(stamp, variance, {}, momentsStart(stamp), settings);
    ASSERT_TRUE(fit.converged) << "seed " << seed << ": " << fit.message;
    EXPECT_NEAR(fit.chi2 / double(fit.degreesOfFreedom), 1.0, 0.05) << "seed " << seed;
    EXPECT_GT(fit.params.axisRatio, 0.95) << "seed " << seed;
    EXPECT_NEAR(fit.params.halfLightRadiusPix / p.halfLightRadiusPix, 1.0,
                3.5 * fit.errors.halfLightRadiusPix / p.halfLightRadiusPix)
        << "seed " << seed;
    EXPECT_NEAR(fit.params.totalFluxAdu, p.totalFluxAdu, 3.5 * fit.errors.totalFluxAdu)
        << "seed " << seed;
  }
}

// Started round along the minor axis, the fit of an elongated galaxy elongates it across that
// axis (an axis ratio above 1, the axes then swapped): the same galaxy and the same errors as
// from a start along the major axis.
TEST(SersicFit, SwappedAxesGiveTheSameFitAndErrors) {
  const SersicParams p = truth();  // q = 0.7, theta = 0.5
  ImageD stamp = simulatedGalaxy(p, 81);
  std::mt19937_64 rng{5};
  std::normal_distribution<double> noise(0.0, 5.0);
  for (double& v : stamp.pixels()) v += noise(rng);
  const ImageD variance(81, 81, 25.0);
  SersicFitSettings settings;
  settings.psfSigmaPix = kPsfSigmaPix;
  SersicParams alongMajor = momentsStart(stamp);
  alongMajor.positionAngleRad = p.positionAngleRad;
  SersicParams roundAcross = alongMajor;
  roundAcross.axisRatio = 1.0;
  roundAcross.positionAngleRad = p.positionAngleRad + 0.5 * std::numbers::pi;
  const SersicFitResult a = fitSersic(stamp, variance, {}, alongMajor, settings);
  const SersicFitResult b = fitSersic(stamp, variance, {}, roundAcross, settings);
  ASSERT_TRUE(a.converged) << a.message;
  ASSERT_TRUE(b.converged) << b.message;
  EXPECT_NEAR(b.params.axisRatio, a.params.axisRatio, 1e-4);
  EXPECT_NEAR(b.params.positionAngleRad, a.params.positionAngleRad, 1e-4);
  EXPECT_NEAR(b.params.halfLightRadiusPix / a.params.halfLightRadiusPix, 1.0, 1e-4);
  EXPECT_NEAR(b.params.totalFluxAdu / a.params.totalFluxAdu, 1.0, 1e-5);
  EXPECT_NEAR(b.errors.axisRatio / a.errors.axisRatio, 1.0, 2e-3);
  EXPECT_NEAR(b.errors.halfLightRadiusPix / a.errors.halfLightRadiusPix, 1.0, 2e-3);
  EXPECT_NEAR(b.errors.positionAngleRad / a.errors.positionAngleRad, 1.0, 2e-3);
  EXPECT_NEAR(a.params.axisRatio, p.axisRatio, 3.5 * a.errors.axisRatio);
}

// An arc: a Gaussian ridge of width 1.2 px along 80 degrees of a circle of radius 11 px about the
// lens, seen through the same PSF.
ImageD arcImage(const SersicParams& lens, int size, double fluxAdu) {
  ImageD arc(size, size, 0.0);
  const double radius = 11.0, width = 1.2, half = 40.0 * std::numbers::pi / 180.0;
  for (std::int64_t y = 0; y < size; ++y) {
    for (std::int64_t x = 0; x < size; ++x) {
      const double dx = double(x) - lens.xPix, dy = double(y) - lens.yPix;
      const double r = std::hypot(dx, dy), phi = std::atan2(dy, dx) - 0.3;
      const double along = std::abs(std::remainder(phi, 2.0 * std::numbers::pi));
      const double taper =
          along < half ? 1.0 : std::exp(-0.5 * std::pow((along - half) * r / width, 2));
      arc(x, y) = taper * std::exp(-0.5 * std::pow((r - radius) / width, 2));
    }
  }
  const double total = sum(arc);
  for (double& v : arc.pixels()) v *= fluxAdu / total;
  return simulation::applyGaussianSeeing(arc, kPsfFwhmPix, 1.0);
}

struct ArcMeasurement {
  double fluxIso = std::nan(""), arcness = std::nan("");
  int objects = 0;
};

// The arc as `octarc detect` would measure it on `image` at one level of 3 sigma: the object
// nearest the arc's middle, 11 px from the lens at angle 0.3 rad.
ArcMeasurement measureArc(const ImageD& image, const SersicParams& lens, double sigmaAdu) {
  ImageF pixels(image.width(), image.height());
  for (std::int64_t i = 0; i < image.size(); ++i) pixels[i] = float(image[i]);
  InMemoryImage description;
  description.sigmaAdu = sigmaAdu;
  PreparedImage prepared = prepareInMemory(std::move(pixels), description);
  const MeasurementPlan plan =
      MeasurementPlan::build({{"X_IMAGE"}, {"Y_IMAGE"}, {"FLUX_ISO"}, {"ARCNESS"}}, {}, nullptr);
  MeasureContext context = prepared.context(0.0, 1.0);
  context.levels = levelsAtThresholds({3.0 * sigmaAdu}, sigmaAdu);
  DetectionRequest request;
  request.levels = context.levels;
  const ImageRunResult run = detectAndMeasure(prepared, plan, context, request);
  const Table rows = run.rowsInCatalogOrder();
  const double ax = lens.xPix + 11.0 * std::cos(0.3) + 1.0,
               ay = lens.yPix + 11.0 * std::sin(0.3) + 1.0;
  ArcMeasurement best;
  double nearest = 4.0;  // pixels
  best.objects = int(rows.rows());
  for (std::int64_t r = 0; r < rows.rows(); ++r) {
    const double d = std::hypot(rows.value(r, 0) - ax, rows.value(r, 1) - ay);
    if (d < nearest) {
      nearest = d;
      best.fluxIso = rows.value(r, 2);
      best.arcness = rows.value(r, 3);
    }
  }
  return best;
}

TEST(LensLight, ResidualRecoversAnArcInsideTheHalo) {
  const SersicParams lens = truth();
  const int size = 81;
  const double sigmaAdu = 5.0;
  const ImageD arc = arcImage(lens, size, 6000.0);
  ImageD noise(size, size, 0.0);
  std::mt19937_64 rng(5);
  std::normal_distribution<double> gauss(0.0, sigmaAdu);
  for (double& v : noise.pixels()) v = gauss(rng);
  ImageD arcOnly = arc, both = simulatedGalaxy(lens, size);
  for (std::int64_t i = 0; i < both.size(); ++i) {
    arcOnly[i] += noise[i];
    both[i] += arc[i] + noise[i];
  }
  const ArcMeasurement alone = measureArc(arcOnly, lens, sigmaAdu);
  ASSERT_TRUE(std::isfinite(alone.fluxIso));
  EXPECT_GT(alone.arcness, 0.1);  // it is an arc

  // Without subtraction, the arc is swallowed by the halo at 3 sigma: no object at its middle.
  EXPECT_FALSE(std::isfinite(measureArc(both, lens, sigmaAdu).fluxIso));

  LensLightSettings settings;
  settings.fit.psfSigmaPix = kPsfSigmaPix;
  const LensLightModel model =
      fitLensLight(both, ImageD(size, size, sigmaAdu * sigmaAdu), settings);
  ASSERT_TRUE(model.fit.converged) << model.fit.message;
  EXPECT_NEAR(model.fit.params.totalFluxAdu / lens.totalFluxAdu, 1.0, 0.02);
  const ArcMeasurement recovered = measureArc(model.residual, lens, sigmaAdu);
  ASSERT_TRUE(std::isfinite(recovered.fluxIso));
  EXPECT_NEAR(recovered.fluxIso / alone.fluxIso, 1.0, 0.1);
  EXPECT_NEAR(recovered.arcness, alone.arcness, 0.03);
}

// A ring: a Gaussian ridge of width 1.2 px all round a circle of `radius` px about the lens,
// seen through the PSF (an Einstein ring, the case where a fit is most tempted to take the arc:
// it is as symmetric as the galaxy).
ImageD ringImage(const SersicParams& lens, int size, double radius, double fluxAdu) {
  ImageD ring(size, size, 0.0);
  for (std::int64_t y = 0; y < size; ++y) {
    for (std::int64_t x = 0; x < size; ++x) {
      const double r = std::hypot(double(x) - lens.xPix, double(y) - lens.yPix);
      ring(x, y) = std::exp(-0.5 * std::pow((r - radius) / 1.2, 2));
    }
  }
  const double total = sum(ring);
  for (double& v : ring.pixels()) v *= fluxAdu / total;
  return simulation::applyGaussianSeeing(ring, kPsfFwhmPix, 1.0);
}

// Within `sigmas` of its error, every parameter of `fit` against `p`; the count of those off.
int parametersOff(const SersicFitResult& fit, const SersicParams& p, double sigmas) {
  auto off = [&](double got, double want, double error) {
    return !(std::isfinite(error) && std::abs(got - want) < sigmas * error);
  };
  return off(fit.params.xPix, p.xPix, fit.errors.xPix) +
         off(fit.params.yPix, p.yPix, fit.errors.yPix) +
         off(fit.params.totalFluxAdu, p.totalFluxAdu, fit.errors.totalFluxAdu) +
         off(fit.params.halfLightRadiusPix, p.halfLightRadiusPix, fit.errors.halfLightRadiusPix) +
         off(fit.params.sersicIndex, p.sersicIndex, fit.errors.sersicIndex) +
         off(fit.params.axisRatio, p.axisRatio, fit.errors.axisRatio) +
         off(fit.params.positionAngleRad, p.positionAngleRad, fit.errors.positionAngleRad);
}

TEST(LensLight, TheRobustFitDoesNotEatARing) {
  // A galaxy with a ring at 10 px holding 6 % of its flux, and noise.
  const SersicParams lens = truth();
  const int size = 81;
  const double sigmaAdu = 5.0;
  ImageD image = simulatedGalaxy(lens, size);
  const ImageD ring = ringImage(lens, size, 10.0, 12000.0);
  std::mt19937_64 rng(17);
  std::normal_distribution<double> gauss(0.0, sigmaAdu);
  for (std::int64_t i = 0; i < image.size(); ++i) image[i] += ring[i] + gauss(rng);
  const ImageD variance(size, size, sigmaAdu * sigmaAdu);

  // Plain least squares takes the ring into the galaxy: its parameters are off by many sigma.
  SersicFitSettings plain;
  plain.psfSigmaPix = kPsfSigmaPix;
  const SersicFitResult eaten = fitSersic(image, variance, {}, momentsStart(image), plain);
  ASSERT_TRUE(eaten.converged) << eaten.message;
  EXPECT_GE(parametersOff(eaten, lens, 5.0), 2);

  // The robust fit, then masked: the galaxy as drawn, every parameter within 3.5 sigma.
  LensLightSettings settings;
  settings.fit.psfSigmaPix = kPsfSigmaPix;
  const LensLightModel model = fitLensLight(image, variance, settings);
  ASSERT_TRUE(model.fit.converged) << model.fit.message;
  EXPECT_EQ(parametersOff(model.fit, lens, 3.5), 0)
      << "n " << model.fit.params.sersicIndex << " +- " << model.fit.errors.sersicIndex << ", r_e "
      << model.fit.params.halfLightRadiusPix << " +- " << model.fit.errors.halfLightRadiusPix;
  EXPECT_FALSE(model.fit.shapeAtBound);
  // The ring is in the residual: its flux within 3 px of the circle, to 5 %.
  double inRing = 0, drawn = 0;
  for (std::int64_t y = 0; y < size; ++y) {
    for (std::int64_t x = 0; x < size; ++x) {
      if (std::abs(std::hypot(double(x) - lens.xPix, double(y) - lens.yPix) - 10.0) > 3.0) continue;
      inRing += model.residual(x, y);
      drawn += ring(x, y);
    }
  }
  EXPECT_NEAR(inRing / drawn, 1.0, 0.05);
}

TEST(SersicFit, AParameterEndingOnItsBoundIsFlagged) {
  // A de Vaucouleurs galaxy fitted with the index held below 3: it ends on that bound.
  const SersicParams p = truth();
  const ImageD stamp = simulatedGalaxy(p, 81);
  const ImageD variance(81, 81, 1.0);
  SersicFitSettings settings;
  settings.psfSigmaPix = kPsfSigmaPix;
  EXPECT_FALSE(fitSersic(stamp, variance, {}, momentsStart(stamp), settings).shapeAtBound);
  settings.maxIndex = 3.0;
  const SersicFitResult capped = fitSersic(stamp, variance, {}, momentsStart(stamp), settings);
  EXPECT_TRUE(capped.shapeAtBound);
  EXPECT_NEAR(capped.params.sersicIndex, 3.0, 1e-3);
  // The axis ratio too: a galaxy of q = 0.7 fitted with q at least 0.9 (on (0.9, 1/0.9]).
  settings.maxIndex = 8.0;
  settings.minAxisRatio = 0.9;
  EXPECT_TRUE(fitSersic(stamp, variance, {}, momentsStart(stamp), settings).shapeAtBound);
}

}  // namespace
}  // namespace octarc::lenslight
