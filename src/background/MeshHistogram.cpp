// SExtractor's clipped histogram mode. Both loops below follow SExtractor's arithmetic operation
// by operation where it is floating point; they differ only in how the integer sums of an
// iteration are obtained.
#include "octarc/background/MeshHistogram.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace octarc {

namespace {

constexpr double kEps = 1e-4;
constexpr int kMaxIterations = 100;
constexpr std::uint64_t kExactLimit = std::uint64_t{1} << 53;  // doubles hold integers exactly

// What one clipping iteration yields: the integer sums over the bins [lcut, hcut] and the end
// of the median walk.
struct IterationSums {
  std::uint64_t sum = 0, lowSum = 0, highSum = 0;
  double mea = 0.0, sig = 0.0;  // sum of count * i and of count * i * i
  int lo = 0, hi = 0;
};

// The state carried between iterations and the final combination (SExtractor's formulas).
class ClipState {
 public:
  ClipState(int nlevels, float meanAdu)
      : lastBin_(nlevels - 1),
        hcut_(lastBin_),
        sig_(10.0 * lastBin_),
        mea_(meanAdu),
        med_(meanAdu) {}

  template <typename SumsFn>
  void run(std::span<const std::int64_t> h, SumsFn&& sums) {
    for (int n = kMaxIterations; n-- && sig_ >= 0.1 && std::fabs(sig_ / sigPrev_ - 1.0) > kEps;) {
      sigPrev_ = sig_;
      const IterationSums s = sums(lcut_, hcut_);
      mea_ = s.mea;
      sig_ = s.sig;
      if (s.hi >= 0) {
        const double peak = static_cast<double>(
            std::max(h[static_cast<std::size_t>(s.lo)], h[static_cast<std::size_t>(s.hi)]));
        med_ = s.hi + 0.5 +
               (static_cast<double>(s.highSum) - static_cast<double>(s.lowSum)) / (2.0 * peak);
      } else {
        med_ = 0.0;
      }
      if (s.sum) {
        mea_ /= static_cast<double>(s.sum);
        sig_ = sig_ / static_cast<double>(s.sum) - mea_ * mea_;
      }
      sig_ = sig_ > 0.0 ? std::sqrt(sig_) : 0.0;
      double t = med_ - 3.0 * sig_;
      lcut_ = t > 0.0 ? static_cast<int>(t + 0.5) : 0;
      t = med_ + 3.0 * sig_;
      hcut_ = t < lastBin_ ? static_cast<int>(t > 0.0 ? t + 0.5 : t - 0.5) : lastBin_;
    }
  }

  MeshMode result(const MeshHistogramScale& s) const {
    double value;
    if (std::fabs(sig_) > 0.0) {
      value = std::fabs((mea_ - med_) / sig_) < 0.3
                  ? s.qzeroAdu + (2.5 * med_ - 1.5 * mea_) * s.qscaleAdu
                  : s.qzeroAdu + med_ * s.qscaleAdu;
    } else {
      value = s.qzeroAdu + mea_ * s.qscaleAdu;
    }
    return {static_cast<float>(value), static_cast<float>(sig_ * s.qscaleAdu)};
  }

 private:
  int lastBin_;
  int lcut_ = 0;
  int hcut_;
  double sig_;
  double sigPrev_ = 1.0;
  double mea_;
  double med_;
};

// The straightforward iteration: one pass over the bins between the cuts, walking in from both
// ends and always feeding the lighter side to locate the median bin.
IterationSums directSums(std::span<const std::int64_t> h, int lcut, int hcut) {
  IterationSums s;
  int lo = lcut;
  int hi = hcut;
  for (int i = lcut; i <= hcut; ++i) {
    if (s.lowSum < s.highSum)
      s.lowSum += static_cast<std::uint64_t>(h[static_cast<std::size_t>(lo++)]);
    else
      s.highSum += static_cast<std::uint64_t>(h[static_cast<std::size_t>(hi--)]);
    const std::int64_t count = h[static_cast<std::size_t>(i)];
    s.sum += static_cast<std::uint64_t>(count);
    const double weighted = static_cast<double>(count) * i;
    s.mea += weighted;
    s.sig += weighted * i;
  }
  s.lo = lo;
  s.hi = hi;
  return s;
}

// The same without a pass over the range. The double sums of the direct loop add integers
// below 2^53 (checked by the caller), so they are exact: they equal integer sums kept for the
// previous range and updated by the bins that enter or leave it (after the first cut, which
// usually drops most of the histogram's tails, the cuts move by a few bins).
//
// The median walk: with L(a) the sum of the a lowest bins of the range and H(b) that of the b
// highest, a step feeds the low side when L(a) < H(b), else the high side. As L and H never
// decrease, this is the merge of the sorted sequences L(0), L(1), ... and H(0), H(1), ... with
// ties taken from H, so L(i) comes out before H(j) exactly when L(i) < H(j). After len = hcut -
// lcut + 1 steps the low side has consumed a bins and the high side b = len - a, where a is the
// largest split with L(a - 1) < H(len - a) (true for a = 0, and false for every larger split once
// false, as L rises and H falls with a): binary search on the cumulative counts.
class FastSums {
 public:
  // `cumulative` has counts.size() + 1 entries, cumulative[k] = sum of the bins below k; s1 and
  // s2 are the sums of count * i and count * i^2 over the whole histogram, the range of the
  // first iteration.
  FastSums(std::span<const std::int64_t> counts, const std::uint64_t* cumulative, std::uint64_t s1,
           std::uint64_t s2)
      : h_(counts), c0_(cumulative), hi_(static_cast<int>(counts.size()) - 1), s1_(s1), s2_(s2) {}

  IterationSums operator()(int lcut, int hcut) {
    IterationSums s;
    s.lo = lcut;
    s.hi = hcut;
    const int len = hcut - lcut + 1;
    if (len <= 0) return s;
    moveTo(lcut, hcut);
    const std::uint64_t base = c0_[lcut];
    const std::uint64_t top = c0_[hcut + 1];
    s.sum = top - base;
    s.mea = static_cast<double>(s1_);
    s.sig = static_cast<double>(s2_);
    auto lowSide = [&](int i) { return c0_[lcut + i] - base; };
    auto highSide = [&](int j) { return top - c0_[hcut + 1 - j]; };
    // Largest a in [0, len] with a == 0 or L(a - 1) < H(len - a); H(len - a) is read at the same
    // place, c0[lcut + a].
    int first = 0, n = len;  // the split is in [first, first + n]
    while (n > 0) {
      const int half = (n + 1) / 2;
      const int a = first + half;
      const bool taken = c0_[lcut + a - 1] - base < top - c0_[lcut + a];
      first = taken ? a : first;
      n = taken ? n - half : half - 1;
    }
    const int a = first;
    const int b = len - a;
    s.lo = lcut + a;
    s.hi = hcut - b;
    s.lowSum = lowSide(a);
    s.highSum = highSide(b);
    return s;
  }

 private:
  // Sums of count * i and count * i^2 over [lo_, hi_]; unsigned, so that the intermediate
  // steps may wrap, the result of each update being exact.
  void add(int i) {
    const std::uint64_t ci =
        static_cast<std::uint64_t>(h_[static_cast<std::size_t>(i)]) * static_cast<std::uint64_t>(i);
    s1_ += ci;
    s2_ += ci * static_cast<std::uint64_t>(i);
  }
  void remove(int i) {
    const std::uint64_t ci =
        static_cast<std::uint64_t>(h_[static_cast<std::size_t>(i)]) * static_cast<std::uint64_t>(i);
    s1_ -= ci;
    s2_ -= ci * static_cast<std::uint64_t>(i);
  }
  // Both ranges are non-empty: grow to their hull first, then shrink; or sum afresh when the
  // new range has fewer bins than would move.
  void moveTo(int lo, int hi) {
    if (std::abs(lo - lo_) + std::abs(hi - hi_) > hi - lo + 1) {
      s1_ = s2_ = 0;
      lo_ = lo;
      hi_ = hi;
      for (int i = lo; i <= hi; ++i) add(i);
      return;
    }
    while (lo_ > lo) add(--lo_);
    while (hi_ < hi) add(++hi_);
    while (lo_ < lo) remove(lo_++);
    while (hi_ > hi) remove(hi_--);
  }

  std::span<const std::int64_t> h_;
  const std::uint64_t* c0_;
  int lo_ = 0, hi_;
  std::uint64_t s1_, s2_;
};

}  // namespace

MeshMode meshHistogramMode(std::span<const std::int64_t> counts, const MeshHistogramScale& scale,
                           std::vector<std::uint64_t>& scratch) {
  const int nlevels = static_cast<int>(counts.size());
  ClipState state(nlevels, scale.meanAdu);
  scratch.resize(counts.size() + 1);
  std::uint64_t* c0 = scratch.data();
  // Unsigned arithmetic: wraps instead of overflowing for absurd counts, which the check below
  // then sends to the direct loop.
  std::uint64_t total = 0, s1 = 0, s2 = 0;
  c0[0] = 0;
  for (int i = 0; i < nlevels; ++i) {
    const std::uint64_t count = static_cast<std::uint64_t>(counts[static_cast<std::size_t>(i)]);
    const std::uint64_t ci = count * static_cast<std::uint64_t>(i);
    total += count;
    s1 += ci;
    s2 += ci * static_cast<std::uint64_t>(i);
    c0[i + 1] = total;
  }
  // Every partial sum of count * i^2 stays below total * lastBin^2; exact when that is < 2^53.
  const std::uint64_t lastBin = nlevels > 1 ? static_cast<std::uint64_t>(nlevels - 1) : 1;
  if (total < kExactLimit / (lastBin * lastBin)) {
    FastSums fast(counts, c0, s1, s2);
    state.run(counts, fast);
  } else {
    state.run(counts, [&](int lcut, int hcut) { return directSums(counts, lcut, hcut); });
  }
  return state.result(scale);
}

MeshMode meshHistogramMode(std::span<const std::int64_t> counts, const MeshHistogramScale& scale) {
  std::vector<std::uint64_t> scratch;
  return meshHistogramMode(counts, scale, scratch);
}

}  // namespace octarc
