#include "octarc/batch/ClusterLenses.h"

#include <cstring>
#include <optional>

#include "octarc/core/AtomicFile.h"
#include "octarc/core/Error.h"

namespace octarc {

namespace {

template <typename T>
void put(std::string& out, const T& value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof value);
}

template <typename T>
T take(const std::string& in, std::size_t& at) {
  if (at + sizeof(T) > in.size()) throw Error("simulate lenses: a rank's results are cut short");
  T value;
  std::memcpy(&value, in.data() + at, sizeof value);
  at += sizeof value;
  return value;
}

void putTable(std::string& out, const Table& t) {
  put(out, t.rows());
  for (std::int64_t r = 0; r < t.rows(); ++r) {
    out.append(reinterpret_cast<const char*>(t.row(r)), sizeof(double) * std::size_t(t.rowWidth()));
  }
}

void appendTable(Table& to, const std::string& in, std::size_t& at) {
  const std::int64_t rows = take<std::int64_t>(in, at);
  const std::size_t bytes = sizeof(double) * std::size_t(to.rowWidth());
  if (rows < 0 || at + std::size_t(rows) * bytes > in.size()) {
    throw Error("simulate lenses: a rank's results are cut short");
  }
  for (std::int64_t r = 0; r < rows; ++r) {
    std::memcpy(to.appendRowUnset(), in.data() + at, bytes);
    at += bytes;
  }
}

// A rank's share as bytes: counters, timings, then the two tables' rows.
std::string serialise(const LensRun& run) {
  std::string out;
  put(out, run.systemsWithArc);
  put(out, run.redraws);
  put(out, run.rejections);
  put(out, run.skipped);
  put(out, run.drawn);
  put(out, run.rendered);
  const StageTimings& t = run.timings;
  for (const double v : {t.drawSec, t.rayTraceSec, t.lensLightSec, t.psfSec, t.noiseSec,
                         t.detectionSec, t.arcRulesSec}) {
    put(out, v);
  }
  putTable(out, run.systems);
  putTable(out, run.arcs);
  return out;
}

void appendShare(LensRun& run, const std::string& in) {
  std::size_t at = 0;
  run.systemsWithArc += take<std::int64_t>(in, at);
  run.redraws += take<std::int64_t>(in, at);
  run.rejections += take<std::int64_t>(in, at);
  run.skipped += take<std::int64_t>(in, at);
  run.drawn += take<std::int64_t>(in, at);
  run.rendered += take<std::int64_t>(in, at);
  StageTimings t;
  for (double* v : {&t.drawSec, &t.rayTraceSec, &t.lensLightSec, &t.psfSec, &t.noiseSec,
                    &t.detectionSec, &t.arcRulesSec}) {
    *v = take<double>(in, at);
  }
  run.timings.add(t);
  appendTable(run.systems, in, at);
  appendTable(run.arcs, in, at);
}

}  // namespace

LensRun runLensSimulationOnCluster(const Cluster& cluster, const SimulationSetup& setup,
                                   const SourceDatabase& sources, std::uint64_t seed,
                                   std::int64_t count, int threads, int stampCount,
                                   const ProgressFn& progress) {
  if (cluster.size() == 1) {
    return runLensSimulation(setup, sources, seed, count, threads, stampCount, progress);
  }
  const std::int64_t n = cluster.size(), r = cluster.rank();
  const std::int64_t first = count * r / n, last = count * (r + 1) / n;
  const int ownStamps = int(std::clamp<std::int64_t>(stampCount - first, 0, last - first));
  LensRun mine = runLensSimulation(setup, sources, seed, last - first, threads, ownStamps,
                                   cluster.isRoot() ? progress : ProgressFn(), first);
  const std::vector<std::string> shares = cluster.gather(cluster.isRoot() ? "" : serialise(mine));
  if (!cluster.isRoot()) return LensRun();
  LensRun all = std::move(mine);
  for (std::size_t k = 1; k < shares.size(); ++k) appendShare(all, shares[k]);
  all.sumWeights();  // in row order, as on one rank
  // Stamps beyond the root's share are remade here: a system is the same wherever it is made.
  for (std::int64_t i = std::int64_t(all.stamps.size()); i < stampCount; ++i) {
    all.stamps.push_back(simulateSystem(setup, sources, seed, i, true).image);
  }
  return all;
}

LensRun runLensJob(const Cluster& cluster, const SimulationSetup& setup,
                   const std::function<SourceDatabase()>& makeSources, const LensJob& job,
                   const ProgressFn& progress) {
  std::optional<SourceDatabase> sources;
  OutputFiles outputs;
  std::exception_ptr error;
  try {
    sources = makeSources();
    // The output names are checked before any system is simulated.
    if (cluster.isRoot()) {
      outputs.add(job.catalogPath);
      if (!job.stampsPath.empty()) outputs.add(job.stampsPath);
      for (const auto& [option, path] : job.inputs) {
        for (std::size_t i = 0; i < outputs.size(); ++i) {
          refuseOutputOverInput(outputs[i].finalPath(), i == 0 ? "-o" : "--stamps", path,
                                option + " file");
        }
      }
    }
    (void)drawLensSystem(setup, *sources, job.seed, 0);
  } catch (const Error&) {
    error = std::current_exception();
  }
  cluster.raiseIfAnyFailed(error);

  LensRun run;
  try {
    run = runLensSimulationOnCluster(cluster, setup, *sources, job.seed, job.count,
                                     job.threadsPerRank, job.stampCount, progress);
    if (!cluster.isRoot()) return run;
    outputs.write(0, [&](const std::string& path) {
      writeLensCatalog(path, run, lensRunCards(run, setup, *sources, job.seed));
    });
    if (!job.stampsPath.empty()) {
      outputs.write(1, [&](const std::string& path) {
        writeLensStamps(path, run, setup.observing.grid.pixelScaleArcsec);
      });
    }
    outputs.commit();
  } catch (const std::exception& e) {
    cluster.abortIfFailedAlone(e.what());  // the other ranks would wait for this one
    throw;
  }
  return run;
}

}  // namespace octarc
