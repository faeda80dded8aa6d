// Sample quantiles against hand-computed values of the type-7 definition.
#include "octarc/core/Statistics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace octarc {
namespace {

TEST(Statistics, QuantilesInterpolateBetweenOrderStatistics) {
  const std::vector<double> v = {4.0, 1.0, 3.0, 2.0};  // sorted 1 2 3 4, h = q * 3
  EXPECT_DOUBLE_EQ(sampleQuantile(v, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(sampleQuantile(v, 0.2), 1.6);  // h = 0.6
  EXPECT_DOUBLE_EQ(sampleMedian(v), 2.5);         // h = 1.5
  EXPECT_DOUBLE_EQ(sampleQuantile(v, 0.8), 3.4);  // h = 2.4
  EXPECT_DOUBLE_EQ(sampleQuantile(v, 1.0), 4.0);
  EXPECT_DOUBLE_EQ(sampleMedian({5.0, 1.0, 3.0}), 3.0);
}

TEST(Statistics, SeveralQuantilesAtOnceAreTheSingleOnes) {
  const std::vector<double> v = {4.0, 1.0, 3.0, 2.0, NAN};
  const std::vector<double> q = sampleQuantiles(v, {0.2, 0.5, 0.8});
  ASSERT_EQ(q.size(), 3u);
  EXPECT_DOUBLE_EQ(q[0], 1.6);
  EXPECT_DOUBLE_EQ(q[1], 2.5);
  EXPECT_DOUBLE_EQ(q[2], 3.4);
  EXPECT_TRUE(std::isnan(sampleQuantiles({}, {0.5}).front()));
}

TEST(Statistics, NonFiniteValuesAreLeftOut) {
  const double nan = std::nan("");
  EXPECT_DOUBLE_EQ(sampleMedian({nan, 2.0, INFINITY, 4.0}), 3.0);
  EXPECT_TRUE(std::isnan(sampleMedian({})));
  EXPECT_TRUE(std::isnan(sampleQuantile({nan}, 0.2)));
  EXPECT_DOUBLE_EQ(sampleQuantile({7.0}, 0.8), 7.0);
}

}  // namespace
}  // namespace octarc

namespace octarc {
namespace {

// A few quantiles are found by selection, more by a sort: the same values either way.
TEST(Statistics, SelectionAndSortGiveTheSameQuantiles) {
  std::vector<double> v;
  std::uint64_t x = 12345;
  for (int i = 0; i < 1001; ++i) {
    x = x * 6364136223846793005ULL + 1442695040888963407ULL;
    v.push_back(double(x >> 11) / double(1ULL << 53));
  }
  v.push_back(std::nan(""));
  const std::vector<double> few = sampleQuantiles(v, {0.1587, 0.5, 0.997});
  const std::vector<double> many = sampleQuantiles(v, {0.1587, 0.5, 0.997, 0.25, 0.75});
  for (std::size_t i = 0; i < few.size(); ++i) EXPECT_EQ(few[i], many[i]);
  std::vector<double> sorted(v.begin(), v.end() - 1);
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(few[1], sorted[500]);
}

// Hand-computed from the formula at z = 1. 3 of 10: p = 0.3, centre = (0.3 + 0.05) / 1.1,
// half = sqrt(0.021 + 0.0025) / 1.1 = 0.153297 / 1.1, so [0.178821, 0.457543].
TEST(Statistics, WilsonIntervalOfThreeInTen) {
  const ProportionInterval i = wilsonInterval(3, 10, 1.0);
  EXPECT_NEAR(i.low, 0.178821, 1e-6);
  EXPECT_NEAR(i.high, 0.457543, 1e-6);
}

// 0 of 5: centre = 0.1 / 1.2 = 1/12 = half, so [0, 1/6]; 5 of 5 mirrors it: [5/6, 1].
// 2 of 4 at z = 2: centre 0.5, half = 2 sqrt(0.0625 + 0.0625) / 2 = 0.353553.
TEST(Statistics, WilsonIntervalAtTheEdgesAndOtherZ) {
  EXPECT_NEAR(wilsonInterval(0, 5).low, 0.0, 1e-15);
  EXPECT_NEAR(wilsonInterval(0, 5).high, 1.0 / 6.0, 1e-15);
  EXPECT_NEAR(wilsonInterval(5, 5).low, 5.0 / 6.0, 1e-15);
  EXPECT_NEAR(wilsonInterval(5, 5).high, 1.0, 1e-15);
  EXPECT_NEAR(wilsonInterval(2, 4, 2.0).low, 0.5 - 0.353553, 1e-6);
  EXPECT_NEAR(wilsonInterval(2, 4, 2.0).high, 0.5 + 0.353553, 1e-6);
  // No trial: nothing is known.
  EXPECT_EQ(wilsonInterval(0, 0).low, 0.0);
  EXPECT_EQ(wilsonInterval(0, 0).high, 1.0);
}

}  // namespace
}  // namespace octarc
