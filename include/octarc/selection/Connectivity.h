// Connectivity of the bins a contour selects (METHOD.md section 4): the selected grid must stay
// connected, every selected bin touching another selected bin along at least one axis, i.e.
// having a selected face neighbour (selection/GridBinning.h: diagonal neighbours do not count).
// A lone selected bin touches nothing, so a contour of one bin is not connected.
//
// This is a local condition: two separate groups of bins, each bin of which has a neighbour,
// pass. The number of face-connected components is reported for information.
#pragma once

#include <cstdint>
#include <vector>

#include "octarc/selection/GridBinning.h"

namespace octarc {

struct Connectivity {
  bool connected = false;         // every selected bin has a selected face neighbour
  std::int64_t isolatedBins = 0;  // selected bins without one
  std::int64_t components = 0;    // face-connected components of the selected bins
};

// Connectivity of a set of bins (packed indices, each once). An empty set is not connected
// (and has no component).
Connectivity analyseConnectivity(const GridBinning& binning, const std::vector<BinIndex>& selected);

}  // namespace octarc
