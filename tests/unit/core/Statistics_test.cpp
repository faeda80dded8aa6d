// Sample quantiles against hand-computed values of the type-7 definition.
#include "octarc/core/Statistics.h"

#include <gtest/gtest.h>

#include <cmath>

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
