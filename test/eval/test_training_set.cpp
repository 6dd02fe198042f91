// Self-supervised sample generation (Sec. III-F) on a synthetic lidar sequence and on the
// Oxford radar scans, and one full training run writing its files.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>
#include <sstream>

#include "coral_introspection/eval/oxford_training.hpp"
#include "coral_introspection/eval/synthetic.hpp"
#include "coral_introspection/eval/training_run.hpp"
#include "coral_introspection/eval/training_set.hpp"
#include "support/test_data.hpp"

using namespace coral_introspection::coral;
using namespace coral_introspection::radar;
using namespace coral_introspection::eval;

namespace {
// Sensor driving along the yard, one scan every 0.5 m.
void syntheticSequence(int n, std::vector<TrainingScan>* scans, Isometries* poses) {
  std::mt19937 rng(3);
  const SyntheticScene scene = SyntheticScene::structuredYard();
  LidarModel lidar;
  lidar.azimuths = 360;
  for (int i = 0; i < n; ++i) {
    const Eigen::Isometry3d T =
        se2(-4.0 + 0.5 * i, 0.5, 0.05 * i) * Eigen::Translation3d(0, 0, 1.0);
    TrainingScan s;
    s.stamp = 0.1 * i;
    s.scan.points = simulateScan(scene, T, lidar, rng);
    scans->push_back(s);
    poses->push_back(T);
  }
}
}  // namespace

TEST(TrainingSet, PairsConsecutiveAndBySpacing) {
  Isometries T;
  for (int i = 0; i < 6; ++i) T.push_back(se2(0.4 * i, 0.0, 0.1 * i));
  const auto c = makePairs(T, 0.0);
  ASSERT_EQ(c.size(), 5u);
  EXPECT_EQ(c[2].a, 2);
  EXPECT_EQ(c[2].b, 3);
  EXPECT_TRUE((T[2] * c[2].T_a_b).isApprox(T[3], 1e-12));  // T_a_b maps b into a
  const auto s = makePairs(T, 1.0);  // first scan >= 1 m away: 3 steps of 0.4 m
  ASSERT_EQ(s.size(), 3u);
  EXPECT_EQ(s[0].b, 3);
  EXPECT_EQ(s[2].a, 2);
  EXPECT_EQ(s[2].b, 5);
}

TEST(TrainingSet, SyntheticLidarSamplesAreLabelledAndCorAlSeparates) {
  std::vector<TrainingScan> scans;
  Isometries poses;
  syntheticSequence(5, &scans, &poses);
  const auto perts = makePerturbations(PerturbationConfig::lidarProtocol());
  SampleSet set;
  std::string err;
  std::size_t calls = 0;
  ASSERT_TRUE(buildSampleSet(
      scans, makePairs(poses, 0.0), perts, FeatureConfig::lidar(),
      [&](std::size_t d, std::size_t t) {
        ++calls;
        EXPECT_LE(d, t);
      },
      &set, &err))
      << err;
  ASSERT_EQ(set.samples.size(), 4u * 5u);
  EXPECT_EQ(calls, 20u);
  ASSERT_EQ(set.methods.size(), 5u);  // no CFEAR for lidar
  EXPECT_EQ(set.groups, std::vector<std::string>{"0.1 m + 0.1 rad"});
  int wins = 0, total = 0;
  qualityOrdering(set, set.groups[0], &wins, &total);
  EXPECT_EQ(total, 16);
  EXPECT_GE(wins, 15);
  for (const Sample& s : set.samples) {
    EXPECT_EQ(s.label, s.offset == "aligned" ? 1 : 0);
    ASSERT_EQ(s.features.size(), 5u);
    EXPECT_TRUE(std::isfinite(s.features[0][0]) && std::isfinite(s.features[3][0]));
  }
}

TEST(TrainingSet, OxfordRadarProtocolAndTrainingRun) {
  CORAL_REQUIRE_DATA("oxford_radar_tiny");
  OxfordDataset ds;
  std::string err;
  ASSERT_TRUE(ds.load(coral_data, &err)) << err;
  std::vector<TrainingScan> scans;
  Isometries poses;
  ASSERT_TRUE(loadOxfordTrainingScans(ds, OxfordTrainingConfig(), nullptr, &scans, &poses, &err))
      << err;
  ASSERT_EQ(scans.size(), 11u);
  for (const TrainingScan& s : scans) {
    EXPECT_GT(s.scan.points.size(), 300u);    // RIP features
    EXPECT_GT(s.cfear_points.size(), 1000u);  // k-strongest points, up to 12 x 400
    EXPECT_LE(s.cfear_points.size(), 4800u);
  }
  SampleSet set;
  ASSERT_TRUE(buildSampleSet(scans, makePairs(poses, 0.0),
                             makePerturbations(PerturbationConfig::radarProtocol()),
                             FeatureConfig::radar(), nullptr, &set, &err))
      << err;
  ASSERT_EQ(set.samples.size(), 10u * 13u);
  ASSERT_EQ(set.methods.size(), 8u);
  // CorAl's Q orders ground truth below the offsets (DESIGN anchor: 39/40, 40/40, 40/40).
  for (const std::string& g : set.groups) {
    int wins = 0, total = 0;
    qualityOrdering(set, g, &wins, &total);
    EXPECT_EQ(total, 40);
    EXPECT_GE(wins, 38) << g;
  }
  TrainingRunConfig cfg;
  cfg.output_dir = ::testing::TempDir() + "/coral_train_test";
  TrainingRunResult res;
  ASSERT_TRUE(runTraining(set, nullptr, cfg, &res, &err)) << err;
  ASSERT_EQ(res.rows.size(), 8u * 3u);
  EXPECT_EQ(res.rows[0].method, "CorAl");
  EXPECT_EQ(res.rows[0].pairs, 10);
  EXPECT_GE(res.rows[0].auc, 0.9);       // held-out, 0.3 m
  EXPECT_GE(res.rows[2].accuracy, 0.9);  // 0.7 m
  std::ifstream y(cfg.output_dir + "/classifier.yaml");
  std::stringstream text;
  text << y.rdbuf();
  for (const char* key : {"\nclassifier:\n  method: classifier\n",
                          "\n  beta0: ", "\n  beta1: ", "\n  beta2: ", "\n  threshold: 0.5\n"})
    EXPECT_NE(text.str().find(key), std::string::npos) << key;
  // The deployed classifier calls the ground-truth pairs aligned and the offsets not.
  const ClassifierConfig c = res.classifier.toClassifierConfig();
  int right = 0;
  for (const Sample& s : set.samples)
    if (s.label == 1 || s.group == "0.7 m")
      right += classify(c, s.features[0][0], s.features[0][1]).aligned == (s.label == 1);
  EXPECT_GE(right, 45);  // of 50
}
