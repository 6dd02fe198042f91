// The training path and the online path make the same features: the Oxford scans and their
// ground-truth poses through loadOxfordTrainingScans + computeFeatures (what coral_train
// trains on) and through online::Introspector (what the nodelet judges) give bit-identical
// de-skewed features and identical H_joint, H_sep and Q on every pair.
#include <gtest/gtest.h>

#include "coral_introspection/eval/oxford_dataset.hpp"
#include "coral_introspection/eval/oxford_training.hpp"
#include "coral_introspection/eval/training_set.hpp"
#include "coral_introspection/online/introspector.hpp"
#include "support/test_data.hpp"

using namespace coral_introspection;

TEST(OxfordTrainingVsIntrospector, IdenticalDeskewedFeaturesAndQ) {
  CORAL_REQUIRE_DATA("oxford_radar_tiny");
  eval::OxfordDataset ds;
  std::string err;
  ASSERT_TRUE(ds.load(coral_data, &err)) << err;
  eval::OxfordTrainingConfig ocfg;  // paper settings, motion compensation on
  ocfg.with_cfear = false;
  std::vector<eval::TrainingScan> train;
  coral::Isometries poses;
  ASSERT_TRUE(eval::loadOxfordTrainingScans(ds, ocfg, nullptr, &train, &poses, &err)) << err;
  const std::vector<eval::ScanPair> pairs = eval::makePairs(poses, 0.0);  // consecutive
  eval::FeatureConfig fcfg = eval::FeatureConfig::radar();
  fcfg.with_cfear = false;

  online::IntrospectorConfig icfg;
  icfg.coral = fcfg.coral;  // CorAl-Radar: 2D, r = 1 m
  online::Introspector intro(icfg);
  online::ProcessOptions keep;
  keep.keep_scans = true;
  std::size_t compared_points = 0;
  for (std::size_t i = 0; i < ds.png_paths.size(); ++i) {
    radar::PolarScan polar;
    online::ScanInput in;
    ASSERT_TRUE(radar::loadOxfordScan(ds.png_paths[i], &polar, &err)) << err;
    ASSERT_TRUE(radar::extractRipFeatures(polar, ocfg.rip, &in.features, &err)) << err;
    in.stamp = polar.stamp;
    in.is_radar = true;
    in.T_fixed_sensor = poses[i];
    const online::Report r = intro.process(in, keep);
    if (i == 0) {
      EXPECT_FALSE(r.judged);
      continue;
    }
    ASSERT_TRUE(r.judged) << r.reason;
    const eval::ScanPair& p = pairs[i - 1];
    ASSERT_EQ(p.b, static_cast<int>(i));
    // De-skewed features: the reference in its own frame, the later scan moved into it.
    const coral::Points& ref = train[p.a].scan.points;
    const coral::Scan cur = coral::transformScan(train[p.b].scan, p.T_a_b);
    ASSERT_EQ(r.pair.ref.points.size(), ref.size()) << "pair " << i;
    ASSERT_EQ(r.pair.cur.points.size(), cur.points.size()) << "pair " << i;
    for (std::size_t k = 0; k < ref.size(); ++k)
      ASSERT_EQ(r.pair.ref.points[k], ref[k]) << "pair " << i << " point " << k;
    for (std::size_t k = 0; k < cur.points.size(); ++k)
      ASSERT_EQ(r.pair.cur.points[k], cur.points[k]) << "pair " << i << " point " << k;
    compared_points += ref.size() + cur.points.size();
    // CorAl as training computes it for the aligned sample (x1 = H_joint, x2 = H_sep).
    const auto f = eval::computeFeatures(train[p.a], train[p.b], {}, {}, p.T_a_b, fcfg);
    ASSERT_TRUE(r.pair.verdict.coral.valid) << r.reason;
    EXPECT_EQ(r.pair.verdict.coral.h_joint, f[0][0]) << "pair " << i;
    EXPECT_EQ(r.pair.verdict.coral.h_sep, f[0][1]) << "pair " << i;
    EXPECT_EQ(r.pair.verdict.coral.quality, f[0][0] - f[0][1]) << "pair " << i;
    std::printf("pair %zu: Q %.6f (both paths), %zu + %zu features\n", i,
                r.pair.verdict.coral.quality, ref.size(), cur.points.size());
  }
  EXPECT_GT(compared_points, 5000u);
}
