// Input conversion of the nodelet (no ROS master): polar images through the radar front
// end, bad images, empty input, Doppler field, laser scans.
#include <gtest/gtest.h>
#include <sensor_msgs/image_encodings.h>
#include <sensor_msgs/point_cloud2_iterator.h>

#include <algorithm>
#include <cmath>
#include <limits>

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

namespace {
// A scan of `n` beams from angle_min in steps of `inc` [rad], every reading `r` [m].
sensor_msgs::LaserScan laserScan(int n, double angle_min, double inc, float r) {
  sensor_msgs::LaserScan s;
  s.header.stamp = ros::Time(50.0);
  s.header.frame_id = "laser";
  s.angle_min = static_cast<float>(angle_min);
  s.angle_increment = static_cast<float>(inc);
  s.angle_max = static_cast<float>(angle_min + (n - 1) * inc);
  s.range_min = 0.1f;
  s.range_max = 30.0f;
  s.ranges.assign(static_cast<std::size_t>(n), r);
  return s;
}

ros_adapters::NodeConfig laserConfig() {
  ros_adapters::NodeConfig c;
  c.input_type = ros_adapters::InputType::kLaserScan;
  c.online.coral.dimension = 2;
  return c;
}
}  // namespace

// Beam i at angle_min + i angle_increment (either sign), z = 0; the readings that are no return
// (REP 117: +-Inf, below range_min, at or past range_max: a driver's "no return" at range_max
// kept as a point is a wall that is not there) are left out, NaN counted.
TEST(LaserScanToSensorScan, BeamsBecomePlanarPointsAndNoReturnsAreLeftOut) {
  const double deg = M_PI / 180.0;
  sensor_msgs::LaserScan s = laserScan(181, -90.0 * deg, 1.0 * deg, 2.0f);
  s.ranges[10] = std::numeric_limits<float>::infinity();
  s.ranges[11] = -std::numeric_limits<float>::infinity();
  s.ranges[12] = std::numeric_limits<float>::quiet_NaN();
  s.ranges[13] = 0.05f;  // below range_min
  s.ranges[14] = 30.0f;  // at range_max: no return
  s.ranges[15] = 45.0f;  // past it
  ros_adapters::SensorScan out;
  std::string err;
  ASSERT_TRUE(ros_adapters::toSensorScan(s, laserConfig(), &out, &err)) << err;
  const coral::Points& p = out.scan.features.points;
  ASSERT_EQ(p.size(), 181u - 6u);
  EXPECT_EQ(out.dropped_non_finite, 1u);
  EXPECT_FALSE(out.scan.is_radar);
  EXPECT_DOUBLE_EQ(out.scan.stamp, 50.0);
  EXPECT_NEAR(p.front().x(), 0.0, 1e-6);  // beam 0 at -90 deg
  EXPECT_NEAR(p.front().y(), -2.0, 1e-6);
  EXPECT_NEAR(p[90 - 6].x(), 2.0, 1e-5);  // beam 90 (six readings before it dropped)
  EXPECT_NEAR(p.back().y(), 2.0, 1e-5);   // beam 180 at +90 deg
  for (const coral::Vec3& q : p) {
    EXPECT_NEAR(q.head<2>().norm(), 2.0, 1e-5);
    EXPECT_EQ(q.z(), 0.0);
  }
  // A clockwise scanner (negative increment): beam 0 at +90 deg, the last at -90 deg.
  const sensor_msgs::LaserScan cw = laserScan(181, 90.0 * deg, -1.0 * deg, 2.0f);
  ASSERT_TRUE(ros_adapters::toSensorScan(cw, laserConfig(), &out, &err)) << err;
  EXPECT_NEAR(out.scan.features.points.front().y(), 2.0, 1e-5);
  EXPECT_NEAR(out.scan.features.points.back().y(), -2.0, 1e-5);
}

// With a time_increment each point carries its beam's time (the header's stamp for beam 0;
// dropped readings keep their slot), for the de-skew; without one (0, or not finite) none.
TEST(LaserScanToSensorScan, EachBeamIsStampedByTimeIncrement) {
  const double deg = M_PI / 180.0;
  sensor_msgs::LaserScan s = laserScan(360, 0.0, 1.0 * deg, 3.0f);
  s.time_increment = 0.1f / 360.0f;  // a 10 Hz scanner
  s.ranges[1] = std::numeric_limits<float>::infinity();
  ros_adapters::SensorScan out;
  std::string err;
  ASSERT_TRUE(ros_adapters::toSensorScan(s, laserConfig(), &out, &err)) << err;
  EXPECT_TRUE(out.scan.point_stamps);
  const std::vector<double>& t = out.scan.features.stamps;
  ASSERT_EQ(t.size(), out.scan.features.points.size());
  ASSERT_EQ(t.size(), 359u);
  EXPECT_DOUBLE_EQ(t[0], 50.0);
  EXPECT_NEAR(t[1], 50.0 + 2.0 * s.time_increment, 1e-9);  // beam 2: beam 1 had no return
  EXPECT_NEAR(t.back(), 50.0 + 359.0 * s.time_increment, 1e-9);
  for (float dt : {0.0f, std::numeric_limits<float>::quiet_NaN()}) {
    s.time_increment = dt;
    ASSERT_TRUE(ros_adapters::toSensorScan(s, laserConfig(), &out, &err)) << err;
    EXPECT_FALSE(out.scan.point_stamps) << dt;
    EXPECT_TRUE(out.scan.features.stamps.empty()) << dt;
  }
}

TEST(LaserScanToSensorScan, ScansThatCannotBeReadAreRefusedWithTheReason) {
  const double deg = M_PI / 180.0;
  ros_adapters::SensorScan out;
  std::string err;
  sensor_msgs::LaserScan s = laserScan(181, -90.0 * deg, 0.0, 2.0f);
  EXPECT_FALSE(ros_adapters::toSensorScan(s, laserConfig(), &out, &err));
  EXPECT_NE(err.find("angle_increment non-zero"), std::string::npos) << err;
  s = laserScan(181, -90.0 * deg, std::nan(""), 2.0f);
  EXPECT_FALSE(ros_adapters::toSensorScan(s, laserConfig(), &out, &err));
  s = laserScan(721, 0.0, 1.0 * deg, 2.0f);  // 720 deg
  EXPECT_FALSE(ros_adapters::toSensorScan(s, laserConfig(), &out, &err));
  EXPECT_NE(err.find("more than a full turn"), std::string::npos) << err;
  s = laserScan(181, -90.0 * deg, 1.0 * deg, 2.0f);
  s.range_max = s.range_min;
  EXPECT_FALSE(ros_adapters::toSensorScan(s, laserConfig(), &out, &err));
  EXPECT_NE(err.find("range_min < range_max"), std::string::npos) << err;
  s = laserScan(181, -90.0 * deg, 1.0 * deg, std::numeric_limits<float>::infinity());
  EXPECT_FALSE(ros_adapters::toSensorScan(s, laserConfig(), &out, &err));  // nothing returned
  EXPECT_NE(err.find("has none in [range_min, range_max)"), std::string::npos) << err;
  s.ranges.clear();
  EXPECT_FALSE(ros_adapters::toSensorScan(s, laserConfig(), &out, &err));
}
