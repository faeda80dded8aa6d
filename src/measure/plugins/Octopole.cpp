#include "octarc/measure/plugins/Octopole.h"

#include <cmath>
#include <vector>

#include "octarc/core/Flags.h"

namespace octarc {

std::vector<OutputColumn> Octopole::columns() const {
  const ColumnType f = ColumnType::Float32, d = ColumnType::Float64;
  // Every value is NaN (ARC_SIDE 0) when the octopole statistics are undefined (OctopoleStats).
  return {
      {{"ARCNESS", "Octopole arcness |I_aab|/SIZE_IMAGE**3", "", "src.morph", f, "%8.4f"},
       [](const MeasuredObject& o) { return o.state.octopole.arcness; }},
      {{"ANTIARCNESS", "Octopole anti-arcness I_abb/SIZE_IMAGE**3", "", "src.morph", f, "%8.4f"},
       [](const MeasuredObject& o) { return o.state.octopole.antiArcness; }},
      {{"SKEW_MAJOR", "Skewness along major axis I_aaa/SIZE_IMAGE**3", "", "src.morph", f, "%8.4f"},
       [](const MeasuredObject& o) { return o.state.octopole.skewA; }},
      {{"SKEW_MINOR", "Skewness along minor axis I_bbb/SIZE_IMAGE**3", "", "src.morph", f, "%8.4f"},
       [](const MeasuredObject& o) { return o.state.octopole.skewB; }},
      {{"I_AAB_IMAGE", "Third moment along major, major, minor axes", "pixel**3",
        "src.morph;instr.det", d, "%18.10e"},
       [](const MeasuredObject& o) { return o.state.octopole.iaab; }},
      {{"I_ABB_IMAGE", "Third moment along major, minor, minor axes", "pixel**3",
        "src.morph;instr.det", d, "%18.10e"},
       [](const MeasuredObject& o) { return o.state.octopole.iabb; }},
      {{"I_AAA_IMAGE", "Third moment along the major axis", "pixel**3", "src.morph;instr.det", d,
        "%18.10e"},
       [](const MeasuredObject& o) { return o.state.octopole.iaaa; }},
      {{"I_BBB_IMAGE", "Third moment along the minor axis", "pixel**3", "src.morph;instr.det", d,
        "%18.10e"},
       [](const MeasuredObject& o) { return o.state.octopole.ibbb; }},
      {{"ARC_SIDE", "Side of the curvature centre: sign(I_aab)", "", "src.morph;pos.posAng",
        ColumnType::Int16, "%2d"},
       [](const MeasuredObject& o) { return double(o.state.octopole.arcSide); }},
      {{"E1_IMAGE", "Distortion component (Ixx-Iyy)/(Ixx+Iyy)", "", "src.ellipticity;instr.det", f,
        "%9.5f"},
       [](const MeasuredObject& o) { return o.state.octopole.e1; }},
      {{"E2_IMAGE", "Distortion component 2Ixy/(Ixx+Iyy)", "", "src.ellipticity;instr.det", f,
        "%9.5f"},
       [](const MeasuredObject& o) { return o.state.octopole.e2; }},
      {{"E_IMAGE", "Distortion (a**2-b**2)/(a**2+b**2)", "", "src.ellipticity;instr.det", f,
        "%9.5f"},
       [](const MeasuredObject& o) { return o.state.octopole.e; }},
      {{"SIZE_IMAGE", "Size sqrt(Ixx+Iyy), unweighted moments", "pixel", "phys.size;instr.det", f,
        "%9.3f"},
       [](const MeasuredObject& o) { return o.state.octopole.sizePix; }},
  };
}

void Octopole::measure(const Segment&, const MeasureContext&, ObjectState& state) const {
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
}

}  // namespace octarc
