// Input conversion of the nodelet (no ROS master): polar images through the radar front
// end, bad images, empty input, Doppler field.
#include <gtest/gtest.h>
#include <sensor_msgs/image_encodings.h>
#include <sensor_msgs/point_cloud2_iterator.h>

#include <algorithm>

#include "coral_introspection/ros/coral_scan_input.hpp"

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
  ASSERT_TRUE(ros_adapters::toSensorScan(polarImage(100, 300, 150), plainRadar(), &s, &err)) << err;
  EXPECT_TRUE(s.scan.is_radar);
  ASSERT_EQ(s.scan.features.points.size(), 100u);
  for (const auto& p : s.scan.features.points) {
    EXPECT_NEAR(p.head<2>().norm(), 15.0, 0.15);  // bin 150 * 0.1 m
    EXPECT_EQ(p.z(), 0.0);
  }
  ASSERT_EQ(s.scan.features.stamps.size(), 100u);
  EXPECT_NEAR(s.scan.features.stamps.front(), 100.0, 1e-9);  // header stamp = row 0
}

TEST(ImageToSensorScan, WrongEncodingOrSizeIsAnError) {
  ros_adapters::SensorScan s;
  std::string err;
  auto im = polarImage(100, 300, 150);
  im.encoding = sensor_msgs::image_encodings::RGB8;
  EXPECT_FALSE(ros_adapters::toSensorScan(im, plainRadar(), &s, &err));
  EXPECT_NE(err.find("mono8"), std::string::npos) << err;
  im = polarImage(100, 300, 150);
  im.data.resize(1000);  // header says more than there is
  EXPECT_FALSE(ros_adapters::toSensorScan(im, plainRadar(), &s, &err));
  EXPECT_FALSE(err.empty());
  // 90 rows where 100 azimuths are configured: rejected by the decoder.
  EXPECT_FALSE(ros_adapters::toSensorScan(polarImage(90, 300, 150), plainRadar(), &s, &err));
  EXPECT_FALSE(err.empty());
  // Oxford layout expects 3779 columns (metadata + bins).
  auto ox = plainRadar();
  ox.polar_format = ros_adapters::PolarFormat::kOxford;
  EXPECT_FALSE(ros_adapters::toSensorScan(polarImage(400, 300, 150), ox, &s, &err));
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
  ASSERT_TRUE(ros_adapters::toSensorScan(im, ox, &s, &err)) << err;
  EXPECT_EQ(s.scan.features.points.size(), 400u);
  sensor_msgs::Image reversed = im;  // row r gets the stamp of row 399 - r
  for (int r = 0; r < 400; ++r)
    std::copy_n(&im.data[static_cast<std::size_t>(399 - r) * 3779], 8,
                &reversed.data[static_cast<std::size_t>(r) * 3779]);
  EXPECT_FALSE(ros_adapters::toSensorScan(reversed, ox, &s, &err));
  EXPECT_NE(err.find("backwards"), std::string::npos) << err;
  EXPECT_TRUE(s.scan.features.points.empty());
  sensor_msgs::Image stuck = im;
  for (int r = 0; r < 400; ++r) stuck.data[r * 3779 + 8] = stuck.data[r * 3779 + 9] = 0;
  EXPECT_FALSE(ros_adapters::toSensorScan(stuck, ox, &s, &err));
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
  ASSERT_TRUE(ros_adapters::toSensorScan(c, cfg, &s, &err)) << err;
  EXPECT_TRUE(s.scan.radial_velocity.empty());
  cfg.online.doppler.enabled = true;
  ASSERT_TRUE(ros_adapters::toSensorScan(c, cfg, &s, &err)) << err;
  ASSERT_EQ(s.scan.radial_velocity.size(), 3u);
  EXPECT_FLOAT_EQ(s.scan.radial_velocity[2], -1.0);
}

TEST(ToSensorScan, HeaderGivesStampAndIdAndEmptyInputIsAnError) {
  sensor_msgs::PointCloud2 c;
  sensor_msgs::PointCloud2Modifier mod(c);
  mod.setPointCloud2FieldsByString(1, "xyz");
  mod.resize(2);
  c.header.stamp = ros::Time(1700000000, 123456789);
  sensor_msgs::PointCloud2Iterator<float> it(c, "x");
  it[0] = 1.f, it[1] = 2.f, it[2] = 3.f;
  ++it;
  it[0] = std::nanf(""), it[1] = 0.f, it[2] = 0.f;
  ros_adapters::NodeConfig cfg;
  ros_adapters::SensorScan s;
  std::string err;
  ASSERT_TRUE(ros_adapters::toSensorScan(c, cfg, &s, &err)) << err;
  EXPECT_EQ(s.scan.id, c.header.stamp.toNSec());  // exact: verdicts carry the header stamps
  EXPECT_DOUBLE_EQ(s.scan.stamp, c.header.stamp.toSec());
  EXPECT_EQ(s.dropped_non_finite, 1u);
  EXPECT_FALSE(s.scan.T_fixed_sensor.has_value());
  // Only NaN points, then no points at all.
  sensor_msgs::PointCloud2Iterator<float> first(c, "x");
  first[0] = std::nanf("");
  EXPECT_FALSE(ros_adapters::toSensorScan(c, cfg, &s, &err));
  EXPECT_NE(err.find("NaN"), std::string::npos) << err;
  EXPECT_EQ(s.dropped_non_finite, 2u);  // still counted
  mod.resize(0);
  EXPECT_FALSE(ros_adapters::toSensorScan(c, cfg, &s, &err));
  EXPECT_NE(err.find("0 points"), std::string::npos) << err;
  // An image whose peaks are all below rip/z_min gives no feature.
  auto cfg_radar = plainRadar();
  cfg_radar.rip.z_min = 250;
  EXPECT_FALSE(ros_adapters::toSensorScan(polarImage(100, 300, 150), cfg_radar, &s, &err));
  EXPECT_NE(err.find("z_min"), std::string::npos) << err;
}

TEST(NoPoseInput, CarriesTheTfErrorAndNoPose) {
  std_msgs::Header h;
  h.stamp = ros::Time(12.5);
  h.frame_id = "lidar";
  const online::ScanInput s = ros_adapters::noPoseInput(h, "odom", "extrapolation");
  EXPECT_FALSE(s.T_fixed_sensor.has_value());
  EXPECT_EQ(s.id, h.stamp.toNSec());
  EXPECT_NE(s.pose_error.find("odom <- 'lidar'"), std::string::npos) << s.pose_error;
  EXPECT_NE(s.pose_error.find("extrapolation"), std::string::npos) << s.pose_error;
}
