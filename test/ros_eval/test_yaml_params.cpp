// YAML parameter files read like rosparam: scalar typing, nesting, merging, errors, and every
// shipped preset loading through the nodelet's own parameter loader.
#include <gtest/gtest.h>

#include <dirent.h>

#include "coral_introspection/ros/params.hpp"
#include "coral_introspection/ros_eval/yaml_params.hpp"

using namespace coral_introspection;
using XmlRpc::XmlRpcValue;

TEST(YamlParams, ScalarsAreTypedLikeRosparam) {
  XmlRpcValue t;
  std::string err;
  ASSERT_TRUE(ros_adapters::parseYamlParams(
      "a: 3\nb: 1.0e-4\nc: true\nd: no\ne: mean\nf: '12'\ng: -2.5\nh: [1, 2.5]\n"
      "grp:\n  x: 0.2  # comment\n",
      &t, &err))
      << err;
  EXPECT_EQ(t["a"].getType(), XmlRpcValue::TypeInt);
  EXPECT_EQ(static_cast<int>(t["a"]), 3);
  EXPECT_EQ(t["b"].getType(), XmlRpcValue::TypeDouble);
  EXPECT_DOUBLE_EQ(static_cast<double>(t["b"]), 1e-4);
  EXPECT_TRUE(static_cast<bool>(t["c"]));
  EXPECT_FALSE(static_cast<bool>(t["d"]));
  EXPECT_EQ(static_cast<std::string>(t["e"]), "mean");
  EXPECT_EQ(t["f"].getType(), XmlRpcValue::TypeString);  // quoted stays a string
  EXPECT_DOUBLE_EQ(static_cast<double>(t["g"]), -2.5);
  ASSERT_EQ(t["h"].size(), 2);
  EXPECT_DOUBLE_EQ(static_cast<double>(t["grp"]["x"]), 0.2);
}

TEST(YamlParams, ErrorsNameTheProblem) {
  XmlRpcValue t;
  std::string err;
  EXPECT_FALSE(ros_adapters::parseYamlParams("a: [1, 2\n", &t, &err));
  EXPECT_NE(err.find("YAML"), std::string::npos);
  EXPECT_FALSE(ros_adapters::parseYamlParams("coral:\n  radius:\n", &t, &err));
  EXPECT_NE(err.find("null"), std::string::npos) << err;
  EXPECT_NE(err.find("line "), std::string::npos) << err;
  EXPECT_FALSE(ros_adapters::parseYamlParams("- 1\n- 2\n", &t, &err));
  EXPECT_FALSE(ros_adapters::loadYamlParams("/nonexistent/preset.yaml", &t, &err));
  EXPECT_NE(err.find("/nonexistent/preset.yaml"), std::string::npos);
}

TEST(YamlParams, ClassifierFileOverridesOnlyItsKeys) {
  XmlRpcValue base, overlay;
  std::string err;
  ASSERT_TRUE(ros_adapters::parseYamlParams(
      "coral:\n  radius: 1.0\nclassifier:\n  beta0: 4.0\n  threshold: 0.5\n", &base, &err));
  ASSERT_TRUE(ros_adapters::parseYamlParams("classifier:\n  beta0: 12.5\n", &overlay, &err));
  ros_adapters::mergeParams(overlay, &base);
  EXPECT_DOUBLE_EQ(static_cast<double>(base["classifier"]["beta0"]), 12.5);
  EXPECT_DOUBLE_EQ(static_cast<double>(base["classifier"]["threshold"]), 0.5);
  EXPECT_DOUBLE_EQ(static_cast<double>(base["coral"]["radius"]), 1.0);
}

// What coral_train and online self-calibration write loads over a preset whose default
// method is relative and makes the nodelet judge with exactly that classifier and tolerance.
TEST(YamlParams, WrittenClassifierFileRoundTripsOverAPreset) {
  core::ClassifierConfig c;
  c.beta0 = 7.25;
  c.beta1 = -91.5;
  c.beta2 = 98.125;
  c.threshold = 0.6;
  core::ToleranceConfig tol;
  tol.translation = 0.4;
  tol.rotation_deg = 3.0;
  XmlRpcValue preset, written;
  std::string err;
  ASSERT_TRUE(ros_adapters::loadYamlParams(std::string(CORAL_SOURCE_DIR) + "/config/lidar_3d.yaml",
                                           &preset, &err))
      << err;
  ASSERT_TRUE(
      ros_adapters::parseYamlParams(core::classifierYaml(c, {"test"}, &tol), &written, &err))
      << err;
  ros_adapters::mergeParams(written, &preset);
  ros_adapters::NodeConfig n;
  ASSERT_TRUE(ros_adapters::loadNodeConfig(preset, &n, &err)) << err;
  const core::VerdictConfig& v = n.online.verdict;
  EXPECT_EQ(v.method, core::VerdictMethod::kClassifier);  // lidar_3d.yaml says relative
  EXPECT_EQ(v.classifier.beta0, 7.25);
  EXPECT_EQ(v.classifier.beta1, -91.5);
  EXPECT_EQ(v.classifier.beta2, 98.125);
  EXPECT_EQ(v.classifier.threshold, 0.6);
  EXPECT_EQ(v.tolerance.translation, 0.4);
  EXPECT_EQ(v.tolerance.rotation_deg, 3.0);
  EXPECT_EQ(n.online.coral.radius, 1.0);  // the preset's CorAl settings stay
}

TEST(YamlParams, EveryShippedPresetLoadsWithoutWarnings) {
  const std::string dir = std::string(CORAL_SOURCE_DIR) + "/config";
  DIR* d = opendir(dir.c_str());
  ASSERT_NE(d, nullptr);
  int n = 0;
  for (dirent* e = readdir(d); e != nullptr; e = readdir(d)) {
    const std::string name = e->d_name;
    if (name.size() < 5 || name.substr(name.size() - 5) != ".yaml") continue;
    XmlRpcValue t;
    std::string err;
    ASSERT_TRUE(ros_adapters::loadYamlParams(dir + "/" + name, &t, &err)) << err;
    ros_adapters::NodeConfig c;
    std::vector<std::string> warnings;
    EXPECT_TRUE(ros_adapters::loadNodeConfig(t, &c, &err, &warnings)) << name << ": " << err;
    EXPECT_TRUE(warnings.empty()) << name << ": " << (warnings.empty() ? "" : warnings[0]);
    ++n;
  }
  closedir(d);
  EXPECT_GE(n, 4);
}
