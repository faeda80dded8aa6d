// SExtractor's estimate of the background of one mesh from its histogram (source-extractor
// 2.25's backguess, SEXTRACTOR.md §5): up to 100 iterations of a +-3 sigma clip around the
// median, then level = 2.5 median - 1.5 mean when |mean - median| < 0.3 sigma, else the median;
// rms = the clipped standard deviation. Bin i holds the values around qzero + i * qscale.
//
// The result is bit-identical to the straightforward loop over the bins between the cuts at
// every iteration, but costs one pass over the histogram plus the bins that enter or leave the
// cuts: the sums of an iteration are integers (exact in double below 2^53), kept up to date as
// the cuts move, and the median walk ("feed the lighter side") is replayed by a binary search
// on the cumulative counts, in O(log nlevels) per iteration. Histograms whose moments could
// reach 2^53 take the straightforward loop.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace octarc {

struct MeshHistogramScale {
  float meanAdu = 0.0f;    // mesh mean: the starting median and mean
  float qzeroAdu = 0.0f;   // value of bin 0
  float qscaleAdu = 1.0f;  // bin width
};

struct MeshMode {
  float levelAdu = 0.0f;
  float rmsAdu = 0.0f;
};

// Counts must be >= 0. `scratch` is reused between calls to avoid allocations.
MeshMode meshHistogramMode(std::span<const std::int64_t> counts, const MeshHistogramScale& scale,
                           std::vector<std::uint64_t>& scratch);
MeshMode meshHistogramMode(std::span<const std::int64_t> counts, const MeshHistogramScale& scale);

}  // namespace octarc
