// The measurement plugins through MeasurementPlan on small images drawn here: hand-computed
// values for the simple objects, and source-extractor 2.25 run by the test on the same pixels
// (written to a FITS file, with the same TAN header for the world columns) for every
// SExtractor-named column.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "ArcClosedForm.h"
#include "FitsTestFiles.h"
#include "TestCommands.h"
#include "TestPaths.h"
#include "octarc/core/Conventions.h"
#include "octarc/core/Flags.h"
#include "octarc/io/FitsHeader.h"
#include "octarc/io/Wcs.h"
#include "octarc/measure/Registry.h"

namespace octarc {
namespace {

// 8-connected components of pixels strictly above the threshold, pixels in raster order
// (a minimal stand-in for the detection stage, enough for these tests).
std::vector<Segment> segmentsAbove(const ImageF& image, double thresholdAdu) {
  std::vector<int> label(std::size_t(image.size()), 0);
  std::vector<Segment> segments;
  for (std::int64_t start = 0; start < image.size(); ++start) {
    if (!(image[start] > thresholdAdu) || label[std::size_t(start)] != 0) continue;
    Segment s;
    s.number = int(segments.size()) + 1;
    std::vector<std::int64_t> stack{start};
    label[std::size_t(start)] = s.number;
    while (!stack.empty()) {
      const std::int64_t p = stack.back();
      stack.pop_back();
      s.pixels.push_back(p);
      const std::int64_t x = p % image.width(), y = p / image.width();
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const std::int64_t nx = x + dx, ny = y + dy;
          if (nx < 0 || ny < 0 || nx >= image.width() || ny >= image.height()) continue;
          const std::int64_t q = image.index(nx, ny);
          if (image[q] > thresholdAdu && label[std::size_t(q)] == 0) {
            label[std::size_t(q)] = s.number;
            stack.push_back(q);
          }
        }
    }
    std::sort(s.pixels.begin(), s.pixels.end());
    segments.push_back(std::move(s));
  }
  return segments;
}

// SEXTRACTOR.md §9 image: 64x48 float, a 3x2 block of 10 at 1-based x 10-12, y 5-6, a 5-pixel
// diagonal of 5 at 1-based 21-25, and an elliptical Gaussian (peak 100, sigma 4 and 2, 30 deg)
// centred at 0-based (45.3, 35.7), added in float as the reference file was made.
ImageF smallImage() {
  ImageF img(64, 48, 0.0f);
  for (int y = 4; y <= 5; ++y)
    for (int x = 9; x <= 11; ++x) img(x, y) = 10.0f;
  for (int k = 0; k < 5; ++k) img(20 + k, 20 + k) = 5.0f;
  const double t = std::numbers::pi / 6;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) {
      const double dx = x - 45.3, dy = y - 35.7;
      const double a = dx * std::cos(t) + dy * std::sin(t),
                   b = -dx * std::sin(t) + dy * std::cos(t);
      img(x, y) += float(100.0 * std::exp(-0.5 * (a * a / 16.0 + b * b / 4.0)));
    }
  return img;
}

// The row of one object, by column name.
class Row {
 public:
  Row(const MeasurementPlan& plan, const Segment& s, const MeasureContext& c)
      : values_(std::size_t(plan.rowWidth()), -12345.0) {
    plan.measure(s, c, values_.data());
    int offset = 0;
    for (const ColumnSpec& col : plan.columns()) {
      offsets_[col.name] = offset;
      offset += col.repeat;
    }
  }
  double operator[](const std::string& name) const {
    auto it = offsets_.find(name);
    EXPECT_NE(it, offsets_.end()) << name;
    return it == offsets_.end() ? kNaN : values_[std::size_t(it->second)];
  }

 private:
  std::vector<double> values_;
  std::map<std::string, int> offsets_;
};

std::vector<ColumnRequest> requestAll() {
  std::vector<ColumnRequest> r;
  for (const ColumnSpec& c : allBuiltinColumns()) r.push_back({c.name});
  return r;
}

struct SmallScene {
  ImageF image = smallImage();
  std::vector<Segment> segments = segmentsAbove(image, 1.0);
  MeasureContext context;
  SmallScene() {
    context.measurement = &image;
    context.detection = &image;
    context.sigmaAdu = 1.0;
    context.gain = 2.0;
    context.magZeropoint = 25.0;
    context.levels = {ThresholdLevel{1, 1.0, 1.0, 1.0}};
  }
  const Segment& containing(int x, int y) const {
    const std::int64_t p = image.index(x, y);
    for (const Segment& s : segments)
      if (std::find(s.pixels.begin(), s.pixels.end(), p) != s.pixels.end()) return s;
    ADD_FAILURE() << "no segment at " << x << "," << y;
    return segments.front();
  }
};

TEST(Plugins, SmallImageSegmentsAsSExtractor) {
  SmallScene scene;
  ASSERT_EQ(scene.segments.size(), 3u);  // source-extractor: 232 + 6 + 5 pixels
  EXPECT_EQ(scene.containing(45, 35).pixels.size(), 232u);
  EXPECT_EQ(scene.containing(10, 4).pixels.size(), 6u);
  EXPECT_EQ(scene.containing(22, 22).pixels.size(), 5u);
}

TEST(Plugins, BlockMatchesItsAnalyticValues) {
  // A 3 x 2 block of 10 at 1-based x 10-12, y 5-6 (the Gaussian's tail there is below 1e-28):
  // X2 = var{-1, 0, 1} = 2/3, Y2 = var{-0.5, 0.5} = 1/4, F = 60, sigma 1, gain 2.
  SmallScene scene;
  const MeasurementPlan plan = MeasurementPlan::build(requestAll(), {}, nullptr);
  const Row r(plan, scene.containing(10, 4), scene.context);
  EXPECT_DOUBLE_EQ(r["X_IMAGE"], 11.0);
  EXPECT_DOUBLE_EQ(r["Y_IMAGE"], 5.5);
  EXPECT_NEAR(r["X2_IMAGE"], 2.0 / 3.0, 1e-12);
  EXPECT_NEAR(r["Y2_IMAGE"], 0.25, 1e-12);
  EXPECT_NEAR(r["A_IMAGE"], std::sqrt(2.0 / 3.0), 1e-12);
  EXPECT_NEAR(r["B_IMAGE"], 0.5, 1e-12);
  EXPECT_NEAR(r["THETA_IMAGE"], 0.0, 1e-9);
  EXPECT_NEAR(r["CXX_IMAGE"], 1.5, 1e-9);
  EXPECT_NEAR(r["CYY_IMAGE"], 4.0, 1e-9);
  EXPECT_EQ(r["XMIN_IMAGE"], 10);
  EXPECT_EQ(r["YMIN_IMAGE"], 5);
  EXPECT_EQ(r["XMAX_IMAGE"], 12);
  EXPECT_EQ(r["YMAX_IMAGE"], 6);
  EXPECT_EQ(r["XPEAK_IMAGE"], 10);  // ties: first pixel in raster order
  EXPECT_EQ(r["YPEAK_IMAGE"], 5);
  EXPECT_EQ(r["ISOAREA_IMAGE"], 6);
  EXPECT_EQ(r["ISOAREAF_IMAGE"], 6);
  EXPECT_DOUBLE_EQ(r["FLUX_ISO"], 60.0);
  EXPECT_DOUBLE_EQ(r["FLUXERR_ISO"], 6.0);  // sqrt(6 * 1 + 60 / 2)
  EXPECT_DOUBLE_EQ(r["MAG_ISO"], 25.0 - 2.5 * std::log10(60.0));
  EXPECT_DOUBLE_EQ(r["MAGERR_ISO"], kMagErrFactor * 6.0 / 60.0);
  EXPECT_DOUBLE_EQ(r["SNR_ISO"], 10.0);
  EXPECT_DOUBLE_EQ(r["FLUX_MAX"], 10.0);
  EXPECT_EQ(r["THRESHOLD"], 1.0);
  EXPECT_EQ(r["NUMBER"], scene.containing(10, 4).number);
  EXPECT_EQ(r["THRESH_LEVEL"], 1);
  EXPECT_EQ(r["PARENT_NUMBER"], 0);
  EXPECT_EQ(r["FLAGS"], 0);
  // No WCS: world columns NaN, flagged.
  EXPECT_TRUE(std::isnan(r["X_WORLD"]));
  EXPECT_TRUE(std::isnan(r["A_WORLD"]));
  EXPECT_EQ(int(r["OCT_FLAGS"]), octflag::kNoWorld);
  // Octopoles of a rectangle: point symmetric, so all zero; s^2 = 2/3 + 1/4.
  EXPECT_NEAR(r["SIZE_IMAGE"], std::sqrt(2.0 / 3.0 + 0.25), 1e-6);
  EXPECT_NEAR(r["I_AAB_IMAGE"], 0.0, 1e-6);
  EXPECT_NEAR(r["ARCNESS"], 0.0, 1e-6);
}

TEST(Plugins, DiagonalMatchesItsAnalyticValues) {
  SmallScene scene;
  const MeasurementPlan plan = MeasurementPlan::build(requestAll(), {}, nullptr);
  const Row d(plan, scene.containing(22, 22), scene.context);
  // Five pixels of 5 on a diagonal: X2 = Y2 = XY = 2 (offsets -2..2), determinant 0, so
  // SExtractor's singular fix adds 0.0833333 to X2 and Y2: eigenvalues 4 + 0.0833333 and
  // 0.0833333, A = sqrt(4.0833333), B = sqrt(0.0833333), THETA = +45 (X2 == Y2). The
  // Gaussian's tail adds about 1e-7 of their value to these pixels, hence the tolerances.
  EXPECT_NEAR(d["X2_IMAGE"], 2.0 + kSingularVariance, 1e-6);
  EXPECT_NEAR(d["XY_IMAGE"], 2.0, 1e-6);
  EXPECT_NEAR(d["A_IMAGE"], std::sqrt(4.0 + kSingularVariance), 1e-6);
  EXPECT_NEAR(d["B_IMAGE"], std::sqrt(kSingularVariance), 1e-6);
  EXPECT_DOUBLE_EQ(d["THETA_IMAGE"], 45.0);
  EXPECT_EQ(d["ISOAREA_IMAGE"], 5);
  EXPECT_NEAR(d["ELONGATION"], std::sqrt((4.0 + kSingularVariance) / kSingularVariance), 1e-5);
  // FLUXERR_ISO = sqrt(n sigma^2 + F / gain) = sqrt(5 + 25 / 2).
  EXPECT_NEAR(d["FLUXERR_ISO"], std::sqrt(17.5), 1e-6);
  EXPECT_TRUE(int(d["OCT_FLAGS"]) & octflag::kSingularIso);
  // Unweighted octarc moments have no singular fix: a line has e = 1.
  EXPECT_NEAR(d["E_IMAGE"], 1.0, 1e-9);
}

TEST(Plugins, GaussianOctarcColumnsAsItsShapeSays) {
  SmallScene scene;
  const MeasurementPlan plan = MeasurementPlan::build(requestAll(), {}, nullptr);
  const Row g(plan, scene.containing(45, 35), scene.context);
  // A symmetric Gaussian (sigma 4 and 2 along axes at 30 deg) clipped by an isophote: the
  // octopoles of a point-symmetric profile vanish but for the pixel grid, and e is near
  // (16 - 4)/(16 + 4) of the whole profile.
  EXPECT_LT(g["ARCNESS"], 0.01);
  EXPECT_NEAR(g["E_IMAGE"], (16.0 - 4.0) / (16.0 + 4.0), 0.05);
}

// Every SExtractor-named column of a source-extractor 2.25 run on `image` (written to
// dir/small.fits with the cards of `header`), in the configuration of SmallScene: ABSOLUTE
// threshold 1 ADU, BACK_TYPE MANUAL 0, FILTER N, DETECT_MINAREA 1, no deblending or cleaning,
// GAIN 2, MAG_ZEROPOINT 25 (SATUR_LEVEL 50000: no pixel saturates). Rows by NUMBER; `sigmaAdu`
// is its SEXBKDEV.
struct SExtractorRun {
  std::vector<std::string> names;
  std::vector<std::map<std::string, double>> rows;
  double sigmaAdu = 0.0;
};

const std::vector<std::string> kSExtractorColumns = {
    "NUMBER",     "X_IMAGE",     "Y_IMAGE",       "XPEAK_IMAGE",    "YPEAK_IMAGE", "XMIN_IMAGE",
    "YMIN_IMAGE", "XMAX_IMAGE",  "YMAX_IMAGE",    "X2_IMAGE",       "Y2_IMAGE",    "XY_IMAGE",
    "A_IMAGE",    "B_IMAGE",     "THETA_IMAGE",   "CXX_IMAGE",      "CYY_IMAGE",   "CXY_IMAGE",
    "ELONGATION", "ELLIPTICITY", "ISOAREA_IMAGE", "ISOAREAF_IMAGE", "FLUX_ISO",    "FLUXERR_ISO",
    "MAG_ISO",    "MAGERR_ISO",  "FLUX_MAX",      "THRESHOLD",      "FLAGS"};
const std::vector<std::string> kWorldColumns = {
    "X_WORLD",  "Y_WORLD",  "ALPHA_J2000", "DELTA_J2000", "X2_WORLD",
    "Y2_WORLD", "XY_WORLD", "A_WORLD",     "B_WORLD",     "THETA_WORLD"};

void writeImage(const std::filesystem::path& path, const ImageF& image, const FitsHeader& header) {
  std::filesystem::remove(path);
  fitsfile* f = nullptr;
  int status = 0;
  long naxes[2] = {long(image.width()), long(image.height())};
  fits_create_file(&f, path.c_str(), &status);
  fits_create_img(f, FLOAT_IMG, 2, naxes, &status);
  for (const std::string& card : header.cards) {
    if (card.rfind("NAXIS", 0) == 0) continue;
    fits_write_record(f, card.c_str(), &status);
  }
  fits_write_img(f, TFLOAT, 1, image.size(), const_cast<float*>(image.data()), &status);
  fits_close_file(f, &status);
  test::checkFits(status, path.string());
}

SExtractorRun readLdac(const std::filesystem::path& path) {
  SExtractorRun run;
  fitsfile* f = nullptr;
  int status = 0;
  fits_open_file(&f, path.c_str(), READONLY, &status);
  // SEXBKDEV from the LDAC_IMHEAD cell of 80-character cards.
  fits_movabs_hdu(f, 2, nullptr, &status);
  long width = 0;
  fits_read_key_lng(f, "NAXIS1", &width, nullptr, &status);
  std::string cell(std::size_t(width), ' ');
  fits_read_tblbytes(f, 1, 1, width, reinterpret_cast<unsigned char*>(cell.data()), &status);
  for (std::size_t at = 0; at + 80 <= cell.size(); at += 80) {
    if (cell.compare(at, 8, "SEXBKDEV") == 0) run.sigmaAdu = std::stod(cell.substr(at + 10, 20));
  }
  fits_movabs_hdu(f, 3, nullptr, &status);
  long rows = 0;
  int columns = 0;
  fits_get_num_rows(f, &rows, &status);
  fits_get_num_cols(f, &columns, &status);
  run.rows.resize(std::size_t(rows));
  for (int c = 1; c <= columns; ++c) {
    char key[FLEN_KEYWORD], name[FLEN_VALUE];
    std::snprintf(key, sizeof key, "TTYPE%d", c);
    fits_read_key(f, TSTRING, key, name, nullptr, &status);
    std::vector<double> values(static_cast<std::size_t>(rows));
    fits_read_col(f, TDOUBLE, c, 1, 1, rows, nullptr, values.data(), nullptr, &status);
    run.names.push_back(name);
    for (long r = 0; r < rows; ++r) run.rows[std::size_t(r)][name] = values[std::size_t(r)];
  }
  fits_close_file(f, &status);
  test::checkFits(status, path.string());
  return run;
}

SExtractorRun runSourceExtractor(const ImageF& image, const FitsHeader& header,
                                 const std::vector<std::string>& columns) {
  const std::filesystem::path dir = test::scratchDir();
  writeImage(dir / "small.fits", image, header);
  {
    std::FILE* p = std::fopen((dir / "p.param").c_str(), "w");
    for (const std::string& c : columns) std::fprintf(p, "%s\n", c.c_str());
    std::fclose(p);
  }
  const std::string share = "/usr/share/source-extractor/";
  const std::string cmd =
      "cd '" + dir.string() + "' && source-extractor small.fits -c " + share +
      "default.sex -PARAMETERS_NAME p.param -CATALOG_TYPE FITS_LDAC -CATALOG_NAME c.ldac"
      " -THRESH_TYPE ABSOLUTE -DETECT_THRESH 1 -ANALYSIS_THRESH 1 -DETECT_MINAREA 1 -FILTER N"
      " -DEBLEND_NTHRESH 1 -DEBLEND_MINCONT 1 -CLEAN N -MASK_TYPE NONE -BACK_TYPE MANUAL"
      " -BACK_VALUE 0 -GAIN 2 -MAG_ZEROPOINT 25 -SATUR_LEVEL 50000 -STARNNW_NAME " +
      share + "default.nnw -FILTER_NAME " + share +
      "default.conv -WRITE_XML N -VERBOSE_TYPE QUIET > se.log 2>&1";
  EXPECT_EQ(test::runQuiet(cmd), 0) << cmd;
  return readLdac(dir / "c.ldac");
}

// What each column reaches against source-extractor (as in the end-to-end tests,
// tests/integration/test_measure_vs_sextractor.py): the integer, position, second-moment,
// shape and flux columns bit for bit once stored with SExtractor's type; the columns SExtractor
// derives in mixed precision within n float ulps; ELLIPTICITY within 2 ulps of 1. World
// columns: positions to 1e-15 relative (reached: equal), A/B/THETA_WORLD within one float ulp,
// X2/Y2/XY_WORLD to 2e-9 relative (reached 8e-10: they are products of the finite-difference
// Jacobian, whose one-pixel differences of world positions lose six digits to cancellation).
void expectLikeSExtractor(const Row& ours, const std::map<std::string, double>& theirs,
                          const MeasurementPlan& plan, const std::string& what) {
  const std::map<std::string, int> ulps = {{"ELONGATION", 2}, {"FLUXERR_ISO", 1}, {"MAG_ISO", 1},
                                           {"MAGERR_ISO", 2}, {"THRESHOLD", 1},   {"A_WORLD", 1},
                                           {"B_WORLD", 1},    {"THETA_WORLD", 1}};
  const std::map<std::string, double> relative = {
      {"X_WORLD", 1e-15}, {"Y_WORLD", 1e-15}, {"ALPHA_J2000", 1e-15}, {"DELTA_J2000", 1e-15},
      {"X2_WORLD", 2e-9}, {"Y2_WORLD", 2e-9}, {"XY_WORLD", 2e-9}};
  for (const ColumnSpec& col : plan.columns()) {
    const auto it = theirs.find(col.name);
    if (it == theirs.end()) continue;
    const double t = it->second;
    const double o =
        col.type == ColumnType::Float32 ? double(float(ours[col.name])) : ours[col.name];
    const std::string where = what + " " + col.name;
    if (col.name == "ELLIPTICITY") {
      EXPECT_NEAR(o, t, std::ldexp(1.0, -22)) << where;
    } else if (ulps.count(col.name)) {
      const double ulp = std::nextafter(float(std::fabs(t)), INFINITY) - float(std::fabs(t));
      EXPECT_LE(std::fabs(o - t), ulps.at(col.name) * ulp) << where << ": " << o << " vs " << t;
    } else if (relative.count(col.name)) {
      EXPECT_LE(std::fabs(o - t), relative.at(col.name) * std::fabs(t))
          << where << ": " << o << " vs " << t;
    } else {
      EXPECT_EQ(o, t) << where;
    }
  }
}

// Each source-extractor object, found by its peak pixel, against octarc's row.
void compareWithSourceExtractor(SmallScene& scene, const FitsHeader& header,
                                const std::vector<std::string>& columns) {
  const SExtractorRun run = runSourceExtractor(scene.image, header, columns);
  ASSERT_EQ(run.rows.size(), scene.segments.size());
  EXPECT_EQ(run.sigmaAdu, scene.context.sigmaAdu);  // zero sky: SExtractor's sigma is 1
  std::vector<ColumnRequest> request;
  for (const std::string& c : columns) request.push_back({c});
  const MeasurementPlan plan = MeasurementPlan::build(request, {}, nullptr);
  for (const auto& theirs : run.rows) {
    const int x = int(theirs.at("XPEAK_IMAGE")) - 1, y = int(theirs.at("YPEAK_IMAGE")) - 1;
    const Segment& s = scene.containing(x, y);
    const Row ours(plan, s, scene.context);
    EXPECT_EQ(ours["NUMBER"], s.number);
    std::map<std::string, double> without = theirs;
    without.erase("NUMBER");  // SExtractor numbers in its own order
    expectLikeSExtractor(ours, without, plan,
                         "object at " + std::to_string(x) + "," + std::to_string(y));
  }
}

TEST(Plugins, EveryObjectMatchesSourceExtractor) {
  OCTARC_REQUIRE_PROGRAM("source-extractor");
  SmallScene scene;
  compareWithSourceExtractor(scene, FitsHeader{}, kSExtractorColumns);
}

TEST(Plugins, WorldColumnsMatchSourceExtractorThroughWcs) {
  OCTARC_REQUIRE_PROGRAM("source-extractor");
  // A TAN header: CRVAL (150, 2), CRPIX (32, 24), CD = 1e-4 deg rotated by 30 deg.
  FitsHeader header;
  const double c = std::cos(std::numbers::pi / 6), s = std::sin(std::numbers::pi / 6);
  header.set("NAXIS", "2");
  header.set("NAXIS1", "64");
  header.set("NAXIS2", "48");
  header.set("CTYPE1", "'RA---TAN'");
  header.set("CTYPE2", "'DEC--TAN'");
  header.set("CRPIX1", "32.0");
  header.set("CRPIX2", "24.0");
  header.set("CRVAL1", "150.0");
  header.set("CRVAL2", "2.0");
  const auto num = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return std::string(buf);
  };
  header.set("CD1_1", num(-1e-4 * c));
  header.set("CD1_2", num(1e-4 * s));
  header.set("CD2_1", num(1e-4 * s));
  header.set("CD2_2", num(1e-4 * c));
  const std::optional<Wcs> wcs = Wcs::fromHeader(header, "small.fits");
  ASSERT_TRUE(wcs.has_value());
  SmallScene scene;
  scene.context.wcs = &*wcs;
  std::vector<std::string> columns = {"NUMBER", "XPEAK_IMAGE", "YPEAK_IMAGE"};
  columns.insert(columns.end(), kWorldColumns.begin(), kWorldColumns.end());
  compareWithSourceExtractor(scene, header, columns);
  // No flag: the WCS gave every world column.
  const MeasurementPlan plan = MeasurementPlan::build({{"OCT_FLAGS"}}, {}, nullptr);
  EXPECT_EQ(
      int(Row(plan, scene.containing(45, 35), scene.context)["OCT_FLAGS"]) & octflag::kNoWorld, 0);
}

// A uniform annular sector (radii r1..r2 about (cx, cy), half-opening phi about direction dir)
// rasterised by area: each pixel's value is the fraction of it inside the sector, from 16 x 16
// sub-pixel samples.
ImageF rasterisedArc(int size, double cx, double cy, double r1, double r2, double phi, double dir) {
  ImageF image(size, size, 0.0f);
  constexpr int kSub = 16;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      if (std::hypot(x - cx, y - cy) > r2 + 1.0 || std::hypot(x - cx, y - cy) < r1 - 1.0) continue;
      int inside = 0;
      for (int j = 0; j < kSub; ++j)
        for (int i = 0; i < kSub; ++i) {
          const double px = x - 0.5 + (i + 0.5) / kSub, py = y - 0.5 + (j + 0.5) / kSub;
          const double r = std::hypot(px - cx, py - cy);
          const double t = std::remainder(std::atan2(py - cy, px - cx) - dir, 2 * std::numbers::pi);
          inside += r >= r1 && r <= r2 && std::fabs(t) <= phi;
        }
      image(x, y) = float(inside) / float(kSub * kSub);
    }
  return image;
}

// The octarc columns of rasterised arcs against the closed form of the same uniform annular
// sector (ArcClosedForm.h), at several openings and orientations, and ARC_SIDE against the
// centre of curvature. Rasterisation is the only difference: pixel values are areas but the
// moments take each pixel at its centre, which moves the second moments by a fraction of a
// pixel^2 (the edge pixels of the 2-pixel-wide band put their weight at centres partly outside
// it). Relative to s^2 that matters most for the shortest arc (phi = 20 deg, s = 8 px): reached
// 4.2e-4 in arcness, 3.0e-3 in e and 1.6e-3 relative in size; allowed 1e-3, 6e-3 and 3e-3.
TEST(Plugins, RasterisedArcsMatchTheClosedForm) {
  const double r1 = 39.0, r2 = 41.0;
  const MeasurementPlan plan = MeasurementPlan::build({{"ARCNESS"},
                                                       {"E_IMAGE"},
                                                       {"E1_IMAGE"},
                                                       {"E2_IMAGE"},
                                                       {"SIZE_IMAGE"},
                                                       {"ARC_SIDE"},
                                                       {"X_IMAGE"},
                                                       {"Y_IMAGE"}},
                                                      {}, nullptr);
  double worstArcness = 0.0, worstE = 0.0, worstSize = 0.0;
  for (double phiDeg : {20.0, 45.0, 90.0, 135.0}) {
    for (double dirDeg : {0.0, 37.0, 128.0, 251.0}) {
      const double phi = phiDeg * std::numbers::pi / 180.0, dir = dirDeg * std::numbers::pi / 180.0;
      const double cx = 60.3, cy = 59.6;
      const ImageF image = rasterisedArc(121, cx, cy, r1, r2, phi, dir);
      Segment s{1, 1, 0, {}, {}};
      for (std::int64_t p = 0; p < image.size(); ++p)
        if (image[p] > 0.0f) s.pixels.push_back(p);
      MeasureContext c;
      c.measurement = &image;
      c.detection = &image;
      const Row r(plan, s, c);
      const test::ArcMoments ref = test::uniformArc(r1, r2, phi);
      const std::string what = std::to_string(phiDeg) + " deg towards " + std::to_string(dirDeg);
      worstArcness = std::max(worstArcness, std::fabs(r["ARCNESS"] - ref.arcness));
      worstE = std::max(worstE, std::fabs(r["E_IMAGE"] - ref.e));
      worstSize = std::max(worstSize, std::fabs(r["SIZE_IMAGE"] / ref.sizePix - 1.0));
      EXPECT_NEAR(r["ARCNESS"], ref.arcness, 1e-3) << what;
      EXPECT_NEAR(r["E_IMAGE"], ref.e, 6e-3) << what;
      EXPECT_NEAR(r["SIZE_IMAGE"], ref.sizePix, 3e-3 * ref.sizePix) << what;
      // The centre of curvature lies on the +b side of the centroid for ARC_SIDE +1.
      const double theta = 0.5 * std::atan2(r["E2_IMAGE"], r["E1_IMAGE"]);
      const double towardsCentre = -std::sin(theta) * (cx + 1.0 - r["X_IMAGE"]) +
                                   std::cos(theta) * (cy + 1.0 - r["Y_IMAGE"]);
      EXPECT_EQ(r["ARC_SIDE"], towardsCentre > 0 ? 1.0 : -1.0) << what;
    }
  }
  std::printf(
      "rasterised arcs: max |arcness - closed form| %.2g, |e - closed form| %.2g, "
      "|size / closed form - 1| %.2g\n",
      worstArcness, worstE, worstSize);
}

// The reference values METHOD.md section 1 quotes for uniform thin circular arcs, measured by
// the ARCNESS and E_IMAGE columns on arcs rasterised here: a band of width w = 1 px at radius
// R, centred off the pixel grid, pointing in an arbitrary direction. What separates these from
// the quoted values:
//  - the quotes are rounded (to 3 decimals: at most 5e-4 off; the maximum 0.2314 to 4);
//  - a pixel's area given to its centre, and the band's width, add 1/12 px^2 of variance along
//    the arc and (1 + w^2)/12 across it: s^2 grows by d = (2 + w^2)/12 px^2 while the third
//    moments (of a symmetric smoothing) stay, so to first order arcness shrinks by 1.5 d / s^2
//    of itself and e moves by at most (1 + e) d / s^2; allowed: twice that;
//  - the ends of the band are cut across pixels whose area sits at their centres, which places
//    each end to within half a pixel along the arc: the opening phi to within 0.5 / R, and
//    arcness and e change with phi by at most 0.25 and 0.5 per radian (the closed form's
//    steepest slopes, ArcClosedForm.h: 0.231 near phi = 0 and 0.475 at 134 deg).
// With R = 1000 px the last two add at most 1.3e-4 to arcness and 2.6e-4 to e (reached: 4e-5 at
// R = 300 px). The full ring (phi = 180 deg) has arcness 0 up to the 1/256 quantisation of the
// rasterised areas (reached: 7e-6).
TEST(Plugins, MethodReferenceTableIsWhatArcnessMeasures) {
  const double width = 1.0, d = (2.0 + width * width) / 12.0;
  const MeasurementPlan plan =
      MeasurementPlan::build({{"ARCNESS"}, {"E_IMAGE"}, {"SIZE_IMAGE"}}, {}, nullptr);
  struct Measured {
    double arcness, e, s2;
  };
  const auto measure = [&](double radius, double phiDeg) {
    const int size = 2 * int(radius) + 21;
    const double c = 0.5 * (size - 1);
    const ImageF image =
        rasterisedArc(size, c + 0.3, c - 0.4, radius - 0.5 * width, radius + 0.5 * width,
                      phiDeg * std::numbers::pi / 180.0, 37.0 * std::numbers::pi / 180.0);
    Segment s{1, 1, 0, {}, {}};
    for (std::int64_t p = 0; p < image.size(); ++p)
      if (image[p] > 0.0f) s.pixels.push_back(p);
    MeasureContext context;
    context.measurement = &image;
    context.detection = &image;
    const Row r(plan, s, context);
    return Measured{r["ARCNESS"], r["E_IMAGE"], r["SIZE_IMAGE"] * r["SIZE_IMAGE"]};
  };
  const double radius = 1000.0, dPhi = 0.5 / radius;
  const double table[][2] = {{5, 0.020},  {15, 0.060}, {30, 0.116},  {45, 0.164},
                             {60, 0.201}, {90, 0.231}, {120, 0.194}, {150, 0.101}};
  for (const auto& [phiDeg, quoted] : table) {
    const Measured m = measure(radius, phiDeg);
    EXPECT_NEAR(m.arcness, quoted, 5e-4 + 2 * 1.5 * d / m.s2 * quoted + 0.25 * dPhi)
        << phiDeg << " deg";
    if (phiDeg == 30.0 || phiDeg == 90.0) {
      const double quotedE = phiDeg == 30.0 ? 0.964 : 0.681;
      EXPECT_NEAR(m.e, quotedE, 5e-4 + 2 * (1 + quotedE) * d / m.s2 + 0.5 * dPhi)
          << phiDeg << " deg";
    }
  }
  EXPECT_NEAR(measure(radius, 180.0).arcness, 0.0, 1e-4);
  // The maximum, 0.2314 at phi = 88.5 deg: on a 1-degree scan (R = 300 px) the largest value,
  // at 88 or 89 deg (the closed form's slope is 0 there, so no end term; its curvature moves it
  // by 1e-5 half a degree away).
  double best = 0.0, bestDeg = 0.0, bestS2 = 0.0;
  for (double phiDeg = 84.0; phiDeg <= 93.0; phiDeg += 1.0) {
    const Measured m = measure(300.0, phiDeg);
    if (m.arcness > best) best = m.arcness, bestDeg = phiDeg, bestS2 = m.s2;
  }
  EXPECT_NEAR(best, 0.2314, 5e-5 + 2 * 1.5 * d / bestS2 * best + 1e-5);
  EXPECT_NEAR(bestDeg, 88.5, 0.5);
}

TEST(Plugins, FilteredDetectionWeightsShapesButNotFlux) {
  // Detection image brighter on the right: the SExtractor-named shape follows it, FLUX_ISO and
  // the octopole columns follow the measurement image.
  ImageF meas(8, 5, 0.0f), det(8, 5, 0.0f);
  Segment s;
  s.number = 1;
  for (int x = 2; x <= 4; ++x) {
    meas(x, 2) = 2.0f;
    det(x, 2) = float(x - 1);  // 1, 2, 3
    s.pixels.push_back(meas.index(x, 2));
  }
  MeasureContext c;
  c.measurement = &meas;
  c.detection = &det;
  c.sigmaAdu = 0.5;
  c.levels = {ThresholdLevel{1, 0.5, 1.5, 1.0}};
  const MeasurementPlan plan = MeasurementPlan::build(
      {{"X_IMAGE"}, {"XPEAK_IMAGE"}, {"FLUX_ISO"}, {"FLUX_MAX"}, {"ISOAREA_IMAGE"}, {"SIZE_IMAGE"}},
      {}, nullptr);
  const Row r(plan, s, c);
  EXPECT_NEAR(r["X_IMAGE"], 1.0 + (2 * 1 + 3 * 2 + 4 * 3) / 6.0, 1e-12);  // 1-based
  EXPECT_EQ(r["XPEAK_IMAGE"], 5);
  EXPECT_DOUBLE_EQ(r["FLUX_ISO"], 6.0);
  EXPECT_DOUBLE_EQ(r["FLUX_MAX"], 2.0);
  EXPECT_EQ(r["ISOAREA_IMAGE"], 3);  // measurement values 2 > analysis threshold 1.5
  EXPECT_NEAR(r["SIZE_IMAGE"], std::sqrt(2.0 / 3.0), 1e-12);  // equal weights on 3 pixels
}

TEST(Plugins, NanPixelIsFlaggedAndLeftOut) {
  SmallScene scene;
  scene.image(10, 4) = std::numeric_limits<float>::quiet_NaN();  // one block pixel
  const MeasurementPlan plan = MeasurementPlan::build(requestAll(), {}, nullptr);
  const Row r(plan, scene.containing(11, 4), scene.context);
  EXPECT_TRUE(int(r["OCT_FLAGS"]) & octflag::kBadPixels);
  EXPECT_NEAR(r["FLUX_ISO"], 50.0, 1e-4);
  EXPECT_NEAR(r["FLUXERR_ISO"], std::sqrt(5.0 + 25.0), 1e-5);  // 5 finite pixels
  // Remaining 0-based pixels x 9, 11, 9, 10, 11 and y 4, 4, 5, 5, 5.
  EXPECT_NEAR(r["X_IMAGE"], 11.0, 1e-6);
  EXPECT_NEAR(r["Y_IMAGE"], 5.6, 1e-6);
  EXPECT_EQ(r["ISOAREAF_IMAGE"], 6);  // the footprint itself is unchanged
  for (const ColumnSpec& col : plan.columns()) {
    if (col.name.find("WORLD") != std::string::npos || col.name.find("J2000") != std::string::npos)
      continue;  // no WCS here
    EXPECT_FALSE(std::isnan(r[col.name])) << col.name;
  }
}

TEST(Plugins, DegenerateObjectsGiveFlagsAndNaN) {
  ImageF img(6, 6, 0.0f);
  img(2, 2) = 7.0f;   // single pixel
  img(4, 4) = -3.0f;  // negative-flux object (possible on an unfiltered image)
  Segment one{1, 1, 0, {img.index(2, 2)}, {}};
  Segment neg{2, 1, 0, {img.index(4, 4)}, {}};
  MeasureContext c;
  c.measurement = &img;
  c.detection = &img;
  c.sigmaAdu = 1.0;
  c.magZeropoint = 30.0;
  c.levels = {ThresholdLevel{1, 0.5, 0.5, 0.5}};
  const MeasurementPlan plan = MeasurementPlan::build(requestAll(), {}, nullptr);

  const Row r1(plan, one, c);
  EXPECT_NEAR(r1["A_IMAGE"], 0.2887, 5e-5);
  EXPECT_DOUBLE_EQ(r1["THETA_IMAGE"], 45.0);
  EXPECT_TRUE(std::isnan(r1["ARCNESS"]));
  EXPECT_TRUE(std::isnan(r1["E_IMAGE"]));
  EXPECT_EQ(r1["ARC_SIDE"], 0);
  EXPECT_TRUE(int(r1["OCT_FLAGS"]) & octflag::kSingularMoments);
  EXPECT_TRUE(int(r1["OCT_FLAGS"]) & octflag::kSingularIso);

  const Row r2(plan, neg, c);
  EXPECT_DOUBLE_EQ(r2["FLUX_ISO"], -3.0);
  EXPECT_EQ(r2["MAG_ISO"], 99.0);
  EXPECT_EQ(r2["MAGERR_ISO"], 99.0);
  EXPECT_TRUE(std::isnan(r2["X_IMAGE"]));
  EXPECT_TRUE(std::isnan(r2["X2_IMAGE"]));
  EXPECT_TRUE(std::isnan(r2["SIZE_IMAGE"]));
  EXPECT_EQ(r2["ISOAREA_IMAGE"], 0);
  EXPECT_TRUE(int(r2["OCT_FLAGS"]) & octflag::kNonPositiveFlux);
  EXPECT_EQ(r2["XMIN_IMAGE"], 5);
}

TEST(Plugins, SaturationAndBorderFlags) {
  ImageF img(10, 10, 0.0f);
  Segment edge{1, 1, 0, {}, {}}, bright{2, 1, 0, {}, {}};
  for (int x = 0; x < 3; ++x) {
    img(x, 5) = 1.0f;
    edge.pixels.push_back(img.index(x, 5));
  }
  img(5, 2) = 80.0f;
  img(6, 2) = 95.0f;
  bright.pixels = {img.index(5, 2), img.index(6, 2)};
  MeasureContext c;
  c.measurement = &img;
  c.detection = &img;
  const std::vector<std::int64_t> saturated = {img.index(9, 0), img.index(6, 2)};
  c.saturatedPixels = &saturated;
  c.levels = {ThresholdLevel{1, 0.5, 0.5, 0.5}};
  const MeasurementPlan plan = MeasurementPlan::build({{"FLAGS"}}, {}, nullptr);
  EXPECT_EQ(Row(plan, edge, c)["FLAGS"], sexflag::kTouchesBorder);
  EXPECT_EQ(Row(plan, bright, c)["FLAGS"], sexflag::kSaturated);
  // The same footprints given as runs.
  Segment edgeRuns{1, 1, 0, {}, {{5, 0, 2}}}, brightRuns{2, 1, 0, {}, {{2, 5, 6}}};
  EXPECT_EQ(Row(plan, edgeRuns, c)["FLAGS"], sexflag::kTouchesBorder);
  EXPECT_EQ(Row(plan, brightRuns, c)["FLAGS"], sexflag::kSaturated);
  const std::vector<std::int64_t> justOutside = {img.index(4, 2), img.index(7, 2)};
  c.saturatedPixels = &justOutside;
  EXPECT_EQ(Row(plan, brightRuns, c)["FLAGS"], 0);
  c.saturatedPixels = nullptr;  // no saturated pixel in the image
  EXPECT_EQ(Row(plan, bright, c)["FLAGS"], 0);
}

// Every column is the same whether a footprint comes as pixel indices or as runs.
TEST(Plugins, RunsAndPixelListsMeasureTheSame) {
  ImageF img = smallImage();
  MeasureContext c;
  c.measurement = &img;
  c.detection = &img;
  c.sigmaAdu = 1.5;
  c.gain = 2.0;
  c.levels = {ThresholdLevel{1, 0.5, 0.5, 0.5}};
  std::vector<ColumnRequest> all;
  for (const ColumnSpec& spec : allBuiltinColumns()) all.push_back({spec.name, spec.repeat});
  const MeasurementPlan plan = MeasurementPlan::build(all, {}, nullptr);
  for (const Segment& s : segmentsAbove(img, 0.5)) {
    Segment runs = s;
    runs.pixels.clear();
    for (const std::int64_t p : s.pixels) {
      const std::int32_t y = std::int32_t(p / img.width()), x = std::int32_t(p % img.width());
      if (!runs.runs.empty() && runs.runs.back().y == y && runs.runs.back().x1 + 1 == x) {
        runs.runs.back().x1 = x;
      } else {
        runs.runs.push_back({y, x, x});
      }
    }
    std::vector<double> a(std::size_t(plan.rowWidth())), b(a.size());
    plan.measure(s, c, a.data());
    plan.measure(runs, c, b.data());
    for (std::size_t k = 0; k < a.size(); ++k) {
      EXPECT_TRUE(a[k] == b[k] || (std::isnan(a[k]) && std::isnan(b[k])))
          << "object " << s.number << " value " << k;
    }
  }
}

TEST(Plugins, FarFromOriginGivesSameMoments) {
  // The same lopsided blob at x = 10 and x = 10000 of one wide image.
  ImageF img(10030, 24, 0.0f);
  Segment nearObj{1, 1, 0, {}, {}}, farObj{2, 1, 0, {}, {}};
  for (int y = 2; y < 22; ++y)
    for (int x = 0; x < 20; ++x) {
      const double dx = x - 9.3, dy = y - 11.6;
      const double r = std::hypot(dx, dy), ang = std::atan2(dy, dx);
      const float v = float(50.0 * std::exp(-0.5 * (r - 6.0) * (r - 6.0)) * (1.2 + std::sin(ang)));
      if (v < 0.5f) continue;
      img(x, y) = v;
      img(x + 9990, y) = v;
      nearObj.pixels.push_back(img.index(x, y));
      farObj.pixels.push_back(img.index(x + 9990, y));
    }
  std::sort(nearObj.pixels.begin(), nearObj.pixels.end());
  std::sort(farObj.pixels.begin(), farObj.pixels.end());
  MeasureContext c;
  c.measurement = &img;
  c.detection = &img;
  const MeasurementPlan plan = MeasurementPlan::build({{"X_IMAGE"},
                                                       {"X2_IMAGE"},
                                                       {"XY_IMAGE"},
                                                       {"I_AAB_IMAGE"},
                                                       {"I_ABB_IMAGE"},
                                                       {"I_AAA_IMAGE"},
                                                       {"I_BBB_IMAGE"},
                                                       {"ARCNESS"}},
                                                      {}, nullptr);
  const Row a(plan, nearObj, c), b(plan, farObj, c);
  EXPECT_NEAR(b["X_IMAGE"] - a["X_IMAGE"], 9990.0, 1e-9);
  for (const char* name : {"X2_IMAGE", "XY_IMAGE", "I_AAB_IMAGE", "I_ABB_IMAGE", "I_AAA_IMAGE",
                           "I_BBB_IMAGE", "ARCNESS"}) {
    EXPECT_GT(std::fabs(a[name]), 1e-4) << name;
    EXPECT_NEAR(b[name], a[name], 1e-9 * std::fabs(a[name])) << name;
  }
}

TEST(Plugins, VarianceMapErrorsAndAnalysisThreshold) {
  // SEXTRACTOR.md §4 with a variance map (WEIGHT_GAIN Y): pixels 10, 20, -5 with variances
  // 1, 4, 9; sigma 2, gain 2. FLUXERR^2 = (1 + 4 + 9) + 10/2 * 1/4 + 20/2 * 4/4 = 25.25.
  // Analysis threshold 6 ADU = 3 sigma, per pixel 3 sqrt(var) = 3, 6, 9: two pixels above.
  ImageF img(3, 1), var(3, 1);
  img(0, 0) = 10.0f;
  img(1, 0) = 20.0f;
  img(2, 0) = -5.0f;
  var(0, 0) = 1.0f;
  var(1, 0) = 4.0f;
  var(2, 0) = 9.0f;
  Segment s{1, 1, 0, {0, 1, 2}, {}};
  MeasureContext c;
  c.measurement = &img;
  c.detection = &img;
  c.variance = &var;
  c.sigmaAdu = 2.0;
  c.gain = 2.0;
  c.levels = {ThresholdLevel{1, 4.0, 6.0, 2.0}};
  const MeasurementPlan plan = MeasurementPlan::build(
      {{"FLUX_ISO"}, {"FLUXERR_ISO"}, {"ISOAREA_IMAGE"}, {"SNR_ISO"}}, {}, nullptr);
  const Row r(plan, s, c);
  EXPECT_DOUBLE_EQ(r["FLUX_ISO"], 25.0);
  EXPECT_DOUBLE_EQ(r["FLUXERR_ISO"], std::sqrt(25.25));
  EXPECT_EQ(r["ISOAREA_IMAGE"], 2);
  EXPECT_DOUBLE_EQ(r["SNR_ISO"], 25.0 / std::sqrt(25.25));
}

TEST(Plugins, LevelsFillIdentityColumns) {
  ImageF img(5, 5, 1.0f);
  Segment s{7, 2, 3, {img.index(2, 2), img.index(3, 2)}, {}};
  MeasureContext c;
  c.measurement = &img;
  c.levels = {ThresholdLevel{1, 0.5, 0.5, 1.0}, ThresholdLevel{2, 0.75, 0.9, 1.5}};
  const MeasurementPlan plan = MeasurementPlan::build(
      {{"NUMBER"}, {"THRESH_LEVEL"}, {"PARENT_NUMBER"}, {"THRESHOLD"}, {"ISOAREA_IMAGE"}}, {},
      nullptr);
  const Row r(plan, s, c);
  EXPECT_EQ(r["NUMBER"], 7);
  EXPECT_EQ(r["THRESH_LEVEL"], 2);
  EXPECT_EQ(r["PARENT_NUMBER"], 3);
  EXPECT_EQ(r["THRESHOLD"], 0.75);
  EXPECT_EQ(r["ISOAREA_IMAGE"], 2);  // 1.0 > 0.9
}

}  // namespace
}  // namespace octarc
