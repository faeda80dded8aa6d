// `octarc simulate lenses` on the ranks of an MPI job: calibration sets of 10^6 systems as one
// cluster job. Rank r of N simulates the systems [count r / N, count (r + 1) / N); each system
// depends only on the master seed and its index (simulation/Seeds.h), so the root's gathered
// tables, in index order, hold the same data as one process makes.
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "octarc/cluster/Cluster.h"
#include "octarc/simulation/engine/LensCatalog.h"

namespace octarc {

// The whole run on the root (the stamps of its first `stampCount` systems included); on the
// other ranks an empty run. `progress` is called on the root, for its own share.
LensRun runLensSimulationOnCluster(const Cluster& cluster, const SimulationSetup& setup,
                                   const SourceDatabase& sources, std::uint64_t seed,
                                   std::int64_t count, int threads, int stampCount,
                                   const ProgressFn& progress);

// A whole `octarc simulate lenses` run and the files it writes.
struct LensJob {
  std::uint64_t seed = 1;
  std::int64_t count = 0;
  int threadsPerRank = 0;
  std::string catalogPath;  // FITS-LDAC: the systems and their arc rows
  std::string stampsPath;   // "": none; else the stamps of the first `stampCount` systems
  int stampCount = 0;
  // The files the run reads, as (option, path): no output may overwrite one.
  std::vector<std::pair<std::string, std::string>> inputs;
};

// Checks the outputs (on the root) and draws system 0 on this thread, so that bad settings
// (e.g. a sigma range giving no lenses) fail with one message before any thread starts; a
// failure on any rank stops every rank. Then runs the job on the cluster and the root writes
// its files, which appear together. `makeSources` is called on every rank. Returns the run
// (empty on the other ranks).
LensRun runLensJob(const Cluster& cluster, const SimulationSetup& setup,
                   const std::function<SourceDatabase()>& makeSources, const LensJob& job,
                   const ProgressFn& progress);

}  // namespace octarc
