// Doppler ego-velocity (Eq. 9-12) and the odometry consistency test, on simulated scans
// with known velocity and on View-of-Delft frames.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <random>

#include "coral_introspection/eval/doppler_simulation.hpp"
#include "coral_introspection/radar/doppler.hpp"
#include "support/test_data.hpp"

using namespace coral_introspection::coral;
using namespace coral_introspection::radar;
using namespace coral_introspection::eval;

namespace {

Vec3 randomVelocity(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  return Vec3(1.75 + 1.25 * u(rng), 0.5 * u(rng), 0.2 * u(rng));  // mostly forward
}

Vec3 randomUnit(std::mt19937& rng) {
  std::normal_distribution<double> g;
  return Vec3(g(rng), g(rng), g(rng)).normalized();
}

Covariances covariancesOf(const Points& pts, const RadarNoiseConfig& noise, int dim) {
  Scan s;
  s.points = pts;
  std::string err;
  EXPECT_TRUE(attachCovariances(s, noise, dim, &err)) << err;
  return s.covariances;
}

}  // namespace

TEST(Doppler, ChiSquareQuantileMatchesTables) {
  EXPECT_NEAR(chiSquareQuantile(0.99, 1), 6.635, 1e-3);
  EXPECT_NEAR(chiSquareQuantile(0.99, 2), 9.210, 1e-3);
  EXPECT_NEAR(chiSquareQuantile(0.99, 3), 11.345, 1e-3);
  EXPECT_NEAR(chiSquareQuantile(0.95, 10), 18.307, 1e-3);
}

// 30% movers, Doppler noise 0.05 m/s, polar position noise. The vertical velocity is
// only as observable as the elevation spread allows: with +-15 deg (TI/VoD-like) and 60
// points the horizontal velocity is within 0.05 m/s, the full 3D velocity needs a wider
// elevation spread or more points (its covariance says so: the NEES check).
void expectWithin5cm(int num_points, double elevation_half_fov, bool horizontal_only,
                     unsigned seed) {
  std::mt19937 rng(seed);
  DopplerSimConfig sim;
  sim.num_points = num_points;
  sim.elevation_half_fov = elevation_half_fov;
  DopplerConfig cfg;
  int within = 0, n = 200;
  double nees = 0.0;
  for (int i = 0; i < n; ++i) {
    const Vec3 v = randomVelocity(rng);
    const DopplerSimScan s = simulateDopplerScan(v, sim, rng);
    const Covariances cov = covariancesOf(s.points, sim.position_noise, 3);
    const EgoVelocityResult r = estimateEgoVelocity(s.points, s.radial_velocity, cfg, &cov);
    ASSERT_TRUE(r.valid) << r.error;
    EXPECT_FALSE(r.planar);
    EXPECT_NEAR(r.inlier_ratio, 0.7, 0.2);
    const Vec3 e = r.velocity - v;
    within += (horizontal_only ? e.head<2>().norm() : e.norm()) < 0.05;
    nees += e.dot(r.covariance.inverse() * e);
  }
  EXPECT_GE(within, 0.95 * n);
  // The covariance is calibrated: mean normalised error close to dof = 3.
  EXPECT_NEAR(nees / n, 3.0, 1.0);
}

TEST(Doppler, SyntheticHorizontalVelocityWithin5cmPerSecondDespite30PercentMovers) {
  expectWithin5cm(60, 0.26, true, 1);
}

TEST(Doppler, Synthetic3DVelocityWithin5cmPerSecondWithWideElevation) {
  expectWithin5cm(150, 0.5, false, 11);
}

TEST(Doppler, PlanarScanHasUnobservableZ) {
  std::mt19937 rng(2);
  DopplerSimConfig sim;
  sim.elevation_half_fov = 0.0;
  sim.position_noise = RadarNoiseConfig::oxfordCts350x();
  const Vec3 v(2.0, -0.4, 0.0);
  const DopplerSimScan s = simulateDopplerScan(v, sim, rng);
  const EgoVelocityResult r = estimateEgoVelocity(s.points, s.radial_velocity, DopplerConfig{});
  ASSERT_TRUE(r.valid) << r.error;
  EXPECT_TRUE(r.planar);
  EXPECT_LT((r.velocity - v).norm(), 0.05);
  EXPECT_EQ(r.velocity.z(), 0.0);
  EXPECT_TRUE(std::isinf(r.covariance(2, 2)));
  const ConsistencyResult c =
      checkVelocityConsistency(s.points, s.radial_velocity, v, DopplerConfig{});
  ASSERT_TRUE(c.valid) << c.error;
  EXPECT_EQ(c.dof, 2);
}

TEST(Doppler, SignConventionIsAConfigField) {
  std::mt19937 rng(3);
  DopplerSimConfig sim;
  sim.radial_velocity_positive_away = false;
  const Vec3 v(1.5, 0.3, 0.0);
  const DopplerSimScan s = simulateDopplerScan(v, sim, rng);
  DopplerConfig cfg;
  cfg.radial_velocity_positive_away = false;
  EgoVelocityResult r = estimateEgoVelocity(s.points, s.radial_velocity, cfg);
  ASSERT_TRUE(r.valid) << r.error;
  EXPECT_LT((r.velocity - v).norm(), 0.1);
  cfg.radial_velocity_positive_away = true;  // wrong convention: the velocity flips
  r = estimateEgoVelocity(s.points, s.radial_velocity, cfg);
  ASSERT_TRUE(r.valid) << r.error;
  EXPECT_LT((r.velocity + v).norm(), 0.1);
}

TEST(Doppler, ConsistencyAcceptsCorrectAndRejectsBiasedVelocity) {
  std::mt19937 rng(4);
  const DopplerSimConfig sim;  // 60 points, 30% movers, realistic noise
  DopplerConfig cfg;
  const int n = 300;
  int accepted = 0, rejected = 0, valid = 0;
  for (int i = 0; i < n; ++i) {
    const Vec3 v = randomVelocity(rng);
    const DopplerSimScan s = simulateDopplerScan(v, sim, rng);
    const Covariances cov = covariancesOf(s.points, sim.position_noise, 3);
    const ConsistencyResult good =
        checkVelocityConsistency(s.points, s.radial_velocity, v, cfg, &cov);
    const ConsistencyResult bad =
        checkVelocityConsistency(s.points, s.radial_velocity, v + 0.3 * randomUnit(rng), cfg, &cov);
    if (!good.valid || !bad.valid) continue;
    ++valid;
    EXPECT_EQ(good.dof, 3);
    EXPECT_NEAR(good.threshold, 11.345, 1e-3);
    accepted += good.consistent;
    rejected += !bad.consistent;
  }
  EXPECT_GE(valid, 0.95 * n);
  EXPECT_GE(accepted, 0.95 * valid);
  EXPECT_GE(rejected, 0.95 * valid);
}

TEST(Doppler, VelocityUnderTestCovarianceWidensTheTest) {
  std::mt19937 rng(6);
  const DopplerSimScan s = simulateDopplerScan(Vec3(2.0, 0.2, 0.0), DopplerSimConfig{}, rng);
  const Vec3 biased(2.5, 0.2, 0.0);  // 0.5 m/s forward error
  const DopplerConfig cfg;
  const ConsistencyResult strict =
      checkVelocityConsistency(s.points, s.radial_velocity, biased, cfg);
  ASSERT_TRUE(strict.valid) << strict.error;
  EXPECT_FALSE(strict.consistent);
  const Mat3 loose = 0.5 * Mat3::Identity();  // odometry claims 0.7 m/s per axis
  const ConsistencyResult wide =
      checkVelocityConsistency(s.points, s.radial_velocity, biased, cfg, nullptr, &loose);
  ASSERT_TRUE(wide.valid) << wide.error;
  EXPECT_TRUE(wide.consistent);
  EXPECT_LT(wide.chi2, strict.chi2);
}

TEST(Doppler, RefusesBadInput) {
  DopplerConfig cfg;
  Points pts(20, Vec3(5.0, 1.0, 0.5));
  std::vector<double> vr(19, 0.0);
  EXPECT_FALSE(estimateEgoVelocity(pts, vr, cfg).valid);
  vr.assign(3, 0.0);
  pts.resize(3);
  EgoVelocityResult r = estimateEgoVelocity(pts, vr, cfg);
  EXPECT_FALSE(r.valid);
  EXPECT_NE(r.error.find("too few"), std::string::npos);
  cfg.confidence = 1.5;
  EXPECT_NE(cfg.validate().find("confidence"), std::string::npos);
  // Mostly movers: no static consensus reaches min_inlier_ratio.
  std::mt19937 rng(5);
  DopplerSimConfig sim;
  sim.outlier_fraction = 0.8;
  const DopplerSimScan s = simulateDopplerScan(Vec3(2.0, 0.0, 0.0), sim, rng);
  r = estimateEgoVelocity(s.points, s.radial_velocity, DopplerConfig{});
  EXPECT_FALSE(r.valid);
  const ConsistencyResult c = checkVelocityConsistency(
      s.points, s.radial_velocity, Vec3(std::nan(""), 0.0, 0.0), DopplerConfig{});
  EXPECT_FALSE(c.valid);
}

// View-of-Delft: v_r - v_r_compensated is the ego-motion part of v_r, i.e. -d^T v_ego for
// every point; the robust fit on raw v_r (with moving objects) must recover v_ego.
TEST(Doppler, ViewOfDelftMatchesEgoMotionFromCompensatedVelocity) {
  CORAL_REQUIRE_DATA("view_of_delft_example");
  for (const char* frame : {"00549", "01047", "01201"}) {
    std::ifstream in(coral_data + "/radar/training/velodyne/" + frame + ".bin", std::ios::binary);
    ASSERT_TRUE(in.good()) << frame;
    Points pts;
    std::vector<double> vr, ego;
    float rec[7];
    while (in.read(reinterpret_cast<char*>(rec), sizeof(rec))) {
      pts.emplace_back(rec[0], rec[1], rec[2]);
      vr.push_back(rec[4]);
      ego.push_back(rec[4] - rec[5]);
    }
    ASSERT_GT(pts.size(), 100u);
    DopplerConfig exact;  // the ego part is noise-free: tight threshold
    exact.ransac_threshold = 0.2;
    const EgoVelocityResult ref = estimateEgoVelocity(pts, ego, exact);
    ASSERT_TRUE(ref.valid) << ref.error;
    EXPECT_GT(ref.inlier_ratio, 0.95) << frame;
    const Covariances cov = covariancesOf(pts, RadarNoiseConfig::vodZfFrgen21(), 3);
    const EgoVelocityResult r = estimateEgoVelocity(pts, vr, DopplerConfig{}, &cov);
    ASSERT_TRUE(r.valid) << r.error;
    EXPECT_LT((r.velocity - ref.velocity).head<2>().norm(), 0.02)
        << frame << " doppler " << r.velocity.transpose() << " ego " << ref.velocity.transpose();
    EXPECT_LT(std::abs(r.velocity.z() - ref.velocity.z()), 0.05) << frame;
    EXPECT_GT(ref.velocity.x(), 1.0) << frame;  // the car drives forward
    const ConsistencyResult c =
        checkVelocityConsistency(pts, vr, ref.velocity, DopplerConfig{}, &cov);
    ASSERT_TRUE(c.valid) << c.error;
    std::cout << frame << ": v_doppler " << r.velocity.transpose() << "  v_ego "
              << ref.velocity.transpose() << "  inliers " << r.inlier_ratio << "  chi2 " << c.chi2
              << " (threshold " << c.threshold << ")\n";
  }
}
