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

}  // namespace
}  // namespace octarc
