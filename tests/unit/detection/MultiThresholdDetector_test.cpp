#include "octarc/detection/MultiThresholdDetector.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <numeric>
#include <random>
#include <set>

#include "ConvKernels.h"
#include "DetectionTestUtil.h"
#include "TestPaths.h"
#include "octarc/core/Error.h"
#include "octarc/detection/Filter.h"
#include "octarc/io/FitsImage.h"

namespace octarc {
namespace {

std::vector<std::int32_t> labelsOf(const ImageI32& image) {
  return {image.pixels().begin(), image.pixels().end()};
}

using Pixels = std::vector<std::int64_t>;
constexpr float kNaNf = std::numeric_limits<float>::quiet_NaN();

// Everything the detector emitted, in emission order, plus the sink call boundaries.
struct Detected {
  std::vector<Segment> objects;
  std::vector<std::size_t> callSizes;
  std::vector<std::int64_t> perLevel;
};

Detected detect(const ImageF& image, const DetectionSettings& settings) {
  Detected out;
  out.perLevel = detectMultiThreshold(image, settings, [&](std::vector<Segment>& objs) {
    out.callSizes.push_back(objs.size());
    for (Segment& s : objs) out.objects.push_back(std::move(s));
  });
  return out;
}

// Rows written top (y = 0) down.
ImageF rows(std::int64_t width, const std::vector<float>& values) {
  ImageF image(width, static_cast<std::int64_t>(values.size()) / width);
  for (std::size_t i = 0; i < values.size(); ++i) image[static_cast<std::int64_t>(i)] = values[i];
  return image;
}

DetectionSettings settingsOf(std::vector<double> thresholds, int minArea, int threads = 1) {
  DetectionSettings s;
  s.thresholdsAdu = std::move(thresholds);
  s.minArea = minArea;
  s.threads = threads;
  return s;
}

struct Expected {
  int level;
  std::int32_t number;
  std::int32_t parent;
  Pixels pixels;
};

void expectObjects(const Detected& got, const std::vector<Expected>& expected) {
  ASSERT_EQ(got.objects.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(got.objects[i].level, expected[i].level);
    EXPECT_EQ(got.objects[i].number, expected[i].number);
    EXPECT_EQ(got.objects[i].parentNumber, expected[i].parent);
    EXPECT_EQ(got.objects[i].pixels, expected[i].pixels);
  }
}

// 8 x 4. Level thresholds 1, 4, 8. Components at level 1: A (7 px, top left), B (4 px, top
// right), C (one pixel of 3, bottom). A holds a 4-pixel level-2 object with one level-3 pixel;
// B likewise.
const ImageF kThreeLevels = rows(8, {2, 2, 0, 0, 0, 6, 6, 0,  //
                                     2, 5, 5, 0, 0, 6, 9, 0,  //
                                     0, 5, 9, 0, 0, 0, 0, 0,  //
                                     0, 0, 0, 0, 3, 0, 0, 0});

TEST(MultiThresholdDetector, ThreeLevelsByHand) {
  const Detected got = detect(kThreeLevels, settingsOf({1, 4, 8}, 1));
  expectObjects(got, {{1, 1, 0, {0, 1, 8, 9, 10, 17, 18}},
                      {2, 1, 1, {9, 10, 17, 18}},
                      {3, 1, 1, {18}},
                      {1, 2, 0, {5, 6, 13, 14}},
                      {2, 2, 2, {5, 6, 13, 14}},
                      {3, 2, 2, {14}},
                      {1, 3, 0, {28}}});
  EXPECT_EQ(got.perLevel, (std::vector<std::int64_t>{3, 2, 2}));
  EXPECT_EQ(got.callSizes, (std::vector<std::size_t>{3, 3, 1}));
}

TEST(MultiThresholdDetector, MinAreaDropsSmallObjectsButKeepsTheirPixelsInTheParent) {
  const Detected got = detect(kThreeLevels, settingsOf({1, 4, 8}, 2));
  // C (1 px) gives no sink call at all; the 1-pixel level-3 peaks are dropped, their pixels
  // remain in the level-2 objects.
  expectObjects(got, {{1, 1, 0, {0, 1, 8, 9, 10, 17, 18}},
                      {2, 1, 1, {9, 10, 17, 18}},
                      {1, 2, 0, {5, 6, 13, 14}},
                      {2, 2, 2, {5, 6, 13, 14}}});
  EXPECT_EQ(got.perLevel, (std::vector<std::int64_t>{2, 2, 0}));
  EXPECT_EQ(got.callSizes, (std::vector<std::size_t>{2, 2}));
}

TEST(MultiThresholdDetector, DiagonalPixelsAreConnected) {
  // A diagonal and an anti-diagonal touching only by corners: one object.
  const ImageF image = rows(5, {5, 0, 0, 0, 5,  //
                                0, 5, 0, 5, 0,  //
                                0, 0, 5, 0, 0,  //
                                0, 0, 0, 0, 0});
  const Detected got = detect(image, settingsOf({1}, 1));
  expectObjects(got, {{1, 1, 0, {0, 4, 6, 8, 12}}});
}

TEST(MultiThresholdDetector, PixelsEqualToTheThresholdStayOut) {
  const ImageF image = rows(4, {2, 2.0001f, 2, 3});
  const Detected got = detect(image, settingsOf({2, 3}, 1));
  // {2.0001} and {3} are separate at level 1 (the 2 between them is not above 2); nothing
  // exceeds 3.
  expectObjects(got, {{1, 1, 0, {1}}, {1, 2, 0, {3}}});
}

TEST(MultiThresholdDetector, ComparesInSinglePrecisionLikeSourceExtractor) {
  // 2.7 is not a float: (float)2.7 = 2.70000005 > 2.7 in double, yet source-extractor does not
  // detect a pixel of that value at DETECT_THRESH 2.7 (checked with source-extractor 2.25:
  // only the next float up is detected). See also SamePartitionAsSourceExtractor*.
  const float f = 2.7f;
  ImageF image(12, 3, 0.0f);
  image(1, 1) = f;
  image(5, 1) = std::nextafter(f, 10.0f);
  image(9, 1) = std::nextafter(f, 0.0f);
  expectObjects(detect(image, settingsOf({2.7}, 1)), {{1, 1, 0, {17}}});
}

TEST(MultiThresholdDetector, NonFinitePixelsNeverJoinAndSplitObjects) {
  const float inf = std::numeric_limits<float>::infinity();
  const ImageF image = rows(5, {5, 5, kNaNf, 5, 5,  //
                                0, 0, kNaNf, 0, inf});
  const Detected got = detect(image, settingsOf({1}, 1));
  expectObjects(got, {{1, 1, 0, {0, 1}}, {1, 2, 0, {3, 4}}});
}

TEST(MultiThresholdDetector, ChildSplitsIntoTwoAtHigherLevel) {
  // One level-1 object, two level-2 peaks; NUMBER of the peaks in raster order of first pixel.
  const ImageF image = rows(7, {0, 0, 0, 0, 0, 9, 0,  //
                                3, 9, 3, 3, 3, 9, 3,  //
                                3, 9, 3, 0, 0, 0, 0});
  const Detected got = detect(image, settingsOf({1, 5}, 1));
  expectObjects(got, {{1, 1, 0, {5, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16}},
                      {2, 1, 1, {5, 12}},
                      {2, 2, 1, {8, 15}}});
}

TEST(MultiThresholdDetector, ThresholdScaleMap) {
  const ImageF image = rows(4, {3, 3, 3, 3});
  ImageF scale = rows(4, {1, 0, 2, kNaNf});
  DetectionSettings settings = settingsOf({2, 5}, 1);
  settings.thresholdScale = &scale;
  // Pixel 0: 3 > 2*1 (level 1 only). Pixel 1: factor 0 -> never. Pixel 2: 3 > 4? no.
  // Pixel 3: NaN -> never.
  expectObjects(detect(image, settings), {{1, 1, 0, {0}}});
  scale = rows(4, {0.5f, 0.5f, -1, 0.1f});
  // Thresholds become 1, 1, -, 0.2 at level 1 and 2.5, 2.5, -, 0.5 at level 2.
  expectObjects(detect(image, settings),
                {{1, 1, 0, {0, 1}}, {2, 1, 1, {0, 1}}, {1, 2, 0, {3}}, {2, 2, 2, {3}}});
}

TEST(MultiThresholdDetector, EmptyAllNaNAndConstantImages) {
  EXPECT_TRUE(detect(ImageF(), settingsOf({1}, 1)).objects.empty());
  EXPECT_TRUE(detect(ImageF(6, 5, kNaNf), settingsOf({1, 2}, 1)).objects.empty());
  EXPECT_TRUE(detect(ImageF(6, 5, 1.0f), settingsOf({1, 2}, 1)).objects.empty());
  // A constant image above the lowest level is one object covering everything.
  const Detected got = detect(ImageF(3, 2, 1.5f), settingsOf({1, 2}, 1));
  expectObjects(got, {{1, 1, 0, {0, 1, 2, 3, 4, 5}}});
  EXPECT_EQ(got.perLevel, (std::vector<std::int64_t>{1, 0}));
}

std::string configError(const ImageF& image, const DetectionSettings& settings) {
  try {
    detectMultiThreshold(image, settings, [](std::vector<Segment>&) {});
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(MultiThresholdDetector, RejectsBadSettings) {
  const ImageF image(4, 4, 0.0f);
  EXPECT_EQ(configError(image, settingsOf({}, 5)), "DETECT_THRESH: no detection threshold given");
  EXPECT_EQ(configError(image, settingsOf({1, 2, 2}, 5)).rfind("DETECT_THRESH: levels must", 0),
            0u);
  EXPECT_EQ(configError(image, settingsOf({2, 1}, 5)).rfind("DETECT_THRESH: levels must", 0), 0u);
  EXPECT_EQ(configError(image, settingsOf({1, std::nan("")}, 5)),
            "DETECT_THRESH: level 2 is not finite");
  EXPECT_EQ(configError(image, settingsOf({1}, 0)), "DETECT_MINAREA: must be at least 1, got 0");
  std::vector<double> many(256);
  std::iota(many.begin(), many.end(), 1.0);
  EXPECT_EQ(configError(image, settingsOf(many, 1)).rfind("DETECT_NLEVELS:", 0), 0u);
  const ImageF scale(4, 3, 1.0f);
  DetectionSettings s = settingsOf({1}, 1);
  s.thresholdScale = &scale;
  EXPECT_EQ(configError(image, s),
            "WEIGHT_IMAGE: threshold map is 4x3 but the detection image is 4x4");
}

// ---------------------------------------------------------------------------------------------
// Random images against a naive per-level flood fill.

// Components (8-connected, >= minArea pixels) of {f > t * scale}, each as an ascending pixel
// list, sorted.
std::vector<Pixels> naiveComponents(const ImageF& image, const ImageF* scale, double t,
                                    int minArea) {
  const std::int64_t w = image.width();
  const std::int64_t h = image.height();
  // Single precision, as SExtractor compares.
  const auto tf = static_cast<float>(t);
  auto above = [&](std::int64_t i) {
    const float f = image[i];
    if (!std::isfinite(f)) return false;
    if (scale == nullptr) return f > tf;
    const float s = (*scale)[i];
    return s > 0 && f > tf * s;
  };
  std::vector<char> seen(static_cast<std::size_t>(image.size()), 0);
  std::vector<Pixels> out;
  for (std::int64_t start = 0; start < image.size(); ++start) {
    if (seen[start] || !above(start)) continue;
    Pixels comp;
    std::vector<std::int64_t> stack{start};
    seen[start] = 1;
    while (!stack.empty()) {
      const std::int64_t p = stack.back();
      stack.pop_back();
      comp.push_back(p);
      const std::int64_t px = p % w;
      const std::int64_t py = p / w;
      for (std::int64_t dy = -1; dy <= 1; ++dy) {
        for (std::int64_t dx = -1; dx <= 1; ++dx) {
          const std::int64_t nx = px + dx;
          const std::int64_t ny = py + dy;
          if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
          const std::int64_t n = ny * w + nx;
          if (!seen[n] && above(n)) {
            seen[n] = 1;
            stack.push_back(n);
          }
        }
      }
    }
    if (static_cast<int>(comp.size()) >= minArea) {
      std::sort(comp.begin(), comp.end());
      out.push_back(std::move(comp));
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

// Smoothed noise (box-summed) with some NaNs: components of all sizes and nested structure.
ImageF randomImage(std::int64_t w, std::int64_t h, std::uint32_t seed, double nanFraction) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> noise(0.0f, 1.0f);
  ImageF white(w, h);
  for (float& v : white.pixels()) v = noise(rng);
  const ConvKernel box{3, 3, {1, 1, 1, 1, 1, 1, 1, 1, 1}};
  ImageF image = applyFilter(white, box);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (float& v : image.pixels()) {
    if (u(rng) < nanFraction) v = kNaNf;
  }
  return image;
}

void checkAgainstNaive(const ImageF& image, const ImageF* scale,
                       const std::vector<double>& thresholds, int minArea) {
  DetectionSettings settings = settingsOf(thresholds, minArea);
  settings.thresholdScale = scale;
  const Detected got = detect(image, settings);
  const int levels = static_cast<int>(thresholds.size());

  std::map<std::pair<int, std::int32_t>, const Segment*> byKey;
  std::vector<std::vector<Pixels>> perLevel(levels);
  for (const Segment& s : got.objects) {
    ASSERT_GE(s.level, 1);
    ASSERT_LE(s.level, levels);
    ASSERT_TRUE(std::is_sorted(s.pixels.begin(), s.pixels.end()));
    ASSERT_TRUE(byKey.emplace(std::make_pair(s.level, s.number), &s).second) << "duplicate";
    perLevel[s.level - 1].push_back(s.pixels);
  }
  for (int k = 0; k < levels; ++k) {
    SCOPED_TRACE("level " + std::to_string(k + 1));
    // NUMBER runs 1..N within each level.
    for (std::int32_t n = 1; n <= static_cast<std::int32_t>(perLevel[k].size()); ++n) {
      EXPECT_TRUE(byKey.count({k + 1, n}));
    }
    EXPECT_EQ(got.perLevel[k], static_cast<std::int64_t>(perLevel[k].size()));
    // Same partition as the naive flood fill: this also says the objects cover exactly the
    // above-threshold pixels of components with >= minArea pixels.
    std::sort(perLevel[k].begin(), perLevel[k].end());
    const std::vector<Pixels> naive = naiveComponents(image, scale, thresholds[k], minArea);
    EXPECT_EQ(perLevel[k], naive);
  }
  // Every object lies inside its parent.
  for (const Segment& s : got.objects) {
    if (s.level == 1) {
      EXPECT_EQ(s.parentNumber, 0);
      continue;
    }
    const auto it = byKey.find({s.level - 1, s.parentNumber});
    ASSERT_NE(it, byKey.end()) << "missing parent";
    const Pixels& parent = it->second->pixels;
    EXPECT_TRUE(std::includes(parent.begin(), parent.end(), s.pixels.begin(), s.pixels.end()));
  }
  // One sink call per level-1 object, holding that object first.
  std::size_t at = 0;
  for (std::size_t size : got.callSizes) {
    ASSERT_LT(at, got.objects.size());
    EXPECT_EQ(got.objects[at].level, 1);
    for (std::size_t i = at + 1; i < at + size; ++i) {
      EXPECT_GE(got.objects[i].level, got.objects[i - 1].level);
      EXPECT_GT(got.objects[i].level, 1);
    }
    at += size;
  }
  EXPECT_EQ(at, got.objects.size());
}

TEST(MultiThresholdDetector, RandomImagesMatchNaiveFloodFillAtEveryLevel) {
  const std::vector<double> thresholds = {0.5, 1.5, 2.5, 3.5, 4.5, 6.0};
  std::uint32_t seed = 100;
  for (const auto& [w, h] :
       std::vector<std::pair<int, int>>{{97, 83}, {1, 60}, {60, 1}, {2, 2}, {256, 200}}) {
    for (int minArea : {1, 3, 7}) {
      SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h) + " minArea " +
                   std::to_string(minArea));
      const ImageF image = randomImage(w, h, ++seed, 0.01);
      checkAgainstNaive(image, nullptr, thresholds, minArea);
    }
  }
}

TEST(MultiThresholdDetector, RandomImagesWithThresholdScaleMatchNaive) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-0.2f, 2.0f);
  const ImageF image = randomImage(120, 90, 77, 0.005);
  ImageF scale(120, 90);
  for (float& v : scale.pixels()) v = u(rng);  // includes factors <= 0
  scale[5] = kNaNf;
  checkAgainstNaive(image, &scale, {0.8, 1.6, 3.2}, 2);
}

void expectSameOutput(const Detected& a, const Detected& b) {
  ASSERT_EQ(a.objects.size(), b.objects.size());
  EXPECT_EQ(a.callSizes, b.callSizes);
  EXPECT_EQ(a.perLevel, b.perLevel);
  for (std::size_t i = 0; i < a.objects.size(); ++i) {
    ASSERT_EQ(a.objects[i].level, b.objects[i].level);
    ASSERT_EQ(a.objects[i].number, b.objects[i].number);
    ASSERT_EQ(a.objects[i].parentNumber, b.objects[i].parentNumber);
    ASSERT_EQ(a.objects[i].pixels, b.objects[i].pixels);
  }
}

TEST(MultiThresholdDetector, OutputIndependentOfThreadCount) {
  // Large enough for several row bands and many parallel tasks.
  const ImageF image = randomImage(700, 650, 2024, 0.001);
  const std::vector<double> thresholds = {1.0, 1.8, 2.6, 3.4, 4.2, 5.0, 6.0, 7.0};
  const Detected one = detect(image, settingsOf(thresholds, 3, 1));
  ASSERT_GT(one.callSizes.size(), 1000u);
  expectSameOutput(one, detect(image, settingsOf(thresholds, 3, 2)));
  expectSameOutput(one, detect(image, settingsOf(thresholds, 3, 5)));
  expectSameOutput(one, detect(image, settingsOf(thresholds, 3, 0)));  // all hardware threads
}

// Footprints as runs: the same objects, the runs covering exactly the pixel list, in raster
// order, and SegmentationRuns renders the same images from either form.
TEST(MultiThresholdDetector, FootprintRunsHoldTheSamePixels) {
  const ImageF image = randomImage(300, 280, 77, 0.002);
  const std::vector<double> thresholds = {1.0, 1.8, 2.6, 3.4, 5.0};
  const Detected pixels = detect(image, settingsOf(thresholds, 3, 2));
  DetectionSettings runSettings = settingsOf(thresholds, 3, 2);
  runSettings.footprintRuns = true;
  const Detected runs = detect(image, runSettings);
  ASSERT_GT(pixels.objects.size(), 100u);
  ASSERT_EQ(runs.objects.size(), pixels.objects.size());
  EXPECT_EQ(runs.perLevel, pixels.perLevel);
  SegmentationRuns fromPixels(300, 280, 5), fromRuns(300, 280, 5);
  for (std::size_t i = 0; i < runs.objects.size(); ++i) {
    const Segment& r = runs.objects[i];
    const Segment& p = pixels.objects[i];
    ASSERT_EQ(r.number, p.number);
    ASSERT_EQ(r.parentNumber, p.parentNumber);
    EXPECT_TRUE(r.pixels.empty());
    EXPECT_EQ(r.pixelCount(), std::int64_t(p.pixels.size()));
    Pixels expanded;
    r.forEachIndex(300, [&](std::int64_t q) { expanded.push_back(q); });
    ASSERT_EQ(expanded, p.pixels) << "object " << i;
    for (std::size_t k = 1; k < r.runs.size(); ++k) {
      const PixelRun& a = r.runs[k - 1];
      const PixelRun& b = r.runs[k];
      ASSERT_TRUE(a.y < b.y || (a.y == b.y && a.x1 + 1 < b.x0)) << "object " << i;
    }
  }
  fromPixels.add(pixels.objects);
  fromRuns.add(runs.objects);
  ImageI32 a, b;
  for (int level = 1; level <= 5; ++level) {
    fromPixels.render(level, a);
    fromRuns.render(level, b);
    ASSERT_EQ(labelsOf(a), labelsOf(b)) << "level " << level;
  }
}

TEST(MultiThresholdDetector, SinkExceptionPropagatesFromWorkers) {
  const ImageF image = randomImage(300, 300, 9, 0.0);
  int calls = 0;
  EXPECT_THROW(detectMultiThreshold(image, settingsOf({1.0, 2.0}, 2, 2),
                                    [&](std::vector<Segment>&) {
                                      if (++calls == 50) throw IoError("sink failed");
                                    }),
               IoError);
  EXPECT_EQ(calls, 50);
}

// ---------------------------------------------------------------------------------------------
// SegmentationRuns

TEST(SegmentationRuns, RendersEachLevelFromOneBuffer) {
  SegmentationRuns runs(8, 4, 3);
  detectMultiThreshold(kThreeLevels, settingsOf({1, 4, 8}, 1),
                       [&](std::vector<Segment>& objs) { runs.add(objs); });
  ImageI32 buffer;
  runs.render(1, buffer);
  const std::vector<std::int32_t> level1 = {1, 1, 0, 0, 0, 2, 2, 0,  //
                                            1, 1, 1, 0, 0, 2, 2, 0,  //
                                            0, 1, 1, 0, 0, 0, 0, 0,  //
                                            0, 0, 0, 0, 3, 0, 0, 0};
  EXPECT_EQ(labelsOf(buffer), level1);
  const std::int32_t* before = buffer.data();
  runs.render(3, buffer);
  EXPECT_EQ(buffer.data(), before);  // the same buffer, reused
  std::vector<std::int32_t> level3(32, 0);
  level3[18] = 1;
  level3[14] = 2;
  EXPECT_EQ(labelsOf(buffer), level3);
  EXPECT_EQ(runs.runCount(1), 6u);  // one per row: A 3, B 2, C 1
}

TEST(SegmentationRuns, UnsortedPixelListsAndBadLevels) {
  SegmentationRuns runs(3, 2, 1);
  Segment s;
  s.number = 4;
  s.pixels = {5, 2, 3, 4};  // (2,0) and (0,1),(1,1),(2,1): the row break splits the runs
  runs.add({s});
  EXPECT_EQ(runs.runCount(1), 2u);
  ImageI32 buffer(3, 2, 77);
  runs.render(1, buffer);
  EXPECT_EQ(labelsOf(buffer), (std::vector<std::int32_t>{0, 0, 4, 4, 4, 4}));
  EXPECT_THROW(runs.render(2, buffer), ConfigError);
  s.level = 2;
  EXPECT_THROW(runs.add({s}), ConfigError);
}

// ---------------------------------------------------------------------------------------------
// Against source-extractor: at each threshold, the same partition as its SEGMENTATION map.

// True if the two label images define the same objects (a bijection between labels).
::testing::AssertionResult samePartition(const ImageI32& a, const ImageI32& b) {
  if (a.size() != b.size()) return ::testing::AssertionFailure() << "sizes differ";
  std::map<std::int32_t, std::int32_t> ab, ba;
  for (std::int64_t i = 0; i < a.size(); ++i) {
    if ((a[i] == 0) != (b[i] == 0)) {
      return ::testing::AssertionFailure()
             << "pixel " << i << ": " << a[i] << " vs " << b[i] << " (one is background)";
    }
    if (a[i] == 0) continue;
    const auto [ia, newA] = ab.emplace(a[i], b[i]);
    const auto [ib, newB] = ba.emplace(b[i], a[i]);
    if (ia->second != b[i] || ib->second != a[i]) {
      return ::testing::AssertionFailure() << "pixel " << i << ": labels " << a[i] << " and "
                                           << b[i] << " are not matched one to one";
    }
  }
  return ::testing::AssertionSuccess() << ab.size() << " objects";
}

void comparePartitionWithSourceExtractor(bool filter) {
  const auto dir = test::scratchDir();
  std::mt19937 rng(31);
  std::normal_distribution<float> noise(0.0f, 1.0f);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const std::int64_t w = 160;
  const std::int64_t h = 120;
  ImageF image(w, h);
  for (float& v : image.pixels()) v = noise(rng);
  for (int s = 0; s < 40; ++s) {
    const double cx = u(rng) * w;
    const double cy = u(rng) * h;
    const double sigma = 0.8 + 2.5 * u(rng);
    const double peak = 3.0 + 60.0 * u(rng) * u(rng);
    for (std::int64_t y = 0; y < h; ++y) {
      for (std::int64_t x = 0; x < w; ++x) {
        const double r2 = (x - cx) * (x - cx) + (y - cy) * (y - cy);
        image(x, y) += static_cast<float>(peak * std::exp(-r2 / (2 * sigma * sigma)));
      }
    }
  }
  test::writeFloatFits(dir / "img.fits", image);

  const std::vector<double> thresholds = {2.0, 3.7, 7.5, 15.0};
  const int minArea = 4;
  ImageF detection = image;
  if (filter) {
    detection = applyFilter(image, test::defaultConvKernel());
  }
  SegmentationRuns runs(w, h, static_cast<int>(thresholds.size()));
  const auto perLevel = detectMultiThreshold(detection, settingsOf(thresholds, minArea, 2),
                                             [&](std::vector<Segment>& objs) { runs.add(objs); });
  ImageI32 ours;
  for (std::size_t k = 0; k < thresholds.size(); ++k) {
    SCOPED_TRACE("threshold " + std::to_string(thresholds[k]));
    const std::string seg = "seg" + std::to_string(k + 1) + ".fits";
    const std::string filterOptions =
        filter ? "-FILTER Y -FILTER_NAME /usr/share/source-extractor/default.conv" : "-FILTER N";
    ASSERT_EQ(test::runSourceExtractor(
                  dir, "img.fits",
                  filterOptions +
                      " -DEBLEND_NTHRESH 1 -CLEAN N -THRESH_TYPE ABSOLUTE"
                      " -BACK_TYPE MANUAL -BACK_VALUE 0 -DETECT_MINAREA " +
                      std::to_string(minArea) + " -DETECT_THRESH " + std::to_string(thresholds[k]) +
                      " -ANALYSIS_THRESH " + std::to_string(thresholds[k]) +
                      " -CHECKIMAGE_TYPE SEGMENTATION -CHECKIMAGE_NAME " + seg),
              0);
    const ImageI32 reference = test::readFits<std::int32_t>(dir / seg);
    runs.render(static_cast<int>(k) + 1, ours);
    EXPECT_TRUE(samePartition(ours, reference));
    std::int32_t maxLabel = 0;
    for (std::int32_t v : reference.pixels()) maxLabel = std::max(maxLabel, v);
    EXPECT_EQ(perLevel[k], maxLabel);
  }
  EXPECT_GT(perLevel[0], 10);
  EXPECT_GT(perLevel[3], 3);
}

// The real NTT/EMMI image, background 6850 ADU subtracted as a constant (noise ~65 ADU), five
// levels from ~2.5 to ~20 sigma, with and without default.conv: every level is the partition of
// a separate source-extractor run at that threshold.
void compareOnRealImage(const std::filesystem::path& data, bool filter) {
  const auto dir = test::scratchDir();
  const std::string path = (data / "ntt-emmi" / "galaxies.fits").string();
  const ImageF raw = readImage(path).pixels;
  ImageF detection = raw;
  for (float& v : detection.pixels()) v -= 6850.0f;
  if (filter) {
    detection = applyFilter(detection, test::defaultConvKernel(), 2);
  }
  const std::vector<double> thresholds = {162.5, 270.0, 433.3, 780.0, 1300.0};
  const int minArea = 5;
  SegmentationRuns runs(raw.width(), raw.height(), static_cast<int>(thresholds.size()));
  const auto perLevel = detectMultiThreshold(detection, settingsOf(thresholds, minArea, 2),
                                             [&](std::vector<Segment>& objs) { runs.add(objs); });
  ImageI32 ours;
  for (std::size_t k = 0; k < thresholds.size(); ++k) {
    SCOPED_TRACE("threshold " + std::to_string(thresholds[k]));
    const std::string seg = "seg" + std::to_string(k + 1) + ".fits";
    const std::string filterOptions =
        filter ? "-FILTER Y -FILTER_NAME /usr/share/source-extractor/default.conv" : "-FILTER N";
    ASSERT_EQ(test::runSourceExtractor(
                  dir, "'" + path + "'",
                  filterOptions +
                      " -DEBLEND_NTHRESH 1 -CLEAN N -THRESH_TYPE ABSOLUTE -BACK_TYPE MANUAL"
                      " -BACK_VALUE 6850 -DETECT_MINAREA " +
                      std::to_string(minArea) + " -DETECT_THRESH " + std::to_string(thresholds[k]) +
                      " -ANALYSIS_THRESH " + std::to_string(thresholds[k]) +
                      " -MEMORY_PIXSTACK 3000000 -MEMORY_OBJSTACK 30000 -MEMORY_BUFSIZE 2048"
                      " -CHECKIMAGE_TYPE SEGMENTATION -CHECKIMAGE_NAME " +
                      seg),
              0);
    const ImageI32 reference = test::readFits<std::int32_t>(dir / seg);
    runs.render(static_cast<int>(k) + 1, ours);
    EXPECT_TRUE(samePartition(ours, reference));
    std::int32_t maxLabel = 0;
    for (std::int32_t v : reference.pixels()) maxLabel = std::max(maxLabel, v);
    EXPECT_EQ(perLevel[k], maxLabel);
  }
  std::printf("galaxies.fits, FILTER %s: objects per level", filter ? "Y" : "N");
  for (std::int64_t n : perLevel) std::printf(" %lld", static_cast<long long>(n));
  std::printf("\n");
  EXPECT_GT(perLevel[0], 100);
}

TEST(MultiThresholdDetector, SamePartitionAsSourceExtractorOnRealImage) {
  OCTARC_REQUIRE_SHARED_DATA(data);
  OCTARC_REQUIRE_SOURCE_EXTRACTOR();
  compareOnRealImage(data, false);
  compareOnRealImage(data, true);
}

TEST(MultiThresholdDetector, SamePartitionAsSourceExtractorFilterN) {
  OCTARC_REQUIRE_SOURCE_EXTRACTOR();
  comparePartitionWithSourceExtractor(false);
}

TEST(MultiThresholdDetector, SamePartitionAsSourceExtractorFilterY) {
  OCTARC_REQUIRE_SOURCE_EXTRACTOR();
  comparePartitionWithSourceExtractor(true);
}

}  // namespace
}  // namespace octarc
