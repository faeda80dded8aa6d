#include "octarc/measure/plugins/IsophotalPhotometry.h"

#include <algorithm>
#include <cmath>

#include "octarc/core/Conventions.h"
#include "octarc/core/Flags.h"

namespace octarc {

namespace {
enum Col { kIsoArea, kFluxIso, kFluxErrIso, kMagIso, kMagErrIso, kFluxMax, kSnrIso };
}  // namespace

std::vector<ColumnSpec> IsophotalPhotometry::columns() const {
  const ColumnType f = ColumnType::Float32;
  return {
      {"ISOAREA_IMAGE", "Isophotal area above Analysis threshold", "pixel**2", "phys.area",
       ColumnType::Int32, "%9d"},
      {"FLUX_ISO", "Isophotal flux", "count", "phot.flux", f, "%12.7g"},
      {"FLUXERR_ISO", "RMS error for isophotal flux", "count", "stat.stdev;phot.flux", f, "%12.7g"},
      {"MAG_ISO", "Isophotal magnitude", "mag", "phot.mag", f, "%8.4f"},
      {"MAGERR_ISO", "RMS error for isophotal magnitude", "mag", "stat.stdev;phot.mag", f, "%8.4f"},
      {"FLUX_MAX", "Peak flux above background", "count", "phot.flux.sb;stat.max", f, "%12.7g"},
      {"SNR_ISO", "Isophotal S/N, FLUX_ISO/FLUXERR_ISO", "", "stat.snr", f, "%10.4g"},
  };
}

void IsophotalPhotometry::measure(const Segment& segment, const MeasureContext& context,
                                  ObjectState& state, const RowWriter& out) const {
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

  out.set(kIsoArea, double(isoArea));
  out.set(kFluxIso, flux);
  out.set(kFluxErrIso, fluxErr);
  out.set(kMagIso, used ? magnitude(flux, context.magZeropoint) : kMagUndefined);
  out.set(kMagErrIso, used ? magnitudeError(flux, fluxErr) : kMagUndefined);
  out.set(kFluxMax, fluxMax);
  out.set(kSnrIso, fluxErr > 0.0 ? flux / fluxErr : kNaN);
}

}  // namespace octarc
