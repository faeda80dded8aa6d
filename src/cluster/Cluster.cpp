// The parts of the cluster that do not depend on MPI.
#include "octarc/cluster/Cluster.h"

#include <sched.h>

#include <algorithm>
#include <cstdlib>
#include <string>
#include <thread>

namespace octarc {

bool launchedAsMpiRank() {
  // Open MPI's mpirun, PMIx launchers (srun --mpi=pmix, prterun) and PMI-1/2 (srun, MPICH).
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE"}) {
    if (std::getenv(name) != nullptr) return true;
  }
  return false;
}

std::string slurmLaunchWarning(const char* stepTasks, const char* jobTasks, const char* stepId,
                               int mpiRanks) {
  if (mpiRanks != 1) return {};
  const bool inStep = stepId != nullptr || stepTasks != nullptr;  // started by srun
  const char* tasksText = stepTasks != nullptr ? stepTasks : jobTasks;
  if (tasksText == nullptr) return {};
  char* end = nullptr;
  const long tasks = std::strtol(tasksText, &end, 10);
  if (end == tasksText || *end != '\0' || tasks <= 1) return {};
  const std::string n = std::to_string(tasks);
  if (inStep) {
    return "Slurm started " + n +
           " tasks but MPI sees 1 rank: launch with srun --mpi=pmix (or mpirun); each task now "
           "runs alone";
  }
  return "the Slurm job has " + n +
         " tasks but this is one process: launch with srun --mpi=pmix (or mpirun) to use them";
}

int Cluster::threadsPerRank(int requested) const {
  if (requested > 0) return requested;
  const int cores = std::max(1, int(std::thread::hardware_concurrency()));
  // A launcher that binds its ranks (srun --cpus-per-task, mpirun --bind-to) gives each the
  // CPUs it may use; an unbound rank shares the machine with the node's other ranks.
  cpu_set_t allowed;
  CPU_ZERO(&allowed);
  if (sched_getaffinity(0, sizeof allowed, &allowed) == 0) {
    const int bound = CPU_COUNT(&allowed);
    if (bound > 0 && bound < cores) return bound;
  }
  return std::max(1, cores / std::max(1, ranksOnNode_));
}

}  // namespace octarc
