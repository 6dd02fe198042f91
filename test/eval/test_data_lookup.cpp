// The shared-data lookup of the tests (support/test_data.hpp): a missing data set skips a
// test only when nobody asked for the data; with CORAL_DATA_DIR or CI set, with a
// misspelled CORAL_DATA_DIR, or with an incomplete data root it is a failure.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <cstdlib>
#include <string>

#include "support/test_data.hpp"

using coral_test::findData;

namespace {

// Sets (or unsets, value nullptr) an environment variable for the scope, restoring it after.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old, had_ = true;
    if (value)
      setenv(name, value, 1);
    else
      unsetenv(name);
  }
  ~ScopedEnv() {
    if (had_)
      setenv(name_.c_str(), old_.c_str(), 1);
    else
      unsetenv(name_.c_str());
  }

 private:
  std::string name_, old_;
  bool had_ = false;
};

// A temporary data root holding one data set directory, "oxford_radar_tiny".
std::string makeRoot() {
  const std::string root = coral_test::tempPath("coral_data_root", "");
  mkdir(root.c_str(), 0755);
  mkdir((root + "/oxford_radar_tiny").c_str(), 0755);
  return root;
}

const std::string kNowhere = "/nonexistent/coral_shared_data";

}  // namespace

TEST(DataLookup, AbsentDataSkipsOnlyWhenNobodyAskedForIt) {
  ScopedEnv dir("CORAL_DATA_DIR", nullptr), ci("CI", nullptr);
  coral_test::DataLookup d = findData("oxford_radar_tiny", kNowhere);
  EXPECT_TRUE(d.path.empty());
  EXPECT_NE(d.problem.find("real data not found"), std::string::npos) << d.problem;
  EXPECT_TRUE(d.required.empty()) << d.required;  // a plain checkout: skip
  {
    ScopedEnv ci_on("CI", "true");
    d = findData("oxford_radar_tiny", kNowhere);
    EXPECT_FALSE(d.problem.empty());
    EXPECT_EQ(d.required, "CI is set");
  }
  {
    ScopedEnv ci_off("CI", "false");  // only true / 1 ask for the data
    EXPECT_TRUE(findData("oxford_radar_tiny", kNowhere).required.empty());
  }
}

TEST(DataLookup, BadCoralDataDirIsAFailure) {
  ScopedEnv ci("CI", nullptr);
  ScopedEnv dir("CORAL_DATA_DIR", kNowhere.c_str());
  const std::string root = makeRoot();
  // Even though a default root with the data exists, the variable wins and is wrong.
  const coral_test::DataLookup d = findData("oxford_radar_tiny", root);
  EXPECT_TRUE(d.path.empty());
  EXPECT_NE(d.problem.find(kNowhere), std::string::npos) << d.problem;
  EXPECT_EQ(d.required, "CORAL_DATA_DIR is set");
}

TEST(DataLookup, MisspelledVariableIsAFailure) {
  ScopedEnv ci("CI", nullptr), dir("CORAL_DATA_DIR", nullptr);
  ScopedEnv typo("CORAL_DATA_DIRS", "/somewhere");
  const coral_test::DataLookup d = findData("oxford_radar_tiny", makeRoot());
  EXPECT_TRUE(d.path.empty());
  EXPECT_NE(d.problem.find("CORAL_DATA_DIRS"), std::string::npos) << d.problem;
  EXPECT_FALSE(d.required.empty());
}

TEST(DataLookup, FindsDataSetsAndFailsOnAnIncompleteRoot) {
  ScopedEnv ci("CI", nullptr), dir("CORAL_DATA_DIR", nullptr);
  const std::string root = makeRoot();
  coral_test::DataLookup d = findData("oxford_radar_tiny", root);
  EXPECT_EQ(d.path, root + "/oxford_radar_tiny");
  EXPECT_TRUE(d.problem.empty()) << d.problem;
  EXPECT_EQ(findData("", root).path, root);
  // The root is there but the data set is not: a broken setup, not a reason to skip.
  d = findData("view_of_delft_example", root);
  EXPECT_TRUE(d.path.empty());
  EXPECT_NE(d.problem.find("view_of_delft_example"), std::string::npos) << d.problem;
  EXPECT_FALSE(d.required.empty());
  // CORAL_DATA_DIR pointing at the same root finds the same data set.
  ScopedEnv dir2("CORAL_DATA_DIR", root.c_str());
  EXPECT_EQ(findData("oxford_radar_tiny", kNowhere).path, root + "/oxford_radar_tiny");
}
