// The Doppler ego-velocity covariance against Monte Carlo (paper: radar_point_uncertainty_slam,
// Eq. 10-12). With bearing noise dominating the Doppler noise, the residual variance of a
// static point is mostly J_k Sigma_k J_k^T (the position noise propagated through Eq. 9);
// a fit that dropped it would report a covariance many times smaller than the real scatter
// of its estimates. The scene is simulated here, independently of the package's simulator.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <random>

#include "coral_introspection/radar/doppler.hpp"
#include "coral_introspection/radar/radar_uncertainty.hpp"

using namespace coral_introspection::coral;
using namespace coral_introspection::radar;

namespace {

Vec3 polarToCartesian(double r, double az, double el) {
  return r * Vec3(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
}

struct MonteCarlo {
  Mat3 scatter = Mat3::Zero();   // empirical covariance of the estimates about the truth
  Mat3 reported = Mat3::Zero();  // mean covariance reported by estimateEgoVelocity
  double nees = 0.0;             // mean (v_hat - v)^T Cov^-1 (v_hat - v)
  int runs = 0;
  // What the Doppler noise alone explains: sigma_doppler^2 (sum_k d_k d_k^T)^-1, true bearings.
  Mat3 doppler_only = Mat3::Zero();
};

// 60 fixed static points (5-40 m, +-60 deg azimuth, +-20 deg elevation), re-measured in every
// run with polar noise on the position and Gaussian noise on v_r; v_r > 0 away from the sensor,
// so a static point has v_r = -d^T v (Eq. 9).
MonteCarlo runMonteCarlo(const Vec3& v, const RadarNoiseConfig& noise, double sigma_doppler,
                         int runs) {
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> range(5.0, 40.0), az(-1.05, 1.05), el(-0.35, 0.35);
  std::vector<Vec3> polar;
  for (int k = 0; k < 60; ++k) polar.push_back(Vec3(range(rng), az(rng), el(rng)));
  MonteCarlo mc;
  Mat3 info = Mat3::Zero();
  for (const Vec3& q : polar) {
    const Vec3 d = polarToCartesian(1.0, q.y(), q.z());
    info += d * d.transpose() / (sigma_doppler * sigma_doppler);
  }
  mc.doppler_only = info.inverse();
  std::normal_distribution<double> g;
  DopplerConfig cfg;
  cfg.sigma_doppler = sigma_doppler;
  cfg.ransac_threshold = 1.0;  // about 10 sigma: every (static) point is an inlier
  for (int run = 0; run < runs; ++run) {
    Scan scan;
    std::vector<double> vr;
    for (const Vec3& q : polar) {
      const Vec3 d = polarToCartesian(1.0, q.y(), q.z());
      scan.points.push_back(polarToCartesian(q.x() + noise.sigma_range * g(rng),
                                             q.y() + noise.sigma_azimuth * g(rng),
                                             q.z() + noise.sigma_elevation * g(rng)));
      vr.push_back(-d.dot(v) + sigma_doppler * g(rng));
    }
    std::string err;
    EXPECT_TRUE(attachCovariances(scan, noise, 3, &err)) << err;
    const EgoVelocityResult r = estimateEgoVelocity(scan.points, vr, cfg, &scan.covariances);
    EXPECT_TRUE(r.valid) << r.error;
    if (!r.valid) continue;
    EXPECT_EQ(r.num_inliers, 60u);
    const Vec3 e = r.velocity - v;
    mc.scatter += e * e.transpose();
    mc.reported += r.covariance;
    mc.nees += e.dot(r.covariance.ldlt().solve(e));
    ++mc.runs;
  }
  mc.scatter /= mc.runs;
  mc.reported /= mc.runs;
  mc.nees /= mc.runs;
  return mc;
}

}  // namespace

TEST(DopplerCovariance, MatchesMonteCarloWhenBearingNoiseDominates) {
  const Vec3 v(3.0, 0.8, 0.3);
  RadarNoiseConfig noise;
  noise.sigma_range = 0.05;
  noise.sigma_azimuth = 0.03;         // |v| sigma_azimuth ~ 0.09 m/s of residual per point ...
  noise.sigma_elevation = 0.03;       // ...
  const double sigma_doppler = 0.02;  // ... against 0.02 m/s of Doppler noise
  const MonteCarlo mc = runMonteCarlo(v, noise, sigma_doppler, 1000);
  ASSERT_EQ(mc.runs, 1000);
  std::printf("Monte Carlo std [m/s]: %.4f %.4f %.4f, reported: %.4f %.4f %.4f, NEES %.2f\n",
              std::sqrt(mc.scatter(0, 0)), std::sqrt(mc.scatter(1, 1)), std::sqrt(mc.scatter(2, 2)),
              std::sqrt(mc.reported(0, 0)), std::sqrt(mc.reported(1, 1)),
              std::sqrt(mc.reported(2, 2)), mc.nees);
  // Each axis: reported variance within -20 % / +25 % of the scatter of 1000 estimates
  // (sampling error of a variance from 1000 runs: about 4.5 %).
  for (int i = 0; i < 3; ++i) {
    EXPECT_GT(mc.reported(i, i), 0.8 * mc.scatter(i, i)) << "axis " << i;
    EXPECT_LT(mc.reported(i, i), 1.25 * mc.scatter(i, i)) << "axis " << i;
  }
  // Normalised estimation error squared: chi-square with 3 dof, mean 3 (std of the mean of
  // 1000: 0.08).
  EXPECT_NEAR(mc.nees, 3.0, 0.4);
  // The Doppler noise alone explains a small part of the scatter: the bearing term of
  // Eq. 11-12 is what this test exercises.
  EXPECT_GT(mc.scatter.trace(), 5.0 * mc.doppler_only.trace());
}
