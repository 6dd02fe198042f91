// The rio YAML loader refuses what it would otherwise guess: no extrinsics (identity), a
// misspelt group or key (its defaults), a duplicate group, an empty file; the error names the
// nearest valid key (config/param_tree.hpp), and from a file also the file and line.
#include <gtest/gtest.h>

#include <fstream>

#include "coral_introspection/config/yaml_tree.hpp"
#include "coral_introspection/rio/config_yaml.hpp"
#include "support/test_data.hpp"

namespace rio = coral_introspection::rio;

namespace {

const char* kExtrinsics = "extrinsics:\n  translation: [0.1, 0, 0]\n  rotation: [0, 0, 0, 1]\n";

// The error of loading `yaml` ("" when it loads).
std::string loadError(const std::string& yaml, const rio::RioConfigRules& rules = {{"ros"}}) {
  rio::RioConfig cfg;
  std::string err;
  const bool ok = rio::loadRioConfig(YAML::Load(yaml), &cfg, &err, rules);
  EXPECT_EQ(ok, err.empty()) << err;
  return err;
}

}  // namespace

TEST(RioConfigYaml, ExtrinsicsAreRequired) {
  EXPECT_EQ(loadError(kExtrinsics), "");
  EXPECT_NE(loadError("solver: {window_size: 8}").find("extrinsics/translation is required"),
            std::string::npos);
  EXPECT_NE(
      loadError("extrinsics: {translation: [0, 0, 0]}").find("extrinsics/rotation is required"),
      std::string::npos);
  // Where TF gives them (RioNodelet, extrinsics_source tf) the file need not.
  EXPECT_EQ(loadError("solver: {window_size: 8}", {{"ros"}, false}), "");
}

TEST(RioConfigYaml, EmptyOrMalformedFileIsRefused) {
  EXPECT_EQ(loadError(""), "the config is empty");
  EXPECT_EQ(loadError("just text"), "the config must be a map of groups (imu, extrinsics, ...)");
  EXPECT_EQ(loadError(std::string(kExtrinsics) + "solver: 8"),
            "group solver must be a map of parameters");
}

TEST(RioConfigYaml, UnknownKeysAreErrorsNamingTheNearestValidKey) {
  const std::string e = kExtrinsics;
  // The case: a misspelt group left the identity extrinsics with only a warning.
  EXPECT_EQ(loadError("extrinsic:\n  translation: [0.1, 0, 0]\n  rotation: [0, 0, 0, 1]\n"),
            "unknown group extrinsic (did you mean extrinsics?)");
  EXPECT_EQ(loadError(e + "front_end: {max_elevaton: 1.0}"),
            "unknown key front_end/max_elevaton (did you mean max_elevation?)");
  // A key without its group, or in the wrong group, finds its group.
  EXPECT_EQ(loadError(e + "window_size: 8"),
            "unknown key window_size (did you mean solver/window_size?)");
  EXPECT_EQ(loadError(e + "solver: {gate_sigma: 3}"),
            "unknown key solver/gate_sigma (did you mean association/gate_sigma?)");
  // Nothing close: no suggestion. Every unknown key is reported at once.
  // (barometer is a group now: rio/barometer.hpp; a lidar group is not.)
  EXPECT_EQ(loadError(e + "colour: blue\nlidar: {rate: 10}"),
            "unknown key colour; unknown group lidar");
  EXPECT_EQ(loadError(e + "barometer: {rate: 10}"), "unknown key barometer/rate");
  // Groups read by the adapters are not unknown when the caller says so.
  EXPECT_EQ(loadError(e + "ros: {time_source: header}"), "");
  EXPECT_EQ(loadError(e + "ros: {time_source: header}", {{}, true}), "unknown group ros");
}

// From a file: the messages rio_offline and RioNodelet print name the file and the line; a
// group given twice is refused (yaml-cpp would read only one of them); --set overrides.
TEST(RioConfigYaml, FileErrorsNameFileAndLine) {
  const std::string path = coral_test::tempPath("rio_config", ".yaml");
  auto loadFile = [&](const std::string& text) {
    std::ofstream(path) << text;
    rio::RioConfig cfg;
    std::string err;
    EXPECT_FALSE(rio::loadRioConfigFile(path, &cfg, &err, {{"ros"}}));
    return err;
  };
  EXPECT_EQ(loadFile(std::string(kExtrinsics) + "solver:\n  window_sise: 8\n"),
            path + ":5: unknown key solver/window_sise (did you mean window_size?)");
  EXPECT_EQ(
      loadFile(std::string(kExtrinsics) + "solver: {window_size: 8}\nsolver: {loss: huber}\n"),
      path + ": duplicate key solver (lines 4 and 5)");
  EXPECT_EQ(loadFile(std::string(kExtrinsics) + "solver:\n  window_size: many\n"),
            path + ":5: parameter solver/window_size must be an integer (got 'many')");
  const std::string invalid = loadFile(std::string(kExtrinsics) + "solver: {window_size: 1}\n");
  EXPECT_EQ(invalid.rfind(path + ": ", 0), 0u) << invalid;  // validate()'s message, of this file
  EXPECT_NE(invalid.find("window_size"), std::string::npos) << invalid;
  std::remove(path.c_str());

  coral_introspection::config::ParamTree tree;
  std::string err;
  ASSERT_TRUE(coral_introspection::config::parseYaml(kExtrinsics, &tree, &err)) << err;
  ASSERT_TRUE(rio::applyOverride(tree, "solver/window_size=8", &err)) << err;
  ASSERT_TRUE(rio::applyOverride(tree, "extrinsics/translation=[0, 0, 0.1]", &err)) << err;
  rio::RioConfig cfg;
  ASSERT_TRUE(rio::loadRioConfig(tree, &cfg, &err)) << err;
  EXPECT_EQ(cfg.solver.window_size, 8);
  EXPECT_EQ(cfg.extrinsics.t.z(), 0.1);
  EXPECT_FALSE(rio::applyOverride(tree, "solver/window_size", &err));
  EXPECT_EQ(err, "override 'solver/window_size' is not key=value");
  ASSERT_TRUE(rio::applyOverride(tree, "solver/window_size=many", &err));
  EXPECT_FALSE(rio::loadRioConfig(tree, &cfg, &err));
  EXPECT_EQ(err,
            "--set solver/window_size=many: parameter solver/window_size must be an integer (got "
            "'many')");
}
