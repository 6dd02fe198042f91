// Odometry yaw calibration (eval/odometry_calibration.hpp) on known answers: an odometry whose
// yaw errs by a known gain per radian turned and bias per metre driven, measured again on every
// other step with a little noise, is fitted to those two numbers and corrected back onto the
// truth; too few, straight-only or mismatched measurements are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "coral_introspection/coral/types.hpp"
#include "coral_introspection/eval/odometry_calibration.hpp"
#include "coral_introspection/eval/pose_graph.hpp"

using namespace coral_introspection;
using namespace coral_introspection::eval;

namespace {

Eigen::Isometry3d planar(double x, double y, double yaw) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(x, y, 0.0);
  return T;
}

// Two laps of a 10 m square, 0.5 m steps, the corners turned over three steps.
std::vector<Eigen::Isometry3d> trueSteps() {
  std::vector<Eigen::Isometry3d> steps;
  for (int lap = 0; lap < 2; ++lap)
    for (int side = 0; side < 4; ++side) {
      for (int k = 0; k < 20; ++k) steps.push_back(planar(0.5, 0.0, 0.0));
      for (int k = 0; k < 3; ++k) steps.push_back(planar(0.2, 0.0, M_PI / 6.0));
    }
  return steps;
}

coral::Isometries chain(const std::vector<Eigen::Isometry3d>& steps) {
  coral::Isometries T = {Eigen::Isometry3d::Identity()};
  for (const Eigen::Isometry3d& s : steps) T.push_back(T.back() * s);
  return T;
}

// The odometry of a true step whose yaw errs by gain * (its own yaw) + bias * (its length).
Eigen::Isometry3d odometryStep(const Eigen::Isometry3d& truth, double gain, double bias) {
  const double len = truth.translation().head<2>().norm();
  const double yaw = (coral::yawOf(truth.linear()) + bias * len) / (1.0 - gain);
  Eigen::Isometry3d s = truth;
  s.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return s;
}

}  // namespace

TEST(OdometryCalibration, FitRecoversAKnownGainAndBias) {
  const double gain = 0.031, bias = -0.059;  // about Intel's (doc/loop_closure.md)
  const std::vector<Eigen::Isometry3d> truth_steps = trueSteps();
  std::vector<Eigen::Isometry3d> odo_steps;
  for (const Eigen::Isometry3d& s : truth_steps) odo_steps.push_back(odometryStep(s, gain, bias));
  const coral::Isometries truth = chain(truth_steps), odo = chain(odo_steps);
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.002);  // [rad] the registration's
  std::vector<std::optional<Eigen::Isometry3d>> measured(truth_steps.size());
  for (std::size_t k = 0; k < truth_steps.size(); k += 2)
    measured[k] = truth_steps[k] * planar(0.0, 0.0, noise(rng));
  OdometryYawModel m;
  std::string error;
  ASSERT_TRUE(fitOdometryYaw(odo, measured, 20, &m, &error)) << error;
  EXPECT_EQ(m.steps, static_cast<int>((truth_steps.size() + 1) / 2));
  EXPECT_NEAR(m.gain, gain, 2e-3);
  EXPECT_NEAR(m.bias_per_m, bias, 2e-3);
  EXPECT_GT(m.rms_before, 0.02);
  EXPECT_LT(m.rms_after, 0.003);  // the noise left
  const coral::Isometries corrected = correctOdometryYaw(odo, m);
  ASSERT_EQ(corrected.size(), odo.size());
  const double ate_odo = absoluteTrajectoryError(odo, truth, 2);
  const double ate_corrected = absoluteTrajectoryError(corrected, truth, 2);
  std::printf("gain %.4f bias %.4f; ATE %.3f -> %.3f m\n", m.gain, m.bias_per_m, ate_odo,
              ate_corrected);
  EXPECT_GT(ate_odo, 2.0);
  EXPECT_LT(ate_corrected, 0.1);
  EXPECT_TRUE(corrected[0].isApprox(odo[0]));
  for (std::size_t k = 0; k + 1 < odo.size(); ++k)  // translations of the steps are kept
    EXPECT_NEAR(
        ((corrected[k].inverse() * corrected[k + 1]).translation() - odo_steps[k].translation())
            .norm(),
        0.0, 1e-9);
}

TEST(OdometryCalibration, TooFewStraightOrMismatchedStepsAreRefused) {
  const std::vector<Eigen::Isometry3d> truth_steps = trueSteps();
  const coral::Isometries odo = chain(truth_steps);
  std::vector<std::optional<Eigen::Isometry3d>> measured(truth_steps.size());
  OdometryYawModel m;
  std::string error;
  for (std::size_t k = 0; k < 10; ++k) measured[k] = truth_steps[k];
  EXPECT_FALSE(fitOdometryYaw(odo, measured, 20, &m, &error));
  EXPECT_NE(error.find("fewer than 20"), std::string::npos) << error;
  for (std::size_t k = 0; k < 20; ++k) measured[k] = truth_steps[k];  // the first side: straight
  EXPECT_FALSE(fitOdometryYaw(odo, measured, 20, &m, &error));
  EXPECT_NE(error.find("never turn"), std::string::npos) << error;
  measured.pop_back();
  EXPECT_FALSE(fitOdometryYaw(odo, measured, 20, &m, &error));
  EXPECT_NE(error.find("one measured step slot"), std::string::npos) << error;
  // An exact odometry, every step measured as it is: nothing to correct.
  measured.assign(truth_steps.size(), std::nullopt);
  for (std::size_t k = 0; k < truth_steps.size(); ++k) measured[k] = truth_steps[k];
  ASSERT_TRUE(fitOdometryYaw(odo, measured, 20, &m, &error)) << error;
  EXPECT_NEAR(m.gain, 0.0, 1e-12);
  EXPECT_NEAR(m.bias_per_m, 0.0, 1e-12);
}
