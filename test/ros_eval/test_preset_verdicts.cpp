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

struct Tally {
  int pairs = 0, aligned_ok = 0, offsets = 0, offsets_ok = 0, no_verdict = 0;
  std::ostringstream wrong;  // the pairs judged wrongly, for the failure message
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
  const std::pair<const char*, core::Vec3> dirs[4] = {
      {"forward", {m, 0, 0}}, {"backward", {-m, 0, 0}}, {"left", {0, m, 0}}, {"right", {0, -m, 0}}};
  for (std::size_t i = 0; i < d.pairs.size(); i += stride) {
    const core::ScanPair& p = d.pairs[i];
    const core::Scan& a = d.scans[p.a].scan;
    const core::Scan& b = d.scans[p.b].scan;
    const core::AlignmentVerdict gt = core::judgeAlignment(a, b, p.T_a_b, node.coral, verdict);
    ++t->pairs;
    t->no_verdict += !gt.valid;
    if (gt.aligned)
      ++t->aligned_ok;
    else
      t->wrong << " pair " << i << " at ground truth (p " << gt.probability << ");";
    for (const auto& dir : dirs) {
      Eigen::Isometry3d delta = Eigen::Isometry3d::Identity();
      delta.translation() = dir.second;
      const core::AlignmentVerdict v =
          core::judgeAlignment(a, b, p.T_a_b * delta, node.coral, verdict);
      ++t->offsets;
      t->no_verdict += !v.valid;
      if (v.valid && !v.aligned)
        ++t->offsets_ok;
      else
        t->wrong << " pair " << i << " " << dir.first << " (p " << v.probability << ");";
    }
  }
  std::cout << preset << " on " << spec.name << " (" << verdictMethodName(verdict.method)
            << "): ground truth aligned " << t->aligned_ok << "/" << t->pairs
            << ", offsets misaligned " << t->offsets_ok << "/" << t->offsets << "\n";
}

}  // namespace

TEST(PresetVerdicts, RadarOxfordOnTheOxfordPairs) {
  CORAL_REQUIRE_DATA("oxford_radar_tiny");
  Tally t;
  judgeDataSet("radar_oxford", "oxford:" + coral_data, &t);
  EXPECT_EQ(t.pairs, 10);
  EXPECT_EQ(t.aligned_ok, t.pairs) << t.wrong.str();
  EXPECT_EQ(t.offsets_ok, t.offsets) << t.wrong.str();
}

TEST(PresetVerdicts, Lidar3dOnTheLibpointmatcherPair) {
  CORAL_REQUIRE_DATA("libpointmatcher_car_cloud");
  Tally t;
  judgeDataSet("lidar_3d", "cloudlist:" + coral_data + "/carCloudList.csv", &t);
  EXPECT_EQ(t.pairs, 1);
  EXPECT_EQ(t.aligned_ok, t.pairs) << t.wrong.str();
  EXPECT_EQ(t.offsets_ok, t.offsets) << t.wrong.str();
}

TEST(PresetVerdicts, Lidar3dOnTheLivoxKeyframes) {
  CORAL_REQUIRE_DATA("hku1_livox_keyframes");
  Tally t;
  const bool all = std::getenv("CORAL_TEST_ALL_PAIRS") != nullptr;
  judgeDataSet("lidar_3d", "keyframes:" + coral_data, &t, all ? 1 : 16);
  EXPECT_EQ(t.pairs, all ? 313 : 20);
  EXPECT_EQ(t.aligned_ok, t.pairs) << t.wrong.str();
  EXPECT_EQ(t.offsets_ok, t.offsets) << t.wrong.str();
}

TEST(PresetVerdicts, Lidar2dOnTheAcesRelations) {
  CORAL_REQUIRE_DATA("radish_aces");
  Tally t;
  judgeDataSet("lidar_2d", "carmen:" + coral_data + "/aces.clf.bz2", &t);
  EXPECT_EQ(t.pairs, 1279);
  EXPECT_EQ(t.aligned_ok, t.pairs) << t.wrong.str();
  EXPECT_EQ(t.offsets_ok, t.offsets) << t.wrong.str();
}
