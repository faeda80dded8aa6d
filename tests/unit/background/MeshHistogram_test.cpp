#include "octarc/background/MeshHistogram.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace octarc {
namespace {

// The reference: SExtractor's backguess as the straightforward loop, one pass over the bins
// between the cuts per iteration, walking in from both ends to the median bin.
MeshMode referenceMode(const std::vector<std::int64_t>& histo, const MeshHistogramScale& s) {
  constexpr double kEps = 1e-4;
  const int lastBin = static_cast<int>(histo.size()) - 1;
  int lcut = 0;
  int hcut = lastBin;
  double sig = 10.0 * lastBin;
  double sigPrev = 1.0;
  double mea = s.meanAdu;
  double med = s.meanAdu;
  for (int n = 100; n-- && sig >= 0.1 && std::fabs(sig / sigPrev - 1.0) > kEps;) {
    sigPrev = sig;
    std::uint64_t sum = 0, lowSum = 0, highSum = 0;
    mea = sig = 0.0;
    int lo = lcut;
    int hi = hcut;
    for (int i = lcut; i <= hcut; ++i) {
      if (lowSum < highSum)
        lowSum += static_cast<std::uint64_t>(histo[static_cast<std::size_t>(lo++)]);
      else
        highSum += static_cast<std::uint64_t>(histo[static_cast<std::size_t>(hi--)]);
      const std::int64_t count = histo[static_cast<std::size_t>(i)];
      sum += static_cast<std::uint64_t>(count);
      const double weighted = static_cast<double>(count) * i;
      mea += weighted;
      sig += weighted * i;
    }
    if (hi >= 0) {
      const double peak = static_cast<double>(
          std::max(histo[static_cast<std::size_t>(lo)], histo[static_cast<std::size_t>(hi)]));
      med = hi + 0.5 + (static_cast<double>(highSum) - static_cast<double>(lowSum)) / (2.0 * peak);
    } else {
      med = 0.0;
    }
    if (sum) {
      mea /= static_cast<double>(sum);
      sig = sig / static_cast<double>(sum) - mea * mea;
    }
    sig = sig > 0.0 ? std::sqrt(sig) : 0.0;
    double t = med - 3.0 * sig;
    lcut = t > 0.0 ? static_cast<int>(t + 0.5) : 0;
    t = med + 3.0 * sig;
    hcut = t < lastBin ? static_cast<int>(t > 0.0 ? t + 0.5 : t - 0.5) : lastBin;
  }
  double value;
  if (std::fabs(sig) > 0.0) {
    value = std::fabs((mea - med) / sig) < 0.3 ? s.qzeroAdu + (2.5 * med - 1.5 * mea) * s.qscaleAdu
                                               : s.qzeroAdu + med * s.qscaleAdu;
  } else {
    value = s.qzeroAdu + mea * s.qscaleAdu;
  }
  return {static_cast<float>(value), static_cast<float>(sig * s.qscaleAdu)};
}

std::string describe(const std::vector<std::int64_t>& histo) {
  std::ostringstream out;
  out << histo.size() << " bins:";
  for (std::size_t i = 0; i < std::min<std::size_t>(histo.size(), 40); ++i) out << ' ' << histo[i];
  if (histo.size() > 40) out << " ...";
  return out.str();
}

// Compares bit patterns (NaN included) with the reference; returns false on a mismatch.
bool sameAsReference(const std::vector<std::int64_t>& histo, const MeshHistogramScale& s,
                     std::vector<std::uint64_t>& scratch) {
  const MeshMode want = referenceMode(histo, s);
  const MeshMode got = meshHistogramMode(histo, s, scratch);
  const bool same =
      std::bit_cast<std::uint32_t>(want.levelAdu) == std::bit_cast<std::uint32_t>(got.levelAdu) &&
      std::bit_cast<std::uint32_t>(want.rmsAdu) == std::bit_cast<std::uint32_t>(got.rmsAdu);
  EXPECT_TRUE(same) << describe(histo) << "\n  level " << got.levelAdu << " vs " << want.levelAdu
                    << ", rms " << got.rmsAdu << " vs " << want.rmsAdu;
  return same;
}

// Scales as MeshBackground derives them: the histogram spans mean +- 5 sigma.
MeshHistogramScale scaleFor(int nlevels, float meanAdu, float sigmaAdu) {
  MeshHistogramScale s;
  s.meanAdu = meanAdu;
  s.qscaleAdu = sigmaAdu > 0.0f ? 10.0f * sigmaAdu / static_cast<float>(nlevels) : 1.0f;
  s.qzeroAdu = meanAdu - 5.0f * sigmaAdu;
  return s;
}

TEST(MeshBackgroundHistogram, HandComputedSymmetricHistogram) {
  // Counts 1, 2, 1: the walk ends between bins 0 and 1 with 1 and 3 counts on either side, so
  // the median is 0 + 0.5 + (3 - 1) / (2 * 2) = 1; the mean is 1 and the variance
  // (0 + 2 + 4) / 4 - 1 = 0.5. The second iteration keeps all bins and sigma, so it stops;
  // |mean - median| < 0.3 sigma gives 2.5 * 1 - 1.5 * 1 = 1.
  const MeshMode m = meshHistogramMode(std::vector<std::int64_t>{1, 2, 1}, {7.0f, 100.0f, 0.5f});
  EXPECT_EQ(m.levelAdu, 100.5f);
  EXPECT_EQ(m.rmsAdu, static_cast<float>(std::sqrt(0.5) * 0.5));
}

TEST(MeshBackgroundHistogram, HandComputedSingleBinAndEmpty) {
  // One bin: sigma starts at 10 * 0 = 0, no iteration, level = qzero + mean * qscale.
  MeshMode m = meshHistogramMode(std::vector<std::int64_t>{5}, {3.0f, 10.0f, 2.0f});
  EXPECT_EQ(m.levelAdu, 16.0f);
  EXPECT_EQ(m.rmsAdu, 0.0f);
  // All bins empty: sum stays 0, so the mean is 0 and sigma 0: level = qzero.
  m = meshHistogramMode(std::vector<std::int64_t>(50, 0), {3.0f, 10.0f, 2.0f});
  EXPECT_EQ(m.levelAdu, 10.0f);
  EXPECT_EQ(m.rmsAdu, 0.0f);
}

TEST(MeshBackgroundHistogram, MatchesReferenceOnGaussianMeshes) {
  // Histograms like those of real meshes: Gaussian noise of various widths, often with a source
  // (a tail of bright pixels), binned over mean +- 5; values outside are dropped.
  std::mt19937_64 rng(2025);
  std::vector<std::uint64_t> scratch;
  int failures = 0;
  for (int trial = 0; trial < 1500 && failures < 5; ++trial) {
    const int npix = std::uniform_int_distribution<int>(1, 6000)(rng);
    const int nlevels = std::min(static_cast<int>(0.997 * npix + 1), 4096);
    const double sigma = std::uniform_real_distribution<double>(0.2, 3.0)(rng);
    const double mean = std::uniform_real_distribution<double>(-2.0, 2.0)(rng);
    const double sourceFraction =
        trial % 3 == 0 ? 0.0 : 0.3 * std::generate_canonical<double, 53>(rng);
    std::normal_distribution<double> noise(mean, sigma);
    std::exponential_distribution<double> source(0.2);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<std::int64_t> histo(static_cast<std::size_t>(nlevels), 0);
    for (int p = 0; p < npix; ++p) {
      double v = noise(rng);
      if (unit(rng) < sourceFraction) v += source(rng);
      const double bin = (v - (mean - 5.0)) / 10.0 * nlevels;
      if (bin >= 0.0 && bin < nlevels) ++histo[static_cast<std::size_t>(bin)];
    }
    if (!sameAsReference(histo, scaleFor(nlevels, static_cast<float>(mean), 1.0f), scratch))
      ++failures;
  }
}

TEST(MeshBackgroundHistogram, MatchesReferenceOnRandomSparseHistograms) {
  // Small histograms with many empty bins and many ties, where every turn of the median walk
  // matters; random starting means (including far outside the histogram).
  std::mt19937_64 rng(7);
  std::vector<std::uint64_t> scratch;
  int failures = 0;
  for (int trial = 0; trial < 40000 && failures < 5; ++trial) {
    const int nlevels = std::uniform_int_distribution<int>(1, trial % 10 == 0 ? 300 : 24)(rng);
    const double emptyFraction = std::generate_canonical<double, 53>(rng);
    const int maxCount = std::array<int, 4>{1, 2, 5, 1000}[static_cast<std::size_t>(trial % 4)];
    std::uniform_int_distribution<int> count(1, maxCount);
    std::vector<std::int64_t> histo(static_cast<std::size_t>(nlevels), 0);
    for (auto& c : histo)
      if (std::generate_canonical<double, 53>(rng) >= emptyFraction) c = count(rng);
    const float meanAdu = std::uniform_real_distribution<float>(-50.0f, 50.0f)(rng);
    if (!sameAsReference(histo, {meanAdu, -3.0f, 0.25f}, scratch)) ++failures;
  }
}

TEST(MeshBackgroundHistogram, MatchesReferenceOnAdversarialHistograms) {
  std::vector<std::vector<std::int64_t>> cases = {
      {},
      {0},
      {1},
      {0, 0},
      {1, 0},
      {0, 1},
      {1, 1},
      {3, 0, 3},
      {2, 0, 0, 2},
      {1, 1, 1, 1000},
      {1000, 1, 1, 1},
      {0, 5, 0, 0},
      {0, 0, 0, 5},
      {5, 0, 0, 0},
      {2, 0, 0, 0, 3},
      {2, 0, 0, 0, 3, 0},
      {1, 2, 3, 4, 5, 4, 3, 2, 1},
      {7, 7, 7, 7, 7, 7, 7, 7},
  };
  // One spike at every position, and spikes at both ends (cuts at the ends).
  for (int n : {2, 3, 10, 101, 4096}) {
    for (int at : {0, 1, n / 2, n - 2, n - 1}) {
      std::vector<std::int64_t> h(static_cast<std::size_t>(n), 0);
      h[static_cast<std::size_t>(std::max(at, 0))] = 17;
      cases.push_back(h);
    }
    std::vector<std::int64_t> ends(static_cast<std::size_t>(n), 0);
    ends.front() = 100;
    ends.back() = 100;
    cases.push_back(ends);
    ends.back() = 101;
    cases.push_back(ends);
    std::vector<std::int64_t> flat(static_cast<std::size_t>(n), 3);
    cases.push_back(flat);
    flat.back() = 0;
    cases.push_back(flat);
  }
  // Huge counts: just below the 2^53 exactness bound of the fast path, at it and far above
  // (where the sums in double round, and the direct loop is used).
  for (std::int64_t big : {std::int64_t{1} << 20, (std::int64_t{1} << 53) / (99 * 99) / 100 - 1,
                           (std::int64_t{1} << 53) / (99 * 99) / 100 + 1, std::int64_t{1} << 40,
                           std::int64_t{1} << 55}) {
    std::vector<std::int64_t> h(100, big);
    cases.push_back(h);
    h[37] += 12345;
    h[0] = 1;
    cases.push_back(h);
  }
  {
    std::vector<std::int64_t> h(4096, 0);
    for (int i = 0; i < 4096; ++i)
      h[static_cast<std::size_t>(i)] = (std::int64_t{1} << 30) + (i * 7919) % 1013;
    cases.push_back(h);
  }
  std::vector<std::uint64_t> scratch;
  for (const auto& h : cases)
    for (float meanAdu : {0.0f, 1.5f, -40.0f, 5000.0f})
      sameAsReference(h, {meanAdu, 2.0f, 0.5f}, scratch);
}

TEST(MeshBackgroundHistogram, ScratchReuseDoesNotChangeResults) {
  // A long histogram first, then short ones with the same scratch buffer.
  std::vector<std::uint64_t> scratch;
  std::vector<std::int64_t> longer(3000, 4);
  longer[1500] = 900;
  sameAsReference(longer, {0.0f, 0.0f, 1.0f}, scratch);
  sameAsReference({1, 2, 1}, {0.0f, 0.0f, 1.0f}, scratch);
  sameAsReference({0, 9}, {0.0f, 0.0f, 1.0f}, scratch);
}

}  // namespace
}  // namespace octarc
