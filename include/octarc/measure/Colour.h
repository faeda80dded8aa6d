// Colours of detected objects (search candidates, simulated arcs and lenses): isophotal
// magnitudes of an object in other bands, measured in the footprint the detection gave it (the
// same pixels as its MAG_ISO), as SExtractor's MAG_ISO and MAGERR_ISO would be in dual-image mode
// with that band as the measurement image.
//
// A colour is a band's magnitude minus the measurement band's, its error the two magnitude
// errors in quadrature. Where the flux is not positive, or no footprint pixel is finite, the
// magnitude and every colour made from it are NaN (SExtractor writes 99 there).
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "octarc/core/Image.h"
#include "octarc/core/Segment.h"

namespace octarc {

// One band's image, on the pixel grid of the footprints.
struct BandImage {
  const ImageF* pixels = nullptr;    // background-subtracted
  const ImageF* variance = nullptr;  // per pixel (ADU^2); null: sigmaAdu everywhere
  double sigmaAdu = 0.0;             // global background noise
  double gain = 0.0;                 // e-/ADU; 0 = infinite (no Poisson term)
  double magZeropoint = 0.0;
};

struct BandMagnitude {
  double mag = std::numeric_limits<double>::quiet_NaN();
  double magErr = std::numeric_limits<double>::quiet_NaN();
};

// The isophotal magnitude of `band` in `footprint` (0-based pixel runs): FLUX_ISO summed over
// the finite pixels, FLUXERR_ISO as SExtractor's (SEXTRACTOR.md section 4: n sigma^2 + F/gain
// without a variance map; the per-pixel variances and per-pixel Poisson term with one).
BandMagnitude isoMagnitude(const BandImage& band, const std::vector<PixelRun>& footprint);

struct Colour {
  double value = std::numeric_limits<double>::quiet_NaN();  // mag
  double error = std::numeric_limits<double>::quiet_NaN();
};

// `band` minus `reference`.
Colour colourOf(const BandMagnitude& band, const BandMagnitude& reference);

// True when `name` can name a band inside column names (MAG_<name>, ARC_COLOUR_<name>): 1 to 16
// letters, digits or underscores.
bool isBandName(const std::string& name);

}  // namespace octarc
