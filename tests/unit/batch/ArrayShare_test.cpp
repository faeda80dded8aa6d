// ARRAY_TASK AUTO: a Slurm array task's share of the tiles from SLURM_ARRAY_TASK_ID, _MIN, _MAX,
// _STEP and _COUNT, as Slurm sets them for each form of --array (slurmctld sets MIN and MAX to
// the lowest and highest id, COUNT to the number of ids, STEP to the number after ':' or 1).
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "octarc/batch/BatchKeys.h"
#include "octarc/core/Error.h"

namespace octarc {
namespace {

struct Case {
  const char* what;
  const char *id, *min, *max, *step, *count;
  int task, tasks;
  const char* note;  // a part of the note; "" for none at all
};

TEST(ArrayShare, EachFormOfArrayAndEachMissingVariable) {
  const Case cases[] = {
      {"not an array task", nullptr, nullptr, nullptr, nullptr, nullptr, 0, 1, ""},
      {"an array's variables without the task's id", nullptr, "0", "9", "1", "10", 0, 1, ""},
      {"no id: the others are not read", nullptr, "x", "x", "x", "ten", 0, 1, ""},
      {"--array=0-9, first", "0", "0", "9", "1", "10", 0, 10, "share 0/10"},
      {"--array=0-9, last", "9", "0", "9", "1", "10", 9, 10, "share 9/10"},
      {"--array=5-7", "7", "5", "7", "1", "3", 2, 3, "(--array=5-7 of 3 tasks): share 2/3"},
      {"--array=0-99:2, first", "0", "0", "98", "2", "50", 0, 50, "share 0/50"},
      {"--array=0-99:2, second", "2", "0", "98", "2", "50", 1, 50, "--array=0-98:2 of 50"},
      {"--array=0-99:2, last", "98", "0", "98", "2", "50", 49, 50, "share 49/50"},
      {"--array=1-7:2", "5", "1", "7", "2", "4", 2, 4, "share 2/4"},
      {"--array=5, one task", "5", "5", "5", "1", "1", 0, 1, "share 0/1"},
      // Lists: a task's position is not in its variables; every task takes the whole manifest.
      {"--array=3,17 (failed tasks sent again), first", "3", "3", "17", "1", "2", 0, 1,
       "task 3, one of 2 ids from 3 to 17 that are not a range with step 1: the whole "
       "manifest, shared"},
      {"--array=3,17, second", "17", "3", "17", "1", "2", 0, 1, "not a range"},
      {"--array=3,5,17, middle", "5", "3", "17", "1", "3", 0, 1,
       "task 5, one of 3 ids from 3 to 17"},
      {"--array=3,5,17, last", "17", "3", "17", "1", "3", 0, 1, "not a range"},
      {"--array=1,3,5,7: a list, so STEP 1", "3", "1", "7", "1", "4", 0, 1, "not a range"},
      {"--array=0-4:2,7", "4", "0", "7", "2", "4", 0, 1, "not a range with step 2"},
      // Variables missing: MIN 0, STEP 1, MAX that of an even array; without COUNT, no share.
      {"ID and COUNT alone", "2", nullptr, nullptr, nullptr, "3", 2, 3, "share 2/3"},
      {"no MAX nor STEP", "7", "5", nullptr, nullptr, "3", 2, 3, "share 2/3"},
      {"no STEP", "12", "10", "12", nullptr, "3", 2, 3, "share 2/3"},
      {"no STEP, MAX of a stepped array", "12", "10", "14", nullptr, "3", 0, 1, "not a range"},
      {"no MAX, stepped", "14", "10", nullptr, "2", "3", 2, 3, "(--array=10-14:2 of 3 tasks)"},
      {"no COUNT", "4", "0", "9", "1", nullptr, 0, 1,
       "task 4 without SLURM_ARRAY_TASK_COUNT: the whole manifest, shared"},
      // Values no array has: no share rather than a wrong one.
      {"id beyond MAX", "20", "0", "9", "1", "10", 0, 1, "not a range"},
      {"id below MIN", "2", "5", "7", "1", "3", 0, 1, "not a range"},
      {"id between two steps", "3", "0", "98", "2", "50", 0, 1, "not a range"},
      {"COUNT 0", "0", "0", "0", "1", "0", 0, 1, "not a range"},
      {"STEP 0", "0", "0", "9", "0", "10", 0, 1, "not a range"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    const ArrayShare share = slurmArrayShare(c.id, c.min, c.max, c.step, c.count);
    EXPECT_EQ(share.task, c.task);
    EXPECT_EQ(share.tasks, c.tasks);
    if (*c.note == '\0') {
      EXPECT_EQ(share.note, "");
    } else {
      EXPECT_NE(share.note.find(c.note), std::string::npos) << share.note;
    }
  }
}

TEST(ArrayShare, TheTasksOfASteppedArrayTakeEveryShareOnce) {
  // --array=0-99:2: ids 0, 2, ... 98.
  std::set<int> shares;
  for (int id = 0; id <= 98; id += 2) {
    const std::string text = std::to_string(id);
    const ArrayShare share = slurmArrayShare(text.c_str(), "0", "98", "2", "50");
    EXPECT_EQ(share.tasks, 50);
    shares.insert(share.task);
  }
  EXPECT_EQ(shares.size(), 50u);
  EXPECT_EQ(*shares.begin(), 0);
  EXPECT_EQ(*shares.rbegin(), 49);
}

TEST(ArrayShare, AValueThatIsNotAWholeNumberIsRefusedNamingItsVariable) {
  const struct {
    const char *id, *min, *max, *step, *count, *message;
  } bad[] = {
      {"x", "0", "9", "1", "10", "SLURM_ARRAY_TASK_ID 'x' is not a whole number"},
      {"1", "-1", "9", "1", "10", "SLURM_ARRAY_TASK_MIN '-1' is not"},
      {"1", "0", "9.5", "1", "10", "SLURM_ARRAY_TASK_MAX '9.5' is not"},
      {"1", "0", "9", "", "10", "SLURM_ARRAY_TASK_STEP '' is not"},
      {"1", "0", "9", "1", "99999999999", "SLURM_ARRAY_TASK_COUNT '99999999999' is not"},
      {"3", "0", "9", "1", "ten", "SLURM_ARRAY_TASK_COUNT 'ten' is not"},
  };
  for (const auto& b : bad) {
    try {
      (void)slurmArrayShare(b.id, b.min, b.max, b.step, b.count);
      ADD_FAILURE() << "accepted: " << b.message;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(b.message), std::string::npos) << e.what();
      EXPECT_EQ(std::string(e.what()).rfind("ARRAY_TASK AUTO: ", 0), 0u) << e.what();
    }
  }
}

}  // namespace
}  // namespace octarc
