// Preset YAML files read as the nodelet reads its parameters (YAML -> config::ParamTree ->
// loadNodeConfig): the verdict settings, classifier files loaded over a preset, every shipped
// preset, and the mistakes that once changed verdicts silently (a misspelt group, a group
// given twice), which now fail naming file and line.
#include <gtest/gtest.h>

#include <fstream>

#include "coral_introspection/ros_eval/preset_file.hpp"
#include "support/test_data.hpp"

using namespace coral_introspection;

namespace {

// The error of loading `text` as a preset file at `path` ("" when it loads).
std::string presetError(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
  ros_adapters::NodeConfig node;
  coral::VerdictConfig v;
  std::string err;
  const bool ok = ros_eval::loadPresetFile(path, &node, &v, &err);
  EXPECT_EQ(ok, err.empty()) << err;
  return err;
}

}  // namespace

TEST(PresetFile, VerdictKeysDefaultsAndErrors) {
  const std::string path = coral_test::tempPath("preset", ".yaml");
  std::ofstream(path) << "input_type: polar_image\ncoral:\n  dimension: 2\n  radius: 2.0\n"
                         "classifier:\n  method: both\n  relative_margin: 0.05\n  beta0: 7\n";
  ros_adapters::NodeConfig node;
  coral::VerdictConfig v;
  std::string err;
  ASSERT_TRUE(ros_eval::loadPresetFile(path, &node, &v, &err)) << err;
  EXPECT_DOUBLE_EQ(node.online.coral.radius, 2.0);
  EXPECT_EQ(node.online.coral.dimension, 2);
  EXPECT_EQ(v.method, coral::VerdictMethod::kBoth);
  EXPECT_DOUBLE_EQ(v.relative.margin, 0.05);
  EXPECT_DOUBLE_EQ(v.classifier.beta0, 7.0);
  EXPECT_DOUBLE_EQ(v.tolerance.translation, coral::ToleranceConfig().translation);  // default
  std::ofstream(path) << "tolerance:\n  translation: 0.2\n  rotation_deg: 3\n";
  ASSERT_TRUE(ros_eval::loadPresetFile(path, &node, &v, &err)) << err;
  EXPECT_DOUBLE_EQ(v.tolerance.translation, 0.2);
  EXPECT_DOUBLE_EQ(v.tolerance.rotation_deg, 3.0);
  EXPECT_NE(presetError(path, "classifier:\n  method: vote\n").find("classifier/method"),
            std::string::npos);
  EXPECT_NE(presetError(path, "tolerance:\n  translation: -1\n").find(path + ": "),
            std::string::npos);  // validate()'s message names the file
  EXPECT_NE(presetError(path, "coral:\n  radius: -1\n"), "");
  std::remove(path.c_str());
  EXPECT_FALSE(ros_eval::loadPresetFile(path, &node, &v, &err));
  EXPECT_EQ(err, "cannot read " + path);
}

// The mistakes of issue 23, each with the message coral_check prints and the nodelet logs.
TEST(PresetFile, MisspeltDuplicateAndMistypedKeysFailNamingFileAndLine) {
  const std::string path = coral_test::tempPath("preset_typo", ".yaml");
  EXPECT_EQ(presetError(path, "coarl:\n  radius: 1.0\n"),
            path + ":1: unknown group coarl (did you mean coral?)");
  EXPECT_EQ(presetError(path, "coral:\n  radius: 1.0\n  min_overlap: 0.1\n  radus: 2\n"),
            path + ":4: unknown key coral/radus (did you mean radius?)");
  EXPECT_EQ(presetError(path, "tolerance:\n  translation: 0.2\n  typo: 1\n"),
            path + ":3: unknown key tolerance/typo");
  EXPECT_EQ(presetError(path, "coral:\n  radius: 1.0\nrip:\n  k: 12\ncoral:\n  radius: 2.0\n"),
            path + ": duplicate key coral (lines 1 and 5)");
  EXPECT_EQ(presetError(path, "coral:\n  radius: one\n"),
            path + ":2: parameter coral/radius must be a number (got 'one')");
  std::remove(path.c_str());
}

// What coral_train and online self-calibration write loads over a preset whose default
// method is relative and makes the nodelet judge with exactly that classifier and tolerance.
TEST(PresetFile, WrittenClassifierFileLoadsOverAPreset) {
  coral::ClassifierConfig c;
  c.beta0 = 7.25;
  c.beta1 = -91.5;
  c.beta2 = 98.125;
  c.threshold = 0.6;
  coral::ToleranceConfig tol;
  tol.translation = 0.4;
  tol.rotation_deg = 3.0;
  const std::string written = coral_test::tempPath("classifier", ".yaml");
  std::ofstream(written) << coral::classifierYaml(c, {"test"}, &tol);
  ros_adapters::NodeConfig n;
  std::string err;
  ASSERT_TRUE(ros_eval::loadPresetFiles(
      {coral_test::sourceDir() + "/config/lidar_3d.yaml", written}, &n, &err))
      << err;
  std::remove(written.c_str());
  const coral::VerdictConfig& v = n.online.verdict;
  EXPECT_EQ(v.method, coral::VerdictMethod::kClassifier);  // lidar_3d.yaml says relative
  EXPECT_EQ(v.classifier.beta0, 7.25);
  EXPECT_EQ(v.classifier.beta1, -91.5);
  EXPECT_EQ(v.classifier.beta2, 98.125);
  EXPECT_EQ(v.classifier.threshold, 0.6);
  EXPECT_EQ(v.tolerance.translation, 0.4);
  EXPECT_EQ(v.tolerance.rotation_deg, 3.0);
  EXPECT_EQ(n.online.coral.radius, 1.0);  // the preset's CorAl settings stay
}

TEST(PresetFile, EveryShippedPresetLoads) {
  for (const char* p : {"lidar_2d", "lidar_3d", "radar_oxford", "radar_mulran", "radar_ti_mmwave",
                        "classifier_radar_oxford"}) {
    ros_adapters::NodeConfig node;
    coral::VerdictConfig v;
    std::string err;
    EXPECT_TRUE(ros_eval::loadPresetFile(coral_test::sourceDir() + "/config/" + p + ".yaml", &node,
                                         &v, &err))
        << p << ": " << err;
  }
  ros_adapters::NodeConfig node;
  std::string err;
  EXPECT_TRUE(
      ros_eval::loadPresetFiles({coral_test::sourceDir() + "/config/radar_oxford.yaml",
                                 coral_test::sourceDir() + "/config/classifier_radar_oxford.yaml"},
                                &node, &err))
      << err;
}
