// The rio YAML loader refuses what it would otherwise guess: no extrinsics (identity), a
// misspelt group or key (its defaults), an empty file; the error names the nearest valid key.
#include <gtest/gtest.h>

#include "coral_introspection/rio/config_keys.hpp"
#include "coral_introspection/rio/config_yaml.hpp"

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
            "unknown parameter front_end/max_elevaton (did you mean front_end/max_elevation?)");
  // A key without its group, or in the wrong group, finds its group.
  EXPECT_EQ(loadError(e + "window_size: 8"),
            "unknown parameter window_size (did you mean solver/window_size?)");
  EXPECT_EQ(loadError(e + "solver: {gate_sigma: 3}"),
            "unknown parameter solver/gate_sigma (did you mean association/gate_sigma?)");
  // Nothing close: no suggestion. Every unknown key is reported at once.
  // (barometer is a group now: rio/barometer.hpp; a lidar group is not.)
  EXPECT_EQ(loadError(e + "colour: blue\nlidar: {rate: 10}"),
            "unknown parameter colour; unknown group lidar");
  EXPECT_EQ(loadError(e + "barometer: {rate: 10}"), "unknown parameter barometer/rate");
  // Groups read by the adapters are not unknown when the caller says so.
  EXPECT_EQ(loadError(e + "ros: {time_source: header}"), "");
  EXPECT_EQ(loadError(e + "ros: {time_source: header}", {{}, true}), "unknown group ros");
}

TEST(RioConfigYaml, DidYouMeanOnlyForCloseNames) {
  const std::vector<std::string> valid = {"imu_topic", "radar_topic", "trigger_topic"};
  EXPECT_EQ(rio::didYouMean("radar_topc", valid), " (did you mean radar_topic?)");
  EXPECT_EQ(rio::didYouMean("lidar", valid), "");
  EXPECT_EQ(rio::didYouMean("x", {"y"}), "");  // one letter off a one-letter key is no hint
}
