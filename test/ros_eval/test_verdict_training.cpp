// coral_train --preset end to end on a simulated planar sequence stored as a cloud list:
// outputs of a direct run, and the same fit from the sample files of two shards.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <fstream>
#include <random>
#include <sstream>

#include "coral_introspection/eval/synthetic.hpp"
#include "coral_introspection/ros_eval/verdict_training.hpp"
#include "support/test_data.hpp"

using namespace coral_introspection;

namespace {

std::string readFile(const std::string& path) {
  std::ifstream f(path);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

// Six planar scans of the yard as CSV clouds + a list with their 4x4 poses.
std::string writeSequence(const std::string& dir) {
  mkdir(dir.c_str(), 0755);
  std::mt19937 rng(4);
  eval::LidarModel lidar;
  lidar.rings = 1;
  lidar.v_min_deg = lidar.v_max_deg = 0.0;
  const eval::SyntheticScene scene = eval::SyntheticScene::structuredYard();
  std::ofstream list(dir + "/list.csv");
  list << "reading, gT00, gT01, gT02, gT03, gT10, gT11, gT12, gT13, gT20, gT21, gT22, gT23, "
          "gT30, gT31, gT32, gT33\n";
  for (int i = 0; i < 6; ++i) {
    const Eigen::Isometry3d T = coral::se2(-5.0 + 0.6 * i, 0.2 * i, 0.04 * i);
    const std::string name = "scan" + std::to_string(i) + ".csv";
    std::ofstream c(dir + "/" + name);
    c << "x,y,z\n";
    for (const coral::Vec3& p : eval::simulateScan(scene, T, lidar, rng))
      c << p.x() << "," << p.y() << "," << p.z() << "\n";
    list << name;
    for (int r = 0; r < 4; ++r)
      for (int k = 0; k < 4; ++k) list << ", " << T.matrix()(r, k);
    list << "\n";
  }
  std::ofstream(dir + "/preset.yaml") << "coral:\n  dimension: 2\n  radius: 0.5\n"
                                         "  epsilon: 1.0e-4\ntolerance:\n  translation: 0.3\n"
                                         "  rotation_deg: 5.0\n";
  return dir + "/list.csv";
}

}  // namespace

TEST(VerdictTraining, DirectRunAndShardsGiveTheSameClassifier) {
  const std::string dir = coral_test::tempPath("verdict_training", "");
  const std::string list = writeSequence(dir);
  ros_eval::VerdictTrainingOptions o;
  o.preset = dir + "/preset.yaml";
  o.datasets = {"yard=cloudlist:" + list};
  o.output_dir = dir + "/direct";
  o.folds = 2;
  o.command = "coral_train (test)";
  std::ostringstream log;
  ASSERT_EQ(ros_eval::runVerdictTraining(o, log), 0) << log.str();
  const std::string report = readFile(o.output_dir + "/report.md");
  EXPECT_NE(report.find("## Leave one data set out"), std::string::npos);
  EXPECT_NE(report.find("yard (first half)"), std::string::npos);
  EXPECT_NE(report.find("coral_train (test)"), std::string::npos);
  const std::string yaml = readFile(o.output_dir + "/verdict.yaml");
  EXPECT_NE(yaml.find("tolerance:\n  translation: 0.3\n  rotation_deg: 5\n"), std::string::npos)
      << yaml;
  EXPECT_NE(yaml.find("  method: "), std::string::npos);
  EXPECT_NE(readFile(o.output_dir + "/summary.md").find("| 0.3 m, 5 deg |"), std::string::npos);
  EXPECT_FALSE(readFile(o.output_dir + "/samples.csv").empty());
  EXPECT_FALSE(readFile(o.output_dir + "/roc.png").empty());

  o.output_dir = dir + "/shards";
  o.shard_count = 2;
  for (int s : {0, 1}) {
    o.shard_index = s;
    ASSERT_EQ(ros_eval::runVerdictTraining(o, log), 0) << log.str();
  }
  o.datasets.clear();
  o.sample_files = {dir + "/shards/samples_shard1of2.csv", dir + "/shards/samples_shard0of2.csv"};
  o.shard_index = 0;
  o.shard_count = 1;
  o.output_dir = dir + "/merged";
  ASSERT_EQ(ros_eval::runVerdictTraining(o, log), 0) << log.str();
  // Same classifier lines (the first comment lines name the command and differ).
  const std::string merged = readFile(o.output_dir + "/verdict.yaml");
  EXPECT_EQ(merged.substr(merged.find("tolerance:")), yaml.substr(yaml.find("tolerance:")));

  o.sample_files.push_back(dir + "/missing.csv");
  EXPECT_EQ(ros_eval::runVerdictTraining(o, log), 1);
  o.preset = dir + "/missing.yaml";
  EXPECT_EQ(ros_eval::runVerdictTraining(o, log), 2);
}
