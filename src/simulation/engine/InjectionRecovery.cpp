#include "octarc/simulation/engine/InjectionRecovery.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ostream>
#include <string>

#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/core/Statistics.h"

namespace octarc {

RecoveryRows recoveryRows(const Table& table, const std::vector<std::int64_t>& order) {
  auto column = [&](const char* name) {
    const int c = table.requireColumn(name, "injection recovery");
    const ColumnType type = table.columns()[std::size_t(c)].type;
    std::vector<double> values;
    for (std::int64_t i = 0; i < table.rows(); ++i) {
      values.push_back(
          storedFloatValue(type, table.value(order.empty() ? i : order[std::size_t(i)], c)));
    }
    return values;
  };
  RecoveryRows c;
  c.level = column("THRESH_LEVEL");
  c.threshold = column("THRESHOLD");
  c.x = column("X_IMAGE");
  c.y = column("Y_IMAGE");
  c.arcness = column("ARCNESS");
  c.size = column("SIZE_IMAGE");
  c.snr = column("SNR_ISO");
  return c;
}

InjectionRecovery recoverInjectedArcs(const std::vector<TruthRow>& truth, const RecoveryRows& cat,
                                      double scale, const ArcRules& rules, double matchArcsec) {
  InjectionRecovery out;
  for (std::size_t i = 0; i < cat.rows(); ++i) {
    const int l = int(cat.level[i]);
    out.objectsPerLevel[l]++;
    out.levelThresholdAdu[l] = cat.threshold[i];
    out.levelCount = std::max(out.levelCount, l);
  }
  for (const TruthRow& r : truth) {
    if (r.systemId == 0) continue;
    InjectedSystem& sys = out.systems[r.systemId];
    sys.einsteinRadiusArcsec = r.einsteinRadiusArcsec;
    if (r.kind == simulation::FieldObjectKind::LensGalaxy) {
      sys.lensXPix = r.xFits;
      sys.lensYPix = r.yFits;
    } else {
      sys.imagesPix.push_back({r.xFits, r.yFits});
    }
  }
  for (std::size_t i = 0; i < cat.rows(); ++i) {
    const bool resolved = std::sqrt(2.0) * cat.size[i] * scale > rules.minSizeArcsec;
    int arcOf = 0;
    bool nearSystem = false;
    for (auto& [id, sys] : out.systems) {
      const double fromLens = std::hypot(cat.x[i] - sys.lensXPix, cat.y[i] - sys.lensYPix) * scale;
      if (fromLens < sys.einsteinRadiusArcsec + 2.0 * matchArcsec) nearSystem = true;
      if (fromLens < rules.minDistanceArcsec || !resolved) continue;
      for (const auto& im : sys.imagesPix) {
        if (std::hypot(cat.x[i] - im[0], cat.y[i] - im[1]) * scale < matchArcsec) arcOf = id;
      }
    }
    if (arcOf && std::isfinite(cat.arcness[i])) {
      out.arcArcness.push_back(cat.arcness[i]);
      InjectedSystem& sys = out.systems[arcOf];
      if (sys.bestRow < 0 || cat.arcness[i] > cat.arcness[std::size_t(sys.bestRow)])
        sys.bestRow = std::int64_t(i);
    } else if (!nearSystem && resolved && std::isfinite(cat.arcness[i])) {
      out.otherArcness.push_back(cat.arcness[i]);
    }
  }
  for (const auto& [id, sys] : out.systems) {
    if (sys.bestRow >= 0) out.bestArcness.push_back(cat.arcness[std::size_t(sys.bestRow)]);
  }
  return out;
}

void printRecovery(std::ostream& o, const InjectionRecovery& r, const RecoveryRows& cat,
                   const ArcRules& rules, double matchArcsec, double arcLikeArcness) {
  o << "  level  threshold [ADU]  objects\n";
  for (const auto& [level, count] : r.objectsPerLevel) {
    char line[80];
    std::snprintf(line, sizeof line, "  %5d  %15.3f  %7lld\n", level, r.levelThresholdAdu.at(level),
                  static_cast<long long>(count));
    o << line;
  }
  o << "\nInjected arcs detected: " << r.bestArcness.size() << " of " << r.systems.size()
    << " systems (an object >= " << rules.minDistanceArcsec << "\" from the lens, sqrt(2) size > "
    << rules.minSizeArcsec << "\", within " << matchArcsec
    << "\" of a lensed image, at some level)\n"
    << "  median best ARCNESS " << formatNumber(sampleMedian(r.bestArcness), "%.3f", true) << "\n"
    << "  system  theta_E[\"]  best ARCNESS  level     S/N\n";
  for (const auto& [id, sys] : r.systems) {
    char line[128];
    if (sys.bestRow >= 0) {
      const auto row = std::size_t(sys.bestRow);
      std::snprintf(line, sizeof line, "  %6d  %10.2f  %12.3f  %5d  %6.1f\n", id,
                    sys.einsteinRadiusArcsec, cat.arcness[row], int(cat.level[row]), cat.snr[row]);
    } else {
      std::snprintf(line, sizeof line, "  %6d  %10.2f  %12s  %5s  %6s\n", id,
                    sys.einsteinRadiusArcsec, "not found", "-", "-");
    }
    o << line;
  }
  o << "\nArcness (resolved objects, every level):\n"
    << "  injected arcs   " << r.arcArcness.size() << " rows: median "
    << formatNumber(sampleMedian(r.arcArcness), "%.3f", true) << ", "
    << formatNumber(100.0 * fractionAbove(r.arcArcness, arcLikeArcness), "%.0f", true) << "% above "
    << arcLikeArcness << "\n"
    << "  other objects   " << r.otherArcness.size() << " rows: median "
    << formatNumber(sampleMedian(r.otherArcness), "%.3f", true) << ", "
    << formatNumber(100.0 * fractionAbove(r.otherArcness, arcLikeArcness), "%.1f", true)
    << "% above " << arcLikeArcness << "\n";
}

double fractionAbove(const std::vector<double>& v, double cut) {
  if (v.empty()) return std::nan("");
  return double(std::count_if(v.begin(), v.end(), [cut](double a) { return a > cut; })) /
         double(v.size());
}

}  // namespace octarc
