// The in-memory run API (run/ImageRun.h) against the catalog path (run/DetectionRun.h + the
// FITS_LDAC writer + reading the file back) on one synthetic image: the same rows, value for
// value, and the objects where they were put.
#include "octarc/run/ImageRun.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "FitsTestFiles.h"
#include "TestPaths.h"
#include "octarc/catalog/Catalog.h"
#include "octarc/catalog/InputCatalog.h"
#include "octarc/core/Error.h"
#include "octarc/run/CatalogAssembly.h"
#include "octarc/run/DetectionRun.h"
#include "octarc/run/Levels.h"
#include "octarc/run/PreparedImage.h"
#include "octarc/sexcompat/ConvFile.h"

namespace octarc {
namespace {

struct Blob {
  double x0, y0;  // 0-based centre
  double peakAdu, sigmaXPix, sigmaYPix;
};

// Two Gaussian galaxies on unit Gaussian noise (fixed seed), no background.
ImageF syntheticImage(const std::vector<Blob>& blobs) {
  ImageF image(200, 150);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (std::int64_t y = 0; y < image.height(); ++y) {
    for (std::int64_t x = 0; x < image.width(); ++x) {
      double v = noise(rng);
      for (const Blob& b : blobs) {
        const double dx = (double(x) - b.x0) / b.sigmaXPix, dy = (double(y) - b.y0) / b.sigmaYPix;
        v += b.peakAdu * std::exp(-0.5 * (dx * dx + dy * dy));
      }
      image(x, y) = float(v);
    }
  }
  return image;
}

const std::vector<std::string> kColumns = {"NUMBER",  "THRESH_LEVEL",  "PARENT_NUMBER", "X_IMAGE",
                                           "Y_IMAGE", "ISOAREA_IMAGE", "FLUX_ISO",      "A_IMAGE",
                                           "B_IMAGE", "ARCNESS",       "SIZE_IMAGE",    "FLAGS"};

TEST(ImageRun, InMemoryRowsEqualTheCatalogsAndFindTheObjectsWherePut) {
  const std::filesystem::path dir = test::scratchDir();
  const std::vector<Blob> blobs = {{50.3, 60.7, 200.0, 2.0, 2.0}, {140.2, 90.4, 120.0, 4.0, 1.5}};
  const ImageF pixels = syntheticImage(blobs);
  const std::string imagePath = (dir / "image.fits").string();
  test::writeFloatFits(imagePath, pixels);
  const std::string paramPath = (dir / "columns.param").string();
  {
    std::ofstream f(paramPath);
    for (const std::string& c : kColumns) f << c << "\n";
  }

  RunSettings s;
  s.imagePaths = {imagePath};
  s.parametersPath = paramPath;
  s.catalogNames = {(dir / "image.ldac").string()};
  s.backgroundType = BackgroundType::Manual;  // the image has no background
  s.filterPath = std::string(OCTARC_SOURCE_DIR) + "/params/default.conv";
  s.detectThreshold = 3.0;
  s.detectThresholdMax = 30.0;
  s.detectLevelCount = 3;
  s.threads = 1;
  const ColumnPlan columns = planColumns(s, true, 3);

  // The catalog path: a whole run, written, read back.
  DetectionRunResult onDisk = runDetection(s, columns, std::nullopt, RunLog());
  writeCatalog(s.catalogNames[0], CatalogType::FitsLdac, onDisk.parts(), onDisk.fits10Cards);
  const std::vector<std::vector<double>> catalog =
      readCatalogColumns(s.catalogNames[0], "LDAC_OBJECTS", kColumns);

  // In memory: the same pixels with the noise the file run found, never written.
  const double sigmaAdu = prepareImage(imagePath, s, {}, false).sigmaAdu;
  const ConvKernel kernel = sexcompat::readConvFile(s.filterPath);
  InMemoryImage description;
  description.sigmaAdu = sigmaAdu;
  description.saturationAdu = s.saturationAdu;
  description.filter = &kernel;
  PreparedImage image = prepareInMemory(pixels, description);
  MeasureContext context = image.context(s);
  context.levels = detectionLevels(s, sigmaAdu);
  DetectionRequest request;
  request.levels = context.levels;
  request.levelsInSigma = levelValues(s);
  request.minAreaPix = s.minAreaPix;
  request.keepSegmentation = true;
  const ImageRunResult run = detectAndMeasure(image, columns.plan, context, request);
  const Table rows = outputTable(columns, run.rowsInCatalogOrder());

  // Two isolated galaxies far above every level: one object each per level.
  EXPECT_EQ(run.objectsPerLevel, (std::vector<std::int64_t>{2, 2, 2}));
  ASSERT_EQ(rows.rows(), 6);
  ASSERT_EQ(std::int64_t(catalog[0].size()), rows.rows());
  for (std::size_t c = 0; c < kColumns.size(); ++c) {
    const int column = rows.findColumn(kColumns[c]);
    ASSERT_GE(column, 0) << kColumns[c];
    const ColumnType type = rows.columns()[std::size_t(column)].type;
    for (std::int64_t r = 0; r < rows.rows(); ++r) {
      EXPECT_EQ(storedFloatValue(type, rows.value(r, column)), catalog[c][std::size_t(r)])
          << kColumns[c] << " row " << r;
    }
  }
  // Level by level, NUMBER order; positions 1-based at the centres put in (within 0.1 pixel: the
  // isophotes follow the noise); the elongated one
  // lies along x.
  const int level = rows.findColumn("THRESH_LEVEL"), number = rows.findColumn("NUMBER");
  const int x = rows.findColumn("X_IMAGE"), y = rows.findColumn("Y_IMAGE");
  const int a = rows.findColumn("A_IMAGE"), b = rows.findColumn("B_IMAGE");
  for (std::int64_t r = 0; r < rows.rows(); ++r) {
    EXPECT_EQ(rows.value(r, level), double(r / 2 + 1));
    EXPECT_EQ(rows.value(r, number), double(r % 2 + 1));
    const Blob& blob = blobs[std::size_t(r % 2)];
    EXPECT_NEAR(rows.value(r, x), blob.x0 + 1.0, 0.1);
    EXPECT_NEAR(rows.value(r, y), blob.y0 + 1.0, 0.1);
    if (r % 2 == 1) {
      EXPECT_GT(rows.value(r, a), 2.0 * rows.value(r, b));
    }
  }
  // The labels: each centre pixel carries its object's NUMBER at every level.
  ASSERT_TRUE(run.segmentation.has_value());
  ImageI32 labels;
  for (int l = 1; l <= 3; ++l) {
    run.segmentation->render(l, labels);
    EXPECT_EQ(labels(50, 61), 1);
    EXPECT_EQ(labels(140, 90), 2);
    EXPECT_EQ(labels(5, 5), 0);
  }
}

// Dual-image mode on a measurement image that is the detection image times two (exact in
// floating point): the same footprints and shapes, FLUX_ISO and FLUXERR_ISO twice the
// single-image values (the measurement image's noise is twice the detection image's), the same
// ISOAREA_IMAGE (its analysis threshold is in the measurement image's sigma) and ARCNESS (scale
// free). Images of different sizes are an IoError naming both.
TEST(ImageRun, DualImageMeasuresOnTheSecondImage) {
  const std::filesystem::path dir = test::scratchDir();
  const std::vector<Blob> blobs = {{50.3, 60.7, 200.0, 2.0, 2.0}, {140.2, 90.4, 120.0, 4.0, 1.5}};
  const ImageF pixels = syntheticImage(blobs);
  ImageF doubled = pixels;
  for (float& v : doubled.pixels()) v *= 2.0f;
  const std::string detectionPath = (dir / "detect.fits").string();
  const std::string measurementPath = (dir / "measure.fits").string();
  test::writeFloatFits(detectionPath, pixels);
  test::writeFloatFits(measurementPath, doubled);
  const std::string paramPath = (dir / "dual.param").string();
  {
    std::ofstream f(paramPath);
    for (const std::string& c : kColumns) f << c << "\n";
    f << "FLUXERR_ISO\n";
  }
  RunSettings s;
  s.parametersPath = paramPath;
  s.backgroundType = BackgroundType::Manual;
  s.measurement.backgroundType = BackgroundType::Manual;
  s.filterPath = std::string(OCTARC_SOURCE_DIR) + "/params/default.conv";
  s.detectThreshold = 3.0;
  s.detectThresholdMax = 30.0;
  s.detectLevelCount = 3;
  s.threads = 1;
  const ColumnPlan columns = planColumns(s, true, 3);
  s.imagePaths = {detectionPath};
  const DetectionRunResult single = runDetection(s, columns, std::nullopt, RunLog());
  s.imagePaths = {detectionPath, measurementPath};
  const DetectionRunResult dual = runDetection(s, columns, std::nullopt, RunLog());
  const Table& one = single.extensions.front().table;
  const Table& two = dual.extensions.front().table;
  ASSERT_EQ(one.rows(), 6);
  ASSERT_EQ(two.rows(), one.rows());
  for (const char* name : {"NUMBER", "THRESH_LEVEL", "PARENT_NUMBER", "X_IMAGE", "Y_IMAGE",
                           "A_IMAGE", "B_IMAGE", "SIZE_IMAGE", "FLAGS", "ISOAREA_IMAGE"}) {
    const int c = one.findColumn(name);
    for (std::int64_t r = 0; r < one.rows(); ++r) {
      EXPECT_EQ(two.value(r, c), one.value(r, c)) << name << " row " << r;
    }
  }
  for (const char* name : {"FLUX_ISO", "FLUXERR_ISO"}) {
    const int c = one.findColumn(name);
    for (std::int64_t r = 0; r < one.rows(); ++r) {
      EXPECT_NEAR(two.value(r, c), 2.0 * one.value(r, c), 1e-6 * std::fabs(one.value(r, c)))
          << name << " row " << r;
    }
  }
  const int arcness = one.findColumn("ARCNESS");
  for (std::int64_t r = 0; r < one.rows(); ++r) {
    EXPECT_NEAR(two.value(r, arcness), one.value(r, arcness), 1e-9) << "row " << r;
  }

  test::writeFloatFits(measurementPath, ImageF(100, 150, 1.0f));
  try {
    runDetection(s, columns, std::nullopt, RunLog());
    ADD_FAILURE() << "no IoError";
  } catch (const IoError& e) {
    EXPECT_EQ(std::string(e.what()),
              detectionPath + " and " + measurementPath +
                  ": the detection and measurement images must share one pixel grid (200x150 "
                  "and 100x150 pixels)");
  }
}

TEST(ImageRun, SaturatedPixelsAreThoseAtOrAboveTheLevel) {
  ImageF image(4, 3, 1.0f);
  image(1, 0) = 5.0f;
  image(3, 2) = 9.5f;
  image(2, 1) = 4.999f;
  for (int threads : {1, 2, 3}) {
    EXPECT_EQ(findSaturatedPixels(image, 5.0, threads), (std::vector<std::int64_t>{1, 11}));
  }
  EXPECT_TRUE(findSaturatedPixels(image, 0.0, 1).empty());
}

}  // namespace
}  // namespace octarc
