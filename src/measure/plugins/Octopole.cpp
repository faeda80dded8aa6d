#include "octarc/measure/plugins/Octopole.h"

#include <cmath>
#include <vector>

#include "octarc/core/Flags.h"

namespace octarc {

namespace {
enum Col {
  kArcness,
  kAntiArcness,
  kSkewMajor,
  kSkewMinor,
  kIaab,
  kIabb,
  kIaaa,
  kIbbb,
  kArcSide,
  kE1,
  kE2,
  kE,
  kSize,
  kCount
};
}  // namespace

std::vector<ColumnSpec> Octopole::columns() const {
  const ColumnType f = ColumnType::Float32, d = ColumnType::Float64;
  return {
      {"ARCNESS", "Octopole arcness |I_aab|/SIZE_IMAGE**3", "", "src.morph", f, "%8.4f"},
      {"ANTIARCNESS", "Octopole anti-arcness I_abb/SIZE_IMAGE**3", "", "src.morph", f, "%8.4f"},
      {"SKEW_MAJOR", "Skewness along major axis I_aaa/SIZE_IMAGE**3", "", "src.morph", f, "%8.4f"},
      {"SKEW_MINOR", "Skewness along minor axis I_bbb/SIZE_IMAGE**3", "", "src.morph", f, "%8.4f"},
      {"I_AAB_IMAGE", "Third moment along major, major, minor axes", "pixel**3",
       "src.morph;instr.det", d, "%18.10e"},
      {"I_ABB_IMAGE", "Third moment along major, minor, minor axes", "pixel**3",
       "src.morph;instr.det", d, "%18.10e"},
      {"I_AAA_IMAGE", "Third moment along the major axis", "pixel**3", "src.morph;instr.det", d,
       "%18.10e"},
      {"I_BBB_IMAGE", "Third moment along the minor axis", "pixel**3", "src.morph;instr.det", d,
       "%18.10e"},
      {"ARC_SIDE", "Side of the curvature centre: sign(I_aab)", "", "src.morph;pos.posAng",
       ColumnType::Int16, "%2d"},
      {"E1_IMAGE", "Distortion component (Ixx-Iyy)/(Ixx+Iyy)", "", "src.ellipticity;instr.det", f,
       "%9.5f"},
      {"E2_IMAGE", "Distortion component 2Ixy/(Ixx+Iyy)", "", "src.ellipticity;instr.det", f,
       "%9.5f"},
      {"E_IMAGE", "Distortion (a**2-b**2)/(a**2+b**2)", "", "src.ellipticity;instr.det", f,
       "%9.5f"},
      {"SIZE_IMAGE", "Size sqrt(Ixx+Iyy), unweighted moments", "pixel", "phys.size;instr.det", f,
       "%9.3f"},
  };
}

void Octopole::measure(const Segment&, const MeasureContext&, ObjectState& state,
                       const RowWriter& out) const {
  const ObjectPixels& pixels = *state.pixels;
  if (pixels.valuesFinite) {
    state.central = centralMoments(pixels.x, pixels.y, pixels.value);
  } else {
    // Non-finite pixels are left out of every sum.
    state.octFlags |= octflag::kBadPixels;
    std::vector<double> xs, ys, ws;
    for (std::size_t i = 0; i < pixels.size(); ++i) {
      if (!std::isfinite(pixels.value[i])) continue;
      xs.push_back(pixels.x[i]);
      ys.push_back(pixels.y[i]);
      ws.push_back(pixels.value[i]);
    }
    state.central = centralMoments(xs, ys, ws);
  }
  state.octopole = octopoleStats(state.central);
  state.haveCentral = state.central.valid;
  if (!state.central.valid)
    state.octFlags |= octflag::kNonPositiveFlux;
  else if (!state.octopole.valid)
    state.octFlags |= octflag::kSingularMoments;

  const OctopoleStats& o = state.octopole;
  out.set(kArcness, o.arcness);
  out.set(kAntiArcness, o.antiArcness);
  out.set(kSkewMajor, o.skewA);
  out.set(kSkewMinor, o.skewB);
  out.set(kIaab, o.iaab);
  out.set(kIabb, o.iabb);
  out.set(kIaaa, o.iaaa);
  out.set(kIbbb, o.ibbb);
  out.set(kArcSide, o.arcSide);
  out.set(kE1, o.e1);
  out.set(kE2, o.e2);
  out.set(kE, o.e);
  out.set(kSize, o.sizePix);
}

}  // namespace octarc
