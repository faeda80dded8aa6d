// The measurement plugins through MeasurementPlan on small images drawn here, against the values
// source-extractor 2.25 wrote for the same pixels.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

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

TEST(Plugins, BlockMatchesSExtractor) {
  SmallScene scene;
  const MeasurementPlan plan = MeasurementPlan::build(requestAll(), {}, nullptr);
  const Row r(plan, scene.containing(10, 4), scene.context);
  EXPECT_DOUBLE_EQ(r["X_IMAGE"], 11.0);
  EXPECT_DOUBLE_EQ(r["Y_IMAGE"], 5.5);
  EXPECT_NEAR(r["X2_IMAGE"], 0.6666666667, 1e-9);
  EXPECT_NEAR(r["Y2_IMAGE"], 0.25, 1e-12);
  EXPECT_NEAR(r["A_IMAGE"], 0.816, 5e-4);
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
  EXPECT_NEAR(r["FLUX_ISO"], 60.0, 1e-4);  // + the Gaussian's far tail, as in SExtractor
  EXPECT_NEAR(r["FLUXERR_ISO"], 6.0, 1e-5);
  EXPECT_NEAR(r["MAG_ISO"], 20.5546, 5e-5);
  EXPECT_NEAR(r["MAGERR_ISO"], 0.1086, 5e-5);
  EXPECT_NEAR(r["SNR_ISO"], 10.0, 1e-4);
  EXPECT_NEAR(r["FLUX_MAX"], 10.0, 1e-4);
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

TEST(Plugins, DiagonalAndGaussianMatchSExtractor) {
  SmallScene scene;
  const MeasurementPlan plan = MeasurementPlan::build(requestAll(), {}, nullptr);
  const Row d(plan, scene.containing(22, 22), scene.context);
  EXPECT_NEAR(d["X2_IMAGE"], 2.0833333, 1e-6);
  EXPECT_NEAR(d["B_IMAGE"], 0.2887, 5e-5);
  EXPECT_DOUBLE_EQ(d["THETA_IMAGE"], 45.0);
  EXPECT_EQ(d["ISOAREA_IMAGE"], 5);
  EXPECT_NEAR(d["ELONGATION"], 7.0, 5e-4);
  EXPECT_NEAR(d["FLUXERR_ISO"], 4.1833, 5e-5);
  EXPECT_TRUE(int(d["OCT_FLAGS"]) & octflag::kSingularIso);
  // Unweighted octarc moments have no singular fix: a line has e = 1.
  EXPECT_NEAR(d["E_IMAGE"], 1.0, 1e-9);

  // source-extractor 2.25 catalog values for the Gaussian.
  const Row g(plan, scene.containing(45, 35), scene.context);
  EXPECT_NEAR(g["X_IMAGE"], 46.3002, 5e-5);
  EXPECT_NEAR(g["Y_IMAGE"], 36.6980, 5e-5);
  EXPECT_NEAR(g["X2_IMAGE"], 1.2395482203e+01, 1e-6);
  EXPECT_NEAR(g["Y2_IMAGE"], 6.6939450620e+00, 1e-6);
  EXPECT_NEAR(g["XY_IMAGE"], 4.9727522818e+00, 1e-6);
  EXPECT_NEAR(g["A_IMAGE"], 3.909, 5e-4);
  EXPECT_NEAR(g["B_IMAGE"], 1.953, 5e-4);
  EXPECT_NEAR(g["THETA_IMAGE"], 30.09, 5e-3);
  EXPECT_NEAR(g["CXX_IMAGE"], 1.1492459e-01, 1e-7);
  EXPECT_NEAR(g["CYY_IMAGE"], 2.1281108e-01, 1e-7);
  EXPECT_NEAR(g["CXY_IMAGE"], -1.7074880e-01, 1e-7);
  EXPECT_EQ(g["XMIN_IMAGE"], 36);
  EXPECT_EQ(g["YMIN_IMAGE"], 29);
  EXPECT_EQ(g["XMAX_IMAGE"], 57);
  EXPECT_EQ(g["YMAX_IMAGE"], 44);
  EXPECT_EQ(g["XPEAK_IMAGE"], 47);
  EXPECT_EQ(g["YPEAK_IMAGE"], 37);
  EXPECT_EQ(g["ISOAREA_IMAGE"], 232);
  EXPECT_NEAR(g["FLUX_ISO"], 4977.05, 5e-3);
  EXPECT_NEAR(g["FLUXERR_ISO"], 52.15865, 5e-5);
  EXPECT_NEAR(g["MAG_ISO"], 15.7576, 5e-5);
  EXPECT_NEAR(g["MAGERR_ISO"], 0.0114, 5e-5);
  EXPECT_NEAR(g["FLUX_MAX"], 98.12896, 5e-5);
  // A symmetric Gaussian clipped by an ellipse-like isophote: octopoles small, e as its axes.
  EXPECT_LT(g["ARCNESS"], 0.01);
  EXPECT_NEAR(g["E_IMAGE"], (16.0 - 4.0) / (16.0 + 4.0), 0.05);
}

TEST(Plugins, WorldColumnsMatchSExtractorThroughWcs) {
  // The TAN header of the reference run: CRVAL (150, 2), CRPIX (32, 24), CD = 1e-4 deg rotated
  // by 30 deg. Values from `source-extractor small.fits ... -CATALOG_TYPE ASCII_HEAD`; X/Y_WORLD
  // are printed with 11 significant digits, hence 6e-9 deg.
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
  const MeasurementPlan plan = MeasurementPlan::build(requestAll(), {}, nullptr);
  const Row g(plan, scene.containing(45, 35), scene.context);
  EXPECT_NEAR(g["X_WORLD"], 1.4999939610e+02, 6e-9);
  EXPECT_NEAR(g["Y_WORLD"], 2.0018146937e+00, 6e-9);
  EXPECT_NEAR(g["ALPHA_J2000"], 149.9993961, 1e-7);
  EXPECT_NEAR(g["DELTA_J2000"], 2.0018147, 1e-7);
  EXPECT_NEAR(g["X2_WORLD"], 8.8168363032e-08, 1e-6 * 8.8e-08);
  EXPECT_NEAR(g["Y2_WORLD"], 1.0272591002e-07, 1e-6 * 1.0e-07);
  EXPECT_NEAR(g["XY_WORLD"], -4.9552161170e-08, 1e-6 * 5.0e-08);
  EXPECT_NEAR(g["A_WORLD"], 0.0003814853, 1e-6 * 3.8e-4);
  EXPECT_NEAR(g["B_WORLD"], 0.0002129865, 1e-6 * 2.1e-4);
  EXPECT_NEAR(g["THETA_WORLD"], -49.18, 5e-3);
  EXPECT_EQ(int(g["OCT_FLAGS"]) & octflag::kNoWorld, 0);

  const Row b(plan, scene.containing(10, 4), scene.context);
  EXPECT_NEAR(b["X_WORLD"], 1.5000089420e+02, 6e-9);
  EXPECT_NEAR(b["Y_WORLD"], 1.9973478528e+00, 6e-9);
  EXPECT_NEAR(b["X2_WORLD"], 5.6249983901e-09, 1e-6 * 5.6e-09);
  EXPECT_NEAR(b["THETA_WORLD"], -30.00, 5e-3);
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
