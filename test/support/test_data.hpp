// Locating the shared real-sensor data for tests; they skip with a message without it.
#pragma once

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>
#include <cstdlib>
#include <string>

namespace coral_test {

// $CORAL_DATA_DIR, else ../shared/data beside the source tree; empty when absent.
inline std::string dataDir() {
  auto is_dir = [](const std::string& p) {
    struct stat st;
    return stat(p.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
  };
  if (const char* env = std::getenv("CORAL_DATA_DIR"); env && is_dir(env)) return env;
#ifdef CORAL_SOURCE_DIR
  const std::string guess = std::string(CORAL_SOURCE_DIR) + "/../shared/data";
  if (is_dir(guess)) return guess;
#endif
  return "";
}

// A per-process path in gtest's temp dir, e.g. tempPath("oxford", ".bag").
inline std::string tempPath(const std::string& name, const std::string& ext) {
  return ::testing::TempDir() + "/" + name + "_" + std::to_string(getpid()) + ext;
}

}  // namespace coral_test

// Skips the current test (with the reason in the output) when the data set is missing.
#define CORAL_REQUIRE_DATA(subdir)                                                     \
  const std::string coral_data_root = coral_test::dataDir();                           \
  if (coral_data_root.empty())                                                         \
    GTEST_SKIP() << "real data not found: set CORAL_DATA_DIR or place ../shared/data"; \
  const std::string coral_data = coral_data_root + "/" subdir
