// `octarc simulate database` on a synthetic deep image with known galaxies, and a lens system
// rendered from one of the database galaxies.
#include <fitsio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include "FitsTestFiles.h"
#include "TestPaths.h"
#include "octarc/core/Error.h"
#include "octarc/io/FitsImage.h"
#include "octarc/app/Commands.h"
#include "octarc/simulation/LensSystem.h"
#include "octarc/simulation/RealGalaxyCatalog.h"

namespace octarc {
namespace {

namespace fs = std::filesystem;
using simulation::RealGalaxyCatalog;

struct Blob {
  int x, y;
  double peakAdu, sigmaPix;
};

constexpr double kSkyAdu = 100.0;
constexpr double kNoiseAdu = 2.0;  // 4 sigma = 8 ADU

// Four galaxies that must enter the database (two isolated, a pair 16 px apart), one cut by the
// left border, one too small for --min-size 25 (about 9 pixels above 8 ADU).
const std::vector<Blob> kGalaxies = {
    {60, 60, 200.0, 3.0}, {180, 70, 120.0, 2.5}, {70, 180, 150.0, 2.5}, {86, 180, 80.0, 2.0}};
const std::vector<Blob> kRejected = {{1, 128, 200.0, 3.0}, {200, 200, 30.0, 1.0}};

double model(const std::vector<Blob>& blobs, int x, int y) {
  double v = 0.0;
  for (const Blob& b : blobs) {
    const double r2 = double((x - b.x) * (x - b.x) + (y - b.y) * (y - b.y));
    v += b.peakAdu * std::exp(-0.5 * r2 / (b.sigmaPix * b.sigmaPix));
  }
  return v;
}

// The deep image: sky + galaxies + Gaussian noise (fixed seed), 256 x 256.
ImageF deepImage() {
  std::vector<Blob> all = kGalaxies;
  all.insert(all.end(), kRejected.begin(), kRejected.end());
  std::mt19937_64 rng(12345);
  std::normal_distribution<double> noise(0.0, kNoiseAdu);
  ImageF img(256, 256);
  for (int y = 0; y < 256; ++y)
    for (int x = 0; x < 256; ++x) img(x, y) = float(kSkyAdu + model(all, x, y) + noise(rng));
  return img;
}

// With a tangent-plane WCS of 0.05"/px whose reference pixel is the first galaxy's centre.
void setWcs(FitsHeader& h) {
  h.set("CTYPE1", quoteFitsString("RA---TAN"));
  h.set("CTYPE2", quoteFitsString("DEC--TAN"));
  h.set("CRVAL1", "53.16");
  h.set("CRVAL2", "-27.78");
  h.set("CRPIX1", "61.0");
  h.set("CRPIX2", "61.0");
  char cd[32];
  std::snprintf(cd, sizeof cd, "%.15E", 0.05 / 3600.0);
  h.set("CD1_1", std::string("-") + cd);
  h.set("CD1_2", "0.0");
  h.set("CD2_1", "0.0");
  h.set("CD2_2", cd);
}

std::string writeDeepImage(const fs::path& dir, bool withPixelScale = true, bool withWcs = false) {
  const ImageF img = deepImage();
  OutputImageHdu hdu;
  hdu.floatPixels = &img;
  if (withWcs) setWcs(hdu.header);
  if (withPixelScale) hdu.header.set("PIXSCALE", "0.06", "arcsec/pixel");
  hdu.header.set("FILTER", quoteFitsString("F850LP"));
  const std::string path = (dir / "deep.fits").string();
  writeImageFile(path, {hdu});
  return path;
}

bool isEmptyDir(const fs::path& dir) {
  return fs::is_empty(dir);
}

TEST(BuildDatabase, CutsTheKnownGalaxies) {
  const fs::path dir = test::scratchDir();
  const std::string image = writeDeepImage(dir);
  const std::string cat = (dir / "db.fits").string();
  ASSERT_EQ(runBuildDatabase({image, "-o", cat, "--zeropoint", "25", "--margin", "12", "--quiet"}),
            0);
  const RealGalaxyCatalog db = RealGalaxyCatalog::load(cat);
  ASSERT_EQ(db.size(), kGalaxies.size());  // border and small objects skipped

  for (std::size_t i = 0; i < db.size(); ++i) {
    const Blob& g = kGalaxies[i];  // rows follow the detection order (raster order of first pixel)
    const long row = long(i) + 1;
    SCOPED_TRACE("galaxy at " + std::to_string(g.x) + "," + std::to_string(g.y));
    EXPECT_NEAR(test::tableValue(cat, "X_IMAGE", row), g.x + 1.0, 0.1);
    EXPECT_NEAR(test::tableValue(cat, "Y_IMAGE", row), g.y + 1.0, 0.1);
    EXPECT_EQ(db.entry(i).band, "F850LP");
    EXPECT_DOUBLE_EQ(db.entry(i).pixelScaleArcsec, 0.06);

    // The stamp's flux is the galaxy's flux above 8 ADU: for a Gaussian of peak A and width s,
    // 2 pi s^2 (A - T) analytically. Noise and pixelisation at the isophote move it by ~1%.
    const double stampFlux = test::tableValue(cat, "stamp_flux", row);
    const double analytic = 2.0 * M_PI * g.sigmaPix * g.sigmaPix * (g.peakAdu - 4.0 * kNoiseAdu);
    EXPECT_NEAR(stampFlux, analytic, 0.03 * analytic);
    EXPECT_NEAR(db.entry(i).mag, 25.0 - 2.5 * std::log10(stampFlux), 1e-9);
    const simulation::SourceStamp s = db.loadGalaxy(i);
    EXPECT_NEAR(simulation::totalFlux(s), stampFlux, 1e-9 * stampFlux);
    // Noise-free: the stamp's border (margin 12 px) is exactly zero.
    const ImageD& p = s.fluxPerPixel;
    for (std::int64_t x = 0; x < p.width(); ++x) {
      EXPECT_EQ(p(x, 0), 0.0);
      EXPECT_EQ(p(x, p.height() - 1), 0.0);
    }
    // The galaxy's peak is the centre pixel.
    EXPECT_NEAR(p((p.width() - 1) / 2, (p.height() - 1) / 2), g.peakAdu, 4.0 * kNoiseAdu);
  }
  // The measured noise is the one put in.
  EXPECT_NEAR(test::tableValue(cat, "NOISE_VARIANCE", 1), kNoiseAdu * kNoiseAdu, 0.05 * 4.0);

  // Clean: the pair's bright member (row 3, at 70,180) has its neighbour (86,180, peak 80 ADU)
  // inside the stamp, zeroed.
  const simulation::SourceStamp pair = db.loadGalaxy(2);
  const std::int64_t cx = (pair.fluxPerPixel.width() - 1) / 2;
  const std::int64_t cy = (pair.fluxPerPixel.height() - 1) / 2;
  ASSERT_LT(cx + 16, pair.fluxPerPixel.width());
  EXPECT_EQ(pair.fluxPerPixel(cx + 16, cy), 0.0);
  EXPECT_EQ(pair.fluxPerPixel(cx + 14, cy), 0.0);
  EXPECT_GT(pair.fluxPerPixel(cx + 2, cy), 50.0);
}

TEST(BuildDatabase, MaxGalaxiesKeepsTheBrightest) {
  const fs::path dir = test::scratchDir();
  const std::string image = writeDeepImage(dir);
  const std::string cat = (dir / "two.fits").string();
  ASSERT_EQ(runBuildDatabase({image, "-o", cat, "--max-galaxies", "2", "--quiet"}), 0);
  const RealGalaxyCatalog db = RealGalaxyCatalog::load(cat);
  ASSERT_EQ(db.size(), 2u);
  // Fluxes 2 pi s^2 (A - 8): 10857, 4398, 5576, 1810 ADU: the galaxies at x = 60 and 70, kept
  // in detection order.
  EXPECT_NEAR(test::tableValue(cat, "X_IMAGE", 1), 61.0, 0.1);
  EXPECT_NEAR(test::tableValue(cat, "X_IMAGE", 2), 71.0, 0.1);
  EXPECT_LT(db.entry(0).mag, db.entry(1).mag);
}

TEST(BuildDatabase, LensedDatabaseGalaxyHasTheAnalyticMagnification) {
  const fs::path dir = test::scratchDir();
  const std::string image = writeDeepImage(dir);
  const std::string cat = (dir / "db.fits").string();
  ASSERT_EQ(runBuildDatabase({image, "-o", cat, "--quiet"}), 0);
  const RealGalaxyCatalog db = RealGalaxyCatalog::load(cat);
  const simulation::SourceStamp source = db.loadGalaxy(0);  // sigma 3 px of 0.06" = 0.18"

  // A singular isothermal sphere (eps = 0, no core) of b = 1": a small source at beta = 3"
  // outside the Einstein radius has one image, magnified by 1 + b / beta = 4/3.
  simulation::LensSystem sys;
  sys.mass = {1.0, 0.0, 0.0, 0.0};
  sys.lensMag = 45.0;  // lens light negligible (1e-6 ADU)
  sys.source.betaArcsec = {3.0, 0.0};
  sys.sourceMag = 22.0;
  simulation::ObservingSetup setup;
  setup.addNoise = false;
  std::mt19937_64 rng(1);
  const simulation::RenderedLensSystem out = simulation::renderLensSystem(sys, source, setup, rng);
  EXPECT_NEAR(out.magnification, 4.0 / 3.0, 0.02);
  const double unlensed = std::pow(10.0, -0.4 * (22.0 - setup.magZeroPoint));
  EXPECT_NEAR(out.lensedSourceFlux, out.magnification * unlensed, 1e-9 * unlensed);
  double sum = 0.0;
  for (double v : out.image.pixels()) sum += v;
  EXPECT_NEAR(sum, out.lensedSourceFlux, 1e-3 * out.lensedSourceFlux);  // the PSF keeps flux
}

TEST(BuildDatabase, PixelScaleAndPositionsFromTheWcs) {
  const fs::path dir = test::scratchDir();
  const std::string image = writeDeepImage(dir, false, true);
  const std::string cat = (dir / "db.fits").string();
  ASSERT_EQ(runBuildDatabase({image, "-o", cat, "--quiet"}), 0);
  const RealGalaxyCatalog db = RealGalaxyCatalog::load(cat);
  ASSERT_EQ(db.size(), kGalaxies.size());
  EXPECT_NEAR(db.entry(0).pixelScaleArcsec, 0.05, 1e-6);
  // The first galaxy sits on the reference pixel (to the 0.1 px of its noisy centroid).
  EXPECT_NEAR(test::tableValue(cat, "RA", 1), 53.16,
              0.1 * 0.05 / 3600.0 / std::cos(27.78 * M_PI / 180));
  EXPECT_NEAR(test::tableValue(cat, "DEC", 1), -27.78, 0.1 * 0.05 / 3600.0);
  // The second is 120 px west (RA falls as x grows, CD1_1 < 0) and 10 px north of it.
  const double cosDec = std::cos(-27.78 * M_PI / 180.0);
  EXPECT_NEAR(test::tableValue(cat, "RA", 2), 53.16 - 120 * 0.05 / 3600.0 / cosDec, 2e-6);
  EXPECT_NEAR(test::tableValue(cat, "DEC", 2), -27.78 + 10 * 0.05 / 3600.0, 2e-6);
}

TEST(BuildDatabase, SurveySettingsComeFromAConfigFile) {
  const fs::path dir = test::scratchDir();
  const std::string image = writeDeepImage(dir, false);
  const std::string sex = (dir / "survey.sex").string();
  std::ofstream(sex) << "PIXEL_SCALE 0.07\nMAG_ZEROPOINT 27.5\nBACK_SIZE 32\n";
  const std::string cat = (dir / "db.fits").string();
  ASSERT_EQ(runBuildDatabase({image, "-o", cat, "--config", sex, "--quiet"}), 0);
  const RealGalaxyCatalog db = RealGalaxyCatalog::load(cat);
  ASSERT_EQ(db.size(), kGalaxies.size());
  EXPECT_DOUBLE_EQ(db.entry(0).pixelScaleArcsec, 0.07);
  EXPECT_NEAR(db.entry(0).mag, 27.5 - 2.5 * std::log10(test::tableValue(cat, "stamp_flux", 1)),
              1e-9);
  // Options win over the file.
  const std::string cat2 = (dir / "db2.fits").string();
  ASSERT_EQ(runBuildDatabase({image, "-o", cat2, "--config", sex, "--pixel-scale", "0.09",
                              "--zeropoint", "20", "--quiet"}),
            0);
  const RealGalaxyCatalog db2 = RealGalaxyCatalog::load(cat2);
  EXPECT_DOUBLE_EQ(db2.entry(0).pixelScaleArcsec, 0.09);
  EXPECT_NEAR(db2.entry(0).mag, 20.0 - 2.5 * std::log10(test::tableValue(cat2, "stamp_flux", 1)),
              1e-9);
  // A configuration file that is not there is an I/O error naming it.
  try {
    runBuildDatabase({image, "-o", cat, "--config", (dir / "missing.sex").string(), "--quiet"});
    ADD_FAILURE() << "no error";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.sex"), std::string::npos) << e.what();
  }
}

// The error of `f`, which must be of type E; "" if none.
template <typename E, typename F>
std::string errorOf(F&& f) {
  try {
    f();
  } catch (const E& e) {
    return e.what();
  }
  return "";
}

TEST(BuildDatabase, BadInputGivesOneLineErrorAndNoOutput) {
  const fs::path in = test::scratchDir();
  const fs::path out = in / "out";
  fs::create_directories(out);
  const std::string cat = (out / "db.fits").string();

  // Not an image at all.
  const std::string text = (in / "notes.fits").string();
  std::ofstream(text) << "not a FITS file\n";
  std::string msg = errorOf<IoError>([&] { runBuildDatabase({text, "-o", cat, "--quiet"}); });
  EXPECT_NE(msg.find("notes.fits"), std::string::npos) << msg;
  EXPECT_EQ(msg.find('\n'), std::string::npos);

  // A table, no image.
  const std::string table = (in / "table.fits").string();
  {
    fitsfile* f = nullptr;
    int status = 0;
    fits_create_file(&f, table.c_str(), &status);
    char* ttype[] = {const_cast<char*>("A")};
    char* tform[] = {const_cast<char*>("1D")};
    fits_create_tbl(f, BINARY_TBL, 0, 1, ttype, tform, nullptr, "T", &status);
    fits_close_file(f, &status);
    ASSERT_EQ(status, 0);
  }
  msg = errorOf<IoError>([&] { runBuildDatabase({table, "-o", cat, "--quiet"}); });
  EXPECT_NE(msg.find("table.fits"), std::string::npos) << msg;
  EXPECT_EQ(msg.find('\n'), std::string::npos);

  // No pixel scale anywhere.
  const fs::path noScaleDir = in / "noscale";
  fs::create_directories(noScaleDir);
  const std::string noScale = writeDeepImage(noScaleDir, false);
  msg = errorOf<ConfigError>([&] { runBuildDatabase({noScale, "-o", cat, "--quiet"}); });
  EXPECT_NE(msg.find("--pixel-scale"), std::string::npos) << msg;
  EXPECT_NE(msg.find("deep.fits"), std::string::npos) << msg;
  // ... which --pixel-scale then supplies.
  EXPECT_EQ(runBuildDatabase({noScale, "-o", (noScaleDir / "ok.fits").string(), "--pixel-scale",
                              "0.05", "--quiet"}),
            0);
  EXPECT_DOUBLE_EQ(
      RealGalaxyCatalog::load((noScaleDir / "ok.fits").string()).entry(0).pixelScaleArcsec, 0.05);

  // Nonsense thresholds and options.
  const std::string image = writeDeepImage(in);
  for (const char* t : {"0", "-1", "nan"}) {
    msg = errorOf<ConfigError>([&] {
      runBuildDatabase({image, "-o", cat, "--threshold", t, "--quiet"});
    });
    EXPECT_NE(msg.find("--threshold"), std::string::npos) << t << ": " << msg;
  }
  msg = errorOf<ConfigError>([&] { runBuildDatabase({image, "--quiet"}); });
  EXPECT_NE(msg.find("--output"), std::string::npos) << msg;
  msg = errorOf<ConfigError>([&] {
    runBuildDatabase({image, "-o", cat, "--pixel-scale", "-0.1", "--quiet"});
  });
  EXPECT_NE(msg.find("--pixel-scale"), std::string::npos) << msg;
  msg = errorOf<ConfigError>([&] { runBuildDatabase({image, "-o", cat, "--bogus", "1"}); });
  EXPECT_NE(msg.find("bogus"), std::string::npos) << msg;
  // A threshold so high that nothing is left: an error, not an empty database.
  msg = errorOf<ConfigError>([&] {
    runBuildDatabase({image, "-o", cat, "--threshold", "1000", "--quiet"});
  });
  EXPECT_NE(msg.find("no galaxy"), std::string::npos) << msg;
  // Writing over the input image is refused.
  msg = errorOf<ConfigError>([&] { runBuildDatabase({image, "-o", image, "--quiet"}); });
  EXPECT_NE(msg.find("overwrite"), std::string::npos) << msg;

  EXPECT_TRUE(isEmptyDir(out));
}

}  // namespace
}  // namespace octarc
