#include "octarc/background/MeshBackground.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <random>
#include <string>

#include "BackgroundTestSupport.h"
#include "TestPaths.h"
#include "octarc/core/Error.h"

namespace octarc {
namespace {

namespace fs = std::filesystem;
using test::maxAbsDiff;

// The acceptance bound: BACKGROUND and BACKGROUND_RMS within 0.1 % of the noise per pixel.
constexpr double kAcceptanceFraction = 1e-3;

// A value as SExtractor prints it into LDAC_IMHEAD (SEXBKGND, SEXBKDEV, SEXDWSCL: "%.12E" of
// the single-precision value), for comparing the printed cards digit for digit.
std::string printedLikeSExtractor(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.12E", value);
  return text;
}
std::string printedInCatalog(const fs::path& catalog, const std::string& key) {
  return printedLikeSExtractor(test::ldacHeaderValue(catalog, key));
}

struct Comparison {
  double levelMaxAdu = 0, rmsMaxAdu = 0, miniLevelMaxAdu = 0, miniRmsMaxAdu = 0;
  double sexBkgnd = 0, sexBkdev = 0;
};

// Runs source-extractor and octarc on the same file with the same settings and compares the
// full-size and mesh-size maps and the global values.
Comparison compareWithSExtractor(const fs::path& imagePath, const fs::path& dir,
                                 const MeshBackgroundSettings& s, const MeshBackground** out,
                                 MeshBackground& storage) {
  std::string args = "-BACK_SIZE " + std::to_string(s.meshWidth) + "," +
                     std::to_string(s.meshHeight) + " -BACK_FILTERSIZE " +
                     std::to_string(s.filterWidth) + "," + std::to_string(s.filterHeight) +
                     " -BACK_FILTTHRESH " + std::to_string(s.filterThresholdAdu);
  test::runSExtractorBackground(imagePath, dir, args,
                                "BACKGROUND,BACKGROUND_RMS,MINIBACKGROUND,MINIBACK_RMS",
                                "b.fits,r.fits,mb.fits,mr.fits");
  const ImageF image = test::readFitsAsSExtractor(imagePath);
  storage = MeshBackground::estimate(image, s, imagePath.filename().string());
  *out = &storage;
  Comparison c;
  const ImageF sexLevel = test::readFits<float>(dir / "b.fits");
  const ImageF sexRms = test::readFits<float>(dir / "r.fits");
  const ImageF sexMiniLevel = test::readFits<float>(dir / "mb.fits");
  const ImageF sexMiniRms = test::readFits<float>(dir / "mr.fits");
  const ImageF level = storage.levelImage();
  const ImageF rms = storage.rmsImage();
  EXPECT_EQ(sexLevel.width(), level.width());
  EXPECT_EQ(sexLevel.height(), level.height());
  EXPECT_EQ(sexMiniLevel.width(), storage.meshCountX());
  EXPECT_EQ(sexMiniLevel.height(), storage.meshCountY());
  c.levelMaxAdu = maxAbsDiff(level, sexLevel);
  c.rmsMaxAdu = maxAbsDiff(rms, sexRms);
  c.miniLevelMaxAdu = maxAbsDiff(storage.meshLevels(), sexMiniLevel);
  c.miniRmsMaxAdu = maxAbsDiff(storage.meshRms(), sexMiniRms);
  c.sexBkgnd = test::ldacHeaderValue(dir / "cat.ldac", "SEXBKGND");
  c.sexBkdev = test::ldacHeaderValue(dir / "cat.ldac", "SEXBKDEV");
  std::cout << "  " << imagePath.filename().string() << " BACK_SIZE " << s.meshWidth << ","
            << s.meshHeight << " FILTER " << s.filterWidth << "," << s.filterHeight
            << ": max |diff| / sigma: BACKGROUND " << c.levelMaxAdu / c.sexBkdev
            << ", BACKGROUND_RMS " << c.rmsMaxAdu / c.sexBkdev << ", MINIBACKGROUND "
            << c.miniLevelMaxAdu / c.sexBkdev << ", MINIBACK_RMS " << c.miniRmsMaxAdu / c.sexBkdev
            << "\n";
  return c;
}

// Bit-identical maps (the README's claim) and global values that print as SExtractor's cards.
void expectAgreement(const Comparison& c, const MeshBackground& b) {
  const double sigma = c.sexBkdev;
  EXPECT_LE(c.levelMaxAdu, kAcceptanceFraction * sigma);
  EXPECT_LE(c.rmsMaxAdu, kAcceptanceFraction * sigma);
  EXPECT_EQ(c.levelMaxAdu, 0.0);
  EXPECT_EQ(c.rmsMaxAdu, 0.0);
  EXPECT_EQ(c.miniLevelMaxAdu, 0.0);
  EXPECT_EQ(c.miniRmsMaxAdu, 0.0);
  EXPECT_EQ(printedLikeSExtractor(b.globalLevelAdu()), printedLikeSExtractor(c.sexBkgnd));
  EXPECT_EQ(printedLikeSExtractor(b.globalSigmaAdu()), printedLikeSExtractor(c.sexBkdev));
}

TEST(MeshBackground, GalaxiesMatchesSExtractorDefaultMesh) {
  OCTARC_REQUIRE_SHARED_DATA(shared);
  if (!test::haveProgram("source-extractor"))
    OCTARC_SKIP_MISSING() << "source-extractor not installed";
  const fs::path dir = test::scratchDir();
  MeshBackground storage;
  const MeshBackground* b = nullptr;
  const Comparison c = compareWithSExtractor(shared / "ntt-emmi" / "galaxies.fits", dir,
                                             MeshBackgroundSettings{}, &b, storage);
  expectAgreement(c, *b);
  EXPECT_TRUE(b->warnings().empty());
}

struct MeshCase {
  int meshWidth, meshHeight, filterWidth, filterHeight;
  double filterThresholdAdu;
};

class GalaxiesMeshSizes : public ::testing::TestWithParam<MeshCase> {};

TEST_P(GalaxiesMeshSizes, MatchesSExtractor) {
  OCTARC_REQUIRE_SHARED_DATA(shared);
  if (!test::haveProgram("source-extractor"))
    OCTARC_SKIP_MISSING() << "source-extractor not installed";
  const MeshCase p = GetParam();
  MeshBackgroundSettings s;
  s.meshWidth = p.meshWidth;
  s.meshHeight = p.meshHeight;
  s.filterWidth = p.filterWidth;
  s.filterHeight = p.filterHeight;
  s.filterThresholdAdu = p.filterThresholdAdu;
  MeshBackground storage;
  const MeshBackground* b = nullptr;
  const Comparison c = compareWithSExtractor(shared / "ntt-emmi" / "galaxies.fits",
                                             test::scratchDir(), s, &b, storage);
  expectAgreement(c, *b);
}

// 1024 is not a multiple of 100, 48 or 300: partial meshes on the right and top edges; even
// and rectangular filters; a filter threshold that leaves some meshes unfiltered.
INSTANTIATE_TEST_SUITE_P(
    Sizes, GalaxiesMeshSizes,
    ::testing::Values(MeshCase{32, 32, 1, 1, 0.0}, MeshCase{100, 100, 5, 5, 0.0},
                      MeshCase{48, 80, 3, 1, 0.0}, MeshCase{128, 128, 3, 3, 0.0},
                      MeshCase{300, 300, 3, 3, 0.0}, MeshCase{64, 64, 4, 2, 0.0},
                      MeshCase{64, 64, 3, 3, 20.0}));

TEST(MeshBackground, SepReferenceCheckImages) {
  // back.fits and rms.fits were written by SExtractor (BACK_SIZE 64, BACK_FILTERSIZE 3) for this
  // 256x256 cutout, independently of this machine's source-extractor.
  OCTARC_REQUIRE_SHARED_DATA(shared);
  const fs::path ref = shared / "sep-reference";
  const ImageF image = test::readFits<float>(ref / "image.fits");
  const MeshBackground b = MeshBackground::estimate(image, MeshBackgroundSettings{});
  const double sigma = b.globalSigmaAdu();
  const double dl = maxAbsDiff(b.levelImage(), test::readFits<float>(ref / "back.fits"));
  const double dr = maxAbsDiff(b.rmsImage(), test::readFits<float>(ref / "rms.fits"));
  std::cout << "  sep-reference: max |diff| / sigma: BACKGROUND " << dl / sigma
            << ", BACKGROUND_RMS " << dr / sigma << "\n";
  // Written by another SExtractor version on another machine: agreement reached 1.34e-4 sigma
  // (BACKGROUND) and 2.9e-5 sigma (BACKGROUND_RMS).
  EXPECT_LE(dl, 1.4e-4 * sigma);
  EXPECT_LE(dr, 3e-5 * sigma);
}

TEST(MeshBackground, SyntheticGradientMatchesTruthAndSExtractor) {
  // Sky 1000 + 0.05 ADU/px along x - 0.02 along y, Gaussian noise sigma 10, no sources: the
  // true background is the plane and the true rms is 10.
  const double sigma = 10.0;
  const ImageF image = test::skyWithGradient(700, 530, 1000.0, 0.05, -0.02, sigma, 42);
  const MeshBackground b = MeshBackground::estimate(image, MeshBackgroundSettings{});
  const ImageF level = b.levelImage();
  const ImageF rms = b.rmsImage();
  double worstLevel = 0.0, sumRms = 0.0, sumError = 0.0;
  for (std::int64_t y = 0; y < image.height(); ++y)
    for (std::int64_t x = 0; x < image.width(); ++x) {
      const double truth = 1000.0 + 0.05 * x - 0.02 * y;
      worstLevel = std::max(worstLevel, std::fabs(level(x, y) - truth));
      sumError += level(x, y) - truth;
      sumRms += rms(x, y);
    }
  // One mesh holds 4096 pixels: its mode has a standard error of a few sigma/64, about 0.3
  // ADU; the 3x3 median filter reduces it and the spline extrapolation at the image edges
  // amplifies it, so bound the worst pixel by 0.25 sigma and the mean error by 0.03 sigma.
  EXPECT_LT(worstLevel, 0.25 * sigma);
  EXPECT_LT(std::fabs(sumError / static_cast<double>(image.size())), 0.03 * sigma);
  EXPECT_NEAR(sumRms / static_cast<double>(image.size()), sigma, 0.03 * sigma);
  EXPECT_NEAR(b.globalSigmaAdu(), sigma, 0.03 * sigma);
  EXPECT_NEAR(b.globalLevelAdu(), 1000.0 + 0.05 * 349.5 - 0.02 * 264.5, 2.0);

  if (!test::haveProgram("source-extractor"))
    OCTARC_SKIP_MISSING() << "source-extractor not installed";
  const fs::path dir = test::scratchDir();
  test::writeFloatFits(dir / "sky.fits", image);
  MeshBackground storage;
  const MeshBackground* ours = nullptr;
  const Comparison c =
      compareWithSExtractor(dir / "sky.fits", dir, MeshBackgroundSettings{}, &ours, storage);
  expectAgreement(c, *ours);
}

TEST(MeshBackground, SampledStatisticsOfWideImagesMatchSExtractor) {
  // A mesh row of 17 000 x 64 pixels exceeds SExtractor's 2^20-pixel statistics buffer: the
  // clipped mean/sigma then come from every other row. The last mesh row (200 % 64 = 8 rows)
  // and the last mesh column (17000 % 64 = 40 columns) are partial.
  if (!test::haveProgram("source-extractor"))
    OCTARC_SKIP_MISSING() << "source-extractor not installed";
  ImageF image = test::skyWithGradient(17000, 200, 200.0, 0.001, 0.1, 4.0, 7);
  test::addSources(image, 3000, 2000.0, 8);
  const fs::path dir = test::scratchDir();
  test::writeFloatFits(dir / "wide.fits", image);
  MeshBackground storage;
  const MeshBackground* b = nullptr;
  const Comparison c =
      compareWithSExtractor(dir / "wide.fits", dir, MeshBackgroundSettings{}, &b, storage);
  expectAgreement(c, *b);
}

TEST(MeshBackground, ConstantImageWarnsAndUsesUnitSigma) {
  const ImageF image(200, 150, 0.0f);
  const MeshBackground b = MeshBackground::estimate(image, MeshBackgroundSettings{}, "zero.fits");
  EXPECT_EQ(b.globalLevelAdu(), 0.0);
  EXPECT_EQ(b.globalSigmaAdu(), 1.0);
  ASSERT_EQ(b.warnings().size(), 1u);
  EXPECT_NE(b.warnings()[0].find("constant"), std::string::npos);
  EXPECT_NE(b.warnings()[0].find("zero.fits"), std::string::npos);
  const ImageF level = b.levelImage();
  const ImageF rms = b.rmsImage();
  for (std::int64_t i = 0; i < image.size(); ++i) {
    ASSERT_EQ(level[i], 0.0f);
    ASSERT_EQ(rms[i], 0.0f);  // SExtractor's BACKGROUND_RMS of constant data is 0 too
  }

  const ImageF seven(130, 70, 7.0f);
  const MeshBackground b7 = MeshBackground::estimate(seven, MeshBackgroundSettings{});
  EXPECT_EQ(b7.globalLevelAdu(), 7.0);
  EXPECT_EQ(b7.globalSigmaAdu(), 1.0);
  std::vector<float> row(130);
  b7.levelRow(69, row.data());
  for (float v : row) ASSERT_EQ(v, 7.0f);
}

TEST(MeshBackground, ConstantImageMatchesSExtractor) {
  if (!test::haveProgram("source-extractor"))
    OCTARC_SKIP_MISSING() << "source-extractor not installed";
  const fs::path dir = test::scratchDir();
  test::writeFloatFits(dir / "flat.fits", ImageF(150, 100, 3.0f));
  test::runSExtractorBackground(dir / "flat.fits", dir, "-BACK_SIZE 64",
                                "BACKGROUND,BACKGROUND_RMS", "b.fits,r.fits");
  const MeshBackground b =
      MeshBackground::estimate(ImageF(150, 100, 3.0f), MeshBackgroundSettings{});
  EXPECT_EQ(maxAbsDiff(b.levelImage(), test::readFits<float>(dir / "b.fits")), 0.0);
  EXPECT_EQ(maxAbsDiff(b.rmsImage(), test::readFits<float>(dir / "r.fits")), 0.0);
  EXPECT_EQ(b.globalSigmaAdu(), test::ldacHeaderValue(dir / "cat.ldac", "SEXBKDEV"));
}

TEST(MeshBackground, AllNanImageIsAnError) {
  const ImageF image(100, 100, std::numeric_limits<float>::quiet_NaN());
  try {
    (void)MeshBackground::estimate(image, MeshBackgroundSettings{}, "nan.fits");
    FAIL() << "expected IoError";
  } catch (const IoError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("nan.fits"), std::string::npos) << what;
    EXPECT_NE(what.find("no valid pixels"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos);
  }
}

TEST(MeshBackground, BadSettingsAreConfigErrors) {
  const ImageF image(10, 10, 1.0f);
  MeshBackgroundSettings s;
  s.meshWidth = 0;
  EXPECT_THROW((void)MeshBackground::estimate(image, s), ConfigError);
  s = {};
  s.filterHeight = 0;
  EXPECT_THROW((void)MeshBackground::estimate(image, s), ConfigError);
  EXPECT_THROW((void)MeshBackground::estimate(ImageF(), MeshBackgroundSettings{}), IoError);
}

TEST(MeshBackground, NanMeshIsReplacedByItsNearestNeighbours) {
  // Without filtering, a mesh with no valid pixel takes the mean of the good meshes at the
  // smallest distance: here its four direct neighbours. Other meshes are unaffected, and NaN
  // and infinite pixels elsewhere are ignored.
  ImageF image = test::skyWithGradient(320, 320, 50.0, 0.1, 0.05, 3.0, 3);
  MeshBackgroundSettings s;
  s.filterWidth = s.filterHeight = 1;
  const MeshBackground clean = MeshBackground::estimate(image, s);
  for (int y = 128; y < 192; ++y)
    for (int x = 128; x < 192; ++x) image(x, y) = std::numeric_limits<float>::quiet_NaN();
  const MeshBackground holed = MeshBackground::estimate(image, s);
  const ImageF& a = clean.meshLevels();
  const ImageF& h = holed.meshLevels();
  const float expected = (((a(2, 1) + a(1, 2)) + a(3, 2)) + a(2, 3)) / 4.0f;
  EXPECT_FLOAT_EQ(h(2, 2), expected);
  const float expectedRms =
      (((clean.meshRms()(2, 1) + clean.meshRms()(1, 2)) + clean.meshRms()(3, 2)) +
       clean.meshRms()(2, 3)) /
      4.0f;
  EXPECT_FLOAT_EQ(holed.meshRms()(2, 2), expectedRms);
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 5; ++x)
      if (x != 2 || y != 2) {
        EXPECT_EQ(h(x, y), a(x, y));
      }
}

TEST(MeshBackground, NanPixelsAndBadMeshesMatchSExtractor) {
  // SExtractor ignores NaN pixels in the mesh statistics and replaces meshes with fewer than
  // half of their pixels valid by their nearest good meshes: a NaN block covering several
  // meshes (ties at equal distances), a mesh 60 % NaN, scattered NaN pixels.
  if (!test::haveProgram("source-extractor"))
    OCTARC_SKIP_MISSING() << "source-extractor not installed";
  ImageF image = test::skyWithGradient(700, 450, 500.0, 0.02, -0.03, 6.0, 21);
  test::addSources(image, 200, 3000.0, 22);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int y = 130; y < 300; ++y)
    for (int x = 200; x < 390; ++x) image(x, y) = nan;
  for (int y = 0; y < 64; ++y)
    for (int x = 576; x < 576 + 39; ++x) image(x, y) = nan;
  for (std::int64_t i = 7; i < image.size(); i += 97) image[i] = nan;
  const fs::path dir = test::scratchDir();
  test::writeFloatFits(dir / "holes.fits", image);
  MeshBackground storage;
  const MeshBackground* b = nullptr;
  const Comparison c =
      compareWithSExtractor(dir / "holes.fits", dir, MeshBackgroundSettings{}, &b, storage);
  expectAgreement(c, *b);
}

struct WeightCase {
  WeightMapType type;
  const char* sexType;
  bool rescale;
  double threshold;  // < 0: SExtractor's default
};

class WeightedBackground : public ::testing::TestWithParam<WeightCase> {};

TEST_P(WeightedBackground, MatchesSExtractor) {
  // Noise 4 ADU on the left half and 9 ADU on the right; weights 1/sigma^2 (or sigma, or
  // sigma^2); a zero-weight block holding garbage (1e5) that must not touch the background. In
  // the thresholded cases the right half (variance 81) reaches the threshold (variance 50), so
  // its meshes are all bad and filled from the left half.
  if (!test::haveProgram("source-extractor"))
    OCTARC_SKIP_MISSING() << "source-extractor not installed";
  const WeightCase p = GetParam();
  const std::int64_t w = 600, h = 420;
  ImageF image(w, h), weight(w, h);
  {
    std::mt19937_64 rng(99);
    std::normal_distribution<double> unit(0.0, 1.0);
    for (std::int64_t y = 0; y < h; ++y)
      for (std::int64_t x = 0; x < w; ++x) {
        const double sigma = x < 300 ? 4.0 : 9.0;
        image(x, y) = static_cast<float>(200.0 + 0.03 * x + sigma * unit(rng));
        const double var = sigma * sigma;
        weight(x, y) = static_cast<float>(p.type == WeightMapType::Weight ? 1.0 / var
                                          : p.type == WeightMapType::Rms  ? sigma
                                                                          : var);
      }
    test::addSources(image, 150, 2000.0, 100);
    for (std::int64_t y = 100; y < 230; ++y)
      for (std::int64_t x = 50; x < 200; ++x) {
        image(x, y) = 1e5f;
        weight(x, y) = p.type == WeightMapType::Weight ? 0.0f : 1e31f;
      }
  }
  const fs::path dir = test::scratchDir();
  test::writeFloatFits(dir / "img.fits", image);
  test::writeFloatFits(dir / "wgt.fits", weight);
  std::string args = std::string("-BACK_SIZE 64 -BACK_FILTERSIZE 3 -WEIGHT_IMAGE wgt.fits ") +
                     "-WEIGHT_TYPE " + p.sexType + " -RESCALE_WEIGHTS " + (p.rescale ? "Y" : "N");
  if (p.threshold >= 0) args += " -WEIGHT_THRESH " + std::to_string(p.threshold);
  test::runSExtractorBackground(dir / "img.fits", dir, args,
                                "BACKGROUND,BACKGROUND_RMS,MINIBACKGROUND,MINIBACK_RMS",
                                "b.fits,r.fits,mb.fits,mr.fits");
  WeightMap wm;
  wm.pixels = &weight;
  wm.type = p.type;
  wm.rescale = p.rescale;
  if (p.threshold >= 0) wm.threshold = p.threshold;
  const MeshBackground b = MeshBackground::estimate(image, MeshBackgroundSettings{}, wm);
  const double sexBkdev = test::ldacHeaderValue(dir / "cat.ldac", "SEXBKDEV");
  const double sexScale = test::ldacHeaderValue(dir / "cat.ldac", "SEXDWSCL");
  const double dl = maxAbsDiff(b.levelImage(), test::readFits<float>(dir / "b.fits"));
  const double dr = maxAbsDiff(b.rmsImage(), test::readFits<float>(dir / "r.fits"));
  const double dml = maxAbsDiff(b.meshLevels(), test::readFits<float>(dir / "mb.fits"));
  const double dmr = maxAbsDiff(b.meshRms(), test::readFits<float>(dir / "mr.fits"));
  std::cout << "  weights " << p.sexType << " rescale " << p.rescale << ": max |diff| / sigma "
            << dl / sexBkdev << ", " << dr / sexBkdev << ", " << dml / sexBkdev << ", "
            << dmr / sexBkdev << "; SEXDWSCL " << sexScale << " vs " << b.weightScale() << "\n";
  EXPECT_TRUE(b.hasWeights());
  EXPECT_EQ(printedLikeSExtractor(b.globalSigmaAdu()),
            printedInCatalog(dir / "cat.ldac", "SEXBKDEV"));
  EXPECT_EQ(printedLikeSExtractor(b.weightScale()), printedInCatalog(dir / "cat.ldac", "SEXDWSCL"));
  EXPECT_EQ(dl, 0.0);
  EXPECT_EQ(dr, 0.0);
  EXPECT_EQ(dml, 0.0);
  EXPECT_EQ(dmr, 0.0);
  // The garbage block is ignored: the background there follows the sky plane.
  EXPECT_NEAR(b.levelImage()(125, 165), 200.0 + 0.03 * 125, 2.0);
}

INSTANTIATE_TEST_SUITE_P(
    Types, WeightedBackground,
    ::testing::Values(WeightCase{WeightMapType::Weight, "MAP_WEIGHT", true, -1.0},
                      WeightCase{WeightMapType::Weight, "MAP_WEIGHT", false, -1.0},
                      WeightCase{WeightMapType::Variance, "MAP_VAR", true, -1.0},
                      WeightCase{WeightMapType::Rms, "MAP_RMS", true, -1.0},
                      WeightCase{WeightMapType::Weight, "MAP_WEIGHT", true, 0.02},
                      WeightCase{WeightMapType::Variance, "MAP_VAR", true, 50.0}));

TEST(MeshBackground, WeightMapOfWrongSizeIsAnError) {
  const ImageF image(100, 80, 1.0f), weight(100, 81, 1.0f);
  WeightMap wm;
  wm.pixels = &weight;
  wm.name = "w.fits";
  try {
    (void)MeshBackground::estimate(image, MeshBackgroundSettings{}, wm, "img.fits");
    FAIL() << "expected IoError";
  } catch (const IoError& e) {
    EXPECT_STREQ(e.what(), "w.fits: weight map is 100x81 but img.fits is 100x80");
  }
}

TEST(MeshBackground, ResultsDoNotDependOnThreadCount) {
  ImageF image = test::skyWithGradient(1000, 777, 300.0, 0.01, 0.02, 5.0, 11);
  test::addSources(image, 400, 5000.0, 12);
  MeshBackgroundSettings s;
  s.threadCount = 1;
  const MeshBackground one = MeshBackground::estimate(image, s);
  s.threadCount = 2;
  const MeshBackground two = MeshBackground::estimate(image, s);
  s.threadCount = 5;
  const MeshBackground five = MeshBackground::estimate(image, s);
  EXPECT_EQ(maxAbsDiff(one.levelImage(), two.levelImage()), 0.0);
  EXPECT_EQ(maxAbsDiff(one.rmsImage(), five.rmsImage()), 0.0);
  EXPECT_EQ(one.globalSigmaAdu(), five.globalSigmaAdu());
}

// Number of pixels whose bit patterns differ (NaN included).
std::int64_t bitDifferences(const ImageF& a, const ImageF& b) {
  if (a.width() != b.width() || a.height() != b.height()) return -1;
  std::int64_t n = 0;
  for (std::int64_t i = 0; i < a.size(); ++i)
    n += std::bit_cast<std::uint32_t>(a[i]) != std::bit_cast<std::uint32_t>(b[i]);
  return n;
}

TEST(MeshBackground, PlainStatisticsMatchTheUnitWeightPath) {
  // Without a weight map the mesh statistics run several meshes at a time with branch-free
  // selections; with a weight map of ones (all variances 1, below the default threshold) the
  // mesh-by-mesh loops select exactly the same pixels. The image maps must agree bit for bit, on
  // images with NaN, infinite and blank (-1e30) pixels, bad meshes, a constant mesh, partial
  // meshes and groups of 8, 4 and single meshes.
  struct Case {
    std::int64_t width, height;
    int meshWidth, meshHeight;
  };
  for (const Case c : {Case{64 * 13 + 17, 64 * 3 + 5, 64, 64}, Case{64 * 16, 64 * 2, 64, 64},
                       Case{301, 97, 7, 5}, Case{250, 90, 32, 16}, Case{17000, 130, 64, 64}}) {
    ImageF image = test::skyWithGradient(c.width, c.height, 100.0, 0.003, -0.01, 3.0, 99);
    test::addSources(image, static_cast<int>(c.width * c.height / 3000), 800.0, 100);
    std::mt19937 rng(5);
    std::uniform_int_distribution<std::int64_t> pick(0, image.size() - 1);
    // The float just above -1e30 is a valid pixel; -1e30f itself is blank.
    const float specials[] = {std::numeric_limits<float>::quiet_NaN(),
                              std::numeric_limits<float>::infinity(),
                              -std::numeric_limits<float>::infinity(),
                              -1e30f,
                              -1.1e30f,
                              std::nextafter(-1e30f, 0.0f),
                              9e29f};
    for (int k = 0; k < 700; ++k) image[pick(rng)] = specials[k % 7];
    // Mesh (1, 1) entirely blank, mesh (2, 0) more than half NaN, mesh (0, 1) constant.
    for (int y = 0; y < c.meshHeight; ++y)
      for (int x = 0; x < c.meshWidth; ++x) {
        image(c.meshWidth + x, c.meshHeight + y) = -1e30f;
        if (x * 3 < c.meshWidth * 2)
          image(2 * c.meshWidth + x, y) = std::numeric_limits<float>::quiet_NaN();
        image(x, c.meshHeight + y) = 42.0f;
      }
    ImageF ones(c.width, c.height);
    for (std::int64_t i = 0; i < ones.size(); ++i) ones[i] = 1.0f;
    WeightMap unit;
    unit.pixels = &ones;
    MeshBackgroundSettings s;
    s.meshWidth = c.meshWidth;
    s.meshHeight = c.meshHeight;
    s.threadCount = 2;
    const MeshBackground plain = MeshBackground::estimate(image, s);
    const MeshBackground weighted = MeshBackground::estimate(image, s, unit);
    SCOPED_TRACE(std::to_string(c.width) + "x" + std::to_string(c.height) + " mesh " +
                 std::to_string(c.meshWidth) + "x" + std::to_string(c.meshHeight));
    EXPECT_EQ(bitDifferences(plain.meshLevels(), weighted.meshLevels()), 0);
    EXPECT_EQ(bitDifferences(plain.meshRms(), weighted.meshRms()), 0);
    EXPECT_EQ(bitDifferences(plain.levelImage(), weighted.levelImage()), 0);
    EXPECT_EQ(bitDifferences(plain.rmsImage(), weighted.rmsImage()), 0);
    EXPECT_EQ(plain.globalLevelAdu(), weighted.globalLevelAdu());
    EXPECT_EQ(plain.globalSigmaAdu(), weighted.globalSigmaAdu());
  }
}

TEST(MeshBackground, RowApiMatchesFullMaps) {
  ImageF image = test::skyWithGradient(333, 222, 10.0, 0.02, 0.03, 1.0, 5);
  MeshBackgroundSettings s;
  s.meshWidth = 40;
  s.meshHeight = 30;
  const MeshBackground b = MeshBackground::estimate(image, s);
  const ImageF level = b.levelImage();
  const ImageF rms = b.rmsImage();
  std::vector<float> row(333);
  for (std::int64_t y : {0, 1, 14, 15, 100, 221}) {
    b.levelRow(y, row.data());
    for (std::int64_t x = 0; x < 333; ++x) ASSERT_EQ(row[x], level(x, y));
    b.rmsRow(y, row.data());
    for (std::int64_t x = 0; x < 333; ++x) ASSERT_EQ(row[x], rms(x, y));
    std::copy(image.data() + y * 333, image.data() + (y + 1) * 333, row.begin());
    b.subtractRow(y, row.data());
    for (std::int64_t x = 0; x < 333; ++x) ASSERT_EQ(row[x], image(x, y) - level(x, y));
  }
}

TEST(MeshBackground, SubtractRowIsRowMinusLevelForEveryGridShape) {
  // subtractRow interpolates and subtracts in one pass; it must equal row - levelRow exactly for
  // the general spline, one mesh column (constant rows), 1-pixel-wide meshes (one node per
  // column) and one mesh row (linear interpolation along x).
  struct Shape {
    std::int64_t width, height;
    int meshWidth, meshHeight;
  };
  for (const Shape c : {Shape{333, 222, 40, 30}, Shape{50, 70, 64, 16}, Shape{40, 90, 1, 30},
                        Shape{300, 20, 32, 64}, Shape{129, 65, 64, 64}}) {
    const ImageF image = test::skyWithGradient(c.width, c.height, 10.0, 0.02, 0.03, 1.0, 8);
    MeshBackgroundSettings s;
    s.meshWidth = c.meshWidth;
    s.meshHeight = c.meshHeight;
    const MeshBackground b = MeshBackground::estimate(image, s);
    std::vector<float> level(static_cast<std::size_t>(c.width)), row(level.size());
    for (std::int64_t y = 0; y < c.height; ++y) {
      b.levelRow(y, level.data());
      std::copy(image.data() + y * c.width, image.data() + (y + 1) * c.width, row.begin());
      b.subtractRow(y, row.data());
      for (std::int64_t x = 0; x < c.width; ++x)
        ASSERT_EQ(row[x], image(x, y) - level[x])
            << "x " << x << " y " << y << " shape " << c.width << "x" << c.height;
    }
  }
}

TEST(MeshBackground, MeshLargerThanImageIsClipped) {
  // SExtractor clips BACK_SIZE to the image: one mesh, a constant map equal to its mode.
  const ImageF image = test::skyWithGradient(50, 40, 20.0, 0.0, 0.0, 2.0, 9);
  const MeshBackground b = MeshBackground::estimate(image, MeshBackgroundSettings{});
  EXPECT_EQ(b.meshWidth(), 50);
  EXPECT_EQ(b.meshHeight(), 40);
  EXPECT_EQ(b.meshCountX(), 1);
  EXPECT_EQ(b.meshCountY(), 1);
  const ImageF level = b.levelImage();
  for (std::int64_t i = 0; i < level.size(); ++i) ASSERT_EQ(level[i], b.meshLevels()[0]);
  EXPECT_EQ(b.globalLevelAdu(), b.meshLevels()[0]);
  EXPECT_NEAR(b.globalLevelAdu(), 20.0, 0.5);
}

class GalaxiesSep : public ::testing::TestWithParam<MeshCase> {};

TEST_P(GalaxiesSep, MatchesPythonSep) {
  // python3-sep's Background on the same pixel values (SEP carries SExtractor's algorithm).
  OCTARC_REQUIRE_SHARED_DATA(shared);
  if (test::runQuiet("/usr/bin/python3 -c 'import sep, astropy'") != 0)
    OCTARC_SKIP_MISSING() << "python3-sep or astropy not available";
  const MeshCase p = GetParam();
  const fs::path dir = test::scratchDir();
  const ImageF image = test::readFitsAsSExtractor(shared / "ntt-emmi" / "galaxies.fits");
  test::writeFloatFits(dir / "in.fits", image);
  const std::string cmd = "/usr/bin/python3 '" + std::string(OCTARC_SOURCE_DIR) +
                          "/tests/unit/background/sep_background.py' '" +
                          (dir / "in.fits").string() + "' '" + (dir / "sb.fits").string() + "' '" +
                          (dir / "sr.fits").string() + "' " + std::to_string(p.meshWidth) + " " +
                          std::to_string(p.meshHeight) + " " + std::to_string(p.filterWidth) + " " +
                          std::to_string(p.filterHeight);
  ASSERT_EQ(test::runQuiet(cmd), 0) << cmd;
  MeshBackgroundSettings s;
  s.meshWidth = p.meshWidth;
  s.meshHeight = p.meshHeight;
  s.filterWidth = p.filterWidth;
  s.filterHeight = p.filterHeight;
  const MeshBackground b = MeshBackground::estimate(image, s);
  const double sigma = b.globalSigmaAdu();
  const double dl = maxAbsDiff(b.levelImage(), test::readFits<float>(dir / "sb.fits"));
  const double dr = maxAbsDiff(b.rmsImage(), test::readFits<float>(dir / "sr.fits"));
  std::cout << "  sep BACK_SIZE " << p.meshWidth << "," << p.meshHeight << " FILTER "
            << p.filterWidth << "," << p.filterHeight << ": max |diff| / sigma: back " << dl / sigma
            << ", rms " << dr / sigma << "\n";
  // SEP carries SExtractor's algorithm in the same single precision: bit-identical too.
  EXPECT_EQ(dl, 0.0);
  EXPECT_EQ(dr, 0.0);
}

INSTANTIATE_TEST_SUITE_P(Sizes, GalaxiesSep,
                         ::testing::Values(MeshCase{64, 64, 3, 3, 0.0},
                                           MeshCase{100, 100, 5, 5, 0.0},
                                           MeshCase{48, 80, 3, 1, 0.0},
                                           MeshCase{32, 32, 1, 1, 0.0}));

}  // namespace
}  // namespace octarc
