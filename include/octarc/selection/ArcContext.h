// The context of a catalog row that its own octopole columns lack (the learned selection's
// inputs, selection/TreeModel.h): where the nearest brighter galaxy lies and how the row is
// oriented about it, and whether a counter-image lies on that galaxy's other side.
//
// Computed from catalog columns alone (X_IMAGE, Y_IMAGE, THRESH_LEVEL, NUMBER, PARENT_NUMBER,
// FLUX_ISO, SIZE_IMAGE, E1_IMAGE, E2_IMAGE, ARC_SIDE), the same way on a survey catalog and on a
// simulated lens system's stamp, so that a model trained on simulations reads survey rows alike.
//
// Definitions (positions 1-based pixels, core/Conventions.h):
//   neighbour: the nearest row (any level) brighter than the row (FLUX_ISO), more than
//     kContextSameObjectPix from it, within maxDistanceArcsec, and not one of its ancestors (the
//     objects of lower levels that contain it, through PARENT_NUMBER: an arc merged with its lens
//     at low levels has the lens in its ancestors, whose centroids are pulled towards the arc).
//   CTX_NB_DIST: the distance to it (arcsec); CTX_NB_DMAG: -2.5 log10(FLUX_ISO / its FLUX_ISO),
//     > 0; CTX_NB_DSIZE: the distance in units of its sqrt(2) SIZE_IMAGE.
//   CTX_TANGENT: the angle (deg, 0-90) between the row's major axis (0.5 atan2(E2, E1)) and the
//     tangential direction about the neighbour (perpendicular to the line joining them): 0 for an
//     arc around it.
//   CTX_CONCAVE: +1 when the neighbour lies on the row's concave side (the +b side of the
//     octopole frame times ARC_SIDE), -1 on the convex side, 0 when ARC_SIDE is 0.
//   counter-image: among rows (any level) that are not the row's ancestors, more than 0.25 and
//     at most 1.5 times the neighbour distance from the neighbour, on its other side (the angle
//     at the neighbour between the row and it at least 135 deg), and fainter than the
//     neighbour, the brightest. CTX_COUNTER: its distance from the neighbour over the row's;
//     CTX_COUNTER_DMAG: its magnitude minus the row's.
// NaN for what does not exist (no neighbour: every column; no counter-image: the two CTX_COUNTER
// columns), and for rows whose position is not finite, whose FLUX_ISO is not positive or whose
// THRESH_LEVEL or PARENT_NUMBER is not finite; rows of no positive flux are never neighbours'
// counter-images. A neighbour of SIZE_IMAGE 0 gives an infinite CTX_NB_DSIZE (the features read
// it as missing, selection/LensModel.h).
#pragma once

#include <string>
#include <vector>

#include "octarc/core/Column.h"
#include "octarc/core/Table.h"

namespace octarc {

inline constexpr double kContextSameObjectPix = 0.5;

struct ArcContextSettings {
  double pixelScaleArcsec = 0.0;  // > 0
  double maxDistanceArcsec = 6.0;
};

struct ArcContext {
  double neighbourDistanceArcsec;
  double neighbourDeltaMag;
  double neighbourDistanceInSizes;
  double tangentialAngleDeg;
  double concaveSide;
  double counterDistanceRatio;
  double counterDeltaMag;
};

// The columns, in ArcContext's order (Float32).
const std::vector<ColumnSpec>& arcContextColumns();
// The catalog columns read.
const std::vector<std::string>& arcContextInputColumns();

// One per catalog row. ConfigError naming a missing column, or for a pixel scale that is not
// positive.
std::vector<ArcContext> arcContexts(const Table& catalog, const ArcContextSettings& settings);

// ArcContext's fields in column order.
std::vector<double> contextValues(const ArcContext& context);

}  // namespace octarc
