// Constant-velocity motion compensation of radar features, checked on a synthetic scene
// scanned by a moving spinning radar.
#include <gtest/gtest.h>

#include <cmath>

#include "coral_introspection/eval/synthetic.hpp"
#include "coral_introspection/radar/motion_compensation.hpp"
#include "coral_introspection/radar/polar_scan.hpp"
#include "coral_introspection/radar/rip_features.hpp"

using namespace coral_introspection::coral;
using namespace coral_introspection::radar;
using namespace coral_introspection::eval;

TEST(MotionCompensation, ExponentialAndLogarithmAgree) {
  Twist tw;
  tw.linear = Vec3(8.0, -1.0, 0.2);
  tw.angular = Vec3(0.05, -0.1, 0.9);
  const Eigen::Isometry3d T = constantVelocityPose(tw, 0.25);
  const Twist back = twistFromRelativePose(T, 0.25);
  EXPECT_TRUE(back.linear.isApprox(tw.linear, 1e-9));
  EXPECT_TRUE(back.angular.isApprox(tw.angular, 1e-9));
  // Composition: exp(2 dt xi) = exp(dt xi)^2 for a constant twist.
  EXPECT_TRUE(constantVelocityPose(tw, 0.5).isApprox(T * T, 1e-12));
  // Planar twist: yaw rate w, forward speed v -> arc of radius v / w.
  Twist planar;
  planar.linear.x() = 10.0;
  planar.angular.z() = 0.5;
  const Eigen::Isometry3d A = constantVelocityPose(planar, 1.0);
  EXPECT_NEAR(A.translation().x(), 20.0 * std::sin(0.5), 1e-12);
  EXPECT_NEAR(A.translation().y(), 20.0 * (1.0 - std::cos(0.5)), 1e-12);
  EXPECT_TRUE(constantVelocityPose(Twist(), 3.0).isApprox(Eigen::Isometry3d::Identity()));
}

TEST(MotionCompensation, ZeroVelocityLeavesPointsUnchanged) {
  RadarFeatures f;
  f.points = {Vec3(1, 2, 0), Vec3(-3, 4, 0)};
  f.stamps = {10.0, 10.2};
  f.intensity = {80.f, 90.f};
  const Points before = f.points;
  compensateMotion(Twist(), 10.0, &f);
  EXPECT_EQ(f.points, before);
  // Pure translation: p + v (t - t_ref).
  Twist tw;
  tw.linear = Vec3(4.0, 0.0, 0.0);
  compensateMotion(tw, 10.0, &f);
  EXPECT_TRUE(f.points[0].isApprox(Vec3(1, 2, 0)));
  EXPECT_TRUE(f.points[1].isApprox(Vec3(-3 + 0.8, 4, 0)));
  compensateMotion(tw, 10.0, nullptr);  // no crash
}

TEST(MotionCompensation, MovingScanMatchesStaticScene) {
  // A radar at 0 m height in the yard (walls and tall boxes cross z = 0) drives at 8 m/s
  // while turning at 0.8 rad/s during one 0.25 s revolution of 400 azimuths.
  const SyntheticScene scene = SyntheticScene::structuredYard();
  const double res = 0.0432, period = 0.25, t0 = 100.0;
  const int rows = 400, cols = 1000;
  Twist tw;
  tw.linear = Vec3(8.0, 0.0, 0.0);
  tw.angular = Vec3(0.0, 0.0, 0.8);
  const Eigen::Isometry3d T_world_ref = se2(-6.0, -1.0, 0.2);  // sensor pose at t0

  cv::Mat img(rows, cols, CV_8UC1, cv::Scalar(0));
  Points truth(rows, Vec3::Constant(NAN));  // exact hit of each row, in the t0 sensor frame
  for (int i = 0; i < rows; ++i) {
    const double t = period * i / rows, az = 2.0 * M_PI * i / rows;
    const Eigen::Isometry3d T_world_sensor = T_world_ref * constantVelocityPose(tw, t);
    const Vec3 d = T_world_sensor.linear() * Vec3(std::cos(az), std::sin(az), 0.0);
    const auto range = scene.castRay(T_world_sensor.translation(), d, 40.0);
    if (!range || *range < 3.0) continue;
    const int bin = static_cast<int>(std::lround(*range / res));
    const int prof[5] = {90, 130, 180, 130, 90};
    for (int j = -2; j <= 2; ++j) img.at<uint8_t>(i, bin + j) = static_cast<uint8_t>(prof[j + 2]);
    truth[i] = T_world_ref.inverse() * (T_world_sensor.translation() + *range * d);
  }
  PolarImageConfig cfg = PolarImageConfig::oxfordCts350x();
  cfg.first_data_column = 0;
  PolarScan scan;
  std::string err;
  ASSERT_TRUE(decodePolarImage(img, cfg, t0, &scan, &err)) << err;
  RadarFeatures f;
  ASSERT_TRUE(extractRipFeatures(scan, RipConfig(), &f, &err)) << err;
  ASSERT_GT(f.points.size(), 300u);
  const Points raw = f.points;
  compensateMotion(tw, t0, &f);

  double max_err = 0.0, max_raw_err = 0.0;
  for (std::size_t k = 0; k < f.points.size(); ++k) {
    const int row = static_cast<int>(std::lround((f.stamps[k] - t0) / period * rows));
    ASSERT_TRUE(truth[row].allFinite());
    max_err = std::max(max_err, (f.points[k] - truth[row]).norm());
    max_raw_err = std::max(max_raw_err, (raw[k] - truth[row]).norm());
    EXPECT_NEAR(f.points[k].z(), 0.0, 1e-9);  // planar motion keeps the cloud planar
  }
  std::printf("max error to the static scene: compensated %.4f m, raw %.3f m\n", max_err,
              max_raw_err);
  EXPECT_LE(max_err, res);      // within the range resolution (quantisation to bins: res / 2)
  EXPECT_GT(max_raw_err, 1.0);  // without compensation the scan is distorted by metres
}
