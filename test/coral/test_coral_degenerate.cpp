// Degenerate and unbounded input is named and counted, never scored (issue 13): identical
// points, lidar no-returns at the origin hiding a 0.7 m error, a point at 1e30, NaN/Inf,
// more points than max_points, and the point filters themselves.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "coral_introspection/coral/classifier.hpp"
#include "coral_introspection/coral/coral.hpp"
#include "coral_introspection/coral/coral_pair.hpp"
#include "coral_introspection/coral/coral_uncertainty.hpp"
#include "coral_introspection/coral/point_filter.hpp"
#include "coral_introspection/eval/synthetic.hpp"

using namespace coral_introspection::coral;
using namespace coral_introspection::eval;

namespace {

CoralConfig lidarConfig() {  // the lidar_3d preset's CorAl settings
  CoralConfig c;
  c.radius = 1.0;
  c.epsilon = 1e-4;
  return c;
}

ClassifierConfig lidarClassifier() {  // the lidar_3d preset's boundary: Q = 0.2 nats
  ClassifierConfig k;
  k.beta0 = 4.0;
  k.beta1 = -20.0;
  k.beta2 = 20.0;
  return k;
}

bool aligned(const CoralResult& r) {
  const ClassifierConfig k = lidarClassifier();
  return r.valid && classify(k, r.h_joint, r.h_sep).aligned;
}

// Sensor-frame scans of the yard; b's pose is off by `lateral` m to its left.
struct Pair {
  Points a_sensor, b_sensor;
  Eigen::Isometry3d T_w_a, T_w_b_est;
};

Pair yard(double lateral) {
  std::mt19937 rng(31);
  const SyntheticScene scene = SyntheticScene::structuredYard();
  Pair p;
  p.T_w_a = se2(0, 0, 0);
  const Eigen::Isometry3d T_w_b = se2(0.8, 0.3, 0.05);
  p.a_sensor = simulateScan(scene, p.T_w_a, LidarModel(), rng);
  p.b_sensor = simulateScan(scene, T_w_b, LidarModel(), rng);
  p.T_w_b_est = T_w_b * se2(0.0, lateral, 0.0);
  return p;
}

CoralResult score(const Pair& p, const CoralConfig& cfg, int origin_points = 0) {
  Scan a, b;
  a.points = p.a_sensor;
  b.points = p.b_sensor;
  // Lidar no-returns reported at (0, 0, 0) of each sensor frame.
  for (int i = 0; i < origin_points; ++i) {
    a.points.push_back(Vec3::Zero());
    b.points.push_back(Vec3::Zero());
  }
  return computeCoral(transformScan(a, p.T_w_a), transformScan(b, p.T_w_b_est), cfg);
}

}  // namespace

TEST(CoralDegenerate, IdenticalPointsAreNeverAligned) {
  Scan a, b;
  a.points.assign(5000, Vec3(1.0, 2.0, 3.0));
  b.points.assign(5000, Vec3(1.0, 2.0, 3.0));
  const CoralResult merged = computeCoral(a, b, lidarConfig());
  EXPECT_FALSE(merged.valid);
  EXPECT_FALSE(aligned(merged));
  EXPECT_EQ(merged.num_merged, 9998u);  // one point left per scan
  EXPECT_FALSE(merged.reason.empty());
  // Without merging every neighbourhood is coincident: no usable covariance, not valid.
  CoralConfig no_merge = lidarConfig();
  no_merge.merge_distance = 0.0;
  const CoralResult raw = computeCoral(a, b, no_merge);
  EXPECT_FALSE(raw.valid);
  EXPECT_EQ(raw.num_valid, 0u);
  EXPECT_EQ(raw.num_degenerate, 10000u);
  EXPECT_NE(raw.reason.find("usable covariance"), std::string::npos) << raw.reason;
}

// The cost of an identical cluster grew with its square (40k points: 36 s per pair). Merged,
// the neighbour search does the same work whatever the cluster size.
TEST(CoralDegenerate, IdenticalClusterWorkIsBounded) {
  const Pair p = yard(0.0);
  const CoralConfig cfg = lidarConfig();
  std::size_t base = 0;
  for (int n : {0, 5000, 10000, 40000}) {
    Scan a, b;
    a.points = p.a_sensor;
    b.points = p.b_sensor;
    a.points.insert(a.points.end(), n, Vec3(2.0, 1.0, 0.5));
    b.points.insert(b.points.end(), n, Vec3(2.0, 1.0, 0.5));
    const CoralResult r = computeCoral(a, b, cfg);
    if (n == 0) {
      base = r.num_distance_tests;
      ASSERT_GT(base, 0u);
      continue;
    }
    // At most the cluster's one merged point per scan more than the clean pair scores,
    // each testing at most every point: linear, not quadratic, in n.
    const std::size_t used = r.num_used_a + r.num_used_b;
    EXPECT_LE(r.num_distance_tests, base + 4 * used) << n;
    EXPECT_EQ(r.num_merged, 2u * (n - 1)) << n;
  }
  // The counter does measure the work: unmerged, a 5000-point cluster alone tests each of
  // its 10000 points against all 10000.
  CoralConfig no_merge = cfg;
  no_merge.merge_distance = 0.0;
  Scan a, b;
  a.points.assign(5000, Vec3(2.0, 1.0, 0.5));
  b.points = a.points;
  EXPECT_EQ(computeCoral(a, b, no_merge).num_distance_tests, 10000u * 10000u);
}

TEST(CoralDegenerate, OriginClusterDoesNotMaskALateralError) {
  const CoralConfig cfg = lidarConfig();
  const CoralResult good = score(yard(0.0), cfg);
  ASSERT_TRUE(aligned(good)) << good.quality;
  const Pair off = yard(0.7);
  const CoralResult clean = score(off, cfg);
  ASSERT_TRUE(clean.valid);
  EXPECT_FALSE(aligned(clean)) << clean.quality;
  for (int n : {1500, 3000}) {
    const CoralResult r = score(off, cfg, n);
    EXPECT_FALSE(aligned(r)) << n << " no-returns: Q " << r.quality;
    EXPECT_NEAR(r.quality, clean.quality, 0.05) << n;
    EXPECT_EQ(r.num_merged, 2u * (n - 1));
  }
  // Without merging the coincident cluster has no usable covariance: never scored as q = 0.
  CoralConfig no_merge = cfg;
  no_merge.merge_distance = 0.0;
  const CoralResult r = score(off, no_merge, 1500);
  EXPECT_FALSE(aligned(r)) << r.quality;
  EXPECT_NEAR(r.quality, clean.quality, 0.05);
}

TEST(CoralDegenerate, FarAndNonFinitePointsAreDroppedAndCounted) {
  const Pair p = yard(0.0);
  const CoralConfig cfg = lidarConfig();
  Scan a, b;
  a.points = p.a_sensor;
  b.points = p.b_sensor;
  a = transformScan(a, p.T_w_a);
  b = transformScan(b, p.T_w_b_est);
  const CoralResult ref = computeCoral(a, b, cfg);
  Scan dirty = b;
  dirty.points.push_back(Vec3(1e30, 0.0, 0.0));
  dirty.points.push_back(Vec3(0.0, -2e7, 0.0));
  dirty.points.push_back(Vec3(std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0));
  dirty.points.push_back(Vec3(0.0, 0.0, std::numeric_limits<double>::infinity()));
  const CoralResult r = computeCoral(a, dirty, cfg);
  EXPECT_EQ(r.num_out_of_range, 2u);
  EXPECT_EQ(r.num_non_finite, 2u);
  EXPECT_EQ(r.num_points_b, b.points.size());
  EXPECT_EQ(r.valid, ref.valid);
  EXPECT_DOUBLE_EQ(r.quality, ref.quality);
  EXPECT_EQ(aligned(r), aligned(ref));
  // Kept (range check off), the 1e30 point sits alone in the clamped outer cells: the rest
  // of the pair is scored exactly as before.
  CoralConfig wide = cfg;
  wide.max_abs_coordinate = kMaxAbsCoordinate;
  Scan far = b;
  far.points.push_back(Vec3(1e30, 0.0, 0.0));
  const CoralResult rf = computeCoral(a, far, wide);
  EXPECT_EQ(rf.num_valid, ref.num_valid);
  EXPECT_DOUBLE_EQ(rf.quality, ref.quality);
}

// No-return readings written at a scanner's maximum range (the Intel log's 81.83 m): with
// max_range they are dropped before anything scores them, measured from each scan's own origin
// (b's sensor is 0.85 m from a's), so the pair is scored exactly as without them.
TEST(CoralDegenerate, NoReturnReadingsBeyondMaxRangeAreDroppedAndCounted) {
  const Pair p = yard(0.0);
  CoralConfig cfg = lidarConfig();
  Scan a, b;
  a.points = p.a_sensor;
  b.points = p.b_sensor;
  Scan a_sat = a, b_sat = b;
  for (int k = 0; k < 36; ++k) {  // a ring of no-returns at 80 m around each sensor
    const double angle = k * M_PI / 18.0;
    a_sat.points.emplace_back(80.0 * std::cos(angle), 80.0 * std::sin(angle), 0.0);
    b_sat.points.emplace_back(80.0 * std::cos(angle), 80.0 * std::sin(angle), 0.0);
  }
  const Scan b_sat_sensor = b_sat;
  a = transformScan(a, p.T_w_a);
  b = transformScan(b, p.T_w_b_est);
  a_sat = transformScan(a_sat, p.T_w_a);
  b_sat = transformScan(b_sat, p.T_w_b_est);
  const CoralResult ref = computeCoral(a, b, cfg);
  ASSERT_TRUE(ref.valid) << ref.reason;
  const CoralResult kept = computeCoral(a_sat, b_sat, cfg);  // max_range 0: scored as returns
  EXPECT_EQ(kept.num_beyond_max_range, 0u);
  EXPECT_EQ(kept.num_points_b, b.points.size() + 36);
  // 79.5 m from each sensor, so beyond 79.5 m of the world origin for some of b's ring: only a
  // range measured from b's own origin keeps exactly a's and b's real points.
  cfg.max_range = 79.5;
  const CoralResult dropped = computeCoral(a_sat, b_sat, cfg);
  EXPECT_EQ(dropped.num_beyond_max_range, 72u);
  EXPECT_EQ(dropped.num_points_a, a.points.size());
  EXPECT_EQ(dropped.num_points_b, b.points.size());
  EXPECT_DOUBLE_EQ(dropped.quality, ref.quality);
  EXPECT_EQ(dropped.num_valid, ref.num_valid);
  // CoralPair (b in its sensor frame): the same hygiene, and the points the free-space term
  // casts rays from.
  const CoralPair pair(a_sat, b_sat_sensor, cfg);
  EXPECT_EQ(pair.points(0).size(), a.points.size());
  EXPECT_EQ(pair.points(1).size(), b.points.size());
  const CoralResult at_pose = pair.evaluate(p.T_w_b_est);
  EXPECT_EQ(at_pose.num_beyond_max_range, 72u);
  EXPECT_NEAR(at_pose.quality, ref.quality, 1e-6);
}

TEST(CoralDegenerate, MaxPointsThinsOrRefuses) {
  const Pair p = yard(0.0);
  CoralConfig cfg = lidarConfig();
  cfg.max_points = 5000;
  Scan a, b;
  a.points = p.a_sensor;
  b.points = p.b_sensor;
  a = transformScan(a, p.T_w_a);
  b = transformScan(b, p.T_w_b_est);
  ASSERT_GT(a.points.size(), 5000u);
  const CoralResult r = computeCoral(a, b, cfg);
  EXPECT_EQ(r.num_thinned, a.points.size() + b.points.size() - 10000u);
  EXPECT_EQ(r.num_queries, 10000u);
  EXPECT_TRUE(aligned(r)) << r.quality;
  cfg.refuse_over_max_points = true;
  const CoralResult refused = computeCoral(a, b, cfg);
  EXPECT_FALSE(refused.valid);
  EXPECT_NE(refused.reason.find("max_points"), std::string::npos) << refused.reason;
}

TEST(CoralDegenerate, MostlyDegenerateResultIsNotValid) {
  // Collinear scans with epsilon = 0: every overlapping neighbourhood is singular.
  CoralConfig cfg = lidarConfig();
  cfg.epsilon = 0.0;
  cfg.radius = 0.3;
  Scan a, b;
  for (int i = 0; i < 200; ++i) {
    a.points.push_back(Vec3(0.01 * i, 0.0, 0.0));
    b.points.push_back(Vec3(0.01 * i + 0.005, 0.0, 0.0));
  }
  // A small well-conditioned blob makes a few points valid.
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0.0, 0.05);
  for (int i = 0; i < 30; ++i) {
    a.points.push_back(Vec3(5 + n(rng), n(rng), n(rng)));
    b.points.push_back(Vec3(5 + n(rng), n(rng), n(rng)));
  }
  const CoralResult r = computeCoral(a, b, cfg);
  EXPECT_GT(r.num_valid, 0u);
  EXPECT_GT(r.num_degenerate, r.num_valid);
  EXPECT_FALSE(r.valid);
  EXPECT_NE(r.reason.find("degenerate"), std::string::npos) << r.reason;
  cfg.max_degenerate_fraction = 1.0;
  EXPECT_TRUE(computeCoral(a, b, cfg).valid);
}

TEST(PointFilter, MergeKeepsOrderAndLonePointsBitIdentical) {
  const Points in = {Vec3(0.3, 0.1, 0.0), Vec3(1.0, 1.0, 1.0), Vec3(0.3004, 0.1002, 0.0),
                     Vec3(-5.0, 2.0, 1.0)};
  Points out;
  EXPECT_EQ(mergeCoincident(in, 1e-3, 3, &out), 1u);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_TRUE(out[0].isApprox(Vec3(0.3002, 0.1001, 0.0), 1e-12));
  EXPECT_EQ(out[1], in[1]);
  EXPECT_EQ(out[2], in[3]);
  EXPECT_EQ(mergeCoincident(in, 0.0, 3, &out), 0u);
  EXPECT_EQ(out.size(), in.size());
}

TEST(PointFilter, StrideSubsampleAndUsablePoints) {
  Points in;
  for (int i = 0; i < 10; ++i) in.emplace_back(i, 0, 0);
  const Points s = strideSubsample(in, 4);
  ASSERT_EQ(s.size(), 4u);
  EXPECT_EQ(s[0].x(), 0.0);
  EXPECT_EQ(s[1].x(), 2.0);
  EXPECT_EQ(s[3].x(), 7.0);
  Points storage;
  std::size_t nf = 0, oor = 0;
  EXPECT_EQ(&usablePoints(in, 100.0, &storage, &nf, &oor), &in);  // nothing to drop: no copy
  in.emplace_back(std::nan(""), 0, 0);
  in.emplace_back(1e9, 0, 0);
  const Points& u = usablePoints(in, 100.0, &storage, &nf, &oor);
  EXPECT_EQ(u.size(), 10u);
  EXPECT_EQ(nf, 1u);
  EXPECT_EQ(oor, 1u);
}

TEST(PointFilter, RangeIsMeasuredFromTheOriginInTheScansDimension) {
  const Vec3 origin(10.0, 0.0, 0.0);
  EXPECT_TRUE(withinRange(Vec3(14.9, 0.0, 0.0), origin, 5.0, 3));
  EXPECT_FALSE(withinRange(Vec3(15.1, 0.0, 0.0), origin, 5.0, 3));
  EXPECT_FALSE(withinRange(Vec3(10.0, 0.0, 6.0), origin, 5.0, 3));
  EXPECT_TRUE(withinRange(Vec3(10.0, 0.0, 6.0), origin, 5.0, 2));  // 2D: z is not a range
  EXPECT_TRUE(withinRange(Vec3(1e6, 0.0, 0.0), origin, 0.0, 3));   // 0 = off
  Points in = {Vec3(11, 0, 0), Vec3(20, 0, 0), Vec3(12, 0, 0)};
  Points storage;
  std::size_t dropped = 7;
  const Points& kept = pointsWithinRange(in, origin, 5.0, 3, &storage, &dropped);
  ASSERT_EQ(kept.size(), 2u);
  EXPECT_EQ(kept[1].x(), 12.0);  // order kept
  EXPECT_EQ(dropped, 1u);
  EXPECT_EQ(&pointsWithinRange(in, origin, 50.0, 3, &storage, &dropped), &in);  // no copy
  EXPECT_EQ(dropped, 0u);
  // In a scan, each point's covariance goes with it.
  Scan s;
  s.origin = origin;
  s.points = in;
  for (int k = 0; k < 3; ++k) s.covariances.push_back(Eigen::Matrix3d::Identity() * (k + 1));
  std::size_t removed = 1;  // added to
  removeBeyondRange(s, 5.0, 3, &removed);
  ASSERT_EQ(s.points.size(), 2u);
  ASSERT_EQ(s.covariances.size(), 2u);
  EXPECT_EQ(s.points[1].x(), 12.0);
  EXPECT_EQ(s.covariances[1](0, 0), 3.0);
  EXPECT_EQ(removed, 2u);
}

TEST(CoralDegenerate, ConfigValidation) {
  CoralConfig c;
  c.max_points = 0;
  EXPECT_NE(c.validate().find("max_points"), std::string::npos);
  c = CoralConfig();
  c.merge_distance = -1.0;
  EXPECT_NE(c.validate().find("merge_distance"), std::string::npos);
  c = CoralConfig();
  c.max_abs_coordinate = 0.0;
  EXPECT_NE(c.validate().find("max_abs_coordinate"), std::string::npos);
  c = CoralConfig();
  c.max_range = -1.0;
  EXPECT_NE(c.validate().find("max_range"), std::string::npos);
  c.max_range = std::nan("");
  EXPECT_NE(c.validate().find("max_range"), std::string::npos);
  c = CoralConfig();
  c.max_degenerate_fraction = 1.5;
  EXPECT_NE(c.validate().find("max_degenerate_fraction"), std::string::npos);
}

// Scored points are stored as float (PointEntropy::position): the coordinate limit cannot
// accept a point whose position would be inf (found by fuzz_coral with a limit of 1e300).
TEST(CoralDegenerate, CoordinateLimitKeepsScoredPositionsFinite) {
  CoralConfig c;
  c.max_abs_coordinate = 1e300;
  EXPECT_NE(c.validate().find("max_abs_coordinate"), std::string::npos) << c.validate();
  c.max_abs_coordinate = std::nextafter(kMaxAbsCoordinate, 1e300);  // 1e38 is the largest
  EXPECT_NE(c.validate().find("max_abs_coordinate"), std::string::npos) << c.validate();
  c = lidarConfig();
  c.max_abs_coordinate = kMaxAbsCoordinate;  // the widest valid limit
  ASSERT_EQ(c.validate(), "");
  // A 3 x 3 x 3 grid at 0.2 m in both scans, a point at the limit (kept, alone) and one at
  // 1e300 (dropped, counted) in b.
  Scan a, b;
  for (int i = 0; i < 27; ++i) a.points.push_back(0.2 * Vec3(i % 3, (i / 3) % 3, i / 9));
  b.points = a.points;
  b.points.push_back(Vec3(0.0, kMaxAbsCoordinate, 0.0));
  b.points.push_back(Vec3(1e300, 0.0, 0.0));
  const CoralResult r = computeCoral(a, b, c);
  EXPECT_EQ(r.num_out_of_range, 1u);
  EXPECT_EQ(r.num_points_b, 28u);
  ASSERT_EQ(r.per_point.size(), 55u);
  for (const PointEntropy& pe : r.per_point) EXPECT_TRUE(pe.position.allFinite());
  EXPECT_FLOAT_EQ(r.per_point.back().position.y(), static_cast<float>(kMaxAbsCoordinate));
  // Moved by a pose (CoralPair: b's points rotated and shifted into a's frame).
  const CoralResult rp = CoralPair(a, b, c).evaluate(se2(1.0, -2.0, M_PI / 4));
  ASSERT_EQ(rp.per_point.size(), 55u);
  for (const PointEntropy& pe : rp.per_point) EXPECT_TRUE(pe.position.allFinite());
  // The covariance-shaped variant applies the same limit.
  UncertainCoralConfig u;
  u.base = c;
  ASSERT_EQ(u.validate(), "");
  const CoralResult ru = computeCoralUncertain(a, b, u);
  EXPECT_EQ(ru.num_out_of_range, 1u);
  EXPECT_EQ(ru.num_points_b, 28u);
  ASSERT_EQ(ru.per_point.size(), 55u);
  for (const PointEntropy& pe : ru.per_point) EXPECT_TRUE(pe.position.allFinite());
}
