#include "octarc/search/CandidateName.h"

#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>

namespace octarc {
namespace {

// 150.1 degrees = 10.006667 h = 10h 00m 24s; 2.2 degrees = 2d 12' 00".
TEST(CandidateName, SexagesimalByHand) {
  EXPECT_EQ(formatRaSexagesimal(150.1), "10:00:24.00");
  EXPECT_EQ(formatDecSexagesimal(2.2), "+02:12:00.0");
  EXPECT_EQ(formatDecSexagesimal(-0.5), "-00:30:00.0");
  EXPECT_EQ(formatRaSexagesimal(-15.0), "23:00:00.00");
  EXPECT_EQ(formatRaSexagesimal(53.16250, 3), "03:32:39.000");
  EXPECT_EQ(formatDecSexagesimal(-27.79139, 2), "-27:47:29.00");
  EXPECT_EQ(formatRaSexagesimal(12.5, 0), "00:50:00");
}

TEST(CandidateName, RoundingCarriesIntoMinutesHoursAndDegrees) {
  // 23h 59m 59.9999s rounds to 24h: 00:00:00.00.
  EXPECT_EQ(formatRaSexagesimal(360.0 - 0.0001 / 3600.0 * 15.0), "00:00:00.00");
  EXPECT_EQ(formatDecSexagesimal(10.0 + 59.0 / 60.0 + 59.96 / 3600.0), "+11:00:00.0");
  EXPECT_EQ(formatDecSexagesimal(-(10.0 + 59.0 / 60.0 + 59.96 / 3600.0)), "-11:00:00.0");
}

// Designations truncate: 24.009 s stays 24.00, 00.09" stays 00.0.
TEST(CandidateName, IauDesignationTruncates) {
  EXPECT_EQ(iauDesignation("OCTARC", 150.1, 2.2), "OCTARC J100024.00+021200.0");
  EXPECT_EQ(iauDesignation("", 150.1 + 0.009 * 15.0 / 3600.0, -(2.2 + 0.09 / 3600.0)),
            "J100024.00-021200.0");
  EXPECT_EQ(iauDesignation("X", 360.0 - 0.0001 / 3600.0 * 15.0, 89.99999), "X J235959.99+895959.9");
}

TEST(CandidateName, NonFinitePositionsAndBadDecimals) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(formatRaSexagesimal(nan), "NaN");
  EXPECT_EQ(formatDecSexagesimal(nan), "NaN");
  EXPECT_EQ(iauDesignation("OCTARC", 150.0, nan), "OCTARC NaN");
  EXPECT_THROW(formatRaSexagesimal(150.0, 10), std::invalid_argument);
  EXPECT_THROW(formatDecSexagesimal(2.0, -1), std::invalid_argument);
}

}  // namespace
}  // namespace octarc
