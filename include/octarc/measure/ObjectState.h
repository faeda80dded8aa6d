// Per-object intermediate results shared between measurements. One ObjectState lives for one
// object of one measurement pass; each measurement fills its own part and reads the parts of the
// measurements it declares as dependencies.
#pragma once

#include <cstdint>

#include "octarc/measure/MomentsMath.h"
#include "octarc/measure/ObjectPixels.h"

namespace octarc {

struct ObjectState {
  // The object's pixels, gathered by the plan before the first measurement runs.
  const ObjectPixels* pixels = nullptr;

  // Footprint (measurement "Footprint"): bounding box in 0-based indices, pixel count.
  bool haveFootprint = false;
  std::int64_t xMin = 0, xMax = -1, yMin = 0, yMax = -1;
  std::int64_t footprintPixels = 0;  // |S| = ISOAREAF_IMAGE

  // SExtractor-compatible moments weighted by the detection image ("IsophotalShape").
  bool haveIso = false;
  IsoMoments iso;
  EllipseShape isoShape;
  std::int64_t xPeak = -1, yPeak = -1;  // 0-based position of the largest detection value

  // Isophotal photometry on the measurement image ("IsophotalPhotometry").
  bool havePhotometry = false;
  double fluxIsoAdu = kNaN;
  double fluxErrIsoAdu = kNaN;
  double fluxMaxAdu = kNaN;
  std::int64_t isoArea = 0;  // pixels above the analysis threshold

  // Measurement-weighted central moments and the octopole set ("Octopole").
  bool haveCentral = false;
  CentralMoments central;
  OctopoleStats octopole;

  // World-frame results ("WorldCoordinates"); NaN where the WCS gives nothing.
  bool haveWorld = false;
  double xWorldDeg = kNaN, yWorldDeg = kNaN;
  double alphaJ2000Deg = kNaN, deltaJ2000Deg = kNaN;
  WorldMoments world;       // X2/Y2/XY_WORLD, deg^2
  EllipseShape worldShape;  // A/B/THETA_WORLD

  // Flag bits: SExtractor FLAGS (sexflag::) and octarc OCT_FLAGS (octflag::), core/Flags.h.
  std::int32_t sexFlags = 0;
  std::int32_t octFlags = 0;
};

}  // namespace octarc
