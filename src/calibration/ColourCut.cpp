#include "octarc/calibration/ColourCut.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "octarc/core/Error.h"
#include "octarc/selection/ColumnExpression.h"

namespace octarc {

std::string arcColourColumn(const std::string& band) {
  return "ARC_COLOUR_" + band;
}

std::string lensColourColumn(const std::string& band) {
  return "LENS_COLOUR_" + band;
}

void checkColourCutSettings(const ColourCutSettings& s) {
  if (!std::isfinite(s.maxLoMag) || !std::isfinite(s.maxHiMag) || !(s.stepMag > 0) ||
      !(s.maxHiMag >= s.maxLoMag) || (s.maxHiMag - s.maxLoMag) / s.stepMag > 10000.0) {
    throw ConfigError(
        "COLOUR_CUT_MAX: give the lowest and highest MAX and a positive step (mag), lowest <= "
        "highest, at most 10000 steps");
  }
  for (const double level : s.completenessLevels) {
    if (!(level > 0 && level <= 1)) {
      throw ConfigError("colour cut study: completeness levels must be in (0, 1]");
    }
  }
}

ColourCutStudy colourCutStudy(const Table& systems, const std::string& band,
                              const std::string& arcSelection, const ColourCutSettings& s) {
  checkColourCutSettings(s);
  const std::string context = "colour cut study (band " + band + ")";
  const int arcColour = systems.requireColumn(arcColourColumn(band), context);
  const int lensColour = systems.requireColumn(lensColourColumn(band), context);
  const std::vector<double> pass = ColumnExpression(arcSelection, context).evaluate(systems);
  const std::vector<double> weights = systemWeights(systems);
  ColourCutStudy out;
  out.band = band;
  out.arcSelection = arcSelection;
  std::vector<std::pair<double, double>> withColours;  // (difference, weight)
  WeightedCount withoutColours;
  for (std::int64_t r = 0; r < systems.rows(); ++r) {
    const double p = pass[std::size_t(r)];
    if (!std::isfinite(p) || p == 0.0) continue;
    const double w = weights[std::size_t(r)];
    out.arcs.add(w);
    const double difference = systems.value(r, arcColour) - systems.value(r, lensColour);
    if (std::isfinite(difference)) {
      withColours.emplace_back(difference, w);
    } else {
      withoutColours.add(w);
    }
  }
  std::sort(withColours.begin(), withColours.end());
  out.withColours = std::int64_t(withColours.size());
  // Cumulative weights of the sorted differences: keptBelow[i] = weight of the first i.
  std::vector<double> keptBelow = {0.0};
  for (const auto& [difference, w] : withColours) {
    out.differences.push_back(difference);
    out.differenceWeights.push_back(w);
    keptBelow.push_back(keptBelow.back() + w);
  }
  const double total = out.arcs.weightSum, effective = out.arcs.effective();
  // The arcs without both colours are kept at every MAX.
  const auto steps = std::int64_t(std::floor((s.maxHiMag - s.maxLoMag) / s.stepMag + 1e-9));
  for (std::int64_t k = 0; k <= steps; ++k) {
    ColourCutRow row;
    row.maxMag = s.maxLoMag + double(k) * s.stepMag;
    // Removed when the difference exceeds MAX: kept when difference <= MAX.
    const auto notAbove =
        std::size_t(std::upper_bound(out.differences.begin(), out.differences.end(), row.maxMag) -
                    out.differences.begin());
    row.kept = withoutColours.count + std::int64_t(notAbove);
    row.keptWeight = withoutColours.weightSum + keptBelow[notAbove];
    row.fraction = weightedFractionInterval(total > 0 ? row.keptWeight / total : 0.0, effective);
    out.rows.push_back(row);
  }
  for (const double level : s.completenessLevels) {
    ColourCutLevel l;
    l.completeness = level;
    // The least weight to keep, level x the total (with a relative tolerance for a product that
    // rounds above a sum it equals), of which the arcs without colours are kept whatever MAX.
    const double needed = level * total * (1.0 - 1e-12) - withoutColours.weightSum;
    if (out.arcs.count == 0) {
      l.maxMag = std::nan("");
    } else if (needed <= 0.0) {
      l.maxMag = -std::numeric_limits<double>::infinity();
    } else {
      // The first difference whose cumulative weight reaches `needed`.
      const auto reach = std::lower_bound(keptBelow.begin() + 1, keptBelow.end(), needed);
      l.maxMag = reach == keptBelow.end()
                     ? out.differences.back()
                     : out.differences[std::size_t(reach - keptBelow.begin()) - 1];
    }
    out.levels.push_back(l);
  }
  return out;
}

}  // namespace octarc
