#include "octarc/simulation/Population.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "LensTestSupport.h"
#include "TestFiles.h"
#include "TestPaths.h"
#include "octarc/core/Error.h"
#include "octarc/simulation/LensModel.h"
#include "octarc/simulation/Seeds.h"

namespace octarc::simulation {
namespace {

// The default file with one "key = ..." line replaced (or removed if replacement is empty),
// written to the scratch directory.
std::string editedDefault(const std::string& key, const std::string& replacement) {
  const std::string text = test::readFile(defaultPopulationModelPath());
  const std::regex line("(^|\n)" + std::regex_replace(key, std::regex("\\."), "\\.") + " *=[^\n]*");
  EXPECT_TRUE(std::regex_search(text, line)) << key;
  const std::string edited =
      std::regex_replace(text, line, "$1" + replacement, std::regex_constants::format_first_only);
  const std::string path = (test::scratchDir() / "population.txt").string();
  std::ofstream(path) << edited;
  return path;
}

// Returns the message of the ConfigError thrown by reading `path` ("" if none).
std::string readError(const std::string& path) {
  try {
    readPopulationModel(path);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(PopulationModel, PresetsShareTheRelationsAndDlsHasThePaperRanges) {
  const PopulationModel physical = readPopulationModel(defaultPopulationModelPath());
  EXPECT_EQ(populationPresetPath("physical"), defaultPopulationModelPath());
  // Choi, Park & Vogeley 2007.
  EXPECT_EQ(physical.lensVdf.phiStarH3PerMpc3, 8.0e-3);
  EXPECT_EQ(physical.lensVdf.sigmaStarKmPerS, 161.0);
  EXPECT_EQ(physical.lensVdf.alpha, 2.32);
  EXPECT_EQ(physical.lensVdf.beta, 2.67);
  const PopulationModel dls = readPopulationModel(populationPresetPath("dls"));
  EXPECT_EQ(dls.name, "population-dls");
  EXPECT_EQ(dls.sourceMagnitude.magMin, 22.0);
  EXPECT_EQ(dls.sourceMagnitude.magMax, 25.0);
  EXPECT_EQ(dls.lensMagMin, 21.0);
  EXPECT_EQ(dls.lensMagMax, 23.0);
  EXPECT_EQ(dls.sourceZMin, 0.2);
  EXPECT_EQ(dls.sourceZMax, 3.0);
  EXPECT_EQ(dls.sigmaMinKmPerS, 250.0);
  EXPECT_EQ(dls.sigmaMaxKmPerS, 400.0);
  // The same relations: only the windows differ.
  EXPECT_EQ(dls.lensVdf.alpha, physical.lensVdf.alpha);
  EXPECT_EQ(dls.fjAbsMagStar, physical.fjAbsMagStar);
  EXPECT_EQ(dls.fjScatterMag, physical.fjScatterMag);
  EXPECT_EQ(dls.sourceSize.halfLightArcsecAtRef, physical.sourceSize.halfLightArcsecAtRef);
  EXPECT_EQ(dls.sourceRedshift.size(), 3u);
  EXPECT_EQ(dls.lensKCorrectionMag.x.size(), dls.lensKCorrectionMag.y.size());
  EXPECT_NEAR(dls.lensKCorrectionMag(0.45), 0.61, 1e-12);  // halfway between 0.52 and 0.70
  EXPECT_THROW(populationPresetPath("sdss"), ConfigError);
}

TEST(PopulationModel, PowerLawMagnitudesHaveTheAnalyticMean) {
  // Density k e^{k m} / (e^{k b} - e^{k a}) on [a, b], k = slope ln 10:
  // mean = (b e^{k b} - a e^{k a}) / (e^{k b} - e^{k a}) - 1/k.
  const MagnitudePowerLaw p{22.0, 25.0, 0.33};
  const double k = 0.33 * std::log(10.0);
  const double a = 22.0, b = 25.0;
  const double mean =
      (b * std::exp(k * b) - a * std::exp(k * a)) / (std::exp(k * b) - std::exp(k * a)) - 1.0 / k;
  std::mt19937_64 rng(17);
  const int n = 200000;
  double s = 0.0;
  for (int i = 0; i < n; ++i) {
    const double m = p.sample(rng);
    ASSERT_GE(m, a);
    ASSERT_LE(m, b);
    s += m;
  }
  // Standard deviation of m is < 0.9, so 4 standard errors < 0.008.
  EXPECT_NEAR(s / n, mean, 0.008);
}

TEST(PopulationModel, DrawsRespectRangesAndAreReproducible) {
  const PopulationModel m = readPopulationModel(populationPresetPath("dls"));
  const FlatLambdaCdm cosmo;
  int lenses = 0;
  for (std::uint64_t i = 0; i < 2000; ++i) {
    auto rng = systemRng(2026, i);
    const std::optional<LensDraw> drawn = m.drawLens(cosmo, rng);
    if (!drawn) continue;  // outside 21 < m < 23
    const LensDraw& lens = *drawn;
    ++lenses;
    EXPECT_GT(lens.sigmaKmPerS, 250.0);
    EXPECT_LT(lens.sigmaKmPerS, 400.0);
    EXPECT_GE(lens.mag, 21.0);
    EXPECT_LE(lens.mag, 23.0);
    EXPECT_GE(lens.redshift, 0.05);
    EXPECT_LE(lens.redshift, 1.5);
    // Faber-Jackson bookkeeping: M = m - DM - K.
    EXPECT_NEAR(
        lens.absoluteMag,
        lens.mag - cosmo.distanceModulusMag(lens.redshift) - m.lensKCorrectionMag(lens.redshift),
        1e-9);
    const std::optional<SourceDraw> source = m.drawSource(GalaxyType::Irregular, rng);
    ASSERT_TRUE(source.has_value());
    EXPECT_GE(source->redshift, 0.2);
    EXPECT_LE(source->redshift, 3.0);
    EXPECT_GT(source->halfLightArcsec, 0.0);
    const double w = m.lensingWeight(lens.redshift, source->redshift, cosmo);
    EXPECT_GE(w, 0.0);
    EXPECT_LT(w, 1.0);
    if (source->redshift < lens.redshift + 0.1) {
      EXPECT_EQ(w, 0.0);
    }
  }
  // The window keeps a fair share of the lenses.
  EXPECT_GT(lenses, 200);
  auto r1 = systemRng(1, 3), r2 = systemRng(1, 3);
  const auto a = m.drawLens(cosmo, r1), b = m.drawLens(cosmo, r2);
  EXPECT_EQ(a.has_value(), b.has_value());
  if (a && b) {
    EXPECT_EQ(a->sigmaKmPerS, b->sigmaKmPerS);
  }
}

TEST(PopulationModel, NoPossibleRedshiftIsAFailedDrawNotAnError) {
  // A relation centred at z = 0.5 with scatter 0.01 cannot give a source behind a lens at 1.5
  // (1000 draws, each 100 sigma away), and no range is left behind a lens at 2.95.
  MagnitudeRedshiftRelation r;
  r.zAtRef = 0.5;
  r.slopePerMag = 0.0;
  r.scatter = 0.01;
  std::mt19937_64 rng(3);
  EXPECT_FALSE(r.sample(22.0, 1.6, 0.2, 3.0, rng).has_value());
  EXPECT_FALSE(r.sample(22.0, 3.05, 0.2, 3.0, rng).has_value());
  const std::optional<double> z = r.sample(22.0, 0.3, 0.2, 3.0, rng);
  ASSERT_TRUE(z.has_value());
  EXPECT_NEAR(*z, 0.5, 0.1);
}

TEST(PopulationModel, FaberJacksonByHand) {
  // No scatter, 224 < sigma_v < 226 km/s, z = 0.4 (a narrow range): M = -21.6 - 10
  // log10(sigma / 225); DM(0.4) = 41.684464 (astropy), K = 0.52, so m = 20.604464 at 225 km/s.
  PopulationModel m = readPopulationModel(defaultPopulationModelPath());
  m.fjScatterMag = 0.0;
  m.sigmaMinKmPerS = 224.0;
  m.sigmaMaxKmPerS = 226.0;
  m.lensZMin = 0.4;
  m.lensZMax = 0.4 + 1e-9;
  m.tabulate(FlatLambdaCdm());
  std::mt19937_64 rng(1);
  const std::optional<LensDraw> d = m.drawLens(FlatLambdaCdm(), rng);
  ASSERT_TRUE(d.has_value());
  EXPECT_NEAR(d->redshift, 0.4, 1e-8);
  const double absMag = -21.6 - 10.0 * std::log10(d->sigmaKmPerS / 225.0);
  EXPECT_NEAR(d->absoluteMag, absMag, 1e-9);
  EXPECT_NEAR(d->mag, absMag + 41.684464 + 0.52, 1e-5);
  EXPECT_NEAR(d->mag, 20.604464, 0.05);
  // Outside the magnitude window: no lens (the caller draws again).
  m.lensMagMin = 21.0;
  EXPECT_FALSE(m.drawLens(FlatLambdaCdm(), rng).has_value());
}

TEST(PopulationModel, BadFilesGiveOneLineErrorsNamingFileAndKey) {
  std::string msg = readError(editedDefault("source.mag_min", "source.mag_min = 26"));
  EXPECT_NE(msg.find("population.txt: key source.mag_min: must be less than source.mag_max"),
            std::string::npos)
      << msg;
  EXPECT_EQ(msg.find('\n'), std::string::npos);
  msg = readError(editedDefault("lens.sigma_max_km_s", "lens.sigma_max_km_s = 90"));
  EXPECT_NE(msg.find("key lens.sigma_min_km_s"), std::string::npos) << msg;
  msg = readError(editedDefault("lens.z_max", "lens.z_max = 1e300"));
  EXPECT_NE(msg.find("key lens.z_max: must be at most 20"), std::string::npos) << msg;
  msg = readError(editedDefault("lens.vdf.beta", "lens.vdf.beta = 0"));
  EXPECT_NE(msg.find("key lens.vdf.beta: must be positive"), std::string::npos) << msg;
  msg = readError(editedDefault("lens.z_min", "lens.zmin = 0.1"));
  EXPECT_NE(msg.find("unknown key 'lens.zmin'"), std::string::npos) << msg;
  EXPECT_NE(msg.find(": line "), std::string::npos) << msg;
  msg = readError(editedDefault("source.size.scatter_dex", ""));
  EXPECT_NE(msg.find("missing key source.size.scatter_dex"), std::string::npos) << msg;
  msg = readError(editedDefault("lens.fj.scatter_mag", "lens.fj.scatter_mag = 0.8x"));
  EXPECT_NE(msg.find("'0.8x' is not a finite number"), std::string::npos) << msg;
  msg = readError(editedDefault("lens.fj.scatter_mag", "lens.fj.scatter_mag = \x1b[31m"));
  EXPECT_NE(msg.find("key lens.fj.scatter_mag: '\\x1B[31m' is not a finite number"),
            std::string::npos)
      << msg;
  msg = readError(editedDefault("lens.z_min", std::string(3000, 'k') + " = 1"));
  EXPECT_NE(msg.find("unknown key '" + std::string(60, 'k') + "'... (3000 characters)"),
            std::string::npos)
      << msg;
  msg = readError(editedDefault("lens.kcorr.mag", "lens.kcorr.mag = 0 0.1"));
  EXPECT_NE(msg.find("key lens.kcorr.mag"), std::string::npos) << msg;
  msg = readError(editedDefault("lens.vdf.alpha", "lens.vdf.alpha = 2.3 2.4"));
  EXPECT_NE(msg.find("takes one number"), std::string::npos) << msg;
  EXPECT_THROW(readPopulationModel("/nonexistent/population.txt"), IoError);
}

TEST(PopulationModel, SigmaRangeGivingNoLensesIsAClearError) {
  PopulationModel m = readPopulationModel(defaultPopulationModelPath());
  m.sigmaMinKmPerS = 900.0;
  m.sigmaMaxKmPerS = 1000.0;
  m.maxLensAttempts = 2000;
  std::mt19937_64 rng(4);
  try {
    m.drawLens(FlatLambdaCdm(), rng);
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("population.txt: lens.sigma_min_km_s/lens.sigma_max_km_s: no lens with "
                       "900 < sigma_v < 1000 km/s from the velocity dispersion function in 2000 "
                       "draws"),
              std::string::npos)
        << msg;
  }
}

// By sampling: with the magnitude window open, sigma_v follows phi(sigma) sigma^4 (the VDF of
// Choi et al. 2007 times the sigma^4 of the SIS cross-section) on (100, 500) km/s. Chi-square
// over 20 equal-width bins against the integrated density; fixed seed; the 0.1 % critical value
// of chi^2 with 19 degrees of freedom is 43.8.
TEST(PopulationModel, SigmaFollowsTheVdfTimesTheCrossSection) {
  const PopulationModel m = readPopulationModel(defaultPopulationModelPath());
  ASSERT_LE(m.lensMagMin, 0.0);
  ASSERT_GE(m.lensMagMax, 99.0);
  const FlatLambdaCdm cosmo;
  std::mt19937_64 rng(31);
  constexpr int kBins = 20, kDraws = 20000;
  const double lo = m.sigmaMinKmPerS, hi = m.sigmaMaxKmPerS;
  std::vector<int> counts(kBins, 0);
  for (int i = 0; i < kDraws; ++i) {
    const std::optional<LensDraw> d = m.drawLens(cosmo, rng);
    ASSERT_TRUE(d.has_value());
    ++counts[std::size_t(std::min(kBins - 1, int((d->sigmaKmPerS - lo) / (hi - lo) * kBins)))];
  }
  // The density from the formula as published, independently of the sampler.
  const auto weighted = [](double s) {
    const double x = s / 161.0;
    return std::pow(x, 2.32) * std::exp(-std::pow(x, 2.67)) / s * std::pow(s, 4.0);
  };
  const double total = test::simpson(weighted, lo, hi);
  double chi2 = 0.0;
  for (int k = 0; k < kBins; ++k) {
    const double a = lo + (hi - lo) * k / kBins, b = lo + (hi - lo) * (k + 1) / kBins;
    const double expected = kDraws * test::simpson(weighted, a, b, 200) / total;
    chi2 += (counts[std::size_t(k)] - expected) * (counts[std::size_t(k)] - expected) / expected;
  }
  EXPECT_LT(chi2, 43.8);
  // The density itself: phi(sigma*) = phi* e^-1 beta / Gamma(alpha / beta) / sigma*.
  EXPECT_NEAR(m.lensVdf.density(161.0),
              8.0e-3 * std::exp(-1.0) * 2.67 / std::tgamma(2.32 / 2.67) / 161.0, 1e-15);
}

// By sampling: lens redshifts follow dV_C/dz on [z_min, z_max] (a non-evolving comoving
// density). Kolmogorov-Smirnov against the CDF integrated here from D_C^2 / E(z); 20 000 draws,
// fixed seed; the 0.1 % critical distance is 1.95 / sqrt(n) = 0.0138.
TEST(PopulationModel, LensRedshiftsFollowTheComovingVolume) {
  const PopulationModel m = readPopulationModel(defaultPopulationModelPath());
  const FlatLambdaCdm cosmo;
  std::mt19937_64 rng(32);
  std::vector<double> z;
  for (int i = 0; i < 20000; ++i) z.push_back(m.drawLens(cosmo, rng)->redshift);
  const auto dVdz = [&](double zz) {
    const double dc = cosmo.comovingDistanceMpc(zz);
    return dc * dc / cosmo.hubbleRatio(zz);
  };
  const double total = test::simpson(dVdz, m.lensZMin, m.lensZMax, 400);
  const double d = test::ksDistance(
      z, [&](double zz) { return test::simpson(dVdz, m.lensZMin, zz, 40) / total; });
  EXPECT_LT(d, 0.0138);
}

}  // namespace
}  // namespace octarc::simulation
