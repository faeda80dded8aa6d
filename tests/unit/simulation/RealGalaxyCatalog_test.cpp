#include "octarc/simulation/RealGalaxyCatalog.h"

#include <fitsio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <string>

#include "LensTestSupport.h"
#include "TestPaths.h"
#include "octarc/core/Error.h"
#include "octarc/simulation/LensLight.h"
#include "octarc/simulation/Morphology.h"

namespace octarc::simulation {
namespace {

// Message of the IoError thrown by f ("" if none).
template <typename F>
std::string ioErrorOf(F&& f) {
  try {
    f();
  } catch (const IoError& e) {
    return e.what();
  }
  return "";
}

TEST(RealGalaxyCatalog, ReadsTheAegisSample) {
  OCTARC_REQUIRE_SHARED_DATA(shared);
  const auto cat =
      RealGalaxyCatalog::load((shared / "hst-galaxies/aegis/AEGIS_F606w_catalog.fits").string());
  ASSERT_EQ(cat.size(), 5u);
  EXPECT_EQ(cat.entry(0).ident, 23409);
  EXPECT_NEAR(cat.entry(0).mag, 25.1206, 1e-12);
  EXPECT_EQ(cat.entry(0).band, "F606W");
  EXPECT_DOUBLE_EQ(cat.entry(0).pixelScaleArcsec, 0.03);
  EXPECT_EQ(cat.entry(3).galaxyHdu, 0);
  EXPECT_NE(cat.entry(3).galaxyPath.find("AEGIS_F606w_images_02.fits"), std::string::npos);
  // Row 1 is HDU 1 of images_01: 142 x 156 pixels; pixel sum 49.128787907739294 (astropy,
  // float64 sum of the float32 data).
  const SourceStamp g = cat.loadGalaxy(1);
  EXPECT_EQ(g.fluxPerPixel.width(), 142);
  EXPECT_EQ(g.fluxPerPixel.height(), 156);
  EXPECT_NEAR(totalFlux(g), 49.128787907739294, 1e-9);
  EXPECT_DOUBLE_EQ(g.pixelScaleArcsec, 0.03);
  // Primary HDU stamps work too (row 0: 70 x 46, pixel (20, 10) = 3.2928936e-06).
  const SourceStamp g0 = cat.loadGalaxy(0);
  EXPECT_EQ(g0.fluxPerPixel.width(), 70);
  EXPECT_NEAR(g0.fluxPerPixel(20, 10), 3.2928936e-06, 1e-12);
  // PSF of row 1: HDU 1 of the PSF file, 20 x 20, normalised; pixel (10, 10) holds 0.0441230
  // of the flux (astropy).
  const ImageD psf = cat.loadPsf(1);
  EXPECT_EQ(psf.width(), 20);
  EXPECT_NEAR(test::pixelSum(psf), 1.0, 1e-12);
  EXPECT_NEAR(psf(10, 10), 0.044122954, 1e-7);
}

TEST(RealGalaxyCatalog, EveryAegisGalaxyAndPsfLoadsInBothBands) {
  OCTARC_REQUIRE_SHARED_DATA(shared);
  for (const char* band : {"F606w", "F814w"}) {
    const auto cat = RealGalaxyCatalog::load(
        (shared / "hst-galaxies/aegis" / (std::string("AEGIS_") + band + "_catalog.fits"))
            .string());
    ASSERT_EQ(cat.size(), 5u) << band;
    for (std::size_t i = 0; i < cat.size(); ++i) {
      const SourceStamp g = cat.loadGalaxy(i);
      EXPECT_GT(g.fluxPerPixel.width(), 10) << band << " row " << i;
      EXPECT_GT(totalFlux(g), 0.0) << band << " row " << i;
      EXPECT_NEAR(test::pixelSum(cat.loadPsf(i)), 1.0, 1e-12) << band << " row " << i;
    }
  }
}

TEST(RealGalaxyCatalog, CosmosGalaxyLoadsThoughItsPsfFileIsMissing) {
  OCTARC_REQUIRE_SHARED_DATA(shared);
  const auto cat = RealGalaxyCatalog::load(
      (shared / "hst-galaxies/cosmos/real_galaxy_catalog_23.5.fits").string());
  ASSERT_EQ(cat.size(), 2u);
  EXPECT_EQ(cat.entry(1).ident, 169753);
  EXPECT_EQ(cat.entry(1).band, "F814W");
  EXPECT_NEAR(cat.entry(0).pixelScaleArcsec, 0.03, 1e-8);
  const SourceStamp g = cat.loadGalaxy(0);  // HDU 2 of test_galaxy_images_23.5.fits
  EXPECT_EQ(g.fluxPerPixel.width(), 154);
  EXPECT_EQ(g.fluxPerPixel.height(), 153);
  EXPECT_NEAR(totalFlux(g), 295.27060361218173, 1e-7);
  const std::string msg = ioErrorOf([&] { cat.loadPsf(0); });
  EXPECT_NE(msg.find("real_galaxy_PSF_images_23.5_n4.fits' does not exist"), std::string::npos)
      << msg;
  EXPECT_EQ(msg.find('\n'), std::string::npos);
}

TEST(RealGalaxyCatalog, MissingImageFileIsAClearError) {
  OCTARC_REQUIRE_SHARED_DATA(shared);
  const std::string path = (shared / "hst-galaxies/real_galaxy_catalog_23.5_example.fits").string();
  std::string msg = ioErrorOf([&] { RealGalaxyCatalog::load(path); });
  EXPECT_NE(msg.find("real_galaxy_catalog_23.5_example.fits: row 1 (IDENT 100027): galaxy image "
                     "file "),
            std::string::npos)
      << msg;
  EXPECT_NE(msg.find("real_galaxy_images.fits' does not exist"), std::string::npos) << msg;
  // Without the up-front check the table loads (100 rows) and the stamp read fails cleanly.
  const auto cat = RealGalaxyCatalog::load(path, false);
  EXPECT_EQ(cat.size(), 100u);
  msg = ioErrorOf([&] { cat.loadGalaxy(7); });
  EXPECT_NE(msg.find("real_galaxy_images.fits' does not exist"), std::string::npos) << msg;
  EXPECT_THROW(cat.entry(100), std::out_of_range);
}

TEST(RealGalaxyCatalog, BadCatalogFiles) {
  const auto dir = test::scratchDir();
  std::string msg = ioErrorOf([&] { RealGalaxyCatalog::load((dir / "none.fits").string()); });
  EXPECT_NE(msg.find("none.fits: RealGalaxyCatalog file does not exist"), std::string::npos);

  // A table without GAL_FILENAME.
  const std::string path = (dir / "partial.fits").string();
  int status = 0;
  fitsfile* f = nullptr;
  fits_create_file(&f, path.c_str(), &status);
  char* names[] = {const_cast<char*>("IDENT"), const_cast<char*>("MAG"), const_cast<char*>("BAND"),
                   const_cast<char*>("PIXEL_SCALE")};
  char* forms[] = {const_cast<char*>("J"), const_cast<char*>("D"), const_cast<char*>("5A"),
                   const_cast<char*>("D")};
  fits_create_tbl(f, BINARY_TBL, 0, 4, names, forms, nullptr, nullptr, &status);
  fits_close_file(f, &status);
  ASSERT_EQ(status, 0);
  msg = ioErrorOf([&] { RealGalaxyCatalog::load(path); });
  EXPECT_NE(msg.find("partial.fits: RealGalaxyCatalog table has no column GAL_FILENAME"),
            std::string::npos)
      << msg;

  // An image instead of a table.
  const std::string imagePath = (dir / "image.fits").string();
  fits_create_file(&f, imagePath.c_str(), &status);
  long naxes[2] = {4, 4};
  fits_create_img(f, FLOAT_IMG, 2, naxes, &status);
  fits_close_file(f, &status);
  ASSERT_EQ(status, 0);
  msg = ioErrorOf([&] { RealGalaxyCatalog::load(imagePath); });
  EXPECT_NE(msg.find("image.fits: not a RealGalaxyCatalog"), std::string::npos) << msg;
}

// A one-row RealGalaxyCatalog table with the given MAG, PIXEL_SCALE and GAL_HDU.
std::string writeCatalog(const std::filesystem::path& path, double mag, double scale,
                         long long hdu) {
  std::filesystem::remove(path);
  int status = 0;
  fitsfile* f = nullptr;
  fits_create_file(&f, path.c_str(), &status);
  const char* names[] = {"IDENT", "MAG", "BAND", "PIXEL_SCALE", "GAL_FILENAME", "GAL_HDU"};
  const char* forms[] = {"J", "D", "5A", "D", "20A", "K"};
  fits_create_tbl(f, BINARY_TBL, 0, 6, const_cast<char**>(names), const_cast<char**>(forms),
                  nullptr, nullptr, &status);
  int ident = 7;
  const char* band[] = {"F814W"};
  const char* file[] = {"gal.fits"};
  fits_write_col(f, TINT, 1, 1, 1, 1, &ident, &status);
  fits_write_col(f, TDOUBLE, 2, 1, 1, 1, &mag, &status);
  fits_write_col(f, TSTRING, 3, 1, 1, 1, const_cast<char**>(band), &status);
  fits_write_col(f, TDOUBLE, 4, 1, 1, 1, &scale, &status);
  fits_write_col(f, TSTRING, 5, 1, 1, 1, const_cast<char**>(file), &status);
  fits_write_col(f, TLONGLONG, 6, 1, 1, 1, &hdu, &status);
  fits_close_file(f, &status);
  EXPECT_EQ(status, 0);
  return path.string();
}

TEST(RealGalaxyCatalog, ImpossibleRowValuesAreRefused) {
  const auto dir = test::scratchDir();
  const std::string good = writeCatalog(dir / "good.fits", 23.5, 0.03, 1);
  EXPECT_EQ(RealGalaxyCatalog::load(good, false).entry(0).galaxyHdu, 1);
  const double inf = std::numeric_limits<double>::infinity();
  std::string msg = ioErrorOf([&] {
    RealGalaxyCatalog::load(writeCatalog(dir / "mag.fits", std::nan(""), 0.03, 1), false);
  });
  EXPECT_NE(msg.find("mag.fits: row 1 (IDENT 7): MAG must be a finite number"), std::string::npos)
      << msg;
  msg = ioErrorOf(
      [&] { RealGalaxyCatalog::load(writeCatalog(dir / "scale.fits", 23.5, inf, 1), false); });
  EXPECT_NE(msg.find("scale.fits: row 1 (IDENT 7): PIXEL_SCALE must be a finite number > 0"),
            std::string::npos)
      << msg;
  // An HDU number beyond an int wrapped to a negative one.
  msg = ioErrorOf([&] {
    RealGalaxyCatalog::load(writeCatalog(dir / "hdu.fits", 23.5, 0.03, 1LL << 32), false);
  });
  EXPECT_NE(msg.find("hdu.fits: row 1 (IDENT 7): HDU number out of range"), std::string::npos)
      << msg;
}

// Three galaxies whose types their light shows: a de Vaucouleurs spheroid, an exponential disc
// and a disc with one bright clump on a side; HDUs 0, 1, 2 of gals.fits.
void writeTypedStamps(const std::filesystem::path& path) {
  std::filesystem::remove(path);
  int status = 0;
  fitsfile* f = nullptr;
  fits_create_file(&f, path.c_str(), &status);
  for (int k = 0; k < 3; ++k) {
    SurveyGrid grid;
    grid.width = grid.height = 201;
    grid.pixelScaleArcsec = 0.03;
    grid.lensXPix = grid.lensYPix = 100.0;
    ImageD img(grid.width, grid.height);
    addSersicLight(img, grid, {k == 0 ? 4.0 : 1.0, 0.35, 0.7, 0.5, 1.0});
    if (k == 2) {
      grid.lensXPix = 128.0;
      addSersicLight(img, grid, {1.0, 0.12, 1.0, 0.0, 1.5});
    }
    std::vector<float> pixels(img.pixels().begin(), img.pixels().end());
    long naxes[2] = {grid.width, grid.height};
    fits_create_img(f, FLOAT_IMG, 2, naxes, &status);
    fits_write_img(f, TFLOAT, 1, LONGLONG(pixels.size()), pixels.data(), &status);
  }
  fits_close_file(f, &status);
  ASSERT_EQ(status, 0);
}

// A three-row catalog of those stamps, with a MORPH_TYPE column when `types` is given.
std::string writeTypedCatalog(const std::filesystem::path& path, const char* const* types) {
  std::filesystem::remove(path);
  int status = 0;
  fitsfile* f = nullptr;
  fits_create_file(&f, path.c_str(), &status);
  const char* names[] = {"IDENT",        "MAG",     "BAND",      "PIXEL_SCALE",
                         "GAL_FILENAME", "GAL_HDU", "MORPH_TYPE"};
  const char* forms[] = {"J", "D", "5A", "D", "20A", "K", "12A"};
  fits_create_tbl(f, BINARY_TBL, 0, types ? 7 : 6, const_cast<char**>(names),
                  const_cast<char**>(forms), nullptr, nullptr, &status);
  for (int k = 0; k < 3; ++k) {
    int ident = 10 + k;
    double mag = 23.0, scale = 0.03;
    long long hdu = k;
    const char* band[] = {"F606W"};
    const char* file[] = {"gals.fits"};
    fits_write_col(f, TINT, 1, k + 1, 1, 1, &ident, &status);
    fits_write_col(f, TDOUBLE, 2, k + 1, 1, 1, &mag, &status);
    fits_write_col(f, TSTRING, 3, k + 1, 1, 1, const_cast<char**>(band), &status);
    fits_write_col(f, TDOUBLE, 4, k + 1, 1, 1, &scale, &status);
    fits_write_col(f, TSTRING, 5, k + 1, 1, 1, const_cast<char**>(file), &status);
    fits_write_col(f, TLONGLONG, 6, k + 1, 1, 1, &hdu, &status);
    if (types) {
      const char* type[] = {types[k]};
      fits_write_col(f, TSTRING, 7, k + 1, 1, 1, const_cast<char**>(type), &status);
    }
  }
  fits_close_file(f, &status);
  EXPECT_EQ(status, 0);
  return path.string();
}

TEST(RealGalaxyCatalog, TypesComeFromTheLightOrFromMorphType) {
  const auto dir = test::scratchDir();
  writeTypedStamps(dir / "gals.fits");
  const auto measured = RealGalaxyCatalog::load(writeTypedCatalog(dir / "cat.fits", nullptr));
  EXPECT_EQ(measured.loadGalaxy(0).type, GalaxyType::Elliptical);
  EXPECT_EQ(measured.loadGalaxy(1).type, GalaxyType::Spiral);
  EXPECT_EQ(measured.loadGalaxy(2).type, GalaxyType::Irregular);
  // A MORPH_TYPE column wins over the light.
  const char* const given[] = {"spiral", "Irregular", "ELLIPTICAL"};
  const auto typed = RealGalaxyCatalog::load(writeTypedCatalog(dir / "typed.fits", given));
  EXPECT_EQ(typed.loadGalaxy(0).type, GalaxyType::Spiral);
  EXPECT_EQ(typed.loadGalaxy(1).type, GalaxyType::Irregular);
  EXPECT_EQ(typed.loadGalaxy(2).type, GalaxyType::Elliptical);
  const char* const bad[] = {"spiral", "S0", "spiral"};
  const std::string msg =
      ioErrorOf([&] { RealGalaxyCatalog::load(writeTypedCatalog(dir / "bad.fits", bad)); });
  EXPECT_NE(msg.find("bad.fits: row 2 (IDENT 11): MORPH_TYPE 'S0' is not elliptical, spiral or "
                     "irregular"),
            std::string::npos)
      << msg;
}

// The real HST samples hold more than one type (they used to be all spirals).
TEST(RealGalaxyCatalog, RealHstGalaxiesAreTypedByTheirLight) {
  OCTARC_REQUIRE_SHARED_DATA(shared);
  std::map<GalaxyType, int> counts;
  for (const char* file : {"aegis/AEGIS_F606w_catalog.fits", "aegis/AEGIS_F814w_catalog.fits",
                           "cosmos/real_galaxy_catalog_23.5.fits"}) {
    const auto cat = RealGalaxyCatalog::load((shared / "hst-galaxies" / file).string());
    for (std::size_t i = 0; i < cat.size(); ++i) {
      const SourceStamp g = cat.loadGalaxy(i);
      const MorphologyMeasures m = measureMorphology(g);
      EXPECT_EQ(g.type, classifyMorphology(m)) << file << " row " << i;
      EXPECT_GT(m.concentration, 1.5) << file << " row " << i;
      EXPECT_LT(m.concentration, 6.5) << file << " row " << i;
      ++counts[g.type];
    }
  }
  EXPECT_GE(counts.size(), 2u);
}

TEST(RealGalaxyCatalog, RowCountTheFileCannotHoldIsRefusedBeforeAllocation) {
  const auto dir = test::scratchDir();
  const std::string good = writeCatalog(dir / "good.fits", 23.5, 0.03, 1);
  std::string bytes;
  {
    std::ifstream in(good, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  const std::size_t at = bytes.find("NAXIS2  =", 2880);
  ASSERT_NE(at, std::string::npos);
  bytes.replace(at, 30, "NAXIS2  =           2147483648");
  const std::string bad = (dir / "rows.fits").string();
  std::ofstream(bad, std::ios::binary) << bytes;
  const std::string msg = ioErrorOf([&] { RealGalaxyCatalog::load(bad, false); });
  EXPECT_NE(msg.find("rows.fits: HDU 1: file is truncated"), std::string::npos) << msg;
  EXPECT_NE(msg.find("x 2147483648"), std::string::npos) << msg;
}

}  // namespace
}  // namespace octarc::simulation
