// The verdict path of check_alignment and of the stream (online::judgePair with the
// preset's parameters as the nodelet loads them, no classifier override) on every shared
// real pair of each preset's
// sensor class: at ground truth the pair must be judged aligned, with the later scan moved
// by one tolerance forward, backward, left or right (its sensor frame) misaligned.
// The Livox keyframes cost about 13 x 5 CorAl evaluations of 0.1 s per pair with the
// lidar_3d preset's r = 1 m: every 16th pair by default, all with CORAL_TEST_ALL_PAIRS=1.
#include <gtest/gtest.h>

#include <cstdlib>
#include <sstream>

#include "coral_introspection/eval/pair_datasets.hpp"
#include "coral_introspection/eval/verdict_evaluation.hpp"
#include "coral_introspection/eval/verdict_samples.hpp"
#include "coral_introspection/online/introspector.hpp"
#include "coral_introspection/ros_eval/preset_file.hpp"
#include "support/test_data.hpp"

using namespace coral_introspection;

namespace {

const char* const kCases[5] = {"ground truth", "forward", "backward", "left", "right"};

struct Tally {
  int pairs = 0;
  int right[5] = {0, 0, 0, 0, 0};  // per case of kCases: verdict as expected
  int wrong_flat = 0;              // wrong verdicts that report a flat (unobservable) axis
  std::ostringstream wrong;        // the pairs judged wrongly, for the failure message
  double rate(int c) const { return pairs ? static_cast<double>(right[c]) / pairs : 0.0; }
  bool allRight() const {
    for (int c = 0; c < 5; ++c)
      if (right[c] != pairs) return false;
    return true;
  }
};

void loadPreset(const std::string& preset, ros_adapters::NodeConfig* node) {
  core::VerdictConfig verdict;
  std::string err;
  ASSERT_TRUE(ros_adapters::loadPresetFile(
      std::string(CORAL_SOURCE_DIR) + "/config/" + preset + ".yaml", node, &verdict, &err))
      << err;
}

void loadData(const ros_adapters::NodeConfig& node, const std::string& spec_text,
              core::PairDataset* d) {
  std::string err;
  core::DatasetSpec spec;
  ASSERT_TRUE(core::parseDatasetSpec(spec_text, &spec, &err)) << err;
  core::DatasetOptions opt;
  opt.oxford.rip = node.rip;
  opt.oxford.with_cfear = false;
  opt.oxford.motion_compensation = node.online.deskew.enabled;
  ASSERT_TRUE(core::loadPairDataset(spec, opt, nullptr, d, &err)) << err;
}

// Judges every `stride`-th pair of `spec` with `preset`.
void judgeDataSet(const std::string& preset, const std::string& spec_text, Tally* t,
                  std::size_t stride = 1) {
  ros_adapters::NodeConfig node;
  loadPreset(preset, &node);
  core::PairDataset d;
  loadData(node, spec_text, &d);
  if (::testing::Test::HasFatalFailure()) return;
  const core::VerdictConfig& verdict = node.online.verdict;
  const double m = verdict.tolerance.translation;
  const core::Vec3 offsets[5] = {{0, 0, 0}, {m, 0, 0}, {-m, 0, 0}, {0, m, 0}, {0, -m, 0}};
  for (std::size_t i = 0; i < d.pairs.size(); i += stride) {
    const core::ScanPair& p = d.pairs[i];
    ++t->pairs;
    for (int c = 0; c < 5; ++c) {
      Eigen::Isometry3d delta = Eigen::Isometry3d::Identity();
      delta.translation() = offsets[c];
      const core::AlignmentVerdict v = online::judgePair(d.scans[p.a].scan, d.scans[p.b].scan,
                                                         p.T_a_b * delta, node.online, false)
                                           .verdict;
      if (v.valid && v.aligned == (c == 0)) {
        ++t->right[c];
        continue;
      }
      t->wrong_flat += !v.relative.flat_axes.empty();
      t->wrong << " pair " << i << " " << kCases[c] << " (p " << v.probability << ", "
               << (v.valid ? "" : v.reason) << ");";
    }
  }
  std::cout << preset << " (" << verdictMethodName(verdict.method) << ") on " << d.name << ", "
            << t->pairs << " pairs, right:";
  for (int c = 0; c < 5; ++c) std::cout << " " << kCases[c] << " " << t->right[c];
  std::cout << "; wrong with a flat axis " << t->wrong_flat << "\n";
}

}  // namespace

// The online verdict (online::judgePair, which check_alignment and the stream call) equals
// coral_train's evaluation of the same samples: same Q values, relative score, verdict and
// classifier probability, for every method.
TEST(PresetVerdicts, OnlineVerdictEqualsTrainingEvaluation) {
  CORAL_REQUIRE_DATA("oxford_radar_tiny");
  ros_adapters::NodeConfig node;
  loadPreset("radar_oxford", &node);
  core::PairDataset d;
  loadData(node, "oxford:" + coral_data, &d);
  ASSERT_FALSE(::testing::Test::HasFatalFailure());
  core::VerdictSampleConfig scfg;
  scfg.coral = node.online.coral;
  scfg.tolerance = node.online.verdict.tolerance;
  core::SampleSet set;
  std::string err;
  ASSERT_TRUE(core::buildVerdictSamples(d.name, d.scans, d.pairs, scfg, nullptr, &set, &err))
      << err;
  const std::vector<core::RelativeCheckResult> rel =
      core::relativeResults(set, node.online.verdict.relative);
  const std::vector<core::ToleranceOffset> offsets =
      core::toleranceOffsets(scfg.tolerance, scfg.coral.dimension);
  ASSERT_EQ(set.samples.size(), d.pairs.size() * (offsets.size() + 1));
  int misaligned = 0;
  for (core::VerdictMethod m : {core::VerdictMethod::kClassifier, core::VerdictMethod::kRelative,
                                core::VerdictMethod::kBoth}) {
    online::IntrospectorConfig cfg = node.online;
    cfg.verdict.method = m;
    for (std::size_t k = 0; k < set.samples.size(); ++k) {
      const core::Sample& s = set.samples[k];
      const int o = static_cast<int>(k % (offsets.size() + 1)) - 1;  // -1: aligned sample
      const core::ScanPair& p = d.pairs[s.pair];
      const online::PairJudgement j = online::judgePair(
          d.scans[p.a].scan, d.scans[p.b].scan,
          p.T_a_b * (o < 0 ? Eigen::Isometry3d::Identity() : offsets[o].delta), cfg, false);
      SCOPED_TRACE("pair " + std::to_string(s.pair) + " " + (o < 0 ? "aligned" : offsets[o].name) +
                   " " + core::verdictMethodName(m));
      ASSERT_TRUE(j.verdict.valid) << j.reason;
      EXPECT_EQ(j.verdict.coral.h_joint, s.features[0][0]);
      EXPECT_EQ(j.verdict.coral.h_sep, s.features[0][1]);
      const core::Verdict c =
          core::classify(cfg.verdict.classifier, s.features[0][0], s.features[0][1]);
      EXPECT_EQ(j.verdict.classifier.probability, c.probability);
      if (m != core::VerdictMethod::kClassifier) {
        EXPECT_EQ(j.verdict.relative.score, rel[k].score);
        EXPECT_EQ(j.verdict.relative.misaligned, rel[k].misaligned);
        EXPECT_EQ(j.verdict.relative.hint.name, rel[k].hint.name);
      }
      const bool rel_aligned = !rel[k].misaligned;
      const bool expect = m == core::VerdictMethod::kClassifier ? c.aligned
                          : m == core::VerdictMethod::kRelative ? rel_aligned
                                                                : c.aligned && rel_aligned;
      EXPECT_EQ(j.verdict.aligned, expect);
      misaligned += !j.verdict.aligned;
    }
  }
  EXPECT_GT(misaligned, 0);  // both outcomes occur, so the comparison means something
}

TEST(PresetVerdicts, RadarOxfordOnTheOxfordPairs) {
  CORAL_REQUIRE_DATA("oxford_radar_tiny");
  Tally t;
  judgeDataSet("radar_oxford", "oxford:" + coral_data, &t);
  EXPECT_EQ(t.pairs, 10);
  EXPECT_TRUE(t.allRight()) << t.wrong.str();
}

TEST(PresetVerdicts, Lidar3dOnTheLibpointmatcherPair) {
  CORAL_REQUIRE_DATA("libpointmatcher_car_cloud");
  Tally t;
  judgeDataSet("lidar_3d", "cloudlist:" + coral_data + "/carCloudList.csv", &t);
  EXPECT_EQ(t.pairs, 1);
  EXPECT_TRUE(t.allRight()) << t.wrong.str();
}

TEST(PresetVerdicts, Lidar3dOnTheLivoxKeyframes) {
  CORAL_REQUIRE_DATA("hku1_livox_keyframes");
  Tally t;
  const bool all = std::getenv("CORAL_TEST_ALL_PAIRS") != nullptr;
  judgeDataSet("lidar_3d", "keyframes:" + coral_data, &t, all ? 1 : 16);
  EXPECT_EQ(t.pairs, all ? 313 : 20);
  EXPECT_TRUE(t.allRight()) << t.wrong.str();
}

TEST(PresetVerdicts, Lidar2dOnTheAcesRelations) {
  CORAL_REQUIRE_DATA("radish_aces");
  Tally t;
  judgeDataSet("lidar_2d", "carmen:" + coral_data + "/aces.clf.bz2", &t);
  EXPECT_EQ(t.pairs, 1279);
  // Not all right: in about a quarter of the relations the robot is in a corridor, Q changes
  // 10-100x less along x than along y (x is reported flat), and its minimum along x can lie
  // a tolerance away from the relation (which a human could not verify along x either).
  // Measured: ground truth 1250, forward 1266, backward 1241, left 1279, right 1278.
  EXPECT_GE(t.rate(0), 0.97) << t.wrong.str();
  EXPECT_GE(t.rate(1), 0.98) << t.wrong.str();
  EXPECT_GE(t.rate(2), 0.96) << t.wrong.str();
  EXPECT_GE(t.rate(3), 0.995) << t.wrong.str();
  EXPECT_GE(t.rate(4), 0.995) << t.wrong.str();
  int wrong = 0;
  for (int c = 0; c < 5; ++c) wrong += t.pairs - t.right[c];
  EXPECT_GE(t.wrong_flat, 0.9 * wrong) << "wrong verdicts should mostly come with a flat axis";
}
