#include "octarc/search/InjectionMatch.h"

#include <cmath>
#include <limits>
#include <map>

namespace octarc {

namespace {

struct TrueSystem {
  double lensX = std::numeric_limits<double>::quiet_NaN();
  double lensY = std::numeric_limits<double>::quiet_NaN();
  double einsteinRadiusArcsec = 0.0;
  double arcMag = std::numeric_limits<double>::infinity();
  std::vector<std::array<double, 2>> images;
};

}  // namespace

std::int64_t InjectionMatch::spurious() const {
  std::int64_t n = 0;
  for (const int s : candidateSystem) n += s == 0;
  return n;
}

InjectionMatch matchInjectedLenses(const std::vector<TruthRow>& truth, const Table& catalog,
                                   const SearchResult& result, double pixelScaleArcsec,
                                   const ArcRules& rules, double matchArcsec,
                                   double lensMatchArcsec) {
  const int cx = catalog.requireColumn("X_IMAGE", "injection match");
  const int cy = catalog.requireColumn("Y_IMAGE", "injection match");
  std::map<int, TrueSystem> systems;
  for (const TruthRow& t : truth) {
    if (t.systemId <= 0) continue;
    TrueSystem& s = systems[t.systemId];
    if (t.kind == simulation::FieldObjectKind::LensGalaxy) {
      s.lensX = t.xFits;
      s.lensY = t.yFits;
      s.einsteinRadiusArcsec = t.einsteinRadiusArcsec;
    } else if (t.kind == simulation::FieldObjectKind::LensedSource) {
      s.images.push_back({t.xFits, t.yFits});
      s.arcMag = std::min(s.arcMag, t.mag);
    }
  }
  const double matchPix = matchArcsec / pixelScaleArcsec;
  const double minDistancePix = rules.minDistanceArcsec / pixelScaleArcsec;
  // The system a row is an arc of, or 0.
  auto systemOf = [&](std::size_t row) {
    const double x = catalog.value(std::int64_t(row), cx);
    const double y = catalog.value(std::int64_t(row), cy);
    for (const auto& [id, s] : systems) {
      if (std::hypot(x - s.lensX, y - s.lensY) < minDistancePix) continue;
      for (const auto& image : s.images) {
        if (std::hypot(x - image[0], y - image[1]) <= matchPix) return id;
      }
    }
    return 0;
  };

  InjectionMatch out;
  std::map<int, InjectedLensOutcome> outcomes;
  for (const auto& [id, s] : systems) {
    InjectedLensOutcome o;
    o.system = id;
    o.einsteinRadiusArcsec = s.einsteinRadiusArcsec;
    o.arcMag = s.arcMag;
    outcomes[id] = o;
  }
  for (std::size_t i = 0; i < result.candidates.size(); ++i) {
    const Candidate& c = result.candidates[i];
    int id = 0;
    for (const std::size_t row : c.rows) {
      if ((id = systemOf(row)) != 0) break;
    }
    out.candidateSystem.push_back(id);
    if (id == 0 || outcomes[id].candidate >= 0) continue;
    InjectedLensOutcome& o = outcomes[id];
    o.candidate = std::int64_t(i);
    o.spaces = c.spaces;
    if (c.lens) {
      const TrueSystem& s = systems[id];
      o.lensRight = std::hypot(c.lens->xPix - s.lensX, c.lens->yPix - s.lensY) * pixelScaleArcsec <=
                    lensMatchArcsec;
      // 0 when the arc lies on the lens (no estimate), as without a lens.
      o.einsteinRadiusEstimateArcsec =
          std::isfinite(c.lens->einsteinRadiusArcsec) ? c.lens->einsteinRadiusArcsec : 0.0;
    }
  }
  for (auto& [id, o] : outcomes) out.systems.push_back(o);
  return out;
}

}  // namespace octarc
