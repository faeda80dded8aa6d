#include "octarc/cluster/Cluster.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "octarc/core/Error.h"

namespace octarc {
namespace {

// Without an MPI launcher's environment the cluster is this process alone.
TEST(Cluster, OneProcessRunsEveryTaskInOrder) {
  ASSERT_FALSE(launchedAsMpiRank());
  const Cluster cluster;
  EXPECT_EQ(cluster.rank(), 0);
  EXPECT_EQ(cluster.size(), 1);
  EXPECT_TRUE(cluster.isRoot());
  EXPECT_FALSE(cluster.usesMpi());
  std::string order;
  cluster.distribute(
      4, [](std::int64_t i) { return std::string(1, char('a' + i)); },
      [&](std::int64_t i, const std::string& report) { order += std::to_string(i) + report; });
  EXPECT_EQ(order, "0a1b2c3d");
  EXPECT_EQ(cluster.gather("bytes"), std::vector<std::string>{"bytes"});
  EXPECT_EQ(cluster.broadcast("plan"), "plan");
  EXPECT_EQ(cluster.threadsPerRank(3), 3);
  EXPECT_GE(cluster.threadsPerRank(0), 1);
  EXPECT_NO_THROW(cluster.raiseIfAnyFailed(nullptr));
  // The error itself, of its own type.
  EXPECT_THROW(cluster.raiseIfAnyFailed(std::make_exception_ptr(IoError("x.fits: gone"))), IoError);
}

TEST(Cluster, TakeSkipsTasksItRefuses) {
  const Cluster cluster;
  std::string order;
  cluster.distribute(
      5, [](std::int64_t i) { return std::string(1, char('a' + i)); },
      [&](std::int64_t i, const std::string& report) { order += std::to_string(i) + report; },
      [](std::int64_t i) { return i != 1 && i != 3; });
  EXPECT_EQ(order, "0a2c4e");
}

// Slurm's SLURM_STEP_NUM_TASKS, SLURM_NTASKS and SLURM_STEP_ID against the ranks MPI sees.
TEST(Cluster, SlurmTasksThatMpiDidNotJoinAreAWrongLaunch) {
  // srun of 16 tasks without --mpi=pmix: each task is a job of one rank.
  const std::string step = slurmLaunchWarning("16", "16", "0", 1);
  EXPECT_NE(step.find("Slurm started 16 tasks but MPI sees 1 rank"), std::string::npos) << step;
  EXPECT_NE(step.find("srun --mpi=pmix"), std::string::npos) << step;
  EXPECT_EQ(slurmLaunchWarning("16", "16", "0", 16), "");  // joined
  EXPECT_EQ(slurmLaunchWarning("1", "1", "0", 1), "");     // one task, as in a job array
  // Inside a step the step's own count holds (srun -n 1 in a job of 16 tasks).
  EXPECT_EQ(slurmLaunchWarning("1", "16", "3", 1), "");
  EXPECT_NE(slurmLaunchWarning(nullptr, "4", "0", 1).find("Slurm started 4 tasks"),
            std::string::npos);
  EXPECT_NE(slurmLaunchWarning("8", nullptr, nullptr, 1).find("Slurm started 8 tasks"),
            std::string::npos);
  // The batch script of a job of 8 tasks, without srun.
  const std::string script = slurmLaunchWarning(nullptr, "8", nullptr, 1);
  EXPECT_NE(script.find("the Slurm job has 8 tasks but this is one process"), std::string::npos)
      << script;
  EXPECT_EQ(slurmLaunchWarning(nullptr, "8", nullptr, 8), "");  // mpirun in the script
  // Outside Slurm, or values that are not a count.
  EXPECT_EQ(slurmLaunchWarning(nullptr, nullptr, nullptr, 1), "");
  EXPECT_EQ(slurmLaunchWarning(nullptr, nullptr, "0", 1), "");
  EXPECT_EQ(slurmLaunchWarning("x", "16", "0", 1), "");
  EXPECT_EQ(slurmLaunchWarning("16x", "16", "0", 1), "");
}

}  // namespace
}  // namespace octarc
