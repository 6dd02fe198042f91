// Verdict samples at the tolerance on a simulated planar sequence: layout, Q ordering, the
// same result for any thread count, shards that merge back into the whole (through the CSV
// files a job array would write), and the three-method evaluation.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "coral_introspection/eval/sample_csv.hpp"
#include "coral_introspection/eval/synthetic.hpp"
#include "coral_introspection/eval/training_report.hpp"
#include "coral_introspection/eval/verdict_evaluation.hpp"
#include "coral_introspection/eval/verdict_samples.hpp"
#include "support/test_data.hpp"

using namespace coral_introspection::coral;
using namespace coral_introspection::eval;

namespace {

// A planar scanner driving through the yard: scans in their sensor frames and poses.
void planarSequence(int n, unsigned seed, std::vector<TrainingScan>* scans,
                    std::vector<ScanPair>* pairs) {
  std::mt19937 rng(seed);
  LidarModel lidar;
  lidar.rings = 1;
  lidar.v_min_deg = lidar.v_max_deg = 0.0;
  const SyntheticScene scene = SyntheticScene::structuredYard();
  Isometries poses;
  for (int i = 0; i < n; ++i) {
    poses.push_back(se2(-6.0 + 0.5 * i, -1.0 + 0.1 * std::sin(i), 0.05 * i));
    TrainingScan s;
    s.stamp = i;
    s.scan.points = simulateScan(scene, poses.back(), lidar, rng);
    scans->push_back(s);
  }
  *pairs = makePairs(poses, 0.0);
}

VerdictSampleConfig planarConfig() {
  VerdictSampleConfig c;
  c.coral.dimension = 2;
  c.coral.radius = 0.5;
  c.coral.epsilon = 1e-4;
  c.tolerance = ToleranceConfig::lidar2d();
  return c;
}

// The yard sequence of the layout tests: 9 scans (seed 3), their consecutive pairs, and the
// planar config on one thread.
struct YardSequence {
  std::vector<TrainingScan> scans;
  std::vector<ScanPair> pairs;
  VerdictSampleConfig cfg;
};

YardSequence yardSequence() {
  YardSequence y;
  planarSequence(9, 3, &y.scans, &y.pairs);
  y.cfg = planarConfig();
  y.cfg.threads = 1;
  return y;
}

}  // namespace

TEST(VerdictSamples, LayoutOrderingThreadsAndShards) {
  const YardSequence y = yardSequence();
  const std::vector<TrainingScan>& scans = y.scans;
  const std::vector<ScanPair>& pairs = y.pairs;
  VerdictSampleConfig cfg = y.cfg;
  SampleSet one;
  std::string err;
  ASSERT_TRUE(buildVerdictSamples("yard", scans, pairs, cfg, nullptr, &one, &err)) << err;
  ASSERT_EQ(one.samples.size(), 8u * 7u);  // aligned + x+-, y+-, yaw+- per pair
  ASSERT_EQ(one.methods.size(), 2u);
  EXPECT_EQ(one.methods[1].feature_names.size(), 7u);
  EXPECT_EQ(one.groups, (std::vector<std::string>{"translation", "rotation"}));
  int lower = 0;
  for (std::size_t i = 0; i < one.samples.size(); i += 7) {
    const Sample& a = one.samples[i];
    EXPECT_EQ(a.label, 1);
    EXPECT_EQ(a.dataset, "yard");
    // Q = H_joint - H_sep, and the aligned sample's neighbour x+ is the sample x+.
    EXPECT_NEAR(a.features[1][0], a.features[0][0] - a.features[0][1], 1e-12);
    EXPECT_DOUBLE_EQ(a.features[1][1], one.samples[i + 1].features[1][0]);
    EXPECT_EQ(one.samples[i + 1].offset, "x+");
    EXPECT_DOUBLE_EQ(one.samples[i + 1].dx, 0.3);
    EXPECT_DOUBLE_EQ(one.samples[i + 1].features[1][2], a.features[1][0]);  // x+ then x-
    EXPECT_NEAR(one.samples[i + 5].dyaw, 5.0 * M_PI / 180, 1e-12);
    for (int k = 1; k < 7; ++k) lower += a.features[1][0] < one.samples[i + k].features[1][0];
  }
  EXPECT_GE(lower, 46);  // of 48: Q lowest at the truth

  cfg.threads = 3;
  SampleSet three;
  ASSERT_TRUE(buildVerdictSamples("yard", scans, pairs, cfg, nullptr, &three, &err));
  // Shards 0/2 and 1/2 through their CSV files, merged in reverse order.
  SampleSet merged;
  for (int s : {1, 0}) {
    cfg.shard_index = s;
    cfg.shard_count = 2;
    SampleSet shard, back;
    ASSERT_TRUE(buildVerdictSamples("yard", scans, pairs, cfg, nullptr, &shard, &err));
    const std::string path = coral_test::tempPath("shard" + std::to_string(s), ".csv");
    ASSERT_TRUE(writeSamplesCsv(path, shard, &err)) << err;
    ASSERT_TRUE(readSamplesCsv(path, &back, &err)) << err;
    ASSERT_TRUE(mergeSampleSets(&merged, back, &err)) << err;
    std::remove(path.c_str());
  }
  EXPECT_FALSE(mergeSampleSets(&merged, one, &err));  // the same pairs twice
  ASSERT_EQ(three.samples.size(), one.samples.size());
  ASSERT_EQ(merged.samples.size(), one.samples.size());
  for (std::size_t i = 0; i < one.samples.size(); ++i) {
    EXPECT_EQ(three.samples[i].features, one.samples[i].features);  // bit-identical
    EXPECT_EQ(merged.samples[i].pair, one.samples[i].pair);
    EXPECT_EQ(merged.samples[i].offset, one.samples[i].offset);
    EXPECT_EQ(merged.samples[i].dataset, "yard");
    for (int m = 0; m < 2; ++m)
      for (std::size_t f = 0; f < one.samples[i].features[m].size(); ++f)
        EXPECT_NEAR(merged.samples[i].features[m][f], one.samples[i].features[m][f],
                    1e-9 * std::abs(one.samples[i].features[m][f]));
  }
  cfg.shard_index = 2;
  EXPECT_FALSE(buildVerdictSamples("yard", scans, pairs, cfg, nullptr, &one, &err));
  EXPECT_NE(err.find("shard_index"), std::string::npos) << err;
}

// aligned_spread: aligned samples a share of the tolerance off, between the exact pose and
// the misaligned offsets, at the scaled offsets, and with Q between the two on average.
TEST(VerdictSamples, AlignedSpreadAddsLabelledAlignedPosesInsideTheTolerance) {
  const YardSequence y = yardSequence();
  const std::vector<TrainingScan>& scans = y.scans;
  const std::vector<ScanPair>& pairs = y.pairs;
  VerdictSampleConfig cfg = y.cfg;
  SampleSet exact, spread;
  std::string err;
  ASSERT_TRUE(buildVerdictSamples("yard", scans, pairs, cfg, nullptr, &exact, &err)) << err;
  cfg.aligned_spread = 0.5;
  ASSERT_TRUE(buildVerdictSamples("yard", scans, pairs, cfg, nullptr, &spread, &err)) << err;
  ASSERT_EQ(spread.samples.size(), 8u * 13u);  // exact + 6 within + 6 misaligned per pair
  double q_exact = 0, q_within = 0, q_offset = 0;
  for (std::size_t p = 0; p < 8; ++p) {
    const Sample* s = &spread.samples[13 * p];
    const Sample* e = &exact.samples[7 * p];
    EXPECT_EQ(s[0].offset, "aligned");
    EXPECT_EQ(s[0].features, e[0].features);  // the exact pose's sample is unchanged
    for (int k = 1; k < 7; ++k) {
      EXPECT_EQ(s[k].label, 1);
      EXPECT_EQ(s[k].group, "");
      EXPECT_EQ(s[k].offset, e[k].offset + "@0.5");
      EXPECT_EQ(s[6 + k].offset, e[k].offset);
      EXPECT_EQ(s[6 + k].label, 0);
      EXPECT_EQ(s[6 + k].features, e[k].features);
      q_exact += s[0].features[1][0] / 48;
      q_within += s[k].features[1][0] / 48;
      q_offset += s[6 + k].features[1][0] / 48;
    }
    EXPECT_DOUBLE_EQ(s[1].dx, 0.15);                             // x+@0.5: half of 0.3 m
    EXPECT_NEAR(s[5].dyaw, 2.5 * M_PI / 180, 1e-12);             // yaw+@0.5: half of 5 deg
    EXPECT_DOUBLE_EQ(s[1].features[1][1], s[1].features[1][1]);  // probes computed (not NaN)
  }
  EXPECT_LT(q_exact, q_within);
  EXPECT_LT(q_within, q_offset);
  for (double bad : {-0.1, 1.0}) {
    cfg.aligned_spread = bad;
    EXPECT_FALSE(buildVerdictSamples("yard", scans, pairs, cfg, nullptr, &spread, &err));
    EXPECT_NE(err.find("aligned_spread"), std::string::npos) << err;
  }
}

TEST(VerdictEvaluation, ScenariosPerDataSetAndMethodChoice) {
  SampleSet set;
  std::string err;
  for (unsigned seed : {5u, 6u, 7u}) {  // three "data sets" of the same kind
    std::vector<TrainingScan> scans;
    std::vector<ScanPair> pairs;
    planarSequence(7, seed, &scans, &pairs);
    SampleSet part;
    ASSERT_TRUE(buildVerdictSamples("d" + std::to_string(seed), scans, pairs, planarConfig(),
                                    nullptr, &part, &err));
    ASSERT_TRUE(mergeSampleSets(&set, part, &err)) << err;
  }
  VerdictEvalConfig cfg;
  cfg.evaluation.folds = 3;
  VerdictEvaluation ev;
  ASSERT_TRUE(evaluateVerdicts(set, cfg, &ev, &err)) << err;
  ASSERT_EQ(ev.datasets.size(), 3u);
  int cv = 0, cross = 0, lodo = 0;
  for (const VerdictScenario& sc : ev.scenarios) {
    cv += sc.kind == "cv";
    cross += sc.kind == "cross";
    lodo += sc.kind == "lodo";
    ASSERT_EQ(sc.rows.size(), 9u);  // 3 methods x {all, translation, rotation}
    ASSERT_EQ(sc.p[0].size(), sc.samples.size());
    EXPECT_EQ(sc.rows[0].aligned + sc.rows[0].misaligned + sc.rows[0].skipped, 6 * 7);
  }
  EXPECT_EQ(cv, 3);
  EXPECT_EQ(cross, 6);
  EXPECT_EQ(lodo, 3);
  // Simulated scans are crisp: every method separates aligned from 0.3 m / 5 deg errors.
  for (int m = 0; m < 3; ++m) EXPECT_GT(ev.lodo_accuracy[m], 0.9) << m;
  EXPECT_EQ(ev.classifier.beta.size(), 3);
  EXPECT_LT(ev.classifier.beta[1], 0.0);  // higher H_joint: less likely aligned
  // A single data set is split into halves.
  SampleSet first = set;
  first.samples.resize(6 * 7);
  ASSERT_TRUE(evaluateVerdicts(first, cfg, &ev, &err)) << err;
  EXPECT_EQ(ev.datasets, (std::vector<std::string>{"d5 (first half)", "d5 (second half)"}));
  first.methods[1].feature_names.pop_back();
  EXPECT_FALSE(evaluateVerdicts(first, cfg, &ev, &err));
}
