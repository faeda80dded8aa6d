// Per-object flag bits. The low byte is SExtractor's FLAGS (same meaning); octarc's own
// conditions live in OCT_FLAGS. Every bit is documented here and listed by `octarc measure -dp`.
#pragma once

#include <cstdint>

namespace octarc {

// SExtractor FLAGS (doc/src/Flagging.rst). Only those a no-deblend isophotal run can set.
namespace sexflag {
constexpr std::int32_t kSaturated = 4;      // at least one pixel at or above SATUR_LEVEL
constexpr std::int32_t kTouchesBorder = 8;  // footprint touches the image border
}  // namespace sexflag

// octarc OCT_FLAGS.
namespace octflag {
constexpr std::int32_t kBadPixels = 1;  // NaN/Inf pixels in the footprint were left out of sums
constexpr std::int32_t kNonPositiveFlux = 2;  // total measurement flux <= 0: centroid/moments NaN
constexpr std::int32_t kSingularMoments = 4;  // Ixx+Iyy == 0 (or not finite): octopoles NaN
constexpr std::int32_t kSingularIso = 8;      // SExtractor singular-moment fix applied to X2/Y2
constexpr std::int32_t kNoWorld = 16;  // no celestial WCS, or it failed here: world columns NaN
}  // namespace octflag

}  // namespace octarc
