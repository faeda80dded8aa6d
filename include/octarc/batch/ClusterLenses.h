// `octarc simulate lenses` on the ranks of an MPI job: calibration sets of 10^6 systems as one
// cluster job. Rank r of N simulates the systems [count r / N, count (r + 1) / N); each system
// depends only on the master seed and its index (simulation/Seeds.h), so the root's gathered
// tables, in index order, hold the same data as one process makes.
#pragma once

#include "octarc/cluster/Cluster.h"
#include "octarc/simulation/engine/LensCatalog.h"

namespace octarc {

// The whole run on the root (the stamps of its first `stampCount` systems included); on the
// other ranks an empty run. `progress` is called on the root, for its own share.
LensRun runLensSimulationOnCluster(const Cluster& cluster, const SimulationSetup& setup,
                                   const SourceDatabase& sources, std::uint64_t seed,
                                   std::int64_t count, int threads, int stampCount,
                                   const ProgressFn& progress);

}  // namespace octarc
