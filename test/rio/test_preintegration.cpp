// IMU preintegration against the integrated ground truth of an analytic trajectory, the
// first-order bias correction against re-integration, and the propagated covariance
// against Monte Carlo.
#include <gtest/gtest.h>

#include <random>

#include "coral_introspection/rio/preintegration.hpp"
#include "rio/rio_test_utils.hpp"

using namespace coral_introspection::rio;
using rio_test::Trajectory;

namespace {
Preintegration integrate(const Trajectory& tr, double t0, double t1, double rate, const Vec3& ba,
                         const Vec3& bg, const Vec3& ba_lin, const Vec3& bg_lin,
                         const ImuNoiseConfig& noise = ImuNoiseConfig()) {
  Preintegration pre(tr.imu(t0, ba, bg), ba_lin, bg_lin, noise);
  const int n = static_cast<int>(std::round((t1 - t0) * rate));
  for (int k = 1; k <= n; ++k) pre.push(tr.imu(t0 + (t1 - t0) * k / n, ba, bg));
  return pre;
}
}  // namespace

TEST(Preintegration, DeltasMatchIntegratedGroundTruth) {
  const Trajectory tr;
  const Vec3 ba(0.05, -0.03, 0.08), bg(0.004, -0.002, 0.003);
  const double t0 = 0.3, t1 = 0.8;  // 0.5 s at 1 kHz
  const Preintegration pre = integrate(tr, t0, t1, 1000.0, ba, bg, ba, bg);
  const NavState i = tr.state(t0, ba, bg), j = tr.state(t1, ba, bg);
  const Vec3 g(0, 0, tr.gravity);
  const double T = t1 - t0;
  EXPECT_NEAR(pre.dt(), T, 1e-12);
  const Mat3 RiT = i.q.toRotationMatrix().transpose();
  // alpha = R_i^T (p_j - p_i - v_i T + g T^2 / 2), beta = R_i^T (v_j - v_i + g T).
  EXPECT_LT((pre.deltaP() - RiT * (j.p - i.p - i.v * T + 0.5 * g * T * T)).norm(), 2e-6);
  EXPECT_LT((pre.deltaV() - RiT * (j.v - i.v + g * T)).norm(), 2e-6);
  EXPECT_LT(logQ(pre.deltaQ().conjugate() * i.q.conjugate() * j.q).norm(), 1e-6);
  // The residual vanishes at the true states and the prediction reproduces state j.
  EXPECT_LT(pre.residual(i, j).norm(), 3e-6);
  const NavState pj = pre.predict(i);
  EXPECT_LT((pj.p - j.p).norm(), 3e-6);
  EXPECT_LT((pj.v - j.v).norm(), 3e-6);
  EXPECT_LT(logQ(pj.q.conjugate() * j.q).norm(), 1e-6);
  // A wrong end state is seen: 1 cm off in x changes r_p by R_i^T (0.01, 0, 0).
  NavState j2 = j;
  j2.p.x() += 0.01;
  EXPECT_NEAR((pre.residual(i, j2).segment<3>(kP) - RiT * Vec3(0.01, 0, 0)).norm(), 0.0, 3e-6);
}

TEST(Preintegration, FirstOrderBiasCorrectionMatchesReintegration) {
  const Trajectory tr;
  const Vec3 ba(0.05, -0.03, 0.08), bg(0.004, -0.002, 0.003);
  const Vec3 dba(0.02, -0.01, 0.015), dbg(0.002, 0.001, -0.0015);
  // Linearised at the wrong biases, corrected to the true ones.
  const Preintegration pre = integrate(tr, 0.0, 0.4, 1000.0, ba, bg, ba + dba, bg + dbg);
  const Preintegration truth = integrate(tr, 0.0, 0.4, 1000.0, ba, bg, ba, bg);
  Vec3 dp, dv;
  Quat dq;
  pre.corrected(ba, bg, &dp, &dq, &dv);
  const double err_p_before = (pre.deltaP() - truth.deltaP()).norm();
  const double err_v_before = (pre.deltaV() - truth.deltaV()).norm();
  const double err_q_before = logQ(pre.deltaQ().conjugate() * truth.deltaQ()).norm();
  const double err_p = (dp - truth.deltaP()).norm(), err_v = (dv - truth.deltaV()).norm();
  const double err_q = logQ(dq.conjugate() * truth.deltaQ()).norm();
  // Second-order remainder: at least 30x smaller than the uncorrected error.
  EXPECT_LT(err_p, err_p_before / 30);
  EXPECT_LT(err_v, err_v_before / 30);
  EXPECT_LT(err_q, err_q_before / 30);
  EXPECT_GT(err_v_before, 5e-3);  // the correction had something to correct
  // Re-propagation at the true biases reproduces the truth exactly.
  Preintegration re = pre;
  re.repropagate(ba, bg);
  EXPECT_LT((re.deltaV() - truth.deltaV()).norm(), 1e-12);
}

TEST(Preintegration, CovarianceMatchesMonteCarlo) {
  const Trajectory tr;
  ImuNoiseConfig noise;
  noise.acc_noise = 0.05;
  noise.gyro_noise = 0.005;
  const double rate = 200.0, t0 = 0.0, t1 = 0.5;
  const int n = static_cast<int>((t1 - t0) * rate);
  const Preintegration clean =
      integrate(tr, t0, t1, rate, Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), noise);
  std::mt19937 rng(7);
  std::normal_distribution<double> g;
  const double sa = noise.acc_noise * std::sqrt(rate), sg = noise.gyro_noise * std::sqrt(rate);
  const int runs = 2000;
  Eigen::Matrix<double, 9, 9> C = Eigen::Matrix<double, 9, 9>::Zero();
  for (int r = 0; r < runs; ++r) {
    auto noisy = [&](double t) {
      ImuSample s = tr.imu(t);
      s.acc += sa * Vec3(g(rng), g(rng), g(rng));
      s.gyro += sg * Vec3(g(rng), g(rng), g(rng));
      return s;
    };
    Preintegration pre(noisy(t0), Vec3::Zero(), Vec3::Zero(), noise);
    for (int k = 1; k <= n; ++k) pre.push(noisy(t0 + (t1 - t0) * k / n));
    Eigen::Matrix<double, 9, 1> e;
    e << pre.deltaP() - clean.deltaP(), logQ(clean.deltaQ().conjugate() * pre.deltaQ()),
        pre.deltaV() - clean.deltaV();
    C += e * e.transpose() / runs;
  }
  // Predicted and Monte Carlo standard deviations agree within 15% per axis (2000 runs:
  // the sampling error of a standard deviation is about 1.6%). Without the factor 2 of
  // the shared mid-point samples the prediction would be 29% low.
  const Eigen::Matrix<double, 9, 9> P = clean.covariance().topLeftCorner<9, 9>();
  for (int k = 0; k < 9; ++k) {
    const double ratio = std::sqrt(P(k, k) / C(k, k));
    EXPECT_GT(ratio, 0.85) << "axis " << k;
    EXPECT_LT(ratio, 1.15) << "axis " << k;
  }
}
