// Binning conventions, filling, normalisation, order, contours and sparse storage of the
// occupation grid, on hand-made point sets whose numbers are worked out in the comments.
#include "octarc/selection/OccupationGrid.h"

#include <gtest/gtest.h>
#include <malloc.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <map>
#include <random>
#include <vector>

#include "SelectionTestSupport.h"
#include "octarc/core/Conventions.h"
#include "octarc/core/Error.h"

// AddressSanitizer's allocator statistics (libasan exports it; GCC ships no header for it). Weak:
// null unless the executable is linked with the sanitizer runtime, as in the sanitizer tree,
// where the test code itself is not instrumented.
extern "C" std::size_t __sanitizer_get_current_allocated_bytes() __attribute__((weak));

namespace octarc {
namespace {

using test::expectError;

GridAxis axis(const char* expression, double lo, double hi, int bins) {
  return GridAxis{expression, lo, hi, bins};
}

TEST(GridBinning, BinsAreHalfOpen) {
  const GridBinning b({axis("X", 0.0, 1.0, 4)});  // bins of 0.25
  EXPECT_EQ(b.binOf(0, 0.0), 0);
  EXPECT_EQ(b.binOf(0, 0.2499), 0);
  EXPECT_EQ(b.binOf(0, 0.25), 1);  // a lower edge belongs to its bin
  EXPECT_EQ(b.binOf(0, 0.75), 3);
  EXPECT_EQ(b.binOf(0, std::nextafter(1.0, 0.0)), 3);
  EXPECT_EQ(b.binOf(0, 1.0), -1);  // hi is excluded
  EXPECT_EQ(b.binOf(0, -1e-12), -1);
  EXPECT_EQ(b.binOf(0, kNaN), -1);
  const GridBinning shifted({axis("X", -2.0, 2.0, 8)});  // bins of 0.5 from -2
  EXPECT_EQ(shifted.binOf(0, -2.0), 0);
  EXPECT_EQ(shifted.binOf(0, -0.5), 3);
  EXPECT_EQ(shifted.binOf(0, 0.0), 4);
  EXPECT_EQ(shifted.binOf(0, 1.99), 7);
}

TEST(GridBinning, PackedIndexRunsFastestAlongTheFirstAxis) {
  const GridBinning b({axis("X", 0, 1, 4), axis("Y", 0, 1, 3), axis("Z", 0, 1, 2)});
  EXPECT_EQ(b.totalBins(), 24u);
  // (1, 2, 1) -> 1 + 4 (2 + 3 * 1) = 21.
  const std::vector<int> k = {1, 2, 1};
  EXPECT_EQ(b.pack(k), 21u);
  EXPECT_EQ(b.unpack(21), k);
  EXPECT_EQ(b.indexAlong(21, 1), 2);
  EXPECT_EQ(b.neighbour(21, 0, -1), std::optional<BinIndex>(20));
  EXPECT_EQ(b.neighbour(21, 0, +1), std::optional<BinIndex>(22));
  EXPECT_EQ(b.neighbour(21, 1, -1), std::optional<BinIndex>(17));
  EXPECT_EQ(b.neighbour(21, 1, +1), std::nullopt);  // Y index 2 is the last
  EXPECT_EQ(b.neighbour(21, 2, -1), std::optional<BinIndex>(9));
  EXPECT_EQ(b.neighbour(21, 2, +1), std::nullopt);
  // (3, 0, 0) = 3 and (0, 1, 0) = 4 are consecutive indices but not neighbours.
  EXPECT_EQ(b.neighbour(3, 0, +1), std::nullopt);
  EXPECT_EQ(b.withBins(5).totalBins(), 125u);
  EXPECT_EQ(defaultAxisExpressions(),
            (std::vector<std::string>{"ARCNESS", "ANTIARCNESS", "SKEW_MAJOR", "SKEW_MINOR",
                                      "E_IMAGE", "log10(SNR_ISO)"}));
}

TEST(GridBinning, BadAxesAreConfigErrors) {
  expectError<ConfigError>([] { GridBinning({}); }, {"at least one axis"});
  expectError<ConfigError>([] { GridBinning({axis("X", 1, 1, 4)}); },
                           {"grid axis 1 (X)", "lo < hi"});
  expectError<ConfigError>(
      [] {
        GridBinning({axis("X", 0, 1, 2), axis("Y", 0, kNaN, 2)});
      },
      {"grid axis 2 (Y)", "not a finite range"});
  expectError<ConfigError>([] { GridBinning({axis("X", 0, 1, 0)}); }, {"0 bins"});
  expectError<ConfigError>([] { GridBinning({axis("", 0, 1, 2)}); }, {"has no expression"});
  // 4 axes of 2^16 bins are 2^64 bins.
  expectError<ConfigError>(
      [] {
        GridBinning({axis("A", 0, 1, 65536), axis("B", 0, 1, 65536), axis("C", 0, 1, 65536),
                     axis("D", 0, 1, 65536)});
      },
      {"more than 2^63 bins", "grid axis 4"});
}

// A 2 x 2 grid over [0, 2) x [0, 2) (bins of 1 x 1) filled with 12 samples:
//   4 at (0.5, 0.5) -> bin (0, 0), packed 0
//   2 at (1.5, 0.5) -> bin (1, 0), packed 1
//   1 at (0.5, 1.5) -> bin (0, 1), packed 2
//   1 at (1.5, 1.5) -> bin (1, 1), packed 3
//   (2.0, 0.5) and (-0.1, 1.0): outside (hi excluded, below lo)
//   (NaN, 0.5) and (0.5, NaN): undefined
// binned = 8, so the probabilities are 4/8 = 0.5, 2/8 = 0.25, 1/8 = 0.125 and 0.125; the
// tie between packed 2 and 3 goes to the lower index. Cumulative: 0.5, 0.75, 0.875, 1.
AxisSamples handMadeSamples() {
  AxisSamples s(2);
  auto add = [&](double x, double y, int times) {
    for (int i = 0; i < times; ++i) {
      s[0].push_back(x);
      s[1].push_back(y);
    }
  };
  add(1.5, 1.5, 1);  // filling order does not matter: the tie is broken by index
  add(0.5, kNaN, 1);
  add(1.5, 0.5, 2);
  add(2.0, 0.5, 1);
  add(0.5, 1.5, 1);
  add(0.5, 0.5, 4);
  add(-0.1, 1.0, 1);
  add(kNaN, 0.5, 1);
  return s;
}

GridBinning twoByTwo() {
  return GridBinning({axis("X", 0, 2, 2), axis("Y", 0, 2, 2)});
}

TEST(OccupationGrid, FillNormaliseAndSort) {
  const OccupationGrid g = OccupationGrid::fill(twoByTwo(), handMadeSamples());
  EXPECT_EQ(g.binnedCount(), 8);
  EXPECT_EQ(g.outsideCount(), 2);
  EXPECT_EQ(g.undefinedCount(), 2);
  ASSERT_EQ(g.occupiedBins(), 4);
  const std::vector<BinIndex> order = {0, 1, 2, 3};
  const std::vector<std::int64_t> counts = {4, 2, 1, 1};
  const std::vector<double> probabilities = {0.5, 0.25, 0.125, 0.125};
  const std::vector<double> cumulative = {0.5, 0.75, 0.875, 1.0};
  double sum = 0.0;
  for (std::size_t r = 0; r < 4; ++r) {
    EXPECT_EQ(g.bins()[r].index, order[r]) << r;
    EXPECT_EQ(g.bins()[r].count, counts[r]) << r;
    EXPECT_EQ(g.bins()[r].probability, probabilities[r]) << r;
    EXPECT_EQ(g.bins()[r].cumulative, cumulative[r]) << r;
    EXPECT_EQ(g.rankOf(order[r]), std::int64_t(r));
    sum += g.bins()[r].probability;
  }
  EXPECT_EQ(sum, 1.0);
  const std::array<double, 2> inside = {1.0, 1.999};
  EXPECT_EQ(g.binOf(inside), std::optional<BinIndex>(3));
  const std::array<double, 2> outside = {1.0, 2.0};
  EXPECT_EQ(g.binOf(outside), std::nullopt);
  const std::array<double, 1> short_ = {1.0};
  expectError<ConfigError>([&] { g.binOf(short_); }, {"a point of 1 values for a grid of 2 axes"});
}

// Weighted samples: a bin's probability is its weight sum over the binned weight, the order is
// by weight (not by count), and the counts are kept beside the weights.
TEST(OccupationGrid, WeightsMakeTheProbabilities) {
  // Bin 0: three samples of weight 1; bin 1: one of weight 5; bin 3: two of weight 0.5 and
  // 1.5; outside (2.0, 0.5) of weight 7 and a sample of weight 0 (stands for nothing).
  const AxisSamples samples = {{0.5, 0.5, 0.5, 1.5, 1.5, 1.5, 2.0, 0.5},
                               {0.5, 0.5, 0.5, 0.5, 1.5, 1.5, 0.5, 0.5}};
  const std::vector<double> weights = {1, 1, 1, 5, 0.5, 1.5, 7, 0};
  const OccupationGrid g = OccupationGrid::fill(twoByTwo(), samples, weights);
  EXPECT_EQ(g.binnedCount(), 6);
  EXPECT_EQ(g.binnedWeight(), 10.0);
  EXPECT_EQ(g.outsideCount(), 1);
  EXPECT_EQ(g.undefinedCount(), 1);
  ASSERT_EQ(g.occupiedBins(), 3);
  // Weights 5 (bin 1), 3 (bin 0, three samples), 2 (bin 3): probabilities 0.5, 0.3, 0.2.
  EXPECT_EQ(g.bins()[0].index, 1u);
  EXPECT_EQ(g.bins()[0].count, 1);
  EXPECT_EQ(g.bins()[0].probability, 0.5);
  EXPECT_EQ(g.bins()[1].index, 0u);
  EXPECT_EQ(g.bins()[1].count, 3);
  EXPECT_DOUBLE_EQ(g.bins()[1].probability, 0.3);
  EXPECT_EQ(g.bins()[2].index, 3u);
  EXPECT_EQ(g.bins()[2].weight, 2.0);
  EXPECT_DOUBLE_EQ(g.bins()[2].probability, 0.2);
  EXPECT_DOUBLE_EQ(g.bins()[1].cumulative, 0.8);
  EXPECT_EQ(g.bins()[2].cumulative, 1.0);
  EXPECT_EQ(g.contour(0.6).selectedBins, 2);
  // The same grid from its bins (as a grid file stores them).
  const OccupationGrid again = OccupationGrid::fromWeights(twoByTwo(), g.bins(), 1, 1);
  for (std::size_t r = 0; r < 3; ++r) {
    EXPECT_EQ(again.bins()[r].index, g.bins()[r].index);
    EXPECT_EQ(again.bins()[r].probability, g.bins()[r].probability);
  }
  expectError<ConfigError>([&] { OccupationGrid::fill(twoByTwo(), samples, {1.0}); },
                           {"8 samples and 1 weights"});
  expectError<ConfigError>(
      [&] {
        OccupationGrid::fromWeights(twoByTwo(), {{0, 1, -1.0, 0, 0}}, 0, 0);
      },
      {"bin 0 has weight -1"});
}

TEST(OccupationGrid, TiesAreBrokenByIndexWhateverTheFillingOrder) {
  // Three bins of one sample each along one axis, filled in the order 2, 0, 1: the order is by
  // index, 0, 1, 2.
  const GridBinning b({axis("X", 0, 3, 3)});
  const OccupationGrid g = OccupationGrid::fill(b, {{2.5, 0.5, 1.5}});
  ASSERT_EQ(g.occupiedBins(), 3);
  EXPECT_EQ(g.bins()[0].index, 0u);
  EXPECT_EQ(g.bins()[1].index, 1u);
  EXPECT_EQ(g.bins()[2].index, 2u);
  // Probabilities 1/3 each; the cumulative is (sum of counts) / 3: 1/3, 2/3, exactly 1.
  EXPECT_EQ(g.bins()[1].cumulative, 2.0 / 3.0);
  EXPECT_EQ(g.bins()[2].cumulative, 1.0);
}

TEST(OccupationGrid, ContourIsTheSmallestSetOfMostProbableBinsReachingTheLevel) {
  const OccupationGrid g = OccupationGrid::fill(twoByTwo(), handMadeSamples());
  // Cumulative 0.5, 0.75, 0.875, 1: the contour stops at the first bin reaching P.
  struct Case {
    double level;
    std::int64_t bins;
    double holds;
  };
  for (const Case& c :
       {Case{0.1, 1, 0.5}, Case{0.5, 1, 0.5}, Case{0.5000001, 2, 0.75}, Case{0.75, 2, 0.75},
        Case{0.8, 3, 0.875}, Case{0.875, 3, 0.875}, Case{0.99, 4, 1.0}, Case{1.0, 4, 1.0}}) {
    const Contour contour = g.contour(c.level);
    EXPECT_EQ(contour.level, c.level);
    EXPECT_EQ(contour.selectedBins, c.bins) << "P = " << c.level;
    EXPECT_EQ(contour.probability, c.holds) << "P = " << c.level;
    EXPECT_GE(contour.probability, c.level);
  }
  const Contour c = g.contour(0.8);
  EXPECT_EQ(g.selectedIndices(c), (std::vector<BinIndex>{0, 1, 2}));
  EXPECT_TRUE(c.selects(2));
  EXPECT_FALSE(c.selects(3));
  EXPECT_FALSE(c.selects(-1));
}

TEST(OccupationGrid, ContourErrors) {
  const OccupationGrid g = OccupationGrid::fill(twoByTwo(), handMadeSamples());
  expectError<ConfigError>([&] { g.contour(0.0); }, {"P = 0 outside (0, 1]"});
  expectError<ConfigError>([&] { g.contour(1.5); }, {"P = 1.5 outside (0, 1]"});
  expectError<ConfigError>([&] { g.contour(kNaN); }, {"outside (0, 1]"});
  // Every sample outside or undefined: the contour selects nothing.
  const OccupationGrid empty = OccupationGrid::fill(twoByTwo(), {{5.0, kNaN}, {0.5, 0.5}});
  EXPECT_EQ(empty.occupiedBins(), 0);
  expectError<ConfigError>(
      [&] { empty.contour(0.99); },
      {"the contour at P = 0.99 selects nothing", "(1 outside the axis ranges, 1 undefined)"});
}

TEST(OccupationGrid, FillAndFromCountsErrors) {
  expectError<ConfigError>([] { OccupationGrid::fill(twoByTwo(), {{0.5}}); },
                           {"grid of 2 axes filled with 1 axes"});
  expectError<ConfigError>(
      [] {
        OccupationGrid::fill(twoByTwo(), {{0.5, 1.0}, {0.5}});
      },
      {"axes of different lengths"});
  // fromCounts gives the grid fill gives for the same counts.
  const OccupationGrid filled = OccupationGrid::fill(twoByTwo(), handMadeSamples());
  const OccupationGrid stored =
      OccupationGrid::fromCounts(twoByTwo(), {{3, 1}, {2, 1}, {1, 2}, {0, 4}}, 2, 2);
  ASSERT_EQ(stored.occupiedBins(), filled.occupiedBins());
  for (std::size_t r = 0; r < filled.bins().size(); ++r) {
    EXPECT_EQ(stored.bins()[r].index, filled.bins()[r].index);
    EXPECT_EQ(stored.bins()[r].cumulative, filled.bins()[r].cumulative);
  }
  expectError<ConfigError>(
      [] {
        OccupationGrid::fromCounts(twoByTwo(), {{4, 1}}, 0, 0);
      },
      {"bin 4 outside the 4 bins"});
  expectError<ConfigError>(
      [] {
        OccupationGrid::fromCounts(twoByTwo(), {{1, 0}}, 0, 0);
      },
      {"bin 1 has count 0"});
  expectError<ConfigError>(
      [] {
        OccupationGrid::fromCounts(twoByTwo(), {{1, 2}, {1, 3}}, 0, 0);
      },
      {"bin 1 given twice"});
}

TEST(OccupationGrid, AxesFromExpressionsOnTheRowsOfASearchSpace) {
  const Table t = test::makeTable(
      {{"ARCNESS", {0.05, 0.2, 0.12}}, {"SNR_ISO", {10, 1000, 100}}, {"KEEP", {1, 0, 1}}});
  const AxisSamples s = evaluateAxes({"ARCNESS", "log10(SNR_ISO)"}, t, {true, false, true});
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[0], (std::vector<double>{0.05, 0.12}));
  EXPECT_EQ(s[1], (std::vector<double>{1.0, 2.0}));
  EXPECT_EQ(evaluateAxes({"KEEP"}, t)[0], (std::vector<double>{1, 0, 1}));
  expectError<ConfigError>(
      [&] {
        evaluateAxes({"ARCNESS", "log10(SNR)"}, t);
      },
      {"grid axis 2 (log10(SNR))", "unknown column SNR"});
  expectError<ConfigError>([&] { evaluateAxes({"ARCNESS"}, t, {true}); },
                           {"mask of 1 rows for a table of 3"});
}

TEST(QuantileRange, LinearInterpolationBetweenOrderStatistics) {
  // Sorted 0, 1, ..., 10 (with a NaN ignored): the 10% quantile is at position 0.1 * 10 = 1,
  // the value 1; the 90% one at 9; hi is moved just above 9 so that 9 is in [lo, hi).
  std::vector<double> v = {10, 3, kNaN, 0, 7, 1, 9, 2, 8, 4, 6, 5};
  const auto [lo, hi] = quantileRange(v, 0.1, "axis");
  EXPECT_EQ(lo, 1.0);
  EXPECT_EQ(hi, std::nextafter(9.0, 10.0));
  // 25% of 0..10 at position 2.5: 2.5; 5% at 0.5: 0.5.
  EXPECT_EQ(quantileRange(v, 0.25, "axis").first, 2.5);
  EXPECT_EQ(quantileRange(v, 0.05, "axis").first, 0.5);
  const auto [min, max] = quantileRange(v, 0.0, "axis");
  EXPECT_EQ(min, 0.0);
  EXPECT_EQ(max, std::nextafter(10.0, 11.0));
  expectError<ConfigError>([] { quantileRange({1.0}, 0.0, "grid axis 3"); },
                           {"grid axis 3", "1 finite values"});
  expectError<ConfigError>(
      [] {
        quantileRange({2.0, 2.0, 2.0}, 0.0, "grid axis 1");
      },
      {"grid axis 1", "all equal"});
  expectError<ConfigError>([] { quantileRange({1.0, 2.0}, 0.5, "a"); }, {"outside [0, 0.5)"});
}

// Bytes the allocator currently hands out to the program (under AddressSanitizer, malloc is the
// sanitizer's and glibc's mallinfo2 sees none of it).
std::size_t allocatedBytes() {
  if (__sanitizer_get_current_allocated_bytes != nullptr) {
    return __sanitizer_get_current_allocated_bytes();
  }
  const struct mallinfo2 info = mallinfo2();
  return info.uordblks + info.hblkhd;
}

TEST(OccupationGrid, SparseStorageCostsMemoryInProportionToTheOccupiedBins) {
  // 6 axes of 100 bins: 10^12 bins (8 TB as a dense array of counts), filled with 10^5
  // uniform random samples.
  constexpr int kDims = 6;
  constexpr int kBins = 100;
  constexpr std::size_t kSamples = 100000;
  std::vector<GridAxis> axes;
  for (int a = 0; a < kDims; ++a) axes.push_back(axis("X", 0.0, 1.0, kBins));
  const GridBinning binning(axes);
  EXPECT_EQ(binning.totalBins(), 1000000000000u);
  std::mt19937_64 rng(20240607);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  AxisSamples samples(kDims, std::vector<double>(kSamples));
  // The occupied bins, counted independently: the distinct tuples of floor(100 v).
  std::map<std::array<int, kDims>, std::int64_t> occupied;
  for (std::size_t i = 0; i < kSamples; ++i) {
    std::array<int, kDims> k{};
    for (int a = 0; a < kDims; ++a) {
      samples[std::size_t(a)][i] = uniform(rng);
      k[std::size_t(a)] = int(std::floor(samples[std::size_t(a)][i] * kBins));
    }
    ++occupied[k];
  }
  const std::size_t before = allocatedBytes();
  const OccupationGrid grid = OccupationGrid::fill(binning, samples);
  const std::size_t bytes = allocatedBytes() - before;
  ASSERT_EQ(grid.occupiedBins(), std::int64_t(occupied.size()));
  EXPECT_EQ(grid.binnedCount(), std::int64_t(kSamples));
  const double perBin = double(bytes) / double(occupied.size());
  RecordProperty("bytes_per_occupied_bin", std::to_string(perBin));
  std::printf("%zu occupied bins of 10^12, %zu bytes held (%.1f per occupied bin)\n",
              occupied.size(), bytes, perBin);
  EXPECT_GT(perBin, 40.0);   // it does hold every bin (a GridBin alone is 40 bytes)
  EXPECT_LT(perBin, 128.0);  // and nothing in proportion to the 10^12 bins
  // The contour at 0.99: the most populated bins first, until they hold 99 000 samples.
  std::vector<std::int64_t> counts;
  for (const auto& [k, n] : occupied) counts.push_back(n);
  std::sort(counts.rbegin(), counts.rend());
  std::int64_t held = 0;
  std::int64_t bins = 0;
  while (held < 99000) held += counts[std::size_t(bins++)];
  EXPECT_EQ(grid.contour(0.99).selectedBins, bins);
}

}  // namespace
}  // namespace octarc
