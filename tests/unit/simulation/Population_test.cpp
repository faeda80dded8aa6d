#include "octarc/simulation/Population.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <optional>
#include <regex>
#include <sstream>
#include <string>

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

TEST(PopulationModel, DefaultFileHasThePaperRanges) {
  const PopulationModel m = readPopulationModel(defaultPopulationModelPath());
  EXPECT_EQ(m.sourceMagnitude.magMin, 22.0);
  EXPECT_EQ(m.sourceMagnitude.magMax, 25.0);
  EXPECT_EQ(m.lensMagnitude.magMin, 21.0);
  EXPECT_EQ(m.lensMagnitude.magMax, 23.0);
  EXPECT_EQ(m.sourceZMin, 0.2);
  EXPECT_EQ(m.sourceZMax, 3.0);
  EXPECT_EQ(m.sigmaMinKmPerS, 250.0);
  EXPECT_EQ(m.sigmaMaxKmPerS, 400.0);
  EXPECT_EQ(m.sourceRedshift.size(), 3u);
  EXPECT_EQ(m.lensKCorrectionMag.x.size(), m.lensKCorrectionMag.y.size());
  EXPECT_NEAR(m.lensKCorrectionMag(0.45), 0.61, 1e-12);  // halfway between 0.52 and 0.70
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
  const PopulationModel m = readPopulationModel(defaultPopulationModelPath());
  const FlatLambdaCdm cosmo;
  for (std::uint64_t i = 0; i < 200; ++i) {
    auto rng = systemRng(2026, i);
    const LensDraw lens = m.drawLens(cosmo, rng);
    EXPECT_GT(lens.sigmaKmPerS, 250.0);
    EXPECT_LT(lens.sigmaKmPerS, 400.0);
    EXPECT_GE(lens.mag, 21.0);
    EXPECT_LE(lens.mag, 23.0);
    // Faber-Jackson bookkeeping: M = m - DM - K.
    EXPECT_NEAR(
        lens.absoluteMag,
        lens.mag - cosmo.distanceModulusMag(lens.redshift) - m.lensKCorrectionMag(lens.redshift),
        1e-9);
    const std::optional<SourceDraw> drawn = m.drawSource(GalaxyType::Irregular, lens.redshift, rng);
    ASSERT_TRUE(drawn.has_value());
    const SourceDraw& src = *drawn;
    EXPECT_GE(src.redshift, std::max(0.2, lens.redshift + 0.1));
    EXPECT_LE(src.redshift, 3.0);
    EXPECT_GT(src.halfLightArcsec, 0.0);
    EXPECT_GT(sisEinsteinRadiusArcsec(lens.sigmaKmPerS, lens.redshift, src.redshift, cosmo), 0.0);
  }
  auto r1 = systemRng(1, 3), r2 = systemRng(1, 3);
  EXPECT_EQ(m.drawLens(cosmo, r1).sigmaKmPerS, m.drawLens(cosmo, r2).sigmaKmPerS);
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
  // No scatter; lens at m = 21 drawn at exactly z = 0.4 (zero redshift scatter):
  // DM(0.4) = 41.684464 (astropy), K = 0.52, M = 21 - 41.684464 - 0.52 = -21.204464;
  // sigma = 225 * 10^(-0.1 (M + 21.6)) = 225 * 10^(-0.0395536) = 205.41 km/s.
  PopulationModel m = readPopulationModel(defaultPopulationModelPath());
  m.lensMagnitude = {21.0, 21.0 + 1e-12, 0.0};
  m.lensRedshift.scatter = 0.0;
  m.fjScatterMag = 0.0;
  m.sigmaMinKmPerS = 100.0;
  std::mt19937_64 rng(1);
  const LensDraw d = m.drawLens(FlatLambdaCdm(), rng);
  EXPECT_NEAR(d.redshift, 0.4, 1e-9);
  EXPECT_NEAR(d.absoluteMag, -21.204464, 1e-5);
  EXPECT_NEAR(d.sigmaKmPerS, 225.0 * std::pow(10.0, -0.1 * (d.absoluteMag + 21.6)), 1e-9);
  EXPECT_NEAR(d.sigmaKmPerS, 205.41, 0.01);
}

TEST(PopulationModel, BadFilesGiveOneLineErrorsNamingFileAndKey) {
  std::string msg = readError(editedDefault("source.mag_min", "source.mag_min = 26"));
  EXPECT_NE(msg.find("population.txt: key source.mag_min: must be less than source.mag_max"),
            std::string::npos)
      << msg;
  EXPECT_EQ(msg.find('\n'), std::string::npos);
  msg = readError(editedDefault("lens.sigma_max_km_s", "lens.sigma_max_km_s = 200"));
  EXPECT_NE(msg.find("key lens.sigma_min_km_s"), std::string::npos) << msg;
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
  msg = readError(editedDefault("lens.mag_slope", "lens.mag_slope = 0.3 0.4"));
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
                       "900 < sigma_v < 1000 km/s"),
              std::string::npos)
        << msg;
  }
}

}  // namespace
}  // namespace octarc::simulation
