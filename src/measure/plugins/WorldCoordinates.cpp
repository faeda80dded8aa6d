#include "octarc/measure/plugins/WorldCoordinates.h"

#include <cmath>

#include "octarc/core/Conventions.h"
#include "octarc/core/Flags.h"
#include "octarc/io/Wcs.h"

namespace octarc {

std::vector<OutputColumn> WorldCoordinates::columns() const {
  const ColumnType f = ColumnType::Float32, d = ColumnType::Float64;
  // NaN wherever the WCS gives nothing (ObjectState's world part stays NaN).
  return {
      {{"X_WORLD", "Barycenter position along world x axis", "deg", "pos.eq.ra", d, "%18.10e"},
       [](const MeasuredObject& o) { return o.state.xWorldDeg; }},
      {{"Y_WORLD", "Barycenter position along world y axis", "deg", "pos.eq.dec", d, "%18.10e"},
       [](const MeasuredObject& o) { return o.state.yWorldDeg; }},
      {{"ALPHA_J2000", "Right ascension of barycenter (J2000)", "deg",
        "pos.eq.ra;pos.barycenter;meta.main", d, "%11.7f"},
       [](const MeasuredObject& o) { return o.state.alphaJ2000Deg; }},
      {{"DELTA_J2000", "Declination of barycenter (J2000)", "deg",
        "pos.eq.dec;pos.barycenter;meta.main", d, "%+11.7f"},
       [](const MeasuredObject& o) { return o.state.deltaJ2000Deg; }},
      {{"X2_WORLD", "Variance along X-WORLD (alpha)", "deg**2", "src.impactParam", d, "%18.10e"},
       [](const MeasuredObject& o) { return o.state.world.x2; }},
      {{"Y2_WORLD", "Variance along Y-WORLD (delta)", "deg**2", "src.impactParam", d, "%18.10e"},
       [](const MeasuredObject& o) { return o.state.world.y2; }},
      {{"XY_WORLD", "Covariance between X-WORLD and Y-WORLD", "deg**2", "src.impactParam", d,
        "%18.10e"},
       [](const MeasuredObject& o) { return o.state.world.xy; }},
      {{"A_WORLD", "Profile RMS along major axis (world units)", "deg",
        "phys.size.smajAxis;meta.main", f, "%12.7g"},
       [](const MeasuredObject& o) { return o.state.worldShape.a; }},
      {{"B_WORLD", "Profile RMS along minor axis (world units)", "deg",
        "phys.size.sminAxis;meta.main", f, "%12.7g"},
       [](const MeasuredObject& o) { return o.state.worldShape.b; }},
      {{"THETA_WORLD", "Position angle (CCW/world-x)", "deg", "pos.posAng", f, "%6.2f"},
       [](const MeasuredObject& o) { return o.state.worldShape.thetaDeg; }},
  };
}

void WorldCoordinates::measure(const Segment&, const MeasureContext& context,
                               ObjectState& state) const {
  if (!state.haveIso) return;  // no isophotal centroid: nothing to convert
  if (context.wcs == nullptr) {
    state.octFlags |= octflag::kNoWorld;
    return;
  }
  const Wcs& wcs = *context.wcs;
  // The centroid and one pixel along each axis from it (for the local Jacobian), in one call.
  const double xFits = toFitsPixel(state.iso.xMean), yFits = toFitsPixel(state.iso.yMean);
  const double pixels[6] = {xFits, yFits, xFits + 1.0, yFits, xFits, yFits + 1.0};
  double worlds[6];
  wcs.pixelsToWorld(pixels, 3, worlds);
  const std::array<double, 2> world = {worlds[0], worlds[1]};
  if (!std::isfinite(world[0]) || !std::isfinite(world[1])) {
    state.octFlags |= octflag::kNoWorld;
    return;
  }
  state.haveWorld = true;
  state.xWorldDeg = world[0];
  state.yWorldDeg = world[1];
  // NaN for non-equatorial frames: ALPHA/DELTA_J2000 have no meaning there.
  const std::array<double, 2> j2000 = wcs.worldToJ2000(world[0], world[1]);
  state.alphaJ2000Deg = j2000[0];
  state.deltaJ2000Deg = j2000[1];

  const WorldJacobian jacobian =
      jacobianFromSamples(world, {worlds[2], worlds[3]}, {worlds[4], worlds[5]});
  if (!jacobian.valid) {
    state.octFlags |= octflag::kNoWorld;
    return;
  }
  state.world = worldMoments(jacobian, state.iso.x2, state.iso.y2, state.iso.xy);
  state.worldShape = ellipseFromMoments(state.world.x2, state.world.y2, state.world.xy);
}

}  // namespace octarc
