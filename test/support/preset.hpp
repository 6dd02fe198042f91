// A shipped preset (config/<name>.yaml) read exactly as the nodelet reads it, for the tests
// that judge real data with it (test/ros_eval). Fails the current test on a load error.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "coral_introspection/ros_eval/preset_file.hpp"
#include "support/source_dir.hpp"

namespace coral_test {

inline void loadPreset(const std::string& name,
                       coral_introspection::ros_adapters::NodeConfig* node) {
  coral_introspection::coral::VerdictConfig verdict;
  std::string err;
  ASSERT_TRUE(coral_introspection::ros_eval::loadPresetFile(
      coral_test::sourceDir() + "/config/" + name + ".yaml", node, &verdict, &err))
      << err;
}

}  // namespace coral_test
