// The cluster of one process, for builds without MPI (OCTARC_MPI=OFF).
#include "octarc/cluster/Cluster.h"
#include "octarc/core/Error.h"

namespace octarc {

Cluster::Cluster() {
  if (launchedAsMpiRank()) {
    throw ConfigError(
        "launched by mpirun or srun, but this octarc was built without MPI (OCTARC_MPI=OFF): "
        "run it as one process, or as a job array (see octarc batch -h)");
  }
}

Cluster::~Cluster() = default;

void Cluster::distribute(std::int64_t count, const std::function<std::string(std::int64_t)>& work,
                         const std::function<void(std::int64_t, const std::string&)>& collect,
                         const std::function<bool(std::int64_t)>& take) const {
  for (std::int64_t i = 0; i < count; ++i) {
    if (!take || take(i)) collect(i, work(i));
  }
}

std::string Cluster::broadcast(const std::string& bytes) const {
  return bytes;
}

std::vector<std::string> Cluster::gather(const std::string& local) const {
  return {local};
}

void Cluster::abortIfFailedAlone(const std::string&) const {}

void Cluster::raiseIfAnyFailed(const std::exception_ptr& error) const {
  if (error) std::rethrow_exception(error);
}

}  // namespace octarc
