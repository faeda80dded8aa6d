// Which injected lenses of a simulated field a search found (the measured completeness and
// purity of the README's "Completeness and purity"): the field's truth list against the
// candidates.
//
// A candidate is an arc of system S when one of its passing rows (resolved by the search's own
// cut) lies at least ArcRules::minDistanceArcsec from S's lens and within `matchArcsec` of one
// of S's lensed images; the first such system, by id, when several qualify. A candidate that is
// no injected arc is spurious. Its lens is right when the lens it names lies within
// `lensMatchArcsec` of S's lens.
#pragma once

#include <cstdint>
#include <vector>

#include "octarc/core/Table.h"
#include "octarc/search/Search.h"
#include "octarc/simulation/engine/FieldSimulation.h"
#include "octarc/simulation/engine/LensSimulation.h"

namespace octarc {

struct InjectedLensOutcome {
  int system = 0;
  double einsteinRadiusArcsec = 0.0;  // truth
  double arcMag = 0.0;                // the brightest lensed image's magnitude (truth)
  std::int64_t candidate = -1;        // index of the (first) candidate that is one of its arcs
  std::uint32_t spaces = 0;           // the report spaces of that candidate
  bool lensRight = false;             // the candidate names this system's lens
  double einsteinRadiusEstimateArcsec = 0.0;  // the candidate's THETA_E (0 without a lens)
};

struct InjectionMatch {
  std::vector<InjectedLensOutcome> systems;  // every injected system, by id
  std::vector<int> candidateSystem;          // per candidate: the system it is an arc of, or 0
  std::int64_t spurious() const;             // candidates that are no injected arc
};

// ConfigError when the catalog lacks X_IMAGE or Y_IMAGE.
InjectionMatch matchInjectedLenses(const std::vector<TruthRow>& truth, const Table& catalog,
                                   const SearchResult& result, double pixelScaleArcsec,
                                   const ArcRules& rules, double matchArcsec,
                                   double lensMatchArcsec);

}  // namespace octarc
