// CorAl (Eq. 2-6, Sec. III-C) on a ray-cast structured scene with induced misalignments,
// degenerate inputs, and the libpointmatcher lidar pair at its reference transform.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "coral_introspection/coral/coral.hpp"
#include "coral_introspection/eval/cloud_io.hpp"
#include "coral_introspection/eval/synthetic.hpp"
#include "support/test_data.hpp"

using namespace coral_introspection::coral;
using namespace coral_introspection::eval;

namespace {

CoralConfig lidarConfig() {
  CoralConfig c;
  c.dimension = 3;
  c.radius = 0.3;
  c.epsilon = 1e-8;  // Sec. III-C (1): the floor rings of a 32-ring lidar are lines
  return c;
}

// Two scans of the yard from nearby poses, each expressed in the world frame.
struct YardPair {
  Scan a, b;
  Eigen::Isometry3d T_w_a, T_w_b;
  Points b_sensor;  // b in its own sensor frame, for re-posing with offsets
};

YardPair makeYardPair(unsigned seed,
                      const SyntheticScene& scene_b = SyntheticScene::structuredYard()) {
  std::mt19937 rng(seed);
  const SyntheticScene scene = SyntheticScene::structuredYard();
  YardPair p;
  p.T_w_a = se2(0.0, 0.0, 0.0);
  p.T_w_b = se2(0.8, 0.3, 0.05);
  LidarModel lidar;
  Scan a_s, b_s;
  a_s.points = simulateScan(scene, p.T_w_a, lidar, rng);
  p.b_sensor = simulateScan(scene_b, p.T_w_b, lidar, rng);
  p.a = transformScan(a_s, p.T_w_a);
  b_s.points = p.b_sensor;
  p.b = transformScan(b_s, p.T_w_b);
  return p;
}

// Scan b placed with an extra offset applied in b's sensor frame (Sec. III-F protocol).
Scan offsetB(const YardPair& p, const Eigen::Isometry3d& delta) {
  Scan b_s;
  b_s.points = p.b_sensor;
  return transformScan(b_s, p.T_w_b * delta);
}

Eigen::Isometry3d yawDelta(double deg) { return se2(0.0, 0.0, deg * M_PI / 180.0); }

}  // namespace

TEST(Coral, AlignedScansOfSameSceneGiveQNearZero) {
  const YardPair p = makeYardPair(11);
  const CoralResult r = computeCoral(p.a, p.b, lidarConfig());
  ASSERT_TRUE(r.valid);
  EXPECT_GT(r.overlap, 0.5);
  EXPECT_GT(r.num_valid, 1000u);
  EXPECT_LT(std::abs(r.quality), 0.1) << "H_joint " << r.h_joint << " H_sep " << r.h_sep;
  EXPECT_NEAR(r.quality, r.h_joint - r.h_sep, 1e-12);
}

TEST(Coral, QGrowsMonotonicallyWithTranslation) {
  const YardPair p = makeYardPair(12);
  const CoralConfig cfg = lidarConfig();
  const Eigen::Vector3d dir = Eigen::Vector3d(1.0, 0.6, 0.0).normalized();
  double prev = computeCoral(p.a, p.b, cfg).quality;
  for (double m : {0.05, 0.1, 0.2, 0.4}) {
    Eigen::Isometry3d d = Eigen::Isometry3d::Identity();
    d.translation() = m * dir;
    const CoralResult r = computeCoral(p.a, offsetB(p, d), cfg);
    ASSERT_TRUE(r.valid) << m;
    EXPECT_GT(r.quality, prev + 0.01) << "offset " << m << " m";
    prev = r.quality;
  }
}

TEST(Coral, QGrowsMonotonicallyWithRotation) {
  const YardPair p = makeYardPair(13);
  const CoralConfig cfg = lidarConfig();
  double prev = computeCoral(p.a, p.b, cfg).quality;
  for (double deg : {0.5, 1.0, 2.0}) {
    const CoralResult r = computeCoral(p.a, offsetB(p, yawDelta(deg)), cfg);
    ASSERT_TRUE(r.valid) << deg;
    EXPECT_GT(r.quality, prev + 0.01) << "yaw offset " << deg << " deg";
    prev = r.quality;
  }
}

TEST(Coral, PerPointQualityIsHighOnDisplacedSurfacesOnly) {
  // Scan b sees the first box moved by 0.25 m: a local change in an otherwise aligned pair.
  SyntheticScene moved = SyntheticScene::structuredYard();
  const Vec3 shift(0.25, -0.15, 0.0);
  const std::size_t first_box = 5, box_faces = 4;  // floor + 4 walls come first
  for (std::size_t i = first_box; i < first_box + box_faces; ++i) moved.rects[i].center += shift;
  const YardPair p = makeYardPair(14, moved);
  const CoralResult r = computeCoral(p.a, p.b, lidarConfig());
  ASSERT_TRUE(r.valid);
  ASSERT_EQ(r.per_point.size(), p.a.points.size() + p.b.points.size());
  const Vec3 box_centre(4.0, 3.0, 0.0);
  double q_box = 0, q_rest = 0;
  int n_box = 0, n_rest = 0;
  for (std::size_t i = 0; i < r.per_point.size(); ++i) {
    const PointEntropy& pe = r.per_point[i];
    if (!pe.valid) continue;
    const Vec3& x = i < p.a.points.size() ? p.a.points[i] : p.b.points[i - p.a.points.size()];
    const bool near_box = (x - box_centre).head<2>().norm() < 1.5 && x.z() > -1.3;
    (near_box ? q_box : q_rest) += pe.q();
    (near_box ? n_box : n_rest) += 1;
  }
  ASSERT_GT(n_box, 50);
  ASSERT_GT(n_rest, 1000);
  q_box /= n_box;
  q_rest /= n_rest;
  EXPECT_GT(q_box, q_rest + 0.3) << "mean q on moved box " << q_box << ", elsewhere " << q_rest;
  EXPECT_LT(std::abs(q_rest), 0.1);
}

TEST(Coral, EReject_RemovesRequestedFraction) {
  const YardPair p = makeYardPair(15);
  CoralConfig cfg = lidarConfig();
  const CoralResult base = computeCoral(p.a, p.b, cfg);
  cfg.e_reject = 0.1;
  const CoralResult r = computeCoral(p.a, p.b, cfg);
  const auto expected = static_cast<std::size_t>(std::floor(0.1 * base.num_valid));
  EXPECT_EQ(r.num_rejected, expected);
  EXPECT_EQ(r.num_valid, base.num_valid - expected);
  // The rejected ones are exactly the lowest separate entropies.
  float max_rejected = -1e9f, min_kept = 1e9f;
  for (std::size_t i = 0; i < r.per_point.size(); ++i) {
    if (!base.per_point[i].valid) continue;
    if (r.per_point[i].valid)
      min_kept = std::min(min_kept, r.per_point[i].h_sep);
    else
      max_rejected = std::max(max_rejected, base.per_point[i].h_sep);
  }
  EXPECT_LE(max_rejected, min_kept);
  EXPECT_GT(r.h_sep, base.h_sep);
}

TEST(Coral, DynamicRadiusStaysWithinBounds) {
  CoralConfig cfg = lidarConfig();
  cfg.dynamic_radius = true;
  cfg.r_min = 0.3;
  cfg.r_max = 0.7;
  cfg.alpha_deg = 1.33;
  for (double d : {0.0, 1.0, 12.0, 15.0, 25.0, 1e4})
    EXPECT_TRUE(dynamicRadius(cfg, d) >= 0.3 && dynamicRadius(cfg, d) <= 0.7) << d;
  EXPECT_NEAR(dynamicRadius(cfg, 20.0), 20.0 * std::sin(1.33 * M_PI / 180.0), 1e-12);
  const YardPair p = makeYardPair(16);
  const CoralResult r = computeCoral(p.a, p.b, cfg);
  ASSERT_TRUE(r.valid);
  float lo = 1e9f, hi = -1e9f;
  for (const PointEntropy& pe : r.per_point) {
    lo = std::min(lo, pe.radius);
    hi = std::max(hi, pe.radius);
  }
  EXPECT_GE(lo, 0.3f - 1e-6f);
  EXPECT_LE(hi, 0.7f + 1e-6f);
  EXPECT_GT(hi, lo);  // far points really got a larger radius
  // The radius is measured from each point's own sensor: moving b's origin changes it.
  Scan b2 = p.b;
  b2.origin += Vec3(30.0, 0.0, 0.0);
  const CoralResult r2 = computeCoral(p.a, b2, cfg);
  bool changed = false;
  for (std::size_t i = p.a.points.size(); i < r.per_point.size(); ++i)
    changed |= r.per_point[i].radius != r2.per_point[i].radius;
  EXPECT_TRUE(changed);
  for (std::size_t i = 0; i < p.a.points.size(); ++i)
    ASSERT_EQ(r.per_point[i].radius, r2.per_point[i].radius);
}

TEST(Coral, MedianAggregationAndMme) {
  const YardPair p = makeYardPair(17);
  CoralConfig cfg = lidarConfig();
  const CoralResult mean = computeCoral(p.a, p.b, cfg);
  cfg.aggregation = Aggregation::kMedian;
  const CoralResult med = computeCoral(p.a, p.b, cfg);
  std::vector<double> hs;
  for (const PointEntropy& pe : med.per_point)
    if (pe.valid) hs.push_back(pe.h_sep);
  std::sort(hs.begin(), hs.end());
  const std::size_t n = hs.size();
  const double expected = n % 2 ? hs[n / 2] : 0.5 * (hs[n / 2 - 1] + hs[n / 2]);
  EXPECT_NEAR(med.h_sep, expected, 1e-9);
  EXPECT_NE(med.h_sep, mean.h_sep);
  EXPECT_TRUE(std::isfinite(mean.mme));
  EXPECT_NE(mean.mme, 0.0);
}

TEST(Coral, DegenerateInputsGiveDefinedResults) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  CoralConfig cfg = lidarConfig();
  cfg.epsilon = 0.0;  // no floor: singular neighbourhoods have no finite entropy
  Scan empty;
  const YardPair p = makeYardPair(18);
  for (const CoralResult& r : {computeCoral(empty, empty, cfg), computeCoral(p.a, empty, cfg),
                               computeCoral(empty, p.b, cfg)}) {
    EXPECT_FALSE(r.valid);
    EXPECT_EQ(r.num_valid, 0u);
    EXPECT_EQ(r.quality, 0.0);
    EXPECT_EQ(r.overlap, 0.0);
  }
  // Collinear points in 3D: every covariance is singular -> excluded, no NaN anywhere.
  Scan line_a, line_b;
  for (int i = 0; i < 50; ++i) {
    line_a.points.push_back(Vec3(0.01 * i, 0, 0));
    line_b.points.push_back(Vec3(0.01 * i + 0.005, 0, 0));
  }
  const CoralResult rl = computeCoral(line_a, line_b, cfg);
  EXPECT_FALSE(rl.valid);
  EXPECT_EQ(rl.num_valid, 0u);
  EXPECT_GT(rl.overlap, 0.9);  // they overlap, there is just no finite entropy
  // With the epsilon floor the same points become valid with finite entropies.
  CoralConfig eps = cfg;
  eps.epsilon = 1e-8;
  const CoralResult re = computeCoral(line_a, line_b, eps);
  EXPECT_TRUE(re.valid);
  EXPECT_TRUE(std::isfinite(re.quality));
  // NaN / Inf points are ignored, the rest is scored as if they were absent.
  Scan dirty = p.b;
  dirty.points.push_back(Vec3(nan, 0, 0));
  dirty.points.push_back(Vec3(0, inf, 0));
  const CoralResult rc = computeCoral(p.a, p.b, cfg), rd = computeCoral(p.a, dirty, cfg);
  EXPECT_EQ(rd.num_points_b, p.b.points.size());
  EXPECT_DOUBLE_EQ(rd.quality, rc.quality);
  // Fewer neighbours than the minimum: isolated points never count.
  Scan sparse_a, sparse_b;
  for (int i = 0; i < 20; ++i) {
    sparse_a.points.push_back(Vec3(i * 5.0, 0, 0));
    sparse_b.points.push_back(Vec3(i * 5.0 + 0.01, 0.01, 0.01));
  }
  const CoralResult rs = computeCoral(sparse_a, sparse_b, cfg);
  EXPECT_FALSE(rs.valid);
  EXPECT_EQ(rs.num_overlap, 0u);
}

TEST(Coral, ConfigValidationNamesTheBadField) {
  CoralConfig c;
  EXPECT_EQ(c.validate(), "");
  c.radius = -1;
  EXPECT_NE(c.validate().find("radius"), std::string::npos);
  c = CoralConfig();
  c.dynamic_radius = true;
  c.r_min = 1.0;
  c.r_max = 0.5;
  EXPECT_NE(c.validate().find("r_min must be <= r_max"), std::string::npos);
  // Radii are limited to [0.01, 10] m (fixed and dynamic alike).
  c = CoralConfig();
  c.dynamic_radius = true;
  c.r_min = 0.01;
  c.r_max = 10.0;
  EXPECT_EQ(c.validate(), "");
  c.r_max = 10.5;
  EXPECT_NE(c.validate().find("r_max must be in [0.01, 10] m"), std::string::npos);
  c.r_max = 1.0;
  c.r_min = 0.005;
  EXPECT_NE(c.validate().find("r_min must be in [0.01, 10] m"), std::string::npos);
  c = CoralConfig();
  c.radius = 12.0;
  EXPECT_NE(c.validate().find("radius must be in [0.01, 10] m (got 12)"), std::string::npos);
  c = CoralConfig();
  c.e_reject = 1.0;
  EXPECT_NE(c.validate().find("e_reject"), std::string::npos);
  c = CoralConfig();
  c.dimension = 4;
  EXPECT_NE(c.validate().find("dimension"), std::string::npos);
  c = CoralConfig();
  c.min_neighbours = 1;
  EXPECT_NE(c.validate().find("min_neighbours"), std::string::npos);
}

// coral::yawOf (types.hpp), which every planar tool reads headings with: the inverse of se2's
// rotation over the whole circle, and the heading of a ZYX rotation with roll and pitch.
TEST(Types, YawOfInvertsSe2AndReadsTheHeadingOfZyx) {
  for (double yaw = -3.1; yaw < 3.15; yaw += 0.2) {
    EXPECT_NEAR(yawOf(se2(1.0, -2.0, yaw).linear()), yaw, 1e-12);
    const Eigen::Matrix3d R = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(-0.4, Eigen::Vector3d::UnitX()))
                                  .toRotationMatrix();
    EXPECT_NEAR(yawOf(R), yaw, 1e-12);
  }
  EXPECT_NEAR(std::abs(yawOf(se2(0.0, 0.0, M_PI).linear())), M_PI, 1e-12);
}

TEST(CoralRealData, LidarPairReferenceTransformBeatsEveryTenCentimetreShift) {
  CORAL_REQUIRE_DATA("libpointmatcher_car_cloud");
  Scan a, b;
  Eigen::Isometry3d T_w_a, T_w_b;
  std::string err;
  ASSERT_TRUE(readCsvPoints(coral_data + "/car_cloud400.csv", &a.points, &err)) << err;
  ASSERT_TRUE(readCsvPoints(coral_data + "/car_cloud401.csv", &b.points, &err)) << err;
  ASSERT_TRUE(readCsvPose(coral_data + "/carCloudList.csv", "car_cloud400.csv", &T_w_a, &err));
  ASSERT_TRUE(readCsvPose(coral_data + "/carCloudList.csv", "car_cloud401.csv", &T_w_b, &err));
  const Scan wa = transformScan(a, T_w_a);
  CoralConfig cfg = lidarConfig();
  const CoralResult ref = computeCoral(wa, transformScan(b, T_w_b), cfg);
  ASSERT_TRUE(ref.valid);
  std::printf("lidar pair at reference: Q = %.4f, overlap %.2f, %zu valid points\n", ref.quality,
              ref.overlap, ref.num_valid);
  for (int k = 0; k < 8; ++k) {
    const double ang = k * M_PI / 4.0;
    Eigen::Isometry3d shift = Eigen::Isometry3d::Identity();
    shift.translation() = 0.1 * Vec3(std::cos(ang), std::sin(ang), 0.0);
    const CoralResult r = computeCoral(wa, transformScan(b, shift * T_w_b), cfg);
    std::printf("  shifted 0.1 m at %3.0f deg: Q = %.4f\n", ang * 180 / M_PI, r.quality);
    EXPECT_LT(ref.quality, r.quality) << "direction " << ang * 180 / M_PI << " deg";
  }
}
