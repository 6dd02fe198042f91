// check_alignment answered as a pure function (no ROS master): a request is judged only
// when it holds the two scans of the nodelet's kind; every other request is refused with
// why. Before, two polar images sent to a 3D lidar nodelet came back "aligned, p = 1,
// Q = 0" for any transform.
#include <gtest/gtest.h>
#include <sensor_msgs/image_encodings.h>
#include <sensor_msgs/point_cloud2_iterator.h>

#include <cstdlib>
#include <initializer_list>

#include "coral_introspection/ros/conversions.hpp"
#include "coral_introspection/ros/coral_check_alignment.hpp"
#include "coral_introspection/ros/coral_scan_input.hpp"
#include "rostest/coral_rostest_utils.hpp"
#include "support/preset.hpp"

using namespace coral_introspection;
using ros_adapters::InputType;

namespace {

// A plain polar image (400 azimuths x 300 bins of 0.1 m) with a bright 5-bin ring at 15 m.
sensor_msgs::Image ringImage(double stamp) {
  sensor_msgs::Image im;
  im.header.stamp = ros::Time(stamp);
  im.header.frame_id = "radar";
  im.encoding = sensor_msgs::image_encodings::MONO8;
  im.height = 400;
  im.width = im.step = 300;
  im.data.assign(400 * 300, 0);
  for (uint32_t r = 0; r < im.height; ++r)
    for (int d = -2; d <= 2; ++d)
      im.data[r * im.step + 150 + d] = static_cast<uint8_t>(200 - 20 * std::abs(d));
  return im;
}

// A small float32 cloud: a 10 x 10 x 4 grid of 0.2 m.
sensor_msgs::PointCloud2 gridCloud(double stamp) {
  coral::Points pts;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j)
      for (int k = 0; k < 4; ++k) pts.emplace_back(0.2 * i, 0.2 * j, 0.2 * k);
  std_msgs::Header h;
  h.stamp = ros::Time(stamp);
  h.frame_id = "lidar";
  return ros_adapters::pointsToCloud(pts, h);
}

ros_adapters::NodeConfig radarConfig() {
  ros_adapters::NodeConfig c;
  c.input_type = InputType::kPolarImage;
  c.polar_format = ros_adapters::PolarFormat::kPlain;
  c.polar.range_resolution = 0.1;
  c.online.coral.dimension = 2;
  return c;
}

// Answers the request and checks it was refused with `why` in error and reason.
void expectRefused(const CheckAlignment::Request& req, const ros_adapters::NodeConfig& cfg,
                   const std::string& why) {
  CheckAlignment::Response res;
  EXPECT_FALSE(ros_adapters::answerCheckAlignment(req, cfg, &res));
  EXPECT_EQ(res.result.status, AlignmentQuality::REFUSED);
  EXPECT_FALSE(res.result.valid);
  EXPECT_FALSE(res.result.aligned);
  EXPECT_EQ(res.result.probability, 0.0);
  EXPECT_EQ(res.error, "request refused: " + why);
  EXPECT_EQ(res.result.reason, res.error);
}

// One refused request: to a nodelet of this config, refused with `why`.
struct Refusal {
  const CheckAlignment::Request& request;
  const ros_adapters::NodeConfig& config;
  const char* why;
};
void expectAllRefused(std::initializer_list<Refusal> cases) {
  for (const Refusal& c : cases) {
    SCOPED_TRACE(c.why);
    expectRefused(c.request, c.config, c.why);
  }
}

}  // namespace

TEST(CheckAlignmentRequest, PolarImagesToAPointCloudNodeletAreRefused) {
  CheckAlignment::Request req;
  req.image_a = ringImage(10.0);
  req.image_b = ringImage(11.0);
  req.transform_a_b.rotation.w = 1.0;
  expectRefused(req, ros_adapters::NodeConfig(),
                "this nodelet is configured for point clouds (input_type pointcloud); the "
                "request holds polar images (image_a, image_b): send them to a nodelet with "
                "input_type polar_image");
  // The same images are judged by a polar-image nodelet.
  CheckAlignment::Response res;
  EXPECT_TRUE(ros_adapters::answerCheckAlignment(req, radarConfig(), &res)) << res.error;
  EXPECT_NE(res.result.status, AlignmentQuality::REFUSED) << res.error;
}

TEST(CheckAlignmentRequest, PointCloudsToAPolarImageNodeletAreRefused) {
  CheckAlignment::Request req;
  req.cloud_a = gridCloud(10.0);
  req.cloud_b = gridCloud(11.0);
  req.transform_a_b.rotation.w = 1.0;
  expectRefused(req, radarConfig(),
                "this nodelet is configured for polar radar images (input_type polar_image); "
                "the request holds point clouds (cloud_a, cloud_b): send them to a nodelet with "
                "input_type pointcloud");
  CheckAlignment::Response res;
  EXPECT_TRUE(ros_adapters::answerCheckAlignment(req, ros_adapters::NodeConfig(), &res))
      << res.error;
  EXPECT_NE(res.result.status, AlignmentQuality::REFUSED) << res.error;
}

// A laser-scan nodelet also answers requests of (planar) point clouds, and refuses polar
// images like a point-cloud nodelet.
TEST(CheckAlignmentRequest, ALaserScanNodeletJudgesPointClouds) {
  ros_adapters::NodeConfig laser;
  laser.input_type = InputType::kLaserScan;
  laser.online.coral.dimension = 2;
  CheckAlignment::Request req;
  req.cloud_a = gridCloud(10.0);
  req.cloud_b = gridCloud(11.0);
  req.transform_a_b.rotation.w = 1.0;
  CheckAlignment::Response res;
  EXPECT_TRUE(ros_adapters::answerCheckAlignment(req, laser, &res)) << res.error;
  EXPECT_NE(res.result.status, AlignmentQuality::REFUSED) << res.error;
  CheckAlignment::Request images;
  images.image_a = ringImage(10.0);
  images.image_b = ringImage(11.0);
  images.transform_a_b.rotation.w = 1.0;
  expectRefused(images, laser,
                "this nodelet is configured for laser scans (input_type laser_scan); the "
                "request holds polar images (image_a, image_b): send them to a nodelet with "
                "input_type polar_image");
}

TEST(CheckAlignmentRequest, NoScanOneScanOrMixedKindsAreRefused) {
  CheckAlignment::Request none, one, one_image, mixed, all_four;
  none.cloud_a.header.frame_id = "lidar";  // a header alone is not a scan
  one.cloud_a = mixed.cloud_a = all_four.cloud_a = gridCloud(10.0);
  all_four.cloud_b = gridCloud(11.0);
  one_image.image_b = mixed.image_b = all_four.image_b = ringImage(11.0);
  all_four.image_a = ringImage(10.0);
  const ros_adapters::NodeConfig lidar, radar = radarConfig();
  expectAllRefused({
      {none, lidar,
       "the request holds no scan (cloud_a, cloud_b, image_a, image_b, scan_a and scan_b are "
       "all empty); this nodelet is configured for point clouds (input_type pointcloud): fill "
       "cloud_a and cloud_b"},
      {one, lidar, "cloud_b is empty: the request needs two point clouds (cloud_a and cloud_b)"},
      {one_image, radar,
       "image_a is empty: the request needs two polar images (image_a and image_b)"},
      {mixed, lidar,
       "the request mixes point clouds and polar images (cloud_a, image_b); this nodelet is "
       "configured for point clouds (input_type pointcloud): fill cloud_a and cloud_b only"},
      // All four set: which pair was meant cannot be told, by either kind of nodelet.
      {all_four, radar,
       "the request mixes point clouds and polar images (cloud_a, cloud_b, image_a, image_b); "
       "this nodelet is configured for polar radar images (input_type polar_image): fill "
       "image_a and image_b only"},
  });
}

namespace {

ros_adapters::NodeConfig laserScanPreset() {
  ros_adapters::NodeConfig c;
  coral_test::loadPreset("lidar_2d", &c);
  c.input_type = InputType::kLaserScan;
  return c;
}

// Two 0.5 deg laser scans of the synthetic yard 2.25 m apart (no returns written at range_max),
// and T_a_b mapping b's points into a's frame.
struct ScanPair {
  sensor_msgs::LaserScan a, b;
  Eigen::Isometry3d T_a_b;
};
ScanPair yardScans() {
  std::mt19937 rng(3);
  const Eigen::Isometry3d Ta = coral_test::trajectory(0.5), Tb = coral_test::trajectory(1.25);
  return {coral_test::laserScan(Ta, ros::Time(10.0), "laser", rng),
          coral_test::laserScan(Tb, ros::Time(11.0), "laser", rng), Ta.inverse() * Tb};
}

}  // namespace

// sensor_msgs/LaserScan in the request (scan_a, scan_b), as a 2D back end holds its scans: a
// laser-scan nodelet judges them as the planar clouds of their readings, the conversion of its
// stream (same Q, p and verdict as the clouds request), as a stream pair and as a loop-closure
// candidate; a transform 0.5 m off is flagged either way.
TEST(CheckAlignmentRequest, ALaserScanNodeletJudgesLaserScansAsTheirReadings) {
  const ros_adapters::NodeConfig laser = laserScanPreset();
  const ScanPair p = yardScans();
  CheckAlignment::Request scans, clouds;
  scans.scan_a = p.a;
  scans.scan_b = p.b;
  for (const auto& [scan, cloud] : {std::pair{&p.a, &clouds.cloud_a}, {&p.b, &clouds.cloud_b}}) {
    ros_adapters::SensorScan s;
    std::string err;
    ASSERT_TRUE(ros_adapters::toSensorScan(*scan, laser, &s, &err)) << err;
    *cloud = ros_adapters::pointsToCloud(s.scan.features.points, scan->header);
  }
  for (const bool loop : {false, true}) {
    for (const double off : {0.0, 0.5}) {
      SCOPED_TRACE(std::string(loop ? "loop closure" : "stream pair") + ", off " +
                   std::to_string(off));
      const Eigen::Isometry3d T = p.T_a_b * Eigen::Translation3d(0.0, off, 0.0);
      CheckAlignment::Response from_scans, from_clouds;
      for (auto* req : {&scans, &clouds}) {
        req->transform_a_b = ros_adapters::toTransformMsg(T);
        req->loop_closure = loop;
      }
      ASSERT_TRUE(ros_adapters::answerCheckAlignment(scans, laser, &from_scans))
          << from_scans.error;
      ASSERT_TRUE(ros_adapters::answerCheckAlignment(clouds, laser, &from_clouds))
          << from_clouds.error;
      const AlignmentQuality& r = from_scans.result;
      EXPECT_EQ(r.status, AlignmentQuality::VERDICT) << from_scans.error;
      EXPECT_TRUE(r.valid);
      EXPECT_EQ(r.aligned, off == 0.0)
          << "Q = " << r.quality << " p = " << r.probability << ": " << r.reason;
      EXPECT_EQ(r.rejected_by.empty(), off == 0.0) << r.rejected_by;
      EXPECT_EQ(r.loop_closure, loop);
      EXPECT_EQ(r.header.frame_id, "laser");
      EXPECT_EQ(r.stamp_b, ros::Time(11.0));
      // 361 beams of 0.5 deg thinned to the preset's 1 deg: at most 181 points a scan.
      EXPECT_GT(r.num_points_a, 100u);
      EXPECT_LE(r.num_points_a, 181u);
      EXPECT_EQ(r.aligned, from_clouds.result.aligned);
      EXPECT_EQ(r.num_points_a, from_clouds.result.num_points_a);
      EXPECT_EQ(r.num_points_b, from_clouds.result.num_points_b);
      EXPECT_NEAR(r.quality, from_clouds.result.quality, 1e-6);
      EXPECT_NEAR(r.probability, from_clouds.result.probability, 1e-6);
    }
  }
}

TEST(CheckAlignmentRequest, LaserScansToOtherNodeletsOneScanOrMixedKindsAreRefused) {
  const ScanPair p = yardScans();
  const ros_adapters::NodeConfig laser = laserScanPreset(), lidar, radar = radarConfig();
  CheckAlignment::Request scans, one, mixed, all, none, unreadable;
  scans.scan_a = one.scan_a = mixed.scan_a = all.scan_a = unreadable.scan_a = p.a;
  scans.scan_b = unreadable.scan_b = p.b;
  mixed.cloud_b = all.cloud_b = gridCloud(11.0);
  all.image_a = ringImage(10.0);
  unreadable.scan_b.angle_increment = 0.0f;  // beams without a direction
  for (auto* r : {&scans, &one, &mixed, &all, &none, &unreadable})
    r->transform_a_b = ros_adapters::toTransformMsg(p.T_a_b);
  expectAllRefused({
      {scans, lidar,
       "this nodelet is configured for point clouds (input_type pointcloud); the request holds "
       "laser scans (scan_a, scan_b): send them to a nodelet with input_type laser_scan"},
      {scans, radar,
       "this nodelet is configured for polar radar images (input_type polar_image); the "
       "request holds laser scans (scan_a, scan_b): send them to a nodelet with input_type "
       "laser_scan"},
      {none, laser,
       "the request holds no scan (cloud_a, cloud_b, image_a, image_b, scan_a and scan_b are "
       "all empty); this nodelet is configured for laser scans (input_type laser_scan): fill "
       "scan_a and scan_b (or cloud_a and cloud_b)"},
      {one, laser, "scan_b is empty: the request needs two laser scans (scan_a and scan_b)"},
      {mixed, laser,
       "the request mixes point clouds and laser scans (cloud_b, scan_a); this nodelet is "
       "configured for laser scans (input_type laser_scan): fill scan_a and scan_b (or cloud_a "
       "and cloud_b) only"},
      {all, lidar,
       "the request mixes point clouds, polar images and laser scans (cloud_b, image_a, "
       "scan_a); this nodelet is configured for point clouds (input_type pointcloud): fill "
       "cloud_a and cloud_b only"},
  });
  // A scan that cannot be read is refused with the field and the reason.
  CheckAlignment::Response res;
  EXPECT_FALSE(ros_adapters::answerCheckAlignment(unreadable, laser, &res));
  EXPECT_EQ(res.result.status, AlignmentQuality::REFUSED);
  EXPECT_EQ(res.error.rfind("request refused: scan_b: laser scan angle_min", 0), 0u) << res.error;
  // The readable pair is judged by the same nodelet.
  EXPECT_TRUE(ros_adapters::answerCheckAlignment(scans, laser, &res)) << res.error;
  EXPECT_TRUE(res.result.aligned) << res.result.reason;
}
