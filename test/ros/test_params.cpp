// Parameter loading and validation of CoralNodelet (no ROS master: XmlRpc trees).
#include <gtest/gtest.h>

#include "coral_introspection/ros/coral_params.hpp"

using namespace coral_introspection;
using XmlRpc::XmlRpcValue;

namespace {
XmlRpcValue group(const std::string& k, XmlRpcValue v) {
  XmlRpcValue g;
  g[k] = v;
  return g;
}
}  // namespace

TEST(Params, EmptyTreeGivesCoreDefaults) {
  ros_adapters::NodeConfig c;
  std::string err;
  ASSERT_TRUE(ros_adapters::loadNodeConfig(XmlRpcValue(), &c, &err)) << err;
  EXPECT_EQ(c.input_type, ros_adapters::InputType::kPointCloud);
  EXPECT_EQ(c.fixed_frame, "odom");
  EXPECT_DOUBLE_EQ(c.online.coral.radius, coral::CoralConfig().radius);
  EXPECT_DOUBLE_EQ(c.online.verdict.classifier.beta0, coral::ClassifierConfig().beta0);
  EXPECT_EQ(c.rip.k, radar::RipConfig().k);
  EXPECT_EQ(c.online.deskew.window, radar::DeskewConfig().window);
  EXPECT_EQ(c.online.doppler.check.seed, radar::DopplerConfig().seed);
}

TEST(Params, ReadsNestedValuesOfEveryType) {
  XmlRpcValue t;
  t["input_type"] = "polar_image";
  t["fixed_frame"] = "map";
  t["queue_size"] = 5;
  t["coral"]["dimension"] = 2;
  t["coral"]["radius"] = 1;  // int accepted for a double
  t["coral"]["aggregation"] = "median";
  t["coral"]["dynamic_radius"] = true;
  t["classifier"]["beta0"] = 11.0;
  t["classifier"]["threshold"] = 0.7;
  t["radar"]["polar_format"] = "plain";
  t["radar"]["azimuth_direction"] = "cw";
  t["radar"]["num_azimuths"] = 400.0;  // integral double accepted for an int
  t["rip"]["k"] = 8;
  t["pairing"]["min_distance"] = 2.5;
  t["doppler"]["enabled"] = true;
  t["doppler"]["velocity_field"] = "v_r";
  t["doppler"]["seed"] = 7;
  t["doppler"]["point_covariances"] = false;
  t["doppler"]["sigma_azimuth"] = 0.01;
  t["motion_compensation"]["enabled"] = false;
  ros_adapters::NodeConfig c;
  std::string err;
  ASSERT_TRUE(ros_adapters::loadNodeConfig(t, &c, &err)) << err;
  EXPECT_EQ(c.input_type, ros_adapters::InputType::kPolarImage);
  EXPECT_EQ(c.online.coral.dimension, 2);
  EXPECT_EQ(c.fixed_frame, "map");
  EXPECT_EQ(c.queue_size, 5);
  EXPECT_DOUBLE_EQ(c.online.coral.radius, 1.0);
  EXPECT_EQ(c.online.coral.aggregation, coral::Aggregation::kMedian);
  EXPECT_TRUE(c.online.coral.dynamic_radius);
  EXPECT_DOUBLE_EQ(c.online.verdict.classifier.beta0, 11.0);
  EXPECT_DOUBLE_EQ(c.online.verdict.classifier.threshold, 0.7);
  EXPECT_EQ(c.polar_format, ros_adapters::PolarFormat::kPlain);
  EXPECT_EQ(c.polar.direction, radar::AzimuthDirection::kClockwise);
  EXPECT_EQ(c.polar.num_azimuths, 400);
  EXPECT_EQ(c.rip.k, 8);
  EXPECT_DOUBLE_EQ(c.online.pairing.min_distance, 2.5);
  EXPECT_TRUE(c.online.doppler.enabled);
  EXPECT_EQ(c.velocity_field, "v_r");
  EXPECT_EQ(c.online.doppler.check.seed, 7u);
  EXPECT_FALSE(c.online.doppler.point_covariances);
  EXPECT_DOUBLE_EQ(c.online.doppler.noise.sigma_azimuth, 0.01);
  EXPECT_FALSE(c.online.deskew.enabled);
}

// No silent switch: polar input with 3D CorAl (the default) is refused with a message that
// names the parameter; the radar presets set coral/dimension: 2.
TEST(Params, PolarInputRequires2dCoral) {
  XmlRpcValue t;
  t["input_type"] = "polar_image";
  ros_adapters::NodeConfig c;
  std::string err;
  EXPECT_FALSE(ros_adapters::loadNodeConfig(t, &c, &err));
  EXPECT_NE(err.find("coral/dimension must be 2 for input_type polar_image"), std::string::npos)
      << err;
  t["coral"]["dimension"] = 2;
  c = ros_adapters::NodeConfig();
  EXPECT_TRUE(ros_adapters::loadNodeConfig(t, &c, &err)) << err;
}

// A LaserScan is planar: input_type laser_scan needs coral/dimension 2 (as a 2D preset sets),
// and has no radial-velocity field for the Doppler check.
TEST(Params, LaserScanInputRequires2dCoralAndNoDoppler) {
  XmlRpcValue t;
  t["input_type"] = "laser_scan";
  ros_adapters::NodeConfig c;
  std::string err;
  EXPECT_FALSE(ros_adapters::loadNodeConfig(t, &c, &err));
  EXPECT_NE(err.find("coral/dimension must be 2 for input_type laser_scan"), std::string::npos)
      << err;
  t["coral"]["dimension"] = 2;
  c = ros_adapters::NodeConfig();
  ASSERT_TRUE(ros_adapters::loadNodeConfig(t, &c, &err)) << err;
  EXPECT_EQ(c.input_type, ros_adapters::InputType::kLaserScan);
  t["doppler"]["enabled"] = true;
  EXPECT_FALSE(ros_adapters::loadNodeConfig(t, &c, &err));
  EXPECT_NE(err.find("a LaserScan has not"), std::string::npos) << err;
}

TEST(Params, DopplerNoiseAndSeedValidated) {
  XmlRpcValue t;
  t["doppler"]["enabled"] = true;
  t["doppler"]["sigma_range"] = -1.0;
  ros_adapters::NodeConfig c;
  std::string err;
  EXPECT_FALSE(ros_adapters::loadNodeConfig(t, &c, &err));
  EXPECT_NE(err.find("doppler/sigma_range"), std::string::npos) << err;
  XmlRpcValue s;
  s["doppler"]["seed"] = -3;
  c = ros_adapters::NodeConfig();
  EXPECT_FALSE(ros_adapters::loadNodeConfig(s, &c, &err));
  EXPECT_NE(err.find("doppler/seed"), std::string::npos) << err;
}

TEST(Params, CalibrationReadAndValidatedWhenEnabled) {
  XmlRpcValue t;
  t["calibration"]["enabled"] = true;
  t["calibration"]["fraction_of_pairs"] = 0.5;
  t["calibration"]["max_samples"] = 300;
  t["calibration"]["output_file"] = std::string("/tmp/c.yaml");
  ros_adapters::NodeConfig c;
  std::string err;
  ASSERT_TRUE(ros_adapters::loadNodeConfig(t, &c, &err)) << err;
  EXPECT_TRUE(c.online.calibration.enabled);
  EXPECT_EQ(c.online.calibration.fraction_of_pairs, 0.5);
  EXPECT_EQ(c.online.calibration.max_samples, 300);
  EXPECT_EQ(c.online.calibration.output_file, "/tmp/c.yaml");
  t["calibration"]["fraction_of_pairs"] = 2.0;
  EXPECT_FALSE(ros_adapters::loadNodeConfig(t, &c, &err));
  EXPECT_NE(err.find("calibration/fraction_of_pairs must be in (0, 1] (got 2)"), std::string::npos)
      << err;
  t["calibration"]["enabled"] = false;  // not validated while off
  EXPECT_TRUE(ros_adapters::loadNodeConfig(t, &c, &err)) << err;
}

TEST(Params, OutOfRangeValueNamesParamValueAndRange) {
  ros_adapters::NodeConfig c;
  std::string err;
  EXPECT_FALSE(ros_adapters::loadNodeConfig(group("coral", group("radius", -0.5)), &c, &err));
  EXPECT_NE(err.find("coral/radius"), std::string::npos) << err;
  EXPECT_NE(err.find("-0.5"), std::string::npos) << err;
  EXPECT_NE(err.find("[0.01, 10]"), std::string::npos) << err;

  c = ros_adapters::NodeConfig();
  EXPECT_FALSE(
      ros_adapters::loadNodeConfig(group("classifier", group("threshold", 1.5)), &c, &err));
  EXPECT_NE(err.find("classifier/threshold"), std::string::npos) << err;
  EXPECT_NE(err.find("1.5"), std::string::npos) << err;

  c = ros_adapters::NodeConfig();
  EXPECT_FALSE(
      ros_adapters::loadNodeConfig(group("pairing", group("max_time_gap", -1.0)), &c, &err));
  EXPECT_NE(err.find("pairing/max_time_gap"), std::string::npos) << err;

  c = ros_adapters::NodeConfig();
  XmlRpcValue q;
  q["queue_size"] = 0;
  EXPECT_FALSE(ros_adapters::loadNodeConfig(q, &c, &err));
  EXPECT_NE(err.find("queue_size"), std::string::npos) << err;

  for (double bad : {-1.0, 3601.0}) {
    XmlRpcValue h;
    h["heap_release_interval"] = bad;
    EXPECT_FALSE(ros_adapters::loadNodeConfig(h, &c, &err));
    EXPECT_NE(err.find("heap_release_interval must be in [0, 3600] s"), std::string::npos) << err;
  }
  XmlRpcValue h;
  h["heap_release_interval"] = 0.0;  // off
  c = ros_adapters::NodeConfig();
  EXPECT_TRUE(ros_adapters::loadNodeConfig(h, &c, &err)) << err;
  EXPECT_EQ(c.heap_release_interval, 0.0);
}

TEST(Params, WrongTypeAndUnknownChoiceAreRejected) {
  ros_adapters::NodeConfig c;
  std::string err;
  EXPECT_FALSE(ros_adapters::loadNodeConfig(group("coral", group("radius", "big")), &c, &err));
  EXPECT_EQ(err, "parameter coral/radius must be a number (got 'big')");
  EXPECT_FALSE(ros_adapters::loadNodeConfig(group("rip", group("k", 2.5)), &c, &err));
  EXPECT_EQ(err, "parameter rip/k must be an integer (got '2.5')");
  XmlRpcValue t;
  t["input_type"] = "laserscan";
  EXPECT_FALSE(ros_adapters::loadNodeConfig(t, &c, &err));
  EXPECT_NE(err.find("laserscan"), std::string::npos) << err;
  EXPECT_NE(err.find("pointcloud polar_image"), std::string::npos) << err;
  EXPECT_FALSE(ros_adapters::loadNodeConfig(group("coral", group("aggregation", "max")), &c, &err));
  EXPECT_NE(err.find("mean median"), std::string::npos) << err;
}

TEST(Params, RadarParamsValidatedOnlyForRadarInput) {
  XmlRpcValue t;
  t["rip"]["k"] = 0;  // invalid, but irrelevant for point clouds
  ros_adapters::NodeConfig c;
  std::string err;
  EXPECT_TRUE(ros_adapters::loadNodeConfig(t, &c, &err)) << err;
  t["input_type"] = "polar_image";
  t["coral"]["dimension"] = 2;
  c = ros_adapters::NodeConfig();
  EXPECT_FALSE(ros_adapters::loadNodeConfig(t, &c, &err));
  EXPECT_NE(err.find("rip/"), std::string::npos) << err;
}

// A typo would leave its setting at the default without a word: the load fails naming the
// nearest parameter, as coral_check does for the same preset (issue 23: `coarl:` made a
// 0.5 m error "aligned"). Keys the caller names (dynamic_reconfigure's) are accepted.
TEST(Params, UnknownGroupsAndKeysAreErrors) {
  ros_adapters::NodeConfig c;
  std::string err;
  EXPECT_FALSE(ros_adapters::loadNodeConfig(group("coral", group("raduis", 1.0)), &c, &err));
  EXPECT_EQ(err, "unknown key coral/raduis (did you mean radius?)");
  EXPECT_FALSE(ros_adapters::loadNodeConfig(group("coarl", group("radius", 1.0)), &c, &err));
  EXPECT_EQ(err, "unknown group coarl (did you mean coral?)");
  XmlRpcValue t;
  t["coral_radius"] = 0.5;
  t["diagnostic_period"] = 2.0;
  EXPECT_FALSE(ros_adapters::loadNodeConfig(t, &c, &err));
  EXPECT_EQ(err,
            "unknown key coral_radius (did you mean coral/radius?); unknown key diagnostic_period");
  EXPECT_TRUE(ros_adapters::loadNodeConfig(t, &c, &err, {"coral_radius", "diagnostic_period"}))
      << err;
}

TEST(Params, DenseLidarKeysReachTheCoralConfig) {
  XmlRpcValue t;
  t["coral"]["voxel_leaf"] = 0.2;
  t["coral"]["max_queries"] = 2000;
  t["coral"]["query_seed"] = 7;
  t["coral"]["threads"] = 2;
  ros_adapters::NodeConfig c;
  std::string err;
  ASSERT_TRUE(ros_adapters::loadNodeConfig(t, &c, &err)) << err;
  EXPECT_DOUBLE_EQ(c.online.coral.voxel_leaf, 0.2);
  EXPECT_EQ(c.online.coral.max_queries, 2000);
  EXPECT_EQ(c.online.coral.query_seed, 7);
  EXPECT_EQ(c.online.coral.threads, 2);
  t["coral"]["max_abs_coordinate"] = 1e5;
  t["coral"]["max_points"] = 300000;
  t["coral"]["refuse_over_max_points"] = true;
  t["coral"]["merge_distance"] = 0.002;
  t["coral"]["max_degenerate_fraction"] = 0.3;
  ASSERT_TRUE(ros_adapters::loadNodeConfig(t, &c, &err)) << err;
  EXPECT_DOUBLE_EQ(c.online.coral.max_abs_coordinate, 1e5);
  EXPECT_EQ(c.online.coral.max_points, 300000);
  EXPECT_TRUE(c.online.coral.refuse_over_max_points);
  EXPECT_DOUBLE_EQ(c.online.coral.merge_distance, 0.002);
  EXPECT_DOUBLE_EQ(c.online.coral.max_degenerate_fraction, 0.3);
  t["coral"]["threads"] = 0;
  EXPECT_FALSE(ros_adapters::loadNodeConfig(t, &c, &err));
  EXPECT_NE(err.find("threads"), std::string::npos) << err;
}

// The restart check and the package's registration (restart/, registration/) reach the verdict
// config; they and free_space/ are validated at load: free_space/bin_deg 0 once reached the
// free-space check and threw there (a crash of every nodelet in the manager).
TEST(Params, RestartRegistrationAndFreeSpaceReadAndValidated) {
  XmlRpcValue t;
  XmlRpcValue radii;
  radii[0] = 1.5;
  radii[1] = 3;  // an integer is a number
  radii[2] = 5.0;
  t["restart"]["radii"] = radii;
  t["restart"]["directions"] = 4;
  t["restart"]["coarse_points"] = 0;
  t["restart"]["coarse_same_within"] = 0.1;
  t["registration"]["normal_radius"] = 1.0;
  t["registration"]["max_iterations"] = 30;
  ros_adapters::NodeConfig c;
  std::string err;
  ASSERT_TRUE(ros_adapters::loadNodeConfig(t, &c, &err)) << err;
  const coral::RestartConfig& r = c.online.verdict.restart;
  EXPECT_EQ(r.radii, (std::vector<double>{1.5, 3.0, 5.0}));
  EXPECT_EQ(r.directions, 4);
  EXPECT_EQ(r.coarse_points, 0u);
  EXPECT_EQ(r.coarse_same_within, 0.1);
  EXPECT_EQ(r.registration.normal_radius, 1.0);
  EXPECT_EQ(r.registration.max_iterations, 30);
  EXPECT_EQ(r.min_distance, coral::RestartConfig().min_distance);  // absent: the default
  const struct {
    const char *group, *key;
    XmlRpcValue value;
    const char* message;
  } bad[] = {
      {"free_space", "bin_deg", XmlRpcValue(0.0), "free_space/bin_deg must be in (0, 10] deg"},
      {"free_space", "margin", XmlRpcValue(-1.0), "free_space/margin"},
      {"restart", "directions", XmlRpcValue(0), "restart/directions must be in [1, 64]"},
      {"restart", "coarse_points", XmlRpcValue(-5), "restart/coarse_points must be >= 0"},
      {"restart", "coarse_same_within", XmlRpcValue(2.0), "restart/coarse_same_within"},
      {"restart", "max_q_ratio", XmlRpcValue(1.5), "restart/max_q_ratio must be in (0, 1]"},
      {"registration", "max_iterations", XmlRpcValue(0), "registration/max_iterations"},
      {"registration", "normal_radius", XmlRpcValue(-1.0), "registration/normal_radius"},
  };
  for (const auto& b : bad) {
    XmlRpcValue u;
    u[b.group][b.key] = b.value;
    c = ros_adapters::NodeConfig();
    EXPECT_FALSE(ros_adapters::loadNodeConfig(u, &c, &err)) << b.group << "/" << b.key;
    EXPECT_NE(err.find(b.message), std::string::npos) << err;
  }
  XmlRpcValue empty;
  empty.setSize(0);
  XmlRpcValue e;
  e["restart"]["radii"] = empty;
  EXPECT_FALSE(ros_adapters::loadNodeConfig(e, &c, &err));
  EXPECT_NE(err.find("restart/radii must be a list of one number or more"), std::string::npos)
      << err;
}
