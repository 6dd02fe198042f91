// Radar-IMU time offset (rio/time_offset.hpp): the time-shifted residuals' Jacobians vs
// numeric differences; the first-order shift explains a point and a Doppler measured later
// than the state's time on an analytic trajectory; the angular acceleration of an interval.
// The estimator on simulated sequences (a radar stamped 0.03 s early, one 0.3 s early) is in
// test_time_offset_estimator.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "coral_introspection/rio/config.hpp"
#include "coral_introspection/rio/config_yaml.hpp"
#include "coral_introspection/rio/radar_factors.hpp"
#include "coral_introspection/rio/time_offset.hpp"
#include "rio/rio_test_utils.hpp"

using namespace coral_introspection::rio;
using rio_test::jacobianError;
using rio_test::testExtrinsics;
using rio_test::Trajectory;

namespace {

// The analytic trajectory's radar at time t (rio_test_utils.hpp; biases zero).
struct Radar {
  Trajectory tr;
  Extrinsics ext = testExtrinsics();
  Mat3 R(double t) const { return tr.q(t).toRotationMatrix() * ext.R; }
  Vec3 p(double t) const { return tr.p(t) + tr.q(t) * ext.t; }
  // A static landmark l as the radar sees it at t, and its Doppler d^T v_r (Eq. 9).
  Vec3 point(const Vec3& l, double t) const { return R(t).transpose() * (l - p(t)); }
  Vec3 velocity(double t) const {
    return ext.R.transpose() * (tr.q(t).conjugate() * tr.v(t) + tr.omega(t).cross(ext.t));
  }
  Vec3 alpha(double t) const {
    const double h = 1e-5;
    return (tr.omega(t + h) - tr.omega(t - h)) / (2 * h);
  }
};

const Vec3 kLandmark(4.0, -3.0, 1.5);

}  // namespace

TEST(RioTimeOffset, ShiftedFactorsJacobians) {
  const Radar rd;
  const double t = 0.7;
  StateBlocks b;
  toBlocks(rd.tr.state(t), &b);
  double td[1] = {0.035};
  const Vec3 p = rd.point(kLandmark, t), d = p.normalized();
  auto doppler =
      std::make_shared<DopplerFactor>(d, d.dot(rd.velocity(t)) + 0.1, rd.tr.omega(t), rd.ext, 4.0);
  const TimeShiftedFactor sd(doppler, Eigen::VectorXd::Constant(1, 2.5), 0.01);
  EXPECT_EQ(sd.parameter_block_sizes(), (std::vector<int32_t>{7, 9, 1}));
  EXPECT_LT(jacobianError(sd, {b.pose, b.speed_bias, td}), 1e-6);
  // The residual moves by (t_d - t_d,ref) c: 0.025 s * 2.5.
  double r0 = 0.0, r1 = 0.0;
  double const* dp[] = {b.pose, b.speed_bias, td};
  double const* dp0[] = {b.pose, b.speed_bias};
  ASSERT_TRUE(sd.Evaluate(dp, &r1, nullptr));
  ASSERT_TRUE(doppler->Evaluate(dp0, &r0, nullptr));
  EXPECT_NEAR(r1 - r0, 0.025 * 2.5, 1e-12);

  const Mat3 W = Vec3(2.0, 5.0, 10.0).asDiagonal();
  Vec3 l = kLandmark + Vec3(0.1, 0.2, -0.1);  // off the measurement: r != 0
  const TimeShiftedFactor sp(std::make_shared<PointFactor>(p, W, rd.ext), Vec3(1.0, -2.0, 0.5),
                             0.0);
  EXPECT_LT(jacobianError(sp, {b.pose, l.data(), td}), 1e-6);
  double prior_td[1] = {0.02};
  const TimeOffsetPrior prior(0.01, 0.005);
  double rp = 0.0;
  double const* pp[] = {prior_td};
  ASSERT_TRUE(prior.Evaluate(pp, &rp, nullptr));
  EXPECT_NEAR(rp, 2.0, 1e-12);
  EXPECT_LT(jacobianError(prior, {prior_td}), 1e-6);
}

// A point measured delta = 25 ms after the state's time: without the shift the residual is
// the radar's motion over delta (turning and moving), with t_d = t_d,ref + delta it is left
// with the second-order remainder only.
TEST(RioTimeOffset, ShiftExplainsAPointMeasuredLater) {
  const Radar rd;
  const double t = 0.7, delta = 0.025, td_ref = 0.01;
  const Vec3 measured = rd.point(kLandmark, t + delta);
  const Vec3 omega_radar = rd.ext.R.transpose() * rd.tr.omega(t);
  const Vec3 rate = staticPointRate(measured, omega_radar, rd.velocity(t));
  // The rate is the derivative of the seen point (central difference).
  const double h = 1e-5;
  const Vec3 numeric = (rd.point(kLandmark, t + h) - rd.point(kLandmark, t - h)) / (2 * h);
  EXPECT_LT((staticPointRate(rd.point(kLandmark, t), omega_radar, rd.velocity(t)) - numeric).norm(),
            1e-6);
  const TimeShiftedFactor f(std::make_shared<PointFactor>(measured, Mat3::Identity(), rd.ext), rate,
                            td_ref);
  StateBlocks b;
  toBlocks(rd.tr.state(t), &b);
  Vec3 l = kLandmark;
  auto residual = [&](double td) {
    double tdb[1] = {td};
    double const* params[] = {b.pose, l.data(), tdb};
    Vec3 r;
    f.Evaluate(params, r.data(), nullptr);
    return r.norm();
  };
  const double unshifted = residual(td_ref), shifted = residual(td_ref + delta);
  EXPECT_GT(unshifted, 0.02);  // [m] the radar moved / turned that much in 25 ms
  EXPECT_LT(shifted, 0.02 * unshifted);
}

// The same for the Doppler of a static point (the bearing and the radar velocity both at the
// later time), with the rate from the IMU reading at the state's time: what is left is of
// second order (halving delta quarters it), the unshifted residual of first order.
TEST(RioTimeOffset, ShiftExplainsADopplerMeasuredLater) {
  const Radar rd;
  const double t = 0.7, td_ref = 0.0;
  const NavState s = rd.tr.state(t);
  const Vec3 acc = radarAcceleration(s, rd.tr.omega(t), rd.alpha(t), rd.tr.specificForce(t), rd.ext,
                                     rd.tr.gravity);
  const double h = 1e-5;
  EXPECT_LT((acc - (rd.velocity(t + h) - rd.velocity(t - h)) / (2 * h)).norm(), 1e-6);
  // A reflector 5 m away along the radar's acceleration: the Doppler changes the most.
  const Vec3 l = rd.p(t) + rd.R(t) * (5.0 * acc.normalized());
  StateBlocks b;
  toBlocks(s, &b);
  const double w = 20.0;  // 1 / (0.05 m/s)
  auto residual = [&](double delta, double td) {
    const Vec3 d = rd.point(l, t + delta).normalized();
    const TimeShiftedFactor f(std::make_shared<DopplerFactor>(d, d.dot(rd.velocity(t + delta)),
                                                              rd.tr.omega(t), rd.ext, w),
                              Eigen::VectorXd::Constant(1, w * d.dot(acc)), td_ref);
    double tdb[1] = {td};
    double const* params[] = {b.pose, b.speed_bias, tdb};
    double r = 0.0;
    f.Evaluate(params, &r, nullptr);
    return std::abs(r);
  };
  const double delta = 0.025;
  const double unshifted = residual(delta, td_ref), shifted = residual(delta, td_ref + delta);
  EXPECT_NEAR(unshifted, w * delta * acc.norm(), 0.1 * unshifted);
  EXPECT_GT(unshifted, 0.5);  // whitened: more than 0.025 m/s of Doppler
  EXPECT_LT(shifted, 0.1 * unshifted);
  EXPECT_NEAR(unshifted / residual(delta / 2, td_ref), 2.0, 0.2);
  EXPECT_NEAR(shifted / residual(delta / 2, td_ref + delta / 2), 4.0, 0.6);
}

TEST(RioTimeOffset, AngularAccelerationIsTheSlopeOfTheLastSamples) {
  std::vector<ImuSample> interval;
  for (int k = 0; k <= 20; ++k) {
    const double t = 10.0 + 0.005 * k;
    // Rate 1 + 2 (t - 10) about x before 10.05 s, then 3 (t - 10.05) + 1.1 about z.
    const Vec3 w =
        t < 10.05 - 1e-9 ? Vec3(1.0 + 2.0 * (t - 10.0), 0, 0) : Vec3(1.1, 0, 3.0 * (t - 10.05));
    interval.push_back({t, Vec3::Zero(), w});
  }
  // Only the last 0.05 s count (the samples from 10.05 s on): slope (0, 0, 3).
  EXPECT_LT((angularAcceleration(interval, 0.05) - Vec3(0, 0, 3.0)).norm(), 1e-9);
  interval.resize(2);
  EXPECT_EQ(angularAcceleration(interval, 0.05), Vec3::Zero());  // too few samples
}

TEST(RioTimeOffset, ConfigValidation) {
  RioConfig cfg;
  EXPECT_FALSE(cfg.time_offset.estimate);  // off by default
  EXPECT_EQ(cfg.validate(), "");
  cfg.time_offset.estimate = true;
  cfg.time_offset.sigma = 0.0;
  EXPECT_NE(cfg.validate().find("time_offset: sigma must be > 0 s"), std::string::npos);
  cfg = RioConfig();
  cfg.time_offset.estimate = true;
  cfg.time_offset.max_abs = 1.5;
  EXPECT_NE(cfg.validate().find("time_offset: max_abs must be in (0, 1) s"), std::string::npos);
  cfg = RioConfig();
  cfg.time_offset.estimate = true;
  cfg.radar_time_offset = 0.2;  // outside the default bound 0.1 s
  EXPECT_NE(cfg.validate().find("radar_time_offset must be inside time_offset/max_abs"),
            std::string::npos)
      << cfg.validate();
  cfg.time_offset.estimate = false;  // not estimated: no bound
  EXPECT_EQ(cfg.validate(), "");
}

TEST(RioTimeOffset, ConfigKeys) {
  const std::string ext = "extrinsics: {translation: [0, 0, 0], rotation: [0, 0, 0, 1]}\n";
  RioConfig cfg;
  std::string err;
  ASSERT_TRUE(
      loadRioConfig(YAML::Load(ext + "radar_time_offset: 0.02\n"
                                     "time_offset: {estimate: true, sigma: 0.005, max_abs: 0.05, "
                                     "max_time_at_bound: 2.0, max_latency: 0.5}\n"),
                    &cfg, &err))
      << err;
  EXPECT_TRUE(cfg.time_offset.estimate);
  EXPECT_EQ(cfg.radar_time_offset, 0.02);
  EXPECT_EQ(cfg.time_offset.sigma, 0.005);
  EXPECT_EQ(cfg.time_offset.max_abs, 0.05);
  EXPECT_EQ(cfg.time_offset.max_time_at_bound, 2.0);
  EXPECT_EQ(cfg.time_offset.max_latency, 0.5);
  cfg = RioConfig();
  EXPECT_FALSE(
      loadRioConfig(YAML::Load(ext + "time_offset: {estimate: true, sigm: 0.01}\n"), &cfg, &err));
  EXPECT_NE(err.find("unknown key time_offset/sigm (did you mean sigma?)"), std::string::npos)
      << err;
  EXPECT_FALSE(loadRioConfig(
      YAML::Load(ext + "radar_time_offset: 0.2\ntime_offset: {estimate: true}\n"), &cfg, &err));
  EXPECT_NE(err.find("radar_time_offset must be inside time_offset/max_abs"), std::string::npos)
      << err;
}
