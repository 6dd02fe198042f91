// RioNodelet: the radar-inertial odometry (rio::Estimator) on live topics. Thin: converts
// inputs with ros/rio_input.hpp, feeds the estimator, publishes what it reports.
//   in:  radar (sensor_msgs/PointCloud2 with a radial-velocity field), imu (sensor_msgs/Imu),
//        trigger (std_msgs/Header, when the config's ros/time_source is trigger),
//        baro (sensor_msgs/FluidPressure, when the config's barometer/enabled is true)
//   out: odometry (nav_msgs/Odometry with covariance), TF odom_frame -> base_frame, path
//        (nav_msgs/Path), landmarks (PointCloud2, odom frame), radar_stamped (each radar
//        frame with its measurement time and frame radar_frame when the cloud has none:
//        the TI driver's scans carry neither, CoralNodelet needs both), /diagnostics
// Radar-to-IMU extrinsics: from the config file (extrinsics_source "config"), or from TF
// (extrinsics_source "tf"): looked up once, imu_frame <- radar frame (the scans' frame_id, else
// radar_frame), when the radar frame first appears and retried on every scan until TF has it;
// the estimator starts then (inputs before it are dropped and counted; diagnostics say which
// transform is missing). The extrinsics are constant afterwards (the estimator assumes a rigid
// mounting). With extrinsics from the config, publish_extrinsics_tf broadcasts them as a static
// TF imu_frame -> radar_frame (what CoralNodelet needs to pose the scans; Debian's ROS has no
// static_transform_publisher).
// Refuse, don't guess: a configuration error (an unknown private parameter or config key,
// missing extrinsics, an invalid value) fails the load (onInit throws, as CoralNodelet); refused
// input (scans without the radial-velocity field, IMU units that cannot be right) gives no odometry
// and an ERROR in the diagnostics with the reason. heap_release_interval (s, default 10, 0 = off):
// as CoralNodelet, the allocator's free pages go back to the system at most that often.
#pragma once

#include <diagnostic_updater/diagnostic_updater.h>
#include <nav_msgs/Path.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <sensor_msgs/FluidPressure.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/Header.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "coral_introspection/rio/estimator.hpp"
#include "coral_introspection/ros/heap_release.hpp"
#include "coral_introspection/ros/rio_input.hpp"

namespace coral_introspection {

class RioNodelet : public nodelet::Nodelet {
 private:
  struct Counters {
    long imu = 0, scans = 0, triggers = 0, baro = 0, frames = 0, tracked = 0, errors = 0;
    long waiting_for_extrinsics = 0;  // radar frames dropped before the TF extrinsics were known
  };

  void onInit() override;
  // Reads the private parameters (config_file, frames, ...; an unknown one is an error naming
  // the nearest valid name, as in the config file); the error, "" when valid.
  std::string readParameters(const ros::NodeHandle& pnh, std::string* config_file,
                             std::string* time_source, bool* publish_extrinsics_tf);
  // Reads the config file and checks the parameters; the error, "" when valid. time_source:
  // "" or an override of the file's ros/time_source.
  std::string loadConfig(const std::string& config_file, const std::string& time_source,
                         bool publish_extrinsics_tf, rio::RioConfig* cfg,
                         ros_adapters::RioInputConfig* in_cfg);
  template <class F>
  void guarded(const char* what, F&& f) noexcept;

  void imuCb(const sensor_msgs::ImuConstPtr& msg);
  void radarCb(const sensor_msgs::PointCloud2ConstPtr& msg);
  void triggerCb(const std_msgs::HeaderConstPtr& msg);
  void baroCb(const sensor_msgs::FluidPressureConstPtr& msg);
  // Called with mutex_ held.
  void handle(const std::vector<rio::FrameReport>& reports);
  void publish(const rio::FrameReport& r);
  void feedRadar(rio::RadarFrame f);
  // extrinsics_source tf: looks up imu_frame_ <- radar_frame; on success starts the estimator.
  void lookupExtrinsics(const std::string& radar_frame);
  void startEstimator();
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat);

  std::mutex mutex_;
  std::string odom_frame_ = "odom", base_frame_ = "base_link", radar_frame_ = "radar";
  std::string velocity_field_ = "velocity";
  double radar_time_offset_ = 0.0;
  rio::RioConfig cfg_;
  std::string extrinsics_source_ = "config", imu_frame_, extrinsics_from_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  std::unique_ptr<tf2_ros::StaticTransformBroadcaster> static_tf_;
  bool publish_tf_ = true;
  int max_path_length_ = 10000;
  std::unique_ptr<rio::Estimator> estimator_;  // null until the extrinsics are known
  std::unique_ptr<ros_adapters::RioInput> input_;
  Counters counters_;
  std::string last_problem_, last_message_;
  std::string scan_error_;  // why the newest radar scan was refused ("" when it was not)
  double heap_release_interval_ = 10.0;          // [s] steady; 0 = off
  ros_adapters::HeapReleaseTimer heap_release_;  // radar callback only (under mutex_)
  rio::FrameStatus last_status_ = rio::FrameStatus::kInitializing;
  nav_msgs::Path path_;  // emptied when the estimator restarts on a time jump back
  long time_jumps_seen_ = 0;

  ros::Subscriber imu_sub_, radar_sub_, trigger_sub_, baro_sub_;
  ros::Publisher odom_pub_, path_pub_, landmarks_pub_, stamped_pub_;
  std::unique_ptr<tf2_ros::TransformBroadcaster> tf_;
  std::shared_ptr<diagnostic_updater::Updater> updater_;
  ros::WallTimer timer_;
};

}  // namespace coral_introspection
