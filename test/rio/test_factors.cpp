// Every residual's analytic Jacobian against central differences on the manifold, at
// states away from the optimum (non-zero residuals), plus the residual values at known
// answers.
#include <gtest/gtest.h>

#include "coral_introspection/rio/imu_factor.hpp"
#include "coral_introspection/rio/prior_factors.hpp"
#include "coral_introspection/rio/radar_factors.hpp"
#include "rio/rio_test_utils.hpp"

using namespace coral_introspection::rio;
using rio_test::jacobianError;
using rio_test::testExtrinsics;
using rio_test::Trajectory;

namespace {
StateBlocks perturbed(const NavState& s, double k) {
  NavState x = s;
  x.p += k * Vec3(0.1, -0.2, 0.05);
  x.q = x.q * expQ(k * Vec3(0.05, 0.02, -0.04));
  x.v += k * Vec3(0.3, 0.1, -0.2);
  x.ba += k * Vec3(0.02, -0.01, 0.03);
  x.bg += k * Vec3(0.003, 0.002, -0.001);
  StateBlocks b;
  toBlocks(x, &b);
  return b;
}
}  // namespace

TEST(RioFactors, ImuFactorJacobians) {
  const Trajectory tr;
  const Vec3 ba(0.05, -0.03, 0.08), bg(0.004, -0.002, 0.003);
  Preintegration pre(tr.imu(0.2, ba, bg), ba, bg, ImuNoiseConfig());
  for (int k = 1; k <= 60; ++k) pre.push(tr.imu(0.2 + k * 0.005, ba, bg));
  const ImuFactor f(&pre);
  StateBlocks i = perturbed(tr.state(0.2, ba, bg), 1.0), j = perturbed(tr.state(0.5, ba, bg), -1.0);
  EXPECT_LT(jacobianError(f, {i.pose, i.speed_bias, j.pose, j.speed_bias}), 1e-5);
  // At the true states the whitened residual is ~0.
  toBlocks(tr.state(0.2, ba, bg), &i);
  toBlocks(tr.state(0.5, ba, bg), &j);
  double const* params[] = {i.pose, i.speed_bias, j.pose, j.speed_bias};
  Vec15 r;
  f.Evaluate(params, r.data(), nullptr);
  EXPECT_LT(r.norm(), 1e-2);
}

TEST(RioFactors, DopplerFactorValueAndJacobians) {
  const Extrinsics ext = testExtrinsics();
  NavState s;
  s.q = expQ(Vec3(0.2, -0.1, 1.2));
  s.v = Vec3(1.0, -0.5, 0.2);
  s.bg = Vec3(0.01, -0.02, 0.005);
  const Vec3 omega(0.3, -0.2, 0.9);
  const Vec3 d = Vec3(0.8, 0.3, -0.2).normalized();
  // Eq. 9 by hand: radar velocity = R_E^T (R^T v + (omega - bg) x t_E).
  const Vec3 v_radar = ext.R.transpose() * (s.q.conjugate() * s.v + (omega - s.bg).cross(ext.t));
  const double m = d.dot(v_radar) - 0.1;  // measurement 0.1 m/s off
  const DopplerFactor f(d, m, omega, ext, 4.0);
  StateBlocks b;
  toBlocks(s, &b);
  double const* params[] = {b.pose, b.speed_bias};
  double r = 0;
  f.Evaluate(params, &r, nullptr);
  EXPECT_NEAR(r, 4.0 * 0.1, 1e-12);
  EXPECT_LT(jacobianError(f, {b.pose, b.speed_bias}), 1e-6);
}

TEST(RioFactors, PointFactorValueAndJacobians) {
  const Extrinsics ext = testExtrinsics();
  NavState s;
  s.p = Vec3(1.0, 2.0, -0.5);
  s.q = expQ(Vec3(0.2, -0.1, 1.2));
  const Vec3 p_radar(4.0, 1.0, 0.5);
  // The landmark the point sees, offset 0.2 m along the radar's x axis.
  const Vec3 l = s.q * (ext.R * (p_radar + Vec3(0.2, 0, 0)) + ext.t) + s.p;
  const Mat3 W = Vec3(2.0, 5.0, 10.0).asDiagonal();
  const PointFactor f(p_radar, W, ext);
  StateBlocks b;
  toBlocks(s, &b);
  Vec3 lm = l;
  double const* params[] = {b.pose, lm.data()};
  Vec3 r;
  f.Evaluate(params, r.data(), nullptr);
  EXPECT_LT((r - Vec3(0.4, 0, 0)).norm(), 1e-12);  // W (0.2, 0, 0)
  EXPECT_LT(jacobianError(f, {b.pose, lm.data()}), 1e-6);
}

TEST(RioFactors, WhiteningGivesInverseCovariance) {
  Mat3 A;
  A << 2, 0.3, 0.1, 0.3, 1, -0.2, 0.1, -0.2, 0.5;
  const Mat3 W = whitening3(A, 1e-12);
  EXPECT_LT((W.transpose() * W - A.inverse()).norm(), 1e-10);
}

TEST(RioFactors, PriorFactorsJacobians) {
  NavState mean;
  mean.p = Vec3(1, 2, 3);
  mean.q = expQ(Vec3(0.1, 0.2, -0.3));
  mean.v = Vec3(0.5, 0, 0);
  Mat15 W = Mat15::Identity();
  W(0, 4) = 0.3;
  const StatePrior prior(mean, W);
  StateBlocks b = perturbed(mean, 1.0);
  EXPECT_LT(jacobianError(prior, {b.pose, b.speed_bias}), 1e-6);
  const ZeroVelocityFactor zv(0.01);
  EXPECT_LT(jacobianError(zv, {b.speed_bias}), 1e-6);
  const GyroBiasFactor gb(Vec3(0.01, 0, 0), 0.001);
  EXPECT_LT(jacobianError(gb, {b.speed_bias}), 1e-6);
  double const* params[] = {b.speed_bias};
  Vec3 r;
  zv.Evaluate(params, r.data(), nullptr);
  EXPECT_LT((r - 100.0 * Eigen::Map<Vec3>(b.speed_bias)).norm(), 1e-12);
}
