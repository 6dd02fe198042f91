// Locating the shared real-sensor data for tests. Without any data a test skips with a
// message, so the package still tests on a machine that has only the project. Whenever the
// data is expected, its absence is a failure, never a silent skip:
// - CORAL_DATA_DIR is set (a misspelled path must not turn the real-data tests off);
// - the environment variable CI is "true" or "1" (.ci/run exports CI=true);
// - an environment variable looks like a misspelling of CORAL_DATA_DIR (CORAL_DATA...);
// - the data root exists but the requested data set in it is missing or unreadable.
#pragma once

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <set>
#include <string>

#include "support/source_dir.hpp"

extern char** environ;

namespace coral_test {

inline bool isReadableDir(const std::string& p) {
  struct stat st;
  return stat(p.c_str(), &st) == 0 && S_ISDIR(st.st_mode) && access(p.c_str(), R_OK | X_OK) == 0;
}

// True when CI asks for the data: CI=true or CI=1.
inline bool dataRequiredByCi() {
  const char* ci = std::getenv("CI");
  return ci != nullptr && (std::strcmp(ci, "true") == 0 || std::strcmp(ci, "1") == 0);
}

// Names of environment variables starting with CORAL_DATA other than CORAL_DATA_DIR.
inline std::string misspelledDataVariables() {
  std::string names;
  for (char** e = environ; e != nullptr && *e != nullptr; ++e) {
    const std::string kv = *e;
    const std::string name = kv.substr(0, kv.find('='));
    if (name.rfind("CORAL_DATA", 0) == 0 && name != "CORAL_DATA_DIR")
      names += (names.empty() ? "" : ", ") + name;
  }
  return names;
}

// Where the data set `subdir` is, or why it is not there.
struct DataLookup {
  std::string path;      // <root>/<subdir> when found
  std::string problem;   // why not found (empty when found)
  std::string required;  // why a missing data set is a failure here (empty: it skips)
};

// ../shared/data beside the (symlink-resolved) source tree.
inline std::string defaultDataRoot() { return sourceDir() + "/../shared/data"; }

// The data set `subdir` ("" = the root) under $CORAL_DATA_DIR, else under default_root.
inline DataLookup findData(const std::string& subdir,
                           const std::string& default_root = defaultDataRoot()) {
  DataLookup d;
  std::string root;
  if (const char* env = std::getenv("CORAL_DATA_DIR")) {
    d.required = "CORAL_DATA_DIR is set";
    root = env;
    if (!isReadableDir(root)) {
      d.problem = "CORAL_DATA_DIR='" + root + "' is not a readable directory";
      return d;
    }
  } else {
    root = default_root;
    const std::string typo = misspelledDataVariables();
    if (!typo.empty()) {
      d.required = "a CORAL_DATA* variable is set";
      d.problem = "CORAL_DATA_DIR is not set but " + typo + " is (misspelled?)";
      return d;
    }
    if (dataRequiredByCi()) d.required = "CI is set";
    if (root.empty() || !isReadableDir(root)) {
      d.problem = "real data not found: set CORAL_DATA_DIR or place ../shared/data" +
                  (root.empty() ? std::string() : " (looked in " + root + ")");
      return d;
    }
  }
  // The root exists: an incomplete data set is a broken setup, whoever runs the tests.
  if (d.required.empty()) d.required = "the data root " + root + " exists";
  const std::string path = subdir.empty() ? root : root + "/" + subdir;
  if (!isReadableDir(path)) {
    d.problem = "data set '" + path + "' is missing or unreadable";
    return d;
  }
  d.path = path;
  return d;
}

// The data root ("" when absent). Prefer CORAL_REQUIRE_DATA, which also fails when required.
inline std::string dataDir() { return findData("").path; }

// CORAL_VERDICT_PAIR_STRIDE (scripts/ci/test_sanitizers.sh, whose build is ~55x slower): the
// real-data tests judge every N-th pair or candidate only and assert what holds for any
// subset. 1 (every pair) when unset; a value that is not a positive integer fails the test.
inline std::size_t pairStride() {
  const char* env = std::getenv("CORAL_VERDICT_PAIR_STRIDE");
  if (env == nullptr || *env == '\0') return 1;
  char* end = nullptr;
  const long v = std::strtol(env, &end, 10);
  if (*end != '\0' || v < 1) {
    ADD_FAILURE() << "CORAL_VERDICT_PAIR_STRIDE=" << env << " is not a positive integer";
    return 1;
  }
  return static_cast<std::size_t>(v);
}

// The paths tempPath handed out, removed (files and directories) when the test binary exits:
// the suite runs many times on one machine, and a run left ~30 files in /tmp. Only the
// process that asked removes them, not a forked child that exits (a death test).
class TempPaths {
 public:
  static TempPaths& instance() {
    static TempPaths paths;
    return paths;
  }
  void add(const std::string& path) {
    const std::lock_guard<std::mutex> lock(mutex_);
    paths_.insert(path);
  }
  ~TempPaths() {
    if (getpid() != owner_) return;
    for (const std::string& path : paths_) {
      std::error_code ignored;
      std::filesystem::remove_all(path, ignored);
    }
  }

 private:
  TempPaths() : owner_(getpid()) {}
  const pid_t owner_;
  std::mutex mutex_;
  std::set<std::string> paths_;
};

// A per-process path in gtest's temp dir, e.g. tempPath("oxford", ".bag"); removed at exit.
inline std::string tempPath(const std::string& name, const std::string& ext) {
  const std::string path = ::testing::TempDir() + "/" + name + "_" + std::to_string(getpid()) + ext;
  TempPaths::instance().add(path);
  return path;
}

}  // namespace coral_test

// Defines `coral_data`, the directory of the data set `subdir` of the data root; without it
// the current test skips with the reason, or fails when the data is required (see above).
#define CORAL_REQUIRE_DATA(subdir)                                                                \
  const coral_test::DataLookup coral_data_lookup = coral_test::findData(subdir);                  \
  if (!coral_data_lookup.problem.empty()) {                                                       \
    if (!coral_data_lookup.required.empty())                                                      \
      FAIL() << coral_data_lookup.problem << " (required: " << coral_data_lookup.required << ")"; \
    GTEST_SKIP() << coral_data_lookup.problem;                                                    \
  }                                                                                               \
  const std::string coral_data = coral_data_lookup.path
