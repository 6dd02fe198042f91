// Preset YAML files read as the nodelet reads its parameters (yaml-cpp -> XmlRpc ->
// loadNodeConfig), plus the verdict settings; every shipped preset loads.
#include <gtest/gtest.h>

#include <fstream>

#include "coral_introspection/ros_eval/preset_file.hpp"
#include "support/test_data.hpp"

using namespace coral_introspection;
using XmlRpc::XmlRpcValue;

TEST(PresetFile, YamlScalarsBecomeTypedXmlRpcValues) {
  XmlRpcValue v;
  std::string err;
  ASSERT_TRUE(ros_adapters::yamlToXmlRpc(
      "a: 3\nb: 1.0e-4\nc: true\nd: mean   # comment\ne: '12'\nf: [1, x]\ng: {h: -2.5}\n", &v,
      &err))
      << err;
  EXPECT_EQ(v["a"].getType(), XmlRpcValue::TypeInt);
  EXPECT_EQ(static_cast<int>(v["a"]), 3);
  EXPECT_EQ(v["b"].getType(), XmlRpcValue::TypeDouble);
  EXPECT_DOUBLE_EQ(static_cast<double>(v["b"]), 1e-4);
  EXPECT_EQ(v["c"].getType(), XmlRpcValue::TypeBoolean);
  EXPECT_EQ(static_cast<std::string>(v["d"]), "mean");
  EXPECT_EQ(v["e"].getType(), XmlRpcValue::TypeString);  // quoted stays a string
  ASSERT_EQ(v["f"].getType(), XmlRpcValue::TypeArray);
  EXPECT_EQ(static_cast<std::string>(v["f"][1]), "x");
  EXPECT_DOUBLE_EQ(static_cast<double>(v["g"]["h"]), -2.5);
  EXPECT_FALSE(ros_adapters::yamlToXmlRpc("a: [1, 2\n", &v, &err));
  EXPECT_NE(err.find("YAML"), std::string::npos);
}

TEST(PresetFile, VerdictKeysDefaultsAndErrors) {
  const std::string path = coral_test::tempPath("preset", ".yaml");
  std::ofstream(path) << "input_type: polar_image\ncoral:\n  dimension: 2\n  radius: 2.0\n"
                         "classifier:\n  method: both\n  relative_margin: 0.05\n  beta0: 7\n";
  ros_adapters::NodeConfig node;
  core::VerdictConfig v;
  std::string err;
  std::vector<std::string> warnings;
  ASSERT_TRUE(ros_adapters::loadPresetFile(path, &node, &v, &err, &warnings)) << err;
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  EXPECT_DOUBLE_EQ(node.online.coral.radius, 2.0);
  EXPECT_EQ(node.online.coral.dimension, 2);
  EXPECT_EQ(v.method, core::VerdictMethod::kBoth);
  EXPECT_DOUBLE_EQ(v.relative.margin, 0.05);
  EXPECT_DOUBLE_EQ(v.classifier.beta0, 7.0);
  EXPECT_DOUBLE_EQ(v.tolerance.translation, core::ToleranceConfig().translation);  // default
  std::ofstream(path) << "tolerance:\n  translation: 0.2\n  rotation_deg: 3\n  typo: 1\n";
  ASSERT_TRUE(ros_adapters::loadPresetFile(path, &node, &v, &err, &warnings)) << err;
  EXPECT_DOUBLE_EQ(v.tolerance.translation, 0.2);
  EXPECT_DOUBLE_EQ(v.tolerance.rotation_deg, 3.0);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("~tolerance/typo"), std::string::npos);
  std::ofstream(path) << "classifier:\n  method: vote\n";
  EXPECT_FALSE(ros_adapters::loadPresetFile(path, &node, &v, &err));
  EXPECT_NE(err.find("classifier/method"), std::string::npos) << err;
  std::ofstream(path) << "tolerance:\n  translation: -1\n";
  EXPECT_FALSE(ros_adapters::loadPresetFile(path, &node, &v, &err));
  EXPECT_NE(err.find("translation"), std::string::npos) << err;
  std::ofstream(path) << "coral:\n  radius: -1\n";
  EXPECT_FALSE(ros_adapters::loadPresetFile(path, &node, &v, &err));
  EXPECT_FALSE(ros_adapters::loadPresetFile(path + ".missing", &node, &v, &err));
  std::remove(path.c_str());
}

TEST(PresetFile, EveryShippedPresetLoads) {
  for (const char* p : {"lidar_2d", "lidar_3d", "radar_oxford", "radar_mulran"}) {
    ros_adapters::NodeConfig node;
    core::VerdictConfig v;
    std::string err;
    std::vector<std::string> warnings;
    EXPECT_TRUE(ros_adapters::loadPresetFile(
        std::string(CORAL_SOURCE_DIR) + "/config/" + p + ".yaml", &node, &v, &err, &warnings))
        << p << ": " << err;
    EXPECT_TRUE(warnings.empty()) << p << ": " << warnings.front();
  }
}
