#include "octarc/measure/plugins/IsophotalPhotometry.h"

#include <algorithm>
#include <cmath>

#include "octarc/core/Conventions.h"
#include "octarc/core/Flags.h"

namespace octarc {

std::vector<OutputColumn> IsophotalPhotometry::columns() const {
  const ColumnType f = ColumnType::Float32;
  return {
      {{"ISOAREA_IMAGE", "Isophotal area above Analysis threshold", "pixel**2", "phys.area",
        ColumnType::Int32, "%9d"},
       [](const MeasuredObject& o) { return double(o.state.isoArea); }},
      {{"FLUX_ISO", "Isophotal flux", "count", "phot.flux", f, "%12.7g"},
       [](const MeasuredObject& o) { return o.state.fluxIsoAdu; }},
      {{"FLUXERR_ISO", "RMS error for isophotal flux", "count", "stat.stdev;phot.flux", f,
        "%12.7g"},
       [](const MeasuredObject& o) { return o.state.fluxErrIsoAdu; }},
      {{"MAG_ISO", "Isophotal magnitude", "mag", "phot.mag", f, "%8.4f"},
       [](const MeasuredObject& o) {
         return o.state.havePhotometry ? magnitude(o.state.fluxIsoAdu, o.context.magZeropoint)
                                       : kMagUndefined;
       }},
      {{"MAGERR_ISO", "RMS error for isophotal magnitude", "mag", "stat.stdev;phot.mag", f,
        "%8.4f"},
       [](const MeasuredObject& o) {
         return o.state.havePhotometry ? magnitudeError(o.state.fluxIsoAdu, o.state.fluxErrIsoAdu)
                                       : kMagUndefined;
       }},
      {{"FLUX_MAX", "Peak flux above background", "count", "phot.flux.sb;stat.max", f, "%12.7g"},
       [](const MeasuredObject& o) { return o.state.fluxMaxAdu; }},
      {{"SNR_ISO", "Isophotal S/N, FLUX_ISO/FLUXERR_ISO", "", "stat.snr", f, "%10.4g"},
       [](const MeasuredObject& o) {
         return o.state.fluxErrIsoAdu > 0.0 ? o.state.fluxIsoAdu / o.state.fluxErrIsoAdu : kNaN;
       }},
  };
}

void IsophotalPhotometry::measure(const Segment& segment, const MeasureContext& context,
                                  ObjectState& state) const {
  const std::size_t level = static_cast<std::size_t>(segment.level - 1);
  const bool haveLevel = level < context.levels.size();
  const double analysisAdu = haveLevel ? context.levels[level].analysisThresholdAdu : 0.0;
  const double sigma2 = context.sigmaAdu * context.sigmaAdu;
  // With a variance map the analysis threshold scales with the local noise, as in SExtractor.
  const double analysisPerSigma = context.sigmaAdu > 0.0 ? analysisAdu / context.sigmaAdu : 0.0;

  double flux = 0.0, fluxMax = -HUGE_VAL, varianceSum = 0.0, poissonVar = 0.0;
  std::int64_t used = 0, isoArea = 0;
  const ObjectPixels& pixels = *state.pixels;
  const bool fast = !context.variance && pixels.valuesFinite && std::isfinite(sigma2);
  if (fast) {
    // The usual case (no variance map, no bad pixel), without tests per pixel.
    const std::size_t n = pixels.size();
    const double threshold = haveLevel ? analysisAdu : -HUGE_VAL;
    for (std::size_t i = 0; i < n; ++i) {
      const double v = pixels.value[i];
      flux += v;
      fluxMax = std::max(fluxMax, v);
      isoArea += v > threshold;
    }
    used = std::int64_t(n);
  }
  for (std::size_t i = 0; i < pixels.size() && !fast; ++i) {
    const double v = pixels.value[i];
    const double var = context.variance ? pixels.variance[i] : sigma2;
    if (!std::isfinite(v) || !std::isfinite(var)) {
      state.octFlags |= octflag::kBadPixels;  // left out of every sum
      continue;
    }
    ++used;
    flux += v;
    fluxMax = std::max(fluxMax, v);
    varianceSum += var;
    if (context.variance && context.gain > 0.0 && v > 0.0 && sigma2 > 0.0) {
      poissonVar += v / context.gain * var / sigma2;
    }
    const double threshold = context.variance && context.sigmaAdu > 0.0
                                 ? analysisPerSigma * std::sqrt(var)
                                 : analysisAdu;
    // Without a known level every footprint pixel counts.
    if (!haveLevel || v > threshold) ++isoArea;
  }

  double fluxErr;
  if (context.variance) {
    // Per-pixel variances; the Poisson term weighted per pixel (WEIGHT_GAIN Y), or once when
    // the global sigma is unknown.
    if (sigma2 > 0.0) {
      fluxErr = std::sqrt(varianceSum + poissonVar);
    } else {
      fluxErr =
          std::sqrt(varianceSum + (context.gain > 0.0 && flux > 0.0 ? flux / context.gain : 0.0));
    }
  } else {
    fluxErr = isoFluxError(used, context.sigmaAdu, flux, context.gain);
  }
  if (used == 0) {
    flux = kNaN;
    fluxErr = kNaN;
    fluxMax = kNaN;
  }
  if (!(flux > 0.0)) state.octFlags |= octflag::kNonPositiveFlux;

  state.havePhotometry = used > 0;
  state.fluxIsoAdu = flux;
  state.fluxErrIsoAdu = fluxErr;
  state.fluxMaxAdu = fluxMax;
  state.isoArea = isoArea;
}

}  // namespace octarc
