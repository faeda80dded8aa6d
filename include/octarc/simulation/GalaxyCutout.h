// Clean, noise-free galaxy stamps cut out of a deep image for a source-galaxy database
// (METHOD.md section 3: real galaxies "thresholded at 4 sigma and cleaned").
//
// The rule, exactly: given the background-subtracted image f and one detected object with
// footprint F (its 8-connected pixels strictly above the detection threshold), the stamp pixel at
// image position p is
//     f(p)   if p is in F,
//     0      otherwise.
// Everything below the threshold (sky noise, the galaxy's faint outskirts) is therefore zero
// ("noise-free"), and so is every pixel of any other object ("clean"): a neighbour is never
// part of F, since objects at one threshold are disjoint. Inside F the pixels keep their noise.
//
// The stamp is centred on the pixel nearest the footprint's flux centroid: its centre pixel
// ((w-1)/2, (h-1)/2), the reference point a SourceStamp is placed by, is that pixel. It reaches
// marginPixels beyond the footprint on the farther side in x and in y, so w and h are odd. Parts
// of the stamp beyond the image edges are zero (they lie outside F).
//
// An object is skipped when its footprint touches the image border or a blank (NaN) pixel (the
// galaxy may continue beyond it), has fewer than minAreaPixels pixels, contains a saturated pixel,
// or has a non-positive total flux.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "octarc/core/Image.h"
#include "octarc/core/Segment.h"

namespace octarc::simulation {

struct CutoutSettings {
  int minAreaPixels = 1;  // smallest footprint kept as a galaxy
  int marginPixels = 4;   // zero pixels around the footprint
};

enum class CutoutVerdict { Kept, TouchesBorder, TooSmall, Saturated, NoFlux };

// "kept", "touching the border or blank pixels", "too small", "saturated", "without positive flux".
const char* cutoutVerdictName(CutoutVerdict verdict);

struct GalaxyCutout {
  CutoutVerdict verdict = CutoutVerdict::Kept;
  ImageF stamp;               // empty unless kept
  double fluxAdu = 0.0;       // sum of f over the footprint (= sum of the stamp)
  double xCentroidPix = 0.0;  // flux-weighted centroid, 0-based image coordinates
  double yCentroidPix = 0.0;
  std::int64_t originX = 0;  // image position of stamp pixel (0, 0); may be negative
  std::int64_t originY = 0;
  std::int64_t areaPixels = 0;  // footprint pixels
};

// Cuts the stamp of `object` (pixel indices y * width + x into `backgroundSubtracted`).
// `saturatedPixels` lists, in ascending order, the linear indices of the saturated pixels of the
// image (raw value at or above the saturation level). Throws ConfigError for minAreaPixels < 1,
// marginPixels < 0, or a footprint pixel outside the image.
GalaxyCutout cutGalaxy(const ImageF& backgroundSubtracted, const Segment& object,
                       const std::vector<std::int64_t>& saturatedPixels,
                       const CutoutSettings& settings);

}  // namespace octarc::simulation
