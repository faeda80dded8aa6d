#include "octarc/simulation/Morphology.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "octarc/simulation/LensLight.h"
#include "octarc/simulation/SyntheticGalaxy.h"

namespace octarc::simulation {
namespace {

// A Sersic galaxy on a 0.03"/px stamp wide enough to hold nearly all its flux.
SourceStamp sersicStamp(double n, double axisRatio) {
  SurveyGrid grid;
  grid.width = grid.height = 241;
  grid.pixelScaleArcsec = 0.03;
  grid.lensXPix = grid.lensYPix = 120.0;
  SourceStamp s;
  s.fluxPerPixel = ImageD(grid.width, grid.height);
  addSersicLight(s.fluxPerPixel, grid, {n, 0.4, axisRatio, 0.3, 1.0});
  s.pixelScaleArcsec = 0.03;
  return s;
}

TEST(Morphology, ConcentrationOfSersicProfilesAndTheirTypes) {
  // C = 5 log10(r80 / r20) of circular profiles: 2.80 (n = 1) and 5.27 (n = 4); the stamp
  // (r_e = 13 px, 9 r_e wide) loses a little of the n = 4 wings, which lowers C slightly.
  const MorphologyMeasures disc = measureMorphology(sersicStamp(1.0, 1.0));
  const MorphologyMeasures spheroid = measureMorphology(sersicStamp(4.0, 1.0));
  EXPECT_NEAR(disc.concentration, 2.80, 0.05);
  EXPECT_NEAR(spheroid.concentration, 5.27, 0.3);
  // Symmetric under a half turn, elongated or not.
  EXPECT_LT(disc.asymmetry, 0.02);
  EXPECT_LT(measureMorphology(sersicStamp(4.0, 0.5)).asymmetry, 0.02);
  EXPECT_EQ(classifyMorphology(disc), GalaxyType::Spiral);
  EXPECT_EQ(classifyMorphology(spheroid), GalaxyType::Elliptical);
  EXPECT_EQ(classifyMorphology(measureMorphology(sersicStamp(4.0, 0.5))), GalaxyType::Elliptical);
}

TEST(Morphology, LopsidedGalaxyIsIrregular) {
  SourceStamp s = sersicStamp(1.0, 1.0);
  // A bright clump on one side only, as large as the disc's core.
  SurveyGrid grid;
  grid.width = grid.height = 241;
  grid.pixelScaleArcsec = 0.03;
  grid.lensXPix = 150.0;
  grid.lensYPix = 130.0;
  addSersicLight(s.fluxPerPixel, grid, {1.0, 0.15, 1.0, 0.0, 1.5});
  const MorphologyMeasures m = measureMorphology(s);
  EXPECT_GT(m.asymmetry, kIrregularAsymmetryMin);
  EXPECT_EQ(classifyMorphology(m), GalaxyType::Irregular);
  EXPECT_TRUE(std::isnan(measureMorphology(SourceStamp{}).concentration));
}

// Sky noise adds to sum |I - I_180|; its expectation is taken off, so a noisy symmetric disc
// stays symmetric.
TEST(Morphology, NoiseDoesNotMakeASymmetricGalaxyAsymmetric) {
  SourceStamp s = sersicStamp(1.0, 0.8);
  double peak = 0.0;
  for (double v : s.fluxPerPixel.pixels()) peak = std::max(peak, v);
  std::mt19937_64 rng(5);
  std::normal_distribution<double> noise(0.0, 0.02 * peak);
  for (double& v : s.fluxPerPixel.pixels()) v += noise(rng);
  const MorphologyMeasures m = measureMorphology(s);
  EXPECT_LT(m.asymmetry, 0.1);
  EXPECT_EQ(classifyMorphology(m), GalaxyType::Spiral);
}

TEST(Morphology, TypeNamesParse) {
  GalaxyType t = GalaxyType::Spiral;
  EXPECT_TRUE(parseGalaxyType(" Elliptical ", &t));
  EXPECT_EQ(t, GalaxyType::Elliptical);
  EXPECT_TRUE(parseGalaxyType("IRREGULAR", &t));
  EXPECT_EQ(t, GalaxyType::Irregular);
  EXPECT_FALSE(parseGalaxyType("S0", &t));
}

}  // namespace
}  // namespace octarc::simulation
