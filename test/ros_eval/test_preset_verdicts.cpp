// The verdict path check_alignment uses (core::judgeAlignment with the preset's CorAl and
// verdict settings, no classifier override) on every shared real pair of each preset's
// sensor class: at ground truth the pair must be judged aligned, with the later scan moved
// by one tolerance forward, backward, left or right (its sensor frame) misaligned.
// The Livox keyframes cost about 13 x 5 CorAl evaluations of 0.1 s per pair with the
// lidar_3d preset's r = 1 m: every 16th pair by default, all with CORAL_TEST_ALL_PAIRS=1.
#include <gtest/gtest.h>

#include <cstdlib>
#include <sstream>

#include "coral_introspection/eval/pair_datasets.hpp"
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

// Judges every `stride`-th pair of `spec` with `preset`.
void judgeDataSet(const std::string& preset, const std::string& spec_text, Tally* t,
                  std::size_t stride = 1) {
  ros_adapters::NodeConfig node;
  core::VerdictConfig verdict;
  std::string err;
  ASSERT_TRUE(ros_adapters::loadPresetFile(
      std::string(CORAL_SOURCE_DIR) + "/config/" + preset + ".yaml", &node, &verdict, &err))
      << err;
  core::DatasetSpec spec;
  ASSERT_TRUE(core::parseDatasetSpec(spec_text, &spec, &err)) << err;
  core::DatasetOptions opt;
  opt.oxford.rip = node.rip;
  opt.oxford.with_cfear = false;
  opt.oxford.motion_compensation = node.motion_compensation;
  core::PairDataset d;
  ASSERT_TRUE(core::loadPairDataset(spec, opt, nullptr, &d, &err)) << err;
  const double m = verdict.tolerance.translation;
  const core::Vec3 offsets[5] = {{0, 0, 0}, {m, 0, 0}, {-m, 0, 0}, {0, m, 0}, {0, -m, 0}};
  for (std::size_t i = 0; i < d.pairs.size(); i += stride) {
    const core::ScanPair& p = d.pairs[i];
    ++t->pairs;
    for (int c = 0; c < 5; ++c) {
      Eigen::Isometry3d delta = Eigen::Isometry3d::Identity();
      delta.translation() = offsets[c];
      const core::AlignmentVerdict v = core::judgeAlignment(d.scans[p.a].scan, d.scans[p.b].scan,
                                                            p.T_a_b * delta, node.coral, verdict);
      if (v.valid && v.aligned == (c == 0)) {
        ++t->right[c];
        continue;
      }
      t->wrong_flat += !v.relative.flat_axes.empty();
      t->wrong << " pair " << i << " " << kCases[c] << " (p " << v.probability << ", "
               << (v.valid ? "" : v.reason) << ");";
    }
  }
  std::cout << preset << " (" << verdictMethodName(verdict.method) << ") on " << spec.name << ", "
            << t->pairs << " pairs, right:";
  for (int c = 0; c < 5; ++c) std::cout << " " << kCases[c] << " " << t->right[c];
  std::cout << "; wrong with a flat axis " << t->wrong_flat << "\n";
}

}  // namespace

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
