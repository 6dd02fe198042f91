// check_alignment answered as a pure function (no ROS master): a request is judged only
// when it holds the two scans of the nodelet's kind; every other request is refused with
// why. Before, two polar images sent to a 3D lidar nodelet came back "aligned, p = 1,
// Q = 0" for any transform.
#include <gtest/gtest.h>
#include <sensor_msgs/image_encodings.h>
#include <sensor_msgs/point_cloud2_iterator.h>

#include <cstdlib>

#include "coral_introspection/ros/conversions.hpp"
#include "coral_introspection/ros/coral_check_alignment.hpp"

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

// A laser-scan nodelet answers requests of point clouds (the service has no LaserScan fields)
// and refuses polar images like a point-cloud nodelet.
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
  const struct {
    const CheckAlignment::Request& request;
    const ros_adapters::NodeConfig& config;
    const char* why;
  } cases[] = {
      {none, lidar,
       "the request holds no scan (cloud_a, cloud_b, image_a and image_b are all empty); this "
       "nodelet is configured for point clouds (input_type pointcloud): fill cloud_a and "
       "cloud_b"},
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
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.why);
    expectRefused(c.request, c.config, c.why);
  }
}
