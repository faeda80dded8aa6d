#include "octarc/selection/Connectivity.h"

#include <unordered_map>
#include <vector>

namespace octarc {

Connectivity analyseConnectivity(const GridBinning& binning,
                                 const std::vector<BinIndex>& selected) {
  // Bin -> component label (-1: not yet labelled); lookups cost O(1), so the whole analysis is
  // O(selected bins x axes) whatever the size of the grid.
  std::unordered_map<BinIndex, std::int64_t> label;
  label.reserve(selected.size());
  for (BinIndex b : selected) label.emplace(b, -1);

  Connectivity result;
  std::vector<BinIndex> stack;
  for (BinIndex start : selected) {
    if (label[start] >= 0) continue;
    const std::int64_t component = result.components++;
    label[start] = component;
    stack.push_back(start);
    while (!stack.empty()) {
      const BinIndex b = stack.back();
      stack.pop_back();
      bool touches = false;
      for (int axis = 0; axis < binning.dimensions(); ++axis) {
        for (int step : {-1, 1}) {
          const std::optional<BinIndex> n = binning.neighbour(b, axis, step);
          if (!n) continue;
          const auto it = label.find(*n);
          if (it == label.end()) continue;
          touches = true;
          if (it->second < 0) {
            it->second = component;
            stack.push_back(*n);
          }
        }
      }
      if (!touches) ++result.isolatedBins;
    }
  }
  result.connected = !selected.empty() && result.isolatedBins == 0;
  return result;
}

}  // namespace octarc
