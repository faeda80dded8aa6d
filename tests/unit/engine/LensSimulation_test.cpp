#include "octarc/simulation/engine/LensSimulation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <set>
#include <vector>

#include "EngineTestSetup.h"
#include "LensTestSupport.h"
#include "TestPaths.h"
#include "octarc/app/Commands.h"
#include "octarc/core/Error.h"
#include "octarc/simulation/MultipleImageRegion.h"
#include "octarc/simulation/Seeds.h"

namespace octarc {
namespace {

namespace sim = octarc::simulation;

// One hand-made object row: only the columns the arc rules read matter.
void addObject(Table& t, int level, double xImage, double yImage, double sizePix, double flux) {
  double* row = t.appendRow();
  (void)row;
  const std::int64_t r = t.rows() - 1;
  t.setValue(r, t.findColumn("THRESH_LEVEL"), level);
  t.setValue(r, t.findColumn("X_IMAGE"), xImage);
  t.setValue(r, t.findColumn("Y_IMAGE"), yImage);
  t.setValue(r, t.findColumn("SIZE_IMAGE"), sizePix);
  t.setValue(r, t.findColumn("FLUX_ISO"), flux);
}

// Lens at 0-based (50, 50), i.e. X_IMAGE = Y_IMAGE = 51; 0.25"/px, so 4 px = 1.0".
constexpr double kLens = 50.0;
constexpr double kScale = 0.25;
// sqrt(2) * size * scale > 1.0" needs size > 2.828 px.
constexpr double kResolved = 3.0;
constexpr double kUnresolved = 2.8;

TEST(SelectArcs, DistanceAndSizeRulesAtTheirEdges) {
  Table t(measuredColumns());
  addObject(t, 1, 51.0, 51.0, 6.0, 1000.0);         // the lens: distance 0
  addObject(t, 1, 55.0, 51.0, kResolved, 50.0);     // exactly 1.0": an arc
  addObject(t, 1, 51.0, 54.96, kResolved, 80.0);    // 0.99": too close
  addObject(t, 1, 47.0, 51.0, kUnresolved, 500.0);  // 1.0" but unresolved
  std::mt19937_64 rng(1);
  const ArcSelection s = selectArcs(t, kLens, kLens, kScale, ArcRules{}, rng);
  ASSERT_EQ(s.arcRows, (std::vector<std::int64_t>{1}));
  EXPECT_EQ(s.chosenRow, 1);
  EXPECT_NEAR(s.distanceArcsec[1], 1.0, 1e-12);
  EXPECT_NEAR(s.distanceArcsec[2], 0.99, 1e-12);
  EXPECT_DOUBLE_EQ(s.distanceArcsec[0], 0.0);
}

TEST(SelectArcs, AnArcAloneAtItsLevelDoesNotCount) {
  Table t(measuredColumns());
  addObject(t, 1, 51.0, 51.0, 8.0, 1000.0);      // level 1: the lens and the arc merged
  addObject(t, 2, 59.0, 51.0, kResolved, 90.0);  // level 2: only the arc (2"), one object
  std::mt19937_64 rng(1);
  const ArcSelection s = selectArcs(t, kLens, kLens, kScale, ArcRules{}, rng);
  EXPECT_TRUE(s.arcRows.empty());
  EXPECT_EQ(s.chosenRow, -1);
  // With the two-object rule relaxed the same arc counts.
  ArcRules one;
  one.minObjects = 1;
  std::mt19937_64 rng2(1);
  EXPECT_EQ(selectArcs(t, kLens, kLens, kScale, one, rng2).chosenRow, 1);
}

TEST(SelectArcs, RandomLevelThenBrightestArcAllRowsKept) {
  Table t(measuredColumns());
  for (int level = 1; level <= 3; ++level) {
    addObject(t, level, 51.0, 51.0, 5.0, 1000.0);               // lens
    addObject(t, level, 61.0, 51.0, kResolved, 100.0 / level);  // arc at 2.5"
    addObject(t, level, 41.0, 51.0, kResolved, 200.0 / level);  // counter-arc, brighter
  }
  // Level 4: only the lens.
  addObject(t, 4, 51.0, 51.0, 3.0, 500.0);
  std::set<std::int64_t> chosen;
  for (std::uint64_t seed = 0; seed < 60; ++seed) {
    std::mt19937_64 rng = sim::systemRng(seed, 0);
    const ArcSelection s = selectArcs(t, kLens, kLens, kScale, ArcRules{}, rng);
    EXPECT_EQ(s.arcRows, (std::vector<std::int64_t>{1, 2, 4, 5, 7, 8}));
    chosen.insert(s.chosenRow);
    // The same stream gives the same choice.
    std::mt19937_64 again = sim::systemRng(seed, 0);
    EXPECT_EQ(selectArcs(t, kLens, kLens, kScale, ArcRules{}, again).chosenRow, s.chosenRow);
  }
  // Every qualifying level gets picked, always its brighter arc (rows 2, 5, 8).
  EXPECT_EQ(chosen, (std::set<std::int64_t>{2, 5, 8}));
}

TEST(SimulateSystem, BigEinsteinRadiusAndBrightSourceGiveAnArc) {
  const SimulationSetup setup = test::engineTestSetup();
  const SourceDatabase sources = test::engineTestSources();
  // A spiral source (database row 1) of 22.5 mag, 1.5" from the centre of a b = 2.5" lens of
  // 23 mag (sky sigma 1 ADU: the source has 1000 times the sky sigma in total flux).
  sim::LensSystem sys;
  sys.mass = {2.5, 0.05, 0.0, 0.3};
  sys.light = {4.0, 0.5, 0.8, 0.3, 0.0};
  sys.lensMag = 23.0;
  sys.source.betaArcsec = {1.5, 0.0};
  sys.sourceMag = 22.5;
  std::mt19937_64 rng(7);
  const sim::RenderedLensSystem r =
      sim::renderLensSystem(sys, sources.stamp(1), setup.observing, rng);
  ImageF image(r.image.width(), r.image.height());
  for (std::int64_t i = 0; i < image.size(); ++i) image[i] = float(r.image[i]);
  std::vector<std::int64_t> counts;
  PreparedImage stamp = prepareStamp(std::move(image), setup);
  const Table objects = detectAndMeasure(stamp, setup, &counts);
  ASSERT_EQ(counts.size(), 15u);
  const ArcSelection s = selectArcs(objects, 50.0, 50.0, 0.257, ArcRules{}, rng);
  ASSERT_GE(s.chosenRow, 0);
  const double d = s.distanceArcsec[std::size_t(s.chosenRow)];
  EXPECT_GE(d, 1.0);
  // For a near-SIS the main image of a source at beta = 1.5" lies at b + beta = 4.0" (the
  // counter-image at b - beta = 1.0", demagnified); the centroid of a curved arc sits a little
  // inside its radius.
  EXPECT_GT(d, 3.0);
  EXPECT_LT(d, 4.5);
  const double arcness = objects.value(s.chosenRow, objects.findColumn("ARCNESS"));
  // A real galaxy's arc has no closed form, so its ARCNESS is only checked to be positive; the
  // uniform disc below pins the value. (The thin-arc maximum of 0.231 in METHOD.md section 1
  // bounds uniform thin arcs only, not arcs of any brightness profile.)
  EXPECT_GT(arcness, 0.0);
}

// The main image of a uniform disc of radius r behind a singular isothermal sphere of Einstein
// radius b, at beta > r on the x axis, by fine integration of the lens equation: a lens-plane
// point at radius rho and angle t maps to (rho - b)(cos t, sin t), so the image is uniform
// (surface brightness is conserved) and spans, at each |t| <= asin(r / beta),
// rho = b + beta cos t -/+ sqrt(r^2 - beta^2 sin^2 t). Its moments about the lens,
// m_pq = int cos^p t sin^q t dt int rho^(p+q+1) d rho, have the radial integral in closed form;
// the angular one runs over t = tmax sin(psi), which removes the square root at the ends.
struct ArcImageMoments {
  double xMeanArcsec = 0.0;                 // centroid, from the lens along +x
  double ixx = 0.0, iyy = 0.0, ixyy = 0.0;  // central moments, arcsec^2 and arcsec^3
};

ArcImageMoments sisImageOfDisc(double bArcsec, double betaArcsec, double radiusArcsec) {
  const double tMax = std::asin(radiusArcsec / betaArcsec);
  constexpr int kSteps = 20000;
  double m00 = 0, m10 = 0, m20 = 0, m02 = 0, m12 = 0;
  for (int k = 0; k < kSteps; ++k) {
    const double psi = -M_PI / 2 + (k + 0.5) * M_PI / kSteps;
    const double t = tMax * std::sin(psi);
    const double dt = tMax * std::cos(psi) * M_PI / kSteps;
    const double half = std::sqrt(
        std::max(0.0, radiusArcsec * radiusArcsec - std::pow(betaArcsec * std::sin(t), 2)));
    const double rho1 = bArcsec + betaArcsec * std::cos(t) - half;
    const double rho2 = bArcsec + betaArcsec * std::cos(t) + half;
    const auto radial = [&](int n) { return (std::pow(rho2, n) - std::pow(rho1, n)) / n; };
    const double c = std::cos(t), s = std::sin(t);
    m00 += dt * radial(2);
    m10 += dt * c * radial(3);
    m20 += dt * c * c * radial(4);
    m02 += dt * s * s * radial(4);
    m12 += dt * c * s * s * radial(5);
  }
  ArcImageMoments m;
  m.xMeanArcsec = m10 / m00;
  m.ixx = m20 / m00 - m.xMeanArcsec * m.xMeanArcsec;
  m.iyy = m02 / m00;  // the image is symmetric about the x axis: y's mean is 0
  m.ixyy = m12 / m00 - m.xMeanArcsec * m.iyy;
  return m;
}

// A uniform disc lensed by an SIS into an arc, rendered with the 0.9" Gaussian seeing and no
// noise, detected and measured: at the lowest threshold the arc's ARCNESS, A_IMAGE and B_IMAGE
// are those of the integrated image. A symmetric PSF adds its variance sigma^2 to each second
// moment and leaves the third central moments as they are (cumulants add under convolution);
// the pixels add 1/12 px^2 to each second moment (Sheppard's correction) and nothing to the
// third. The surface brightness (2e4 ADU per pixel against a 2.5 ADU threshold) leaves the PSF
// wings outside the object below 0.2 % of the second moments.
TEST(SimulateSystem, AnSisArcOfAUniformDiscHasTheIntegratedArcness) {
  SimulationSetup setup = test::engineTestSetup();
  setup.observing.addNoise = false;
  const double bArcsec = 2.5, betaArcsec = 0.6, radiusArcsec = 0.4;
  sim::LensSystem sys;
  sys.mass = {bArcsec, 0.0, 0.0, 0.0};
  sys.lensMag = 99.0;  // no lens light
  sys.source.betaArcsec = {betaArcsec, 0.0};
  sys.sourceMag = 17.0;
  std::mt19937_64 rng(1);
  const sim::RenderedLensSystem r = sim::renderLensSystem(
      sys, test::uniformDiscSource(radiusArcsec, 0.02, 25), setup.observing, rng);
  ImageF image(r.image.width(), r.image.height());
  for (std::int64_t i = 0; i < image.size(); ++i) image[i] = float(r.image[i]);
  PreparedImage stamp = prepareStamp(std::move(image), setup);
  const Table objects = detectAndMeasure(stamp, setup, nullptr);

  const double scale = setup.observing.grid.pixelScaleArcsec;
  const ArcImageMoments truth = sisImageOfDisc(bArcsec, betaArcsec, radiusArcsec);
  const double sigmaPsfPix = 0.9 / (2.0 * std::sqrt(2.0 * std::log(2.0))) / scale;
  const double ixxPix2 = truth.ixx / (scale * scale) + sigmaPsfPix * sigmaPsfPix + 1.0 / 12;
  const double iyyPix2 = truth.iyy / (scale * scale) + sigmaPsfPix * sigmaPsfPix + 1.0 / 12;
  const double ixyyPix3 = truth.ixyy / (scale * scale * scale);
  ASSERT_GT(iyyPix2, ixxPix2);  // tangential: y is the major axis, so I_aab = I_xyy
  const double arcness = std::fabs(ixyyPix3) / std::pow(ixxPix2 + iyyPix2, 1.5);
  // The lens at 0-based (50, 50) of the 101-pixel stamp, i.e. 1-based (51, 51).
  const double xImage = 51.0 + truth.xMeanArcsec / scale;

  std::int64_t arcRow = -1;
  for (std::int64_t row = 0; row < objects.rows(); ++row)
    if (objects.value(row, objects.findColumn("THRESH_LEVEL")) == 1 &&
        objects.value(row, objects.findColumn("X_IMAGE")) > 51.0)
      arcRow = row;
  ASSERT_GE(arcRow, 0);
  const auto value = [&](const char* column) {
    return objects.value(arcRow, objects.findColumn(column));
  };
  EXPECT_NEAR(value("X_IMAGE"), xImage, 0.01);
  EXPECT_NEAR(value("Y_IMAGE"), 51.0, 0.01);
  // What is left (0.1 % on the axes, 0.6 % on ARCNESS here) is the discretisation of the
  // 0.02" source stamp and of the PSF kernel: a stamp of 0.01" brings ARCNESS within 0.2 %.
  EXPECT_NEAR(value("A_IMAGE") / std::sqrt(iyyPix2), 1.0, 0.004);
  EXPECT_NEAR(value("B_IMAGE") / std::sqrt(ixxPix2), 1.0, 0.004);
  EXPECT_NEAR(value("ARCNESS") / arcness, 1.0, 0.01) << "integrated " << arcness;
}

TEST(SimulateSystem, EachIndexIsReproducibleOnItsOwn) {
  const SimulationSetup setup = test::engineTestSetup();
  const SourceDatabase sources = test::engineTestSources();
  const SimulatedSystem a = simulateSystem(setup, sources, 99, 5, true);
  (void)simulateSystem(setup, sources, 99, 4, false);  // other systems in between change nothing
  const SimulatedSystem b = simulateSystem(setup, sources, 99, 5, true);
  EXPECT_EQ(a.image.pixels(), b.image.pixels());
  ASSERT_EQ(a.objects.rows(), b.objects.rows());
  for (std::int64_t r = 0; r < a.objects.rows(); ++r) {
    for (int c = 0; c < a.objects.rowWidth(); ++c) {
      const double x = a.objects.row(r)[c], y = b.objects.row(r)[c];
      EXPECT_TRUE(x == y || (std::isnan(x) && std::isnan(y)));
    }
  }
  EXPECT_EQ(a.arcs.chosenRow, b.arcs.chosenRow);
  // The draw alone is the same as the one inside the simulation.
  const LensSystemDraw d = drawLensSystem(setup, sources, std::uint64_t(99), 5);
  EXPECT_EQ(d.lens.sigmaKmPerS, a.draw.lens.sigmaKmPerS);
  EXPECT_EQ(d.source.redshift, a.draw.source.redshift);
  EXPECT_EQ(d.system.source.betaArcsec, a.draw.system.source.betaArcsec);
  // The source lies inside the multiple-image region, behind the lens, within the sigma cuts.
  EXPECT_TRUE(sim::MultipleImageRegion(d.system.mass).contains(d.system.source.betaArcsec));
  EXPECT_GT(d.source.redshift, d.lens.redshift);
  EXPECT_GT(d.lens.sigmaKmPerS, 250.0);
  EXPECT_LT(d.lens.sigmaKmPerS, 400.0);
  // Another index, another system.
  EXPECT_NE(drawLensSystem(setup, sources, std::uint64_t(99), 6).lens.mag, d.lens.mag);
}

// Every drawn system is strongly lensed: its source has at least two images (counted from the
// lens equation), and the region beyond theta_E inside the cut is drawn too.
TEST(DrawLensSystem, EverySourceHasAtLeastTwoImages) {
  const SimulationSetup setup = test::engineTestSetup();
  const SourceDatabase sources = test::engineTestSources();
  int beyondEinsteinRadius = 0;
  for (std::int64_t i = 0; i < 1000; ++i) {
    const LensSystemDraw d = drawLensSystem(setup, sources, std::uint64_t(21), i);
    const sim::Vec2 beta = d.system.source.betaArcsec;
    ASSERT_GE(test::countImagesCoreless(sim::EllipticalPotentialLens(d.system.mass), beta), 2)
        << "system " << i;
    if (std::hypot(beta[0], beta[1]) > d.einsteinRadiusArcsec) ++beyondEinsteinRadius;
  }
  EXPECT_GT(beyondEinsteinRadius, 0);
}

// By sampling, the joint draw: with every source at z_s = 2 and the magnitude window open, the
// kept lens redshifts follow dV_C/dz (D_ls/D_s)^2, the cross-section weighting over volume
// (Kolmogorov-Smirnov, 4000 systems, fixed seed, 0.1 % critical distance 1.95 / sqrt(n) =
// 0.031), sigma_v still follows phi(sigma) sigma^4 (mean within 4 standard errors), and every
// theta_E is the SIS closed form 4 pi (sigma/c)^2 D_ls/D_s with D_ls = (D_C(z_s) - D_C(z_l)) /
// (1 + z_s).
TEST(DrawLensSystem, PairsFollowTheCrossSectionOverVolume) {
  SimulationSetup setup = test::engineTestSetup();
  setup.population = sim::readPopulationModel(sim::populationPresetPath("physical"));
  for (auto& [type, relation] : setup.population.sourceRedshift) {
    relation.zAtRef = 2.0;
    relation.slopePerMag = 0.0;
    relation.scatter = 0.0;
  }
  const SourceDatabase sources = test::engineTestSources();
  const sim::FlatLambdaCdm& c = setup.cosmology;
  const double zs = 2.0, dcS = c.comovingDistanceMpc(zs);
  constexpr int kSystems = 4000;
  std::vector<double> zLens;
  double sigmaSum = 0.0, sigmaSum2 = 0.0;
  for (std::int64_t i = 0; i < kSystems; ++i) {
    const LensSystemDraw d = drawLensSystem(setup, sources, std::uint64_t(77), i);
    ASSERT_EQ(d.source.redshift, zs);
    zLens.push_back(d.lens.redshift);
    sigmaSum += d.lens.sigmaKmPerS;
    sigmaSum2 += d.lens.sigmaKmPerS * d.lens.sigmaKmPerS;
    const double dcL = c.comovingDistanceMpc(d.lens.redshift);
    const double ratio = (dcS - dcL) / (1.0 + zs) / (dcS / (1.0 + zs));
    const double v = d.lens.sigmaKmPerS / 299792.458;
    const double thetaE = 4.0 * 3.14159265358979323846 * v * v * ratio * 206264.80624709636;
    ASSERT_NEAR(d.einsteinRadiusArcsec / thetaE, 1.0, 1e-9);
  }
  const double zMin = setup.population.lensZMin;
  const double zMax = std::min(setup.population.lensZMax, zs - 0.1);  // 0.1 behind the lens
  const auto weight = [&](double z) {
    const double dc = c.comovingDistanceMpc(z);
    const double ratio = (dcS - dc) / dcS;
    return dc * dc / c.hubbleRatio(z) * ratio * ratio;
  };
  const double total = test::simpson(weight, zMin, zMax, 400);
  const double ks =
      test::ksDistance(zLens, [&](double z) { return test::simpson(weight, zMin, z, 40) / total; });
  EXPECT_LT(ks, 0.031);
  const auto vdf4 = [](double s) {
    const double x = s / 161.0;
    return std::pow(x, 2.32) * std::exp(-std::pow(x, 2.67)) * s * s * s;
  };
  const double lo = setup.population.sigmaMinKmPerS, hi = setup.population.sigmaMaxKmPerS;
  const double norm = test::simpson(vdf4, lo, hi);
  const double mean = test::simpson([&](double s) { return s * vdf4(s); }, lo, hi) / norm;
  const double sampleMean = sigmaSum / kSystems;
  const double sampleSd = std::sqrt(sigmaSum2 / kSystems - sampleMean * sampleMean);
  EXPECT_NEAR(sampleMean, mean, 4.0 * sampleSd / std::sqrt(double(kSystems)));
}

TEST(DrawLensSystem, PairsWithoutASourceRedshiftAreRedrawnReproducibly) {
  SimulationSetup setup = test::engineTestSetup();
  // The sources' types are in turn elliptical, spiral, irregular.
  const SourceDatabase sources = test::engineTestSources();
  // Elliptical sources at z = 5 +- 0.01: never inside 0.2 < z < 3, so pairs with an elliptical
  // stamp are drawn again; the other types at z = 0.6 +- 0.05, so lenses at z > 0.7 have no
  // cross-section (source.min_dz_behind_lens 0.1) and are turned down.
  for (auto& [type, relation] : setup.population.sourceRedshift) {
    relation.zAtRef = type == sim::GalaxyType::Elliptical ? 5.0 : 0.6;
    relation.slopePerMag = 0.0;
    relation.scatter = type == sim::GalaxyType::Elliptical ? 0.01 : 0.05;
  }
  int redrawn = 0;
  std::int64_t rejected = 0;
  for (std::int64_t i = 0; i < 100; ++i) {
    const LensSystemDraw d = drawLensSystem(setup, sources, std::uint64_t(7), i);
    EXPECT_NE(sources.stamp(d.sourceIndex).type, sim::GalaxyType::Elliptical);
    EXPECT_GT(d.source.redshift, d.lens.redshift + 0.1);
    EXPECT_LE(d.lens.redshift, 0.8);
    redrawn += d.redraws;
    rejected += d.rejections;
    // The same system again: the same draw, the same counts.
    const LensSystemDraw again = drawLensSystem(setup, sources, std::uint64_t(7), i);
    EXPECT_EQ(again.redraws, d.redraws);
    EXPECT_EQ(again.rejections, d.rejections);
    EXPECT_EQ(again.lens.mag, d.lens.mag);
  }
  EXPECT_GT(redrawn, 0);
  EXPECT_GT(rejected, 0);
  // A relation that never leaves room behind any lens is a configuration error, not a hang.
  for (auto& [type, relation] : setup.population.sourceRedshift) {
    relation.zAtRef = 0.01;
    relation.scatter = 0.0;
  }
  setup.population.maxLensAttempts = 2000;
  EXPECT_THROW(drawLensSystem(setup, sources, std::uint64_t(7), 0), ConfigError);
}

std::string readBytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The render probability of importance sampling, by hand: logit p = c0 + c1 ln(theta_E / 1") +
// c2 (m_s - m_lim) + c3 ln(r_s / FWHM) + c4 (m_l - m_lim), r = clamp(scale sqrt(p), floor, 1);
// 0 below the skip limit, 1 above it for a plain draw.
TEST(RenderProbability, IsTheClampedRootOfTheLogisticArcProbability) {
  SimulationSetup setup = test::engineTestSetup();
  setup.population.skipEinsteinRadiusBelowArcsec = 0.5;
  LensSystemDraw d;
  d.einsteinRadiusArcsec = 1.3;
  d.source.mag = 24.5;
  d.source.halfLightArcsec = 0.35;
  d.lens.mag = 21.5;
  EXPECT_EQ(renderProbability(setup, d), 1.0);  // plain
  setup.sampling = Sampling::Importance;
  // The 5-sigma limit in a 2" aperture: sigma * 5 * sqrt(pi (1"/scale)^2) is its flux.
  const double scale = setup.observing.grid.pixelScaleArcsec;
  const double mLim = setup.observing.magZeroPoint -
                      2.5 * std::log10(5.0 * setup.observing.skySigmaAdu *
                                       std::sqrt(3.141592653589793 / (scale * scale)));
  EXPECT_NEAR(limitingMagnitude(setup.observing), mLim, 1e-12);
  const double* c = setup.importance.coefficients;
  const double logit = c[0] + c[1] * std::log(1.3) + c[2] * (24.5 - mLim) +
                       c[3] * std::log(0.35 / setup.observing.seeingFwhmArcsec) +
                       c[4] * (21.5 - mLim);
  const double expected = std::clamp(setup.importance.scale / std::sqrt(1.0 + std::exp(-logit)),
                                     setup.importance.floor, 1.0);
  ASSERT_GT(expected, setup.importance.floor);  // the case tests the formula, not a bound
  ASSERT_LT(expected, 1.0) << "logit " << logit << ", limiting magnitude " << mLim;
  EXPECT_NEAR(renderProbability(setup, d), expected, 1e-12);
  d.einsteinRadiusArcsec = 0.55;  // just above the skip limit, an arc near impossible: the floor
  EXPECT_EQ(renderProbability(setup, d), setup.importance.floor);
  d.einsteinRadiusArcsec = 0.49;  // below the skip limit: never rendered
  EXPECT_EQ(renderProbability(setup, d), 0.0);
  d.einsteinRadiusArcsec = 4.0;  // an arc is near certain: always rendered
  EXPECT_EQ(renderProbability(setup, d), 1.0);
}

// A system that importance sampling renders is the plain run's system of that index, pixel for
// pixel; the weights of the rendered systems add up to the systems above the skip limit (the
// Horvitz-Thompson estimate, within 4 of its standard errors sqrt(sum (1 - r) / r^2) over the
// rendered), and the weighted mean theta_E is the mean over every system above the limit.
TEST(ImportanceSampling, RendersPlainSystemsAndItsWeightsGiveThePopulation) {
  SimulationSetup plain = test::engineTestSetup();
  plain.population.skipEinsteinRadiusBelowArcsec = 0.5;
  SimulationSetup weighted = plain;
  weighted.sampling = Sampling::Importance;
  const SourceDatabase sources = test::engineTestSources();
  const std::uint64_t seed = 17;
  double above = 0, weightSum = 0, variance = 0, thetaSum = 0, weightedThetaSum = 0;
  std::int64_t rendered = 0, firstRendered = -1;
  for (std::int64_t i = 0; i < 20000; ++i) {
    const LensSystemDraw p = drawLensSystem(plain, sources, seed, i);
    const LensSystemDraw w = drawLensSystem(weighted, sources, seed, i);
    ASSERT_EQ(p.einsteinRadiusArcsec, w.einsteinRadiusArcsec);
    if (p.skipped) {
      ASSERT_FALSE(w.rendered);
      continue;
    }
    above += 1;
    thetaSum += p.einsteinRadiusArcsec;
    if (!w.rendered) continue;
    ++rendered;
    if (firstRendered < 0 && w.renderProbability < 1.0) firstRendered = i;
    ASSERT_EQ(p.system.source.betaArcsec, w.system.source.betaArcsec);
    const double r = w.renderProbability;
    weightSum += w.weight();
    weightedThetaSum += w.weight() * w.einsteinRadiusArcsec;
    variance += (1.0 - r) / (r * r);
  }
  EXPECT_LT(rendered, above / 4);  // it does leave most systems out
  EXPECT_NEAR(weightSum, above, 4.0 * std::sqrt(variance));
  EXPECT_NEAR(weightedThetaSum / weightSum, thetaSum / above, 0.02);
  // Pixel for pixel: the first system rendered with a probability below 1.
  ASSERT_GE(firstRendered, 0);
  const SimulatedSystem a = simulateSystem(plain, sources, seed, firstRendered, true);
  const SimulatedSystem b = simulateSystem(weighted, sources, seed, firstRendered, true);
  EXPECT_EQ(a.image.pixels(), b.image.pixels());
  EXPECT_EQ(a.objects.rows(), b.objects.rows());
  EXPECT_EQ(a.arcs.chosenRow, b.arcs.chosenRow);
}

TEST(SimulateLensesCommand, OutputDoesNotDependOnTheThreadCount) {
  const auto dir = test::scratchDir();
  auto run = [&](const std::string& threads, const std::string& name) {
    const std::string out = (dir / name).string();
    EXPECT_EQ(runSimulateLenses({"-n", "24", "--seed", "11", "-o", out, "--threads", threads,
                                 "--quiet", "--sources", "6", "--stamps", out + ".stamps.fits",
                                 "--stamp-count", "3"}),
              0);
    return out;
  };
  const std::string one = run("1", "one.fits");
  const std::string two = run("2", "two.fits");
  const std::string a = readBytes(one), b = readBytes(two);
  ASSERT_FALSE(a.empty());
  EXPECT_TRUE(a == b);
  EXPECT_TRUE(readBytes(one + ".stamps.fits") == readBytes(two + ".stamps.fits"));
  // A different seed gives a different file.
  const std::string other = (dir / "other.fits").string();
  ASSERT_EQ(
      runSimulateLenses({"-n", "24", "--seed", "12", "-o", other, "--quiet", "--sources", "6"}), 0);
  EXPECT_FALSE(readBytes(other) == a);
}

TEST(SimulateLensesCommand, BadInputThrowsAndWritesNothing) {
  const auto dir = test::scratchDir();
  const std::string out = (dir / "bad.fits").string();
  EXPECT_THROW(runSimulateLenses({"-n", "-3", "-o", out}), ConfigError);
  EXPECT_THROW(
      runSimulateLenses({"-n", "5", "-o", out, "--lens-mag-min", "23", "--lens-mag-max", "21"}),
      ConfigError);
  EXPECT_THROW(runSimulateLenses(
                   {"-n", "5", "-o", out, "--sigma-min", "1000", "--sigma-max", "1100", "--quiet"}),
               ConfigError);
  EXPECT_THROW(
      runSimulateLenses({"-n", "5", "-o", out, "--database", (dir / "missing.fits").string()}),
      IoError);
  EXPECT_FALSE(std::filesystem::exists(out));
  EXPECT_TRUE(std::filesystem::is_empty(dir));
}

TEST(SourceDatabase, RealGalaxyCatalogsLoadOrFailClearly) {
  OCTARC_REQUIRE_SHARED_DATA(shared);
  const auto hst = shared / "hst-galaxies";
  const SourceDatabase aegis =
      SourceDatabase::fromRealGalaxyCatalog((hst / "aegis" / "AEGIS_F606w_catalog.fits").string());
  EXPECT_GT(aegis.size(), 0u);
  for (std::size_t i = 0; i < aegis.size(); ++i) EXPECT_GT(aegis.halfLightArcsec(i), 0.0);
  // The COSMOS catalog names a PSF file that is absent: galaxies alone still load.
  EXPECT_GT(SourceDatabase::fromRealGalaxyCatalog(
                (hst / "cosmos" / "real_galaxy_catalog_23.5.fits").string())
                .size(),
            0u);
  // GalSim's example names an image file that is absent: one IoError naming the catalog.
  const std::string example = (hst / "real_galaxy_catalog_23.5_example.fits").string();
  try {
    SourceDatabase::fromRealGalaxyCatalog(example);
    FAIL() << "no error";
  } catch (const IoError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(example), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace octarc
