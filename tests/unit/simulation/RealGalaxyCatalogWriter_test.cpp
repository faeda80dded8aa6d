#include "octarc/simulation/RealGalaxyCatalogWriter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "FitsTestFiles.h"
#include "TestPaths.h"
#include "octarc/core/Error.h"
#include "octarc/simulation/Psf.h"
#include "octarc/simulation/RealGalaxyCatalog.h"

namespace octarc::simulation {
namespace {

namespace fs = std::filesystem;

RealGalaxyRecord record(std::int64_t ident, int width, int height, float scale) {
  RealGalaxyRecord r;
  r.ident = ident;
  r.raDeg = 53.0 + 0.001 * double(ident);
  r.decDeg = -27.8;
  r.mag = 20.0 + 0.5 * double(ident);
  r.noiseVariance = 4.0;
  r.xImage = 10.0 * double(ident);
  r.yImage = 5.0;
  r.isoAreaPixels = width * height;
  r.stamp = ImageF(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) r.stamp(x, y) = scale * float(1 + x + 10 * y);
  return r;
}

std::vector<std::string> filesIn(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

TEST(RealGalaxyCatalogWriter, ReadsBackThroughTheReader) {
  const fs::path dir = test::scratchDir();
  const std::string cat = (dir / "db.fits").string();
  const std::vector<RealGalaxyRecord> records = {record(1, 7, 5, 1.0f), record(2, 9, 11, 0.5f),
                                                 record(3, 3, 3, 2.0f)};
  RealGalaxyCatalogInfo info;
  info.band = "F775W";
  info.pixelScaleArcsec = 0.06;
  const RealGalaxyCatalogPaths paths = writeRealGalaxyCatalog(cat, records, info);
  EXPECT_EQ(paths.galaxyImages, (dir / "db_images.fits").string());
  EXPECT_EQ(paths.psfImage, "");
  EXPECT_EQ(filesIn(dir), (std::vector<std::string>{"db.fits", "db_images.fits"}));

  const RealGalaxyCatalog loaded = RealGalaxyCatalog::load(cat);
  ASSERT_EQ(loaded.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    const RealGalaxyEntry& e = loaded.entry(i);
    EXPECT_EQ(e.ident, records[i].ident);
    EXPECT_DOUBLE_EQ(e.mag, records[i].mag);
    EXPECT_EQ(e.band, "F775W");
    EXPECT_DOUBLE_EQ(e.pixelScaleArcsec, 0.06);
    EXPECT_EQ(e.galaxyHdu, int(i) + 1);  // empty primary, then one extension per galaxy
    EXPECT_EQ(e.psfPath, "");            // empty PSF_FILENAME: no PSF
    const SourceStamp s = loaded.loadGalaxy(i);
    ASSERT_EQ(s.fluxPerPixel.width(), records[i].stamp.width());
    ASSERT_EQ(s.fluxPerPixel.height(), records[i].stamp.height());
    for (std::int64_t k = 0; k < s.fluxPerPixel.size(); ++k)
      EXPECT_EQ(s.fluxPerPixel[k], double(records[i].stamp[k]));
  }
  EXPECT_THROW(loaded.loadPsf(0), IoError);
  // stamp_flux of row 2: 0.5 * sum_{x<9, y<11} (1 + x + 10 y) = 0.5 * (99 + 11*36 + 10*9*55)
  EXPECT_DOUBLE_EQ(test::tableValue(cat, "stamp_flux", 2), 2722.5);
  EXPECT_DOUBLE_EQ(test::tableValue(cat, "RA", 3), 53.003);
  EXPECT_DOUBLE_EQ(test::tableValue(cat, "NOISE_VARIANCE", 1), 4.0);
  EXPECT_DOUBLE_EQ(test::tableValue(cat, "X_IMAGE", 2), 20.0);
  EXPECT_DOUBLE_EQ(test::tableValue(cat, "ISOAREA_IMAGE", 3), 9.0);
  EXPECT_DOUBLE_EQ(test::tableValue(cat, "WEIGHT", 1), 1.0);
}

TEST(RealGalaxyCatalogWriter, OneGalaxyIsThePrimaryImageAndThePsfFileIsNamed) {
  const fs::path dir = test::scratchDir();
  const std::string cat = (dir / "one.fits").string();
  RealGalaxyCatalogInfo info;
  info.band = "R";
  info.pixelScaleArcsec = 0.1;
  info.psf = gaussianPsfImage(0.3, 0.1, PsfSampling::PixelIntegrated);
  writeRealGalaxyCatalog(cat, {record(7, 5, 5, 1.0f)}, info);
  EXPECT_EQ(filesIn(dir),
            (std::vector<std::string>{"one.fits", "one_images.fits", "one_psf.fits"}));
  const RealGalaxyCatalog loaded = RealGalaxyCatalog::load(cat);
  ASSERT_EQ(loaded.size(), 1u);
  EXPECT_EQ(loaded.entry(0).galaxyHdu, 0);
  EXPECT_NEAR(totalFlux(loaded.loadGalaxy(0)), 575.0, 1e-9);  // 25 + 5*10 + 10*5*10
  const ImageD psf = loaded.loadPsf(0);
  const ImageD expected = gaussianPsfImage(0.3, 0.1, PsfSampling::PixelIntegrated);
  ASSERT_EQ(psf.width(), expected.width());
  for (std::int64_t k = 0; k < psf.size(); ++k) EXPECT_NEAR(psf[k], expected[k], 1e-7);
}

TEST(RealGalaxyCatalogWriter, BadInputWritesNothing) {
  const fs::path dir = test::scratchDir();
  const std::string cat = (dir / "bad.fits").string();
  RealGalaxyCatalogInfo info;
  info.band = "R";
  info.pixelScaleArcsec = 0.1;
  EXPECT_THROW(writeRealGalaxyCatalog(cat, {}, info), ConfigError);
  RealGalaxyRecord empty;
  EXPECT_THROW(writeRealGalaxyCatalog(cat, {empty}, info), ConfigError);
  info.pixelScaleArcsec = 0.0;
  EXPECT_THROW(writeRealGalaxyCatalog(cat, {record(1, 3, 3, 1.0f)}, info), ConfigError);
  // A directory that does not exist: the error names the file, and nothing is left behind.
  info.pixelScaleArcsec = 0.1;
  const std::string missing = (dir / "no-such-dir" / "x.fits").string();
  try {
    writeRealGalaxyCatalog(missing, {record(1, 3, 3, 1.0f)}, info);
    ADD_FAILURE() << "no error";
  } catch (const IoError& e) {
    EXPECT_EQ(std::string(e.what()).find(missing + ": "), 0u) << e.what();
  }
  EXPECT_TRUE(filesIn(dir).empty());
}

}  // namespace
}  // namespace octarc::simulation
