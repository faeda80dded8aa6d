#include "octarc/measure/plugins/IsophotalShape.h"

#include <algorithm>
#include <cmath>

#include "octarc/core/Conventions.h"
#include "octarc/core/Flags.h"

namespace octarc {

std::vector<OutputColumn> IsophotalShape::columns() const {
  const ColumnType f = ColumnType::Float32, d = ColumnType::Float64;
  // Everything but the peak is NaN when the detection-weighted flux is not positive; the peak is
  // 1-based, 0 when there is no finite pixel.
  return {
      {{"X_IMAGE", "Object position along x", "pixel",
        "pos.cartesian.x;pos.barycenter;instr.det;meta.main", f, "%11.4f"},
       [](const MeasuredObject& o) {
         return o.state.haveIso ? toFitsPixel(o.state.iso.xMean) : kNaN;
       }},
      {{"Y_IMAGE", "Object position along y", "pixel",
        "pos.cartesian.y;pos.barycenter;instr.det;meta.main", f, "%11.4f"},
       [](const MeasuredObject& o) {
         return o.state.haveIso ? toFitsPixel(o.state.iso.yMean) : kNaN;
       }},
      {{"XPEAK_IMAGE", "x-coordinate of the brightest pixel", "pixel", "pos.cartesian.x",
        ColumnType::Int32, "%10d"},
       [](const MeasuredObject& o) {
         return o.state.xPeak >= 0 ? double(o.state.xPeak) + 1.0 : 0.0;
       }},
      {{"YPEAK_IMAGE", "y-coordinate of the brightest pixel", "pixel", "pos.cartesian.y",
        ColumnType::Int32, "%10d"},
       [](const MeasuredObject& o) {
         return o.state.yPeak >= 0 ? double(o.state.yPeak) + 1.0 : 0.0;
       }},
      {{"X2_IMAGE", "Variance along x", "pixel**2", "src.impactParam;instr.det", d, "%18.10e"},
       [](const MeasuredObject& o) { return o.state.haveIso ? o.state.iso.x2 : kNaN; }},
      {{"Y2_IMAGE", "Variance along y", "pixel**2", "src.impactParam;instr.det", d, "%18.10e"},
       [](const MeasuredObject& o) { return o.state.haveIso ? o.state.iso.y2 : kNaN; }},
      {{"XY_IMAGE", "Covariance between x and y", "pixel**2", "src.impactParam;instr.det", d,
        "%18.10e"},
       [](const MeasuredObject& o) { return o.state.haveIso ? o.state.iso.xy : kNaN; }},
      {{"A_IMAGE", "Profile RMS along major axis", "pixel",
        "phys.size.smajAxis;instr.det;meta.main", f, "%9.3f"},
       [](const MeasuredObject& o) { return o.state.haveIso ? o.state.isoShape.a : kNaN; }},
      {{"B_IMAGE", "Profile RMS along minor axis", "pixel",
        "phys.size.sminAxis;instr.det;meta.main", f, "%9.3f"},
       [](const MeasuredObject& o) { return o.state.haveIso ? o.state.isoShape.b : kNaN; }},
      {{"THETA_IMAGE", "Position angle (CCW/x)", "deg", "pos.posAng;instr.det;meta.main", f,
        "%6.2f"},
       [](const MeasuredObject& o) { return o.state.haveIso ? o.state.isoShape.thetaDeg : kNaN; }},
      {{"CXX_IMAGE", "Cxx object ellipse parameter", "pixel**(-2)", "src.impactParam;instr.det", f,
        "%15.7e"},
       [](const MeasuredObject& o) { return o.state.haveIso ? o.state.isoShape.cxx : kNaN; }},
      {{"CYY_IMAGE", "Cyy object ellipse parameter", "pixel**(-2)", "src.impactParam;instr.det", f,
        "%15.7e"},
       [](const MeasuredObject& o) { return o.state.haveIso ? o.state.isoShape.cyy : kNaN; }},
      {{"CXY_IMAGE", "Cxy object ellipse parameter", "pixel**(-2)", "src.impactParam;instr.det", f,
        "%15.7e"},
       [](const MeasuredObject& o) { return o.state.haveIso ? o.state.isoShape.cxy : kNaN; }},
      {{"ELONGATION", "A_IMAGE/B_IMAGE", "", "src.ellipticity;arith.ratio;instr.det", f, "%8.3f"},
       [](const MeasuredObject& o) {
         return o.state.haveIso ? o.state.isoShape.elongation : kNaN;
       }},
      {{"ELLIPTICITY", "1 - B_IMAGE/A_IMAGE", "", "src.ellipticity;instr.det", f, "%8.3f"},
       [](const MeasuredObject& o) {
         return o.state.haveIso ? o.state.isoShape.ellipticity : kNaN;
       }},
  };
}

void IsophotalShape::measure(const Segment&, const MeasureContext& context,
                             ObjectState& state) const {
  const std::int64_t width = context.measurement->width();
  const ObjectPixels& pixels = *state.pixels;
  // SExtractor sums relative to (xmin, ymin) to limit round-off; keep the same origin.
  IsoMomentAccumulator sums(double(state.xMin), double(state.yMin));
  double peak = -HUGE_VAL;
  std::int64_t peakIndex = -1;
  const std::vector<double>& detection = pixels.detectionValues();
  const std::size_t n = pixels.size();
  // The usual case has no bad pixel: the peak and a check for NaN or infinities in one pass,
  // then the sums without a test per pixel.
  int bad = 0;
  for (std::size_t i = 0; i < n; ++i) {
    peak = std::max(peak, detection[i]);
    bad |= int(!(std::fabs(detection[i]) < HUGE_VAL));
  }
  if (bad == 0) {
    sums.addAll(pixels.x, pixels.y, detection);
  } else {
    peak = -HUGE_VAL;
    state.octFlags |= octflag::kBadPixels;  // left out of every sum
    for (std::size_t i = 0; i < n; ++i) {
      if (!std::isfinite(detection[i])) continue;
      sums.add(pixels.x[i], pixels.y[i], detection[i]);
      peak = std::max(peak, detection[i]);
    }
  }
  // Ties go to the first pixel in raster order.
  for (std::size_t i = 0; i < n && std::isfinite(peak); ++i) {
    if (detection[i] != peak) continue;
    const std::int64_t p = std::int64_t(pixels.y[i]) * width + std::int64_t(pixels.x[i]);
    if (peakIndex < 0 || p < peakIndex) peakIndex = p;
  }
  state.iso = sums.result();
  if (peakIndex >= 0) {
    state.xPeak = peakIndex % width;
    state.yPeak = peakIndex / width;
  }
  if (!state.iso.valid) {
    state.octFlags |= octflag::kNonPositiveFlux;
    return;
  }
  if (state.iso.singular) state.octFlags |= octflag::kSingularIso;
  state.isoShape = ellipseFromMoments(state.iso.x2, state.iso.y2, state.iso.xy);
  state.haveIso = true;
}

}  // namespace octarc
