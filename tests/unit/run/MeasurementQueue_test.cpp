// Measuring on worker threads while objects keep coming: every row is filled exactly as a
// direct measurement fills it, whatever the number of threads, and huge objects do not block.
#include "octarc/run/MeasurementQueue.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "octarc/core/Table.h"

namespace octarc {
namespace {

MeasurementPlan planOf(const std::vector<std::string>& names) {
  std::vector<ColumnRequest> requests;
  for (const std::string& n : names) requests.push_back({n, 1});
  return MeasurementPlan::build(requests, {}, nullptr);
}

// Random blocks of pixels on a random image: many small objects and a few large ones.
std::vector<Segment> randomSegments(const ImageF& image, int count, std::mt19937& rng) {
  std::vector<Segment> out;
  std::uniform_int_distribution<int> side(1, 12);
  for (int k = 0; k < count; ++k) {
    Segment s;
    s.number = k + 1;
    const int w = (k % 97 == 0) ? 150 : side(rng), h = (k % 97 == 0) ? 150 : side(rng);
    std::uniform_int_distribution<int> x0(0, int(image.width()) - w);
    std::uniform_int_distribution<int> y0(0, int(image.height()) - h);
    const int x = x0(rng), y = y0(rng);
    for (int j = y; j < y + h; ++j) {
      for (int i = x; i < x + w; ++i) s.pixels.push_back(std::int64_t(j) * image.width() + i);
    }
    out.push_back(std::move(s));
  }
  return out;
}

TEST(MeasurementQueue, RowsEqualDirectMeasurementForAnyThreadCount) {
  std::mt19937 rng(7);
  ImageF image(200, 180);
  std::uniform_real_distribution<float> value(0.5f, 100.0f);
  for (float& v : image.pixels()) v = value(rng);
  MeasureContext context;
  context.measurement = &image;
  context.detection = &image;
  context.sigmaAdu = 2.0;
  const MeasurementPlan plan =
      planOf({"NUMBER", "X_IMAGE", "Y_IMAGE", "X2_IMAGE", "FLUX_ISO", "ARCNESS", "I_AAA_IMAGE"});
  const std::vector<Segment> segments = randomSegments(image, 3000, rng);

  Table expected(plan.columns());
  for (const Segment& s : segments) plan.measure(s, context, expected.appendRow());

  for (int threads : {1, 2, 5}) {
    Table table(plan.columns());
    {
      MeasurementQueue queue(plan, context, threads);
      for (Segment s : segments) queue.add(std::move(s), table.appendRow());
      queue.finish();
    }
    ASSERT_EQ(table.rows(), expected.rows());
    for (std::int64_t r = 0; r < table.rows(); ++r) {
      for (int c = 0; c < table.rowWidth(); ++c) {
        const double a = table.row(r)[c], b = expected.row(r)[c];
        ASSERT_TRUE(a == b || (std::isnan(a) && std::isnan(b)))
            << "threads " << threads << " row " << r << " value " << c;
      }
    }
  }
}

// finish() with nothing queued returns at once (a hang would stop the test at ctest's timeout),
// touches no row and leaves the queue working: an object added afterwards is measured into its
// row by the next finish(), whether measured in add() (1 thread) or on the workers.
TEST(MeasurementQueue, FinishWithNothingQueuedReturns) {
  ImageF image(4, 4, 1.0f);
  MeasureContext context;
  context.measurement = &image;
  context.detection = &image;
  const MeasurementPlan plan = planOf({"NUMBER", "FLUX_ISO"});
  for (int threads : {1, 2}) {
    Table table(plan.columns());
    double* untouched = table.appendRow();
    untouched[0] = -7.0;
    untouched[1] = -8.0;
    MeasurementQueue queue(plan, context, threads);
    queue.finish();
    queue.finish();
    EXPECT_EQ(table.row(0)[0], -7.0) << "threads " << threads;
    EXPECT_EQ(table.row(0)[1], -8.0) << "threads " << threads;
    Segment s;
    s.number = 5;
    for (std::int64_t p = 0; p < 3; ++p) s.pixels.push_back(p);
    queue.add(std::move(s), table.appendRow());
    queue.finish();
    ASSERT_EQ(table.rows(), 2);
    EXPECT_EQ(table.row(1)[0], 5.0) << "threads " << threads;
    EXPECT_EQ(table.row(1)[1], 3.0) << "threads " << threads;  // three pixels of 1
    EXPECT_EQ(table.row(0)[0], -7.0) << "threads " << threads;
  }
}

}  // namespace
}  // namespace octarc
