// The grades CSV of the vetting page read and merged into a hand-made candidate table: each
// grade lands on the row of its NUMBER, and each fault is one message naming the file and line.
#include "octarc/search/Grades.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "octarc/core/Error.h"

namespace octarc {
namespace {

class GradesCsv : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("octarc-grades-" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
            "-" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::string csv(const std::string& text) {
    const std::string path = (dir_ / "grades.csv").string();
    std::ofstream(path) << text;
    return path;
  }

  // The message of the IoError that reading (and merging) `text` throws; "" when none.
  std::string failure(const std::string& text) {
    const std::string path = csv(text);
    try {
      gradedCandidates(table(), readGradesCsv(path), path);
    } catch (const IoError& e) {
      return e.what();
    }
    return "";
  }

  static FitsTable table() {
    FitsTable t;
    t.name = "LDAC_OBJECTS";
    t.columns = {{"NUMBER", "", "", "", 1, std::vector<std::int32_t>{1, 2, 3}, "", ""},
                 {"NAME", "", "", "", 0, std::vector<std::string>{"A", "B C", "D"}, "", ""}};
    return t;
  }

  std::filesystem::path dir_;
};

TEST_F(GradesCsv, GradesLandOnTheirNumbers) {
  const std::string path =
      csv("NUMBER,NAME,ALPHA_J2000,DELTA_J2000,GRADE\r\n"
          "3,D,150.1,2.2,No\r\n"
          "\"1\",\"A\",150,2,lens\r\n"
          "2,B C,,,\r\n\r\n");
  const auto grades = readGradesCsv(path);
  ASSERT_EQ(grades.size(), 2u);  // the empty grade of 2 is no grade
  EXPECT_EQ(grades.at(3).grade, "no");
  EXPECT_EQ(grades.at(3).line, 2);
  EXPECT_EQ(grades.at(1).name, "A");
  const FitsTable graded = gradedCandidates(table(), grades, path);
  EXPECT_EQ(graded.strings("GRADE"), (std::vector<std::string>{"lens", "", "no"}));
  EXPECT_EQ(graded.column("GRADE").repeat, 5);
  // Grading again replaces the column rather than adding a second one.
  const FitsTable again = gradedCandidates(graded, {{2, {"maybe", "", 9}}}, path);
  EXPECT_EQ(again.columns.size(), 3u);
  EXPECT_EQ(again.strings("GRADE"), (std::vector<std::string>{"", "maybe", ""}));
}

TEST_F(GradesCsv, EachFaultNamesTheFileAndLine) {
  const std::string path = (dir_ / "grades.csv").string();
  EXPECT_EQ(failure("NUMBER,NAME\n1,A\n"), path +
                                               ":1: the header line 'NUMBER,NAME' must "
                                               "name the columns NUMBER and GRADE (a CSV "
                                               "exported by the vetting page)");
  EXPECT_EQ(failure("NUMBER,GRADE\n1,lens\n2,good\n"),
            path + ":3: GRADE 'good' is not lens, maybe or no");
  EXPECT_EQ(failure("NUMBER,GRADE\n1,lens\n1,no\n"),
            path + ":3: NUMBER 1 is graded again (first on line 2)");
  EXPECT_EQ(failure("NUMBER,GRADE\n1,lens,x\n"), path + ":2: 3 fields, the header has 2");
  EXPECT_EQ(failure("NUMBER,GRADE\n1.5,lens\n"),
            path + ":2: NUMBER '1.5' is not a positive integer");
  EXPECT_EQ(failure("NUMBER,GRADE\n\"1,lens\n"), path + ":2: a quote is not closed");
  EXPECT_EQ(failure("NUMBER,GRADE\n1,lens\n7,no\n"),
            path + ":3: NUMBER 7 is not in [LDAC_OBJECTS]");
  EXPECT_EQ(failure("NUMBER,NAME,GRADE\n2,X,maybe\n"),
            path +
                ":2: NUMBER 2 is 'B C' in [LDAC_OBJECTS], not 'X': grades of another "
                "catalog?");
  EXPECT_EQ(failure(""), path + ":1: empty file; expected a header line");
  EXPECT_THROW(readGradesCsv((dir_ / "absent.csv").string()), IoError);
}

}  // namespace
}  // namespace octarc
