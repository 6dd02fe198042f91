// Input conversion of the nodelet (no ROS master): polar images through the radar front
// end, bad images, Doppler field, velocity from two poses.
#include <gtest/gtest.h>
#include <sensor_msgs/image_encodings.h>
#include <sensor_msgs/point_cloud2_iterator.h>

#include <algorithm>

#include "coral_introspection/radar/motion_compensation.hpp"
#include "coral_introspection/ros/scan_input.hpp"

using namespace coral_introspection;

namespace {
// Plain polar image: rows = azimuths, one bright 5-bin peak per row at `bin`.
sensor_msgs::Image polarImage(int rows, int cols, int bin) {
  sensor_msgs::Image im;
  im.header.stamp = ros::Time(100.0);
  im.header.frame_id = "radar";
  im.encoding = sensor_msgs::image_encodings::MONO8;
  im.height = rows;
  im.width = cols;
  im.step = cols;
  im.data.assign(static_cast<std::size_t>(rows) * cols, 0);
  for (int r = 0; r < rows; ++r)
    for (int d = -2; d <= 2; ++d)
      im.data[r * cols + bin + d] = static_cast<uint8_t>(200 - 20 * std::abs(d));
  return im;
}

ros_adapters::NodeConfig plainRadar() {
  ros_adapters::NodeConfig c;
  c.input_type = ros_adapters::InputType::kPolarImage;
  c.polar_format = ros_adapters::PolarFormat::kPlain;
  c.polar.range_resolution = 0.1;
  c.polar.num_azimuths = 100;
  c.rip.min_range = 1.0;
  return c;
}
}  // namespace

TEST(ImageToSensorScan, PeakBecomesOneFeaturePerAzimuthAtItsRange) {
  ros_adapters::SensorScan s;
  std::string err;
  ASSERT_TRUE(ros_adapters::imageToSensorScan(polarImage(100, 300, 150), plainRadar(), &s, &err))
      << err;
  EXPECT_TRUE(s.is_radar);
  ASSERT_EQ(s.features.points.size(), 100u);
  for (const auto& p : s.features.points) {
    EXPECT_NEAR(p.head<2>().norm(), 15.0, 0.15);  // bin 150 * 0.1 m
    EXPECT_EQ(p.z(), 0.0);
  }
  ASSERT_EQ(s.features.stamps.size(), 100u);
  EXPECT_NEAR(s.features.stamps.front(), 100.0, 1e-9);  // header stamp = row 0
}

TEST(ImageToSensorScan, WrongEncodingOrSizeIsAnError) {
  ros_adapters::SensorScan s;
  std::string err;
  auto im = polarImage(100, 300, 150);
  im.encoding = sensor_msgs::image_encodings::RGB8;
  EXPECT_FALSE(ros_adapters::imageToSensorScan(im, plainRadar(), &s, &err));
  EXPECT_NE(err.find("mono8"), std::string::npos) << err;
  im = polarImage(100, 300, 150);
  im.data.resize(1000);  // header says more than there is
  EXPECT_FALSE(ros_adapters::imageToSensorScan(im, plainRadar(), &s, &err));
  EXPECT_FALSE(err.empty());
  // 90 rows where 100 azimuths are configured: rejected by the decoder.
  EXPECT_FALSE(ros_adapters::imageToSensorScan(polarImage(90, 300, 150), plainRadar(), &s, &err));
  EXPECT_FALSE(err.empty());
  // Oxford layout expects 3779 columns (metadata + bins).
  auto ox = plainRadar();
  ox.polar_format = ros_adapters::PolarFormat::kOxford;
  EXPECT_FALSE(ros_adapters::imageToSensorScan(polarImage(400, 300, 150), ox, &s, &err));
  EXPECT_FALSE(err.empty());
}

// Oxford-layout image messages whose row metadata is not one sweep give no features (and so
// no verdict) but an error naming the problem: reversed row stamps, a stuck encoder.
TEST(ImageToSensorScan, OxfordRowsThatAreNotOneSweepAreRefused) {
  sensor_msgs::Image im = polarImage(400, 3779, 1000);
  for (int r = 0; r < 400; ++r) {
    uint8_t* row = &im.data[static_cast<std::size_t>(r) * 3779];
    const int64_t us = 100000000 + 625 * r;  // 100 s + 625 us per row
    for (int b = 0; b < 8; ++b) row[b] = static_cast<uint8_t>((us >> (8 * b)) & 0xFF);
    row[8] = (14 * r) & 0xFF;
    row[9] = (14 * r) >> 8;
    row[10] = 255;
  }
  auto ox = plainRadar();
  ox.polar_format = ros_adapters::PolarFormat::kOxford;
  ros_adapters::SensorScan s;
  std::string err;
  ASSERT_TRUE(ros_adapters::imageToSensorScan(im, ox, &s, &err)) << err;
  EXPECT_EQ(s.features.points.size(), 400u);
  sensor_msgs::Image reversed = im;  // row r gets the stamp of row 399 - r
  for (int r = 0; r < 400; ++r)
    std::copy_n(&im.data[static_cast<std::size_t>(399 - r) * 3779], 8,
                &reversed.data[static_cast<std::size_t>(r) * 3779]);
  EXPECT_FALSE(ros_adapters::imageToSensorScan(reversed, ox, &s, &err));
  EXPECT_NE(err.find("backwards"), std::string::npos) << err;
  EXPECT_TRUE(s.features.points.empty());
  sensor_msgs::Image stuck = im;
  for (int r = 0; r < 400; ++r) stuck.data[r * 3779 + 8] = stuck.data[r * 3779 + 9] = 0;
  EXPECT_FALSE(ros_adapters::imageToSensorScan(stuck, ox, &s, &err));
  EXPECT_NE(err.find("stuck encoder"), std::string::npos) << err;
}

TEST(CloudToSensorScan, ReadsDopplerFieldOnlyWhenEnabled) {
  sensor_msgs::PointCloud2 c;
  sensor_msgs::PointCloud2Modifier mod(c);
  mod.setPointCloud2Fields(
      4, "x", 1, sensor_msgs::PointField::FLOAT32, "y", 1, sensor_msgs::PointField::FLOAT32, "z", 1,
      sensor_msgs::PointField::FLOAT32, "velocity", 1, sensor_msgs::PointField::FLOAT32);
  mod.resize(3);
  sensor_msgs::PointCloud2Iterator<float> it(c, "x");
  for (int i = 0; i < 3; ++i, ++it) {
    it[0] = 1.f + i;
    it[1] = 0.f;
    it[2] = 0.f;
    it[3] = -0.5f * i;
  }
  ros_adapters::NodeConfig cfg;
  ros_adapters::SensorScan s;
  std::string err;
  ASSERT_TRUE(ros_adapters::cloudToSensorScan(c, cfg, &s, &err)) << err;
  EXPECT_TRUE(s.radial_velocity.empty());
  cfg.doppler.enabled = true;
  ASSERT_TRUE(ros_adapters::cloudToSensorScan(c, cfg, &s, &err)) << err;
  ASSERT_EQ(s.radial_velocity.size(), 3u);
  EXPECT_FLOAT_EQ(s.radial_velocity[2], -1.0);
}

TEST(TwistBetween, InvertsTheConstantVelocityModel) {
  core::Twist v;
  v.linear = core::Vec3(5.0, 0.4, 0.0);
  v.angular = core::Vec3(0.0, 0.0, 0.8);
  const double dt = 0.25;
  const Eigen::Isometry3d T_fixed_prev = core::se2(3.0, -1.0, 0.4);
  const Eigen::Isometry3d T_fixed_curr = T_fixed_prev * core::constantVelocityPose(v, dt);
  core::Twist est;
  ASSERT_TRUE(ros_adapters::twistBetween(T_fixed_prev, T_fixed_curr, dt, &est));
  EXPECT_NEAR((est.linear - v.linear).norm(), 0.0, 1e-9);
  EXPECT_NEAR((est.angular - v.angular).norm(), 0.0, 1e-9);
  EXPECT_FALSE(ros_adapters::twistBetween(T_fixed_prev, T_fixed_curr, 0.0, &est));
}

TEST(RobustTwist, MedianIgnoresOneOdometryJump) {
  core::Twist good, jump_in, jump_out;
  good.linear = core::Vec3(3.0, 0.0, 0.0);
  good.angular = core::Vec3(0.0, 0.0, 0.3);
  jump_in = good;
  jump_in.linear.y() += 2.0;  // 0.5 m lateral jump over 0.25 s
  jump_out = good;
  jump_out.linear.y() -= 2.0;  // and back (a single displaced pose)
  const core::Twist m1 = ros_adapters::robustTwist({good, good, jump_in});
  EXPECT_NEAR((m1.linear - good.linear).norm(), 0.0, 1e-12);
  const core::Twist m2 = ros_adapters::robustTwist({good, jump_in, jump_out});
  EXPECT_NEAR((m2.linear - good.linear).norm(), 0.0, 1e-12);
  EXPECT_NEAR((m2.angular - good.angular).norm(), 0.0, 1e-12);
  // Fewer than three: the latest.
  EXPECT_NEAR((ros_adapters::robustTwist({good, jump_in}).linear - jump_in.linear).norm(), 0.0,
              1e-12);
}
