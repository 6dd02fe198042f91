// rostest: the check_alignment service (see nodelet_service.test).
#include "coral_rostest_utils.hpp"
#include "rostest_main.hpp"

#include "coral_introspection/CheckAlignment.h"

using namespace coral_test;
using coral_introspection::CheckAlignment;

namespace {

// b is 0.75 s further along the trajectory than a; T_a_b maps b's points into a's frame.
const Eigen::Isometry3d T_world_a = trajectory(0.5), T_world_b = trajectory(1.25);
const Eigen::Isometry3d T_a_b = T_world_a.inverse() * T_world_b;
const Eigen::Isometry3d T_a_b_wrong = T_a_b * Eigen::Translation3d(0.0, 0.5, 0.0);

bool call(const std::string& name, CheckAlignment& srv) {
  if (!ros::service::waitForService(name, ros::Duration(20.0))) return false;
  return ros::service::call(name, srv);
}

TEST(CheckAlignment, CloudsCorrectVsOffsetTransform) {
  std::mt19937 rng(5);
  CheckAlignment srv;
  srv.request.cloud_a = lidarCloud(T_world_a, ros::Time(10.0), "lidar_a", rng);
  srv.request.cloud_b = lidarCloud(T_world_b, ros::Time(11.0), "lidar_b", rng);
  srv.request.transform_a_b = ros_adapters::toTransformMsg(T_a_b);
  ASSERT_TRUE(call("/lidar/check_alignment", srv));
  const auto good = srv.response.result;
  EXPECT_TRUE(good.valid);
  EXPECT_TRUE(good.aligned) << "Q = " << good.quality << " p = " << good.probability;
  EXPECT_EQ(good.header.frame_id, "lidar_a");
  EXPECT_EQ(good.stamp_b, ros::Time(11.0));
  EXPECT_GT(good.num_points_b, 1000u);

  srv.request.transform_a_b = ros_adapters::toTransformMsg(T_a_b_wrong);
  ASSERT_TRUE(call("/lidar/check_alignment", srv));
  const auto bad = srv.response.result;
  EXPECT_TRUE(bad.valid);
  EXPECT_FALSE(bad.aligned) << "Q = " << bad.quality << " p = " << bad.probability;
  EXPECT_GT(bad.quality, good.quality);
  EXPECT_LT(bad.probability, good.probability);

  EXPECT_TRUE(srv.response.error.empty()) << srv.response.error;

  // A refused request is answered with the reason (not a failed call, no crash), and the
  // service keeps working.
  CheckAlignment broken = srv;
  broken.request.transform_a_b.rotation.w = 0.0;  // not a unit quaternion
  ASSERT_TRUE(call("/lidar/check_alignment", broken));
  EXPECT_FALSE(broken.response.result.valid);
  EXPECT_NE(broken.response.error.find("unit quaternion"), std::string::npos)
      << broken.response.error;
  broken = srv;
  broken.request.cloud_b.fields.pop_back();  // no z
  ASSERT_TRUE(call("/lidar/check_alignment", broken));
  EXPECT_FALSE(broken.response.result.valid);
  EXPECT_NE(broken.response.error.find("cloud_b"), std::string::npos) << broken.response.error;
  EXPECT_NE(broken.response.error.find("'z'"), std::string::npos) << broken.response.error;
  // Well-formed but 100 m off: judged, no verdict, and the reason is the overlap.
  broken = srv;
  broken.request.transform_a_b = ros_adapters::toTransformMsg(coral::se2(100.0, 0.0, 0.0));
  ASSERT_TRUE(call("/lidar/check_alignment", broken));
  EXPECT_FALSE(broken.response.result.valid);
  EXPECT_FALSE(broken.response.result.aligned);
  EXPECT_NE(broken.response.error.find("overlap"), std::string::npos) << broken.response.error;
  srv.request.transform_a_b = ros_adapters::toTransformMsg(T_a_b);
  ASSERT_TRUE(call("/lidar/check_alignment", srv));
  EXPECT_TRUE(srv.response.result.aligned);
  EXPECT_TRUE(srv.response.error.empty()) << srv.response.error;
}

TEST(CheckAlignment, PolarImagesCorrectVsOffsetTransform) {
  CheckAlignment srv;
  // Static renders (one pose per image): the service has no velocity to de-skew with.
  srv.request.image_a = polarImage([](double) { return T_world_a; }, 0.0, ros::Time(10.0), "radar");
  srv.request.image_b = polarImage([](double) { return T_world_b; }, 0.0, ros::Time(11.0), "radar");
  srv.request.transform_a_b = ros_adapters::toTransformMsg(T_a_b);
  ASSERT_TRUE(call("/radar/check_alignment", srv));
  const auto good = srv.response.result;
  EXPECT_TRUE(good.valid);
  EXPECT_TRUE(good.aligned) << "Q = " << good.quality;
  EXPECT_GT(good.num_points_a, 200u);
  srv.request.transform_a_b = ros_adapters::toTransformMsg(T_a_b_wrong);
  ASSERT_TRUE(call("/radar/check_alignment", srv));
  EXPECT_TRUE(srv.response.result.valid);
  EXPECT_FALSE(srv.response.result.aligned) << "Q = " << srv.response.result.quality;
}

// sensor_msgs/LaserScan in the request (scan_a, scan_b) to a laser-scan nodelet (lidar_2d), as a
// 2D back end asks about a loop candidate: the right transform accepted, one 0.5 m off rejected
// with the reason; the same scans to the 3D lidar nodelet are refused.
TEST(CheckAlignment, LaserScansCorrectVsOffsetTransform) {
  std::mt19937 rng(11);
  CheckAlignment srv;
  srv.request.scan_a = laserScan(T_world_a, ros::Time(10.0), "laser", rng);
  srv.request.scan_b = laserScan(T_world_b, ros::Time(11.0), "laser", rng);
  srv.request.loop_closure = true;
  srv.request.transform_a_b = ros_adapters::toTransformMsg(T_a_b);
  ASSERT_TRUE(call("/laser/check_alignment", srv));
  const auto good = srv.response.result;
  EXPECT_TRUE(good.valid) << srv.response.error;
  EXPECT_TRUE(good.aligned) << "Q = " << good.quality << " p = " << good.probability;
  EXPECT_TRUE(good.loop_closure);
  EXPECT_EQ(good.header.frame_id, "laser");
  EXPECT_GT(good.num_points_a, 100u);
  srv.request.transform_a_b = ros_adapters::toTransformMsg(T_a_b_wrong);
  ASSERT_TRUE(call("/laser/check_alignment", srv));
  EXPECT_TRUE(srv.response.result.valid) << srv.response.error;
  EXPECT_FALSE(srv.response.result.aligned) << "Q = " << srv.response.result.quality;
  EXPECT_FALSE(srv.response.result.rejected_by.empty());  // which term rejected it
  ASSERT_TRUE(call("/lidar/check_alignment", srv));
  EXPECT_EQ(srv.response.result.status, coral_introspection::AlignmentQuality::REFUSED);
  EXPECT_NE(srv.response.error.find("send them to a nodelet with input_type laser_scan"),
            std::string::npos)
      << srv.response.error;
}

// Each nodelet judges only its own kind of scans: the other kind, no scan, one scan or
// both kinds are refused with the reason (a call that succeeds, status REFUSED), and the
// service keeps judging. Polar images sent to the 3D lidar nodelet were answered "aligned,
// p = 1, Q = 0" for any transform before.
TEST(CheckAlignment, WrongKindsOfScansAreRefusedWithTheReason) {
  std::mt19937 rng(7);
  CheckAlignment clouds, images;
  clouds.request.cloud_a = lidarCloud(T_world_a, ros::Time(10.0), "lidar_a", rng);
  clouds.request.cloud_b = lidarCloud(T_world_b, ros::Time(11.0), "lidar_b", rng);
  images.request.image_a =
      polarImage([](double) { return T_world_a; }, 0.0, ros::Time(10.0), "radar");
  images.request.image_b =
      polarImage([](double) { return T_world_b; }, 0.0, ros::Time(11.0), "radar");
  CheckAlignment none, one, mixed;
  one.request.cloud_a = clouds.request.cloud_a;
  mixed.request.cloud_a = clouds.request.cloud_a;
  mixed.request.image_b = images.request.image_b;
  const struct {
    const char* service;
    CheckAlignment* srv;
    const char* why;
  } cases[] = {
      {"/lidar/check_alignment", &images,
       "this nodelet is configured for point clouds (input_type pointcloud); the request holds "
       "polar images (image_a, image_b)"},
      {"/radar/check_alignment", &clouds,
       "this nodelet is configured for polar radar images (input_type polar_image); the "
       "request holds point clouds (cloud_a, cloud_b)"},
      {"/lidar/check_alignment", &none, "the request holds no scan"},
      {"/lidar/check_alignment", &one, "cloud_b is empty"},
      {"/radar/check_alignment", &mixed, "the request mixes point clouds and polar images"},
  };
  for (const auto& c : cases) {
    for (const Eigen::Isometry3d& T : {T_a_b, T_a_b_wrong}) {
      c.srv->request.transform_a_b = ros_adapters::toTransformMsg(T);
      ASSERT_TRUE(call(c.service, *c.srv)) << c.why;
      const auto& r = c.srv->response.result;
      EXPECT_EQ(r.status, coral_introspection::AlignmentQuality::REFUSED) << c.why;
      EXPECT_FALSE(r.valid);
      EXPECT_FALSE(r.aligned);
      EXPECT_EQ(r.quality, 0.0);
      EXPECT_EQ(c.srv->response.error.rfind(std::string("request refused: ") + c.why, 0), 0u)
          << c.srv->response.error;
    }
  }
  // Each kind to its own nodelet is judged as before.
  for (const auto& [service, srv] :
       {std::pair<const char*, CheckAlignment*>{"/lidar/check_alignment", &clouds},
        {"/radar/check_alignment", &images}}) {
    srv->request.transform_a_b = ros_adapters::toTransformMsg(T_a_b);
    ASSERT_TRUE(call(service, *srv));
    EXPECT_TRUE(srv->response.result.valid) << service << ": " << srv->response.error;
    EXPECT_TRUE(srv->response.result.aligned) << service;
  }
}

TEST(CheckAlignment, TrainedClassifierFileIsUsedAsIs) {
  // The nodelet in /trained loaded config/classifier_radar_oxford.yaml (coral_train's
  // output) on top of the radar preset: its verdicts must follow Eq. 9 with those betas.
  double b0 = 0, b1 = 0, b2 = 0, th = 0;
  ASSERT_TRUE(ros::param::get("/trained/coral/classifier/beta0", b0));
  ASSERT_TRUE(ros::param::get("/trained/coral/classifier/beta1", b1));
  ASSERT_TRUE(ros::param::get("/trained/coral/classifier/beta2", b2));
  ASSERT_TRUE(ros::param::get("/trained/coral/classifier/threshold", th));
  double preset_b0 = 0;
  ASSERT_TRUE(ros::param::get("/radar/coral/classifier/beta0", preset_b0));
  ASSERT_NE(b0, preset_b0);  // the file really overrides the preset
  CheckAlignment srv;
  srv.request.image_a = polarImage([](double) { return T_world_a; }, 0.0, ros::Time(10.0), "radar");
  srv.request.image_b = polarImage([](double) { return T_world_b; }, 0.0, ros::Time(11.0), "radar");
  for (const Eigen::Isometry3d& T : {T_a_b, T_a_b_wrong}) {
    srv.request.transform_a_b = ros_adapters::toTransformMsg(T);
    ASSERT_TRUE(call("/trained/check_alignment", srv));
    const auto& r = srv.response.result;
    ASSERT_TRUE(r.valid);
    const double p = 1.0 / (1.0 + std::exp(-(b0 + b1 * r.h_joint + b2 * r.h_sep)));  // Eq. 9
    EXPECT_NEAR(r.probability, p, 1e-9);
    EXPECT_EQ(r.aligned, p >= th);  // Eq. 10
  }
}

}  // namespace

// main(): test/rostest/rostest_main.cpp.
const coral_test::RostestNode coral_test::kRostestNode{"nodelet_service_test", 1};
