// ROS messages -> inputs of the radar-inertial odometry (rio::Estimator), shared by the
// offline runner (rio_offline, a bag) and RioNodelet (live topics): sensor_msgs/Imu ->
// rio::ImuSample, radar PointCloud2 with a radial-velocity field -> rio::RadarFrame,
// radar time from the header or from a trigger topic matched by sequence number
// (rio::TriggerMatcher; the TI mmWave driver stamps its scans with zero). Nothing throws:
// bad messages return false / nothing with a message for a throttled log and a counter.
#pragma once

#include <geometry_msgs/Transform.h>
#include <sensor_msgs/FluidPressure.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/Header.h>

#include <string>
#include <vector>

#include "coral_introspection/config/param_tree.hpp"
#include "coral_introspection/rio/barometer.hpp"
#include "coral_introspection/rio/radar_factors.hpp"
#include "coral_introspection/rio/trigger_matcher.hpp"
#include "coral_introspection/rio/types.hpp"

namespace coral_introspection {
namespace ros_adapters {

// The adapter settings: the `ros` group of a rio YAML file (config/rio_ti_mmwave.yaml).
struct RioInputConfig {
  std::string imu_topic = "imu";      // rio_offline: bag topic; the nodelet subscribes "imu"
  std::string radar_topic = "radar";  // rio_offline: bag topic; the nodelet subscribes "radar"
  std::string trigger_topic = "";     // rio_offline: bag topic; the nodelet "trigger"
  // sensor_msgs/FluidPressure [Pa]; read only with barometer/enabled. The nodelet "baro".
  std::string baro_topic = "baro";
  std::string time_source = "header";       // header | trigger
  std::string velocity_field = "velocity";  // PointCloud2 field of the radial velocity [m/s]
  int trigger_seq_offset = 0;               // trigger seq = scan seq + offset
  std::string validate() const;             // empty when valid
};

// Reads the `ros` group of a rio config file (missing keys keep defaults). False with *error
// on a group that is not a map, a bad type, an unknown key (naming the nearest valid one) or
// an invalid result.
bool loadRioInputConfig(const config::ParamTree& file, RioInputConfig* cfg, std::string* error);

struct RioInputCounters {
  long bad_imu = 0, bad_clouds = 0, no_velocity_field = 0, unmatched_scans = 0, bad_baro = 0;
};

// A radar frame back to a PointCloud2 (float32 x, y, z and the radial velocity under
// `velocity_field`), e.g. the scan re-stamped with its trigger time for CoralNodelet.
sensor_msgs::PointCloud2 radarFrameToCloud(const rio::RadarFrame& frame,
                                           const std_msgs::Header& header,
                                           const std::string& velocity_field);

// The radar pose in the body (IMU) frame from a TF transform body <- radar (what
// tf2 lookupTransform(body_frame, radar_frame, ...) returns: p_body = R p_radar + t). False
// with *error on a non-finite value or a quaternion whose norm is not 1 (+-1e-3; within it
// the quaternion is normalised).
bool extrinsicsFromTransform(const geometry_msgs::Transform& body_radar, rio::Extrinsics* out,
                             std::string* error);

class RioInput {
 public:
  explicit RioInput(const RioInputConfig& cfg) : cfg_(cfg), matcher_(cfg.trigger_seq_offset) {}

  // False with *error on a non-finite sample or a zero stamp.
  bool imu(const sensor_msgs::Imu& msg, rio::ImuSample* out, std::string* error);
  // False with *error on a zero stamp or a pressure that is not a positive finite number.
  bool baro(const sensor_msgs::FluidPressure& msg, rio::BaroSample* out, std::string* error);
  // The radar frames this scan completes (with time_source trigger, a scan waits for its
  // trigger). A cloud without the radial-velocity field gives no frame (counted) and *error
  // names the fields it has; *error is empty for a good cloud.
  std::vector<rio::RadarFrame> radar(const sensor_msgs::PointCloud2& msg, std::string* error);
  std::vector<rio::RadarFrame> trigger(const std_msgs::Header& msg);
  bool usesTrigger() const { return cfg_.time_source == "trigger"; }
  const RioInputCounters& counters() const { return counters_; }
  long waitingScans() const { return static_cast<long>(matcher_.waiting()); }
  // Trigger sequence restarts (seq back: a looping bag, a restarted driver; TriggerMatcher).
  long triggerRestarts() const { return matcher_.restarts(); }
  void reset() { matcher_.clear(); }

 private:
  RioInputConfig cfg_;
  rio::TriggerMatcher matcher_;
  RioInputCounters counters_;
};

}  // namespace ros_adapters
}  // namespace coral_introspection
