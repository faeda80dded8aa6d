// The processes of a run: one process, or the ranks of an MPI job (mpirun, srun). MPI is used
// here and nowhere else; a build without it (OCTARC_MPI=OFF) has the one-process cluster only.
//
// A process is an MPI rank when its launcher says so in the environment (OMPI_COMM_WORLD_SIZE,
// PMIX_RANK, PMI_SIZE): `octarc batch` run by hand starts no MPI at all.
//
// Everything that crosses between ranks is bytes (std::string): the callers serialise their
// own results, so that the MPI calls stay a handful of well-known ones.
#pragma once

#include <cstdint>
#include <exception>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace octarc {

// Thrown on the ranks that stop because another one failed first (that one prints the error):
// main() ends such a rank with status 1 and no message of its own.
class PeerFailed : public std::runtime_error {
 public:
  PeerFailed() : std::runtime_error("another rank failed") {}
};

class Cluster {
 public:
  // Starts MPI when the process was launched as a rank (see above), else a cluster of one.
  // ConfigError when launched as a rank by a build without MPI. MPI ends with the object.
  Cluster();
  ~Cluster();
  Cluster(const Cluster&) = delete;
  Cluster& operator=(const Cluster&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool isRoot() const { return rank_ == 0; }
  bool usesMpi() const { return usesMpi_; }
  // Ranks of this job on this machine (1 without MPI).
  int ranksOnThisNode() const { return ranksOnNode_; }
  // Worker threads for one rank: `requested` when positive; else the CPUs the launcher bound
  // the rank to, or, unbound, the machine's cores shared between its ranks (at least 1).
  int threadsPerRank(int requested) const;

  // Dynamic scheduling of tasks 0..count-1: each rank, the root included, asks for the next
  // task as soon as it is free (tasks differ in cost). work(i) runs on the rank that got i and
  // returns a report; collect(i, report) runs on the root's calling thread, once per task, as
  // reports arrive. work must not throw (a failed task is a report). On the root, work runs on
  // a thread of its own while the calling thread serves the other ranks; without MPI, tasks
  // run in order on the calling thread. When given, take(i) runs on the root just before task
  // i would be handed out, on either of the root's threads (it must be thread-safe): false
  // skips the task (no work, no collect); an exception from it ends the run as collect's do.
  void distribute(std::int64_t count, const std::function<std::string(std::int64_t)>& work,
                  const std::function<void(std::int64_t, const std::string&)>& collect,
                  const std::function<bool(std::int64_t)>& take = {}) const;

  // The root's bytes on every rank (the root's `bytes`; the others' are ignored).
  std::string broadcast(const std::string& bytes) const;
  // Every rank's bytes at the root, in rank order (one element per rank); empty elsewhere.
  std::vector<std::string> gather(const std::string& local) const;
  // For a command's last catch: an error that only this rank met (not one raiseIfAnyFailed
  // shared) leaves the other ranks waiting for it, so the whole job ends here, after `message`
  // is printed. Does nothing without MPI, on one rank, or for an error every rank knows of.
  void abortIfFailedAlone(const std::string& message) const;
  // After a step every rank ran: when any rank's `error` is set (the exception it caught), the
  // lowest such rank rethrows its own and every other rank throws PeerFailed; otherwise
  // returns. Without MPI: rethrows `error` when set.
  void raiseIfAnyFailed(const std::exception_ptr& error) const;

 private:
  int rank_ = 0;
  int size_ = 1;
  int ranksOnNode_ = 1;
  bool usesMpi_ = false;
  mutable bool failureShared_ = false;  // raiseIfAnyFailed threw on every rank
};

// True when the environment says this process is an MPI rank.
bool launchedAsMpiRank();

// A wrong launch, said in one line (empty when there is nothing to say): Slurm started several
// tasks but MPI joined none of them (srun without --mpi=pmix where PMIx is not the default, say),
// so each runs as a job of one rank; or a job of several tasks runs this one process without
// srun. The arguments are Slurm's SLURM_STEP_NUM_TASKS, SLURM_NTASKS and SLURM_STEP_ID as the
// environment has them (nullptr: not set) and the ranks MPI sees.
std::string slurmLaunchWarning(const char* stepTasks, const char* jobTasks, const char* stepId,
                               int mpiRanks);

}  // namespace octarc
