// CoralNodelet: online CorAl introspection of consecutive scans (or scan vs keyframe).
// Thin: converts inputs with the adapters, pairs scans, calls the core, publishes.
#pragma once

#include <diagnostic_updater/diagnostic_updater.h>
#include <dynamic_reconfigure/server.h>
#include <message_filters/subscriber.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/message_filter.h>
#include <tf2_ros/transform_listener.h>

#include <boost/thread/recursive_mutex.hpp>
#include <map>
#include <memory>
#include <mutex>
#include <optional>

#include "coral_introspection/CheckAlignment.h"
#include "coral_introspection/CoralConfig.h"
#include "coral_introspection/VelocityConsistency.h"
#include "coral_introspection/online/pairing.hpp"
#include "coral_introspection/ros/params.hpp"
#include "coral_introspection/ros/scan_input.hpp"

namespace coral_introspection {

class CoralNodelet : public nodelet::Nodelet {
 public:
  CoralNodelet() = default;
  ~CoralNodelet() override;

 private:
  using ReconfigureConfig = coral_introspection::CoralConfig;  // generated from cfg/Coral.cfg

  // A scan ready for pairing: points in its sensor frame and the sensor pose.
  struct PosedScan {
    core::RadarFeatures features;  // points in the sensor frame (+ row stamps for radar)
    Eigen::Isometry3d T_fixed_sensor = Eigen::Isometry3d::Identity();
    ros::Time stamp;
    bool needs_deskew = false;  // radar scan not yet motion-compensated (no velocity known)
  };
  struct Counters {
    uint64_t received = 0, processed = 0, pairs = 0, valid_pairs = 0, misaligned = 0;
    uint64_t tf_failures = 0, bad_inputs = 0, non_finite_points = 0, time_resets = 0,
             duplicate_stamps = 0, gap_resets = 0, errors = 0;
    uint64_t doppler_checks = 0, doppler_inconsistent = 0;
    double latency_sum = 0.0, processing_sum = 0.0;  // [s] over processed scans / pairs
  };

  void onInit() override;

  // Runs f(); an exception of any kind is logged (throttled) and counted in the diagnostics
  // instead of escaping: an exception out of a callback would kill every nodelet in the
  // manager. The counter is taken under state_mutex_, after f's own locks were released.
  template <class F>
  void guarded(const char* what, F&& f) noexcept {
    try {
      std::string error;
      try {
        f();
        return;
      } catch (const std::exception& e) {
        error = e.what();
      } catch (...) {
        error = "unknown exception";
      }
      std::lock_guard<std::mutex> lock(state_mutex_);
      ++counters_.errors;
      last_error_ = std::string(what) + " failed: " + error;
      NODELET_ERROR_THROTTLE(5.0, "%s", last_error_.c_str());
    } catch (...) {  // logging itself failed (out of memory): nothing sensible left to do
    }
  }

  void connectCb();
  void reconfigureCb(ReconfigureConfig& config, uint32_t level);

  void cloudCb(const sensor_msgs::PointCloud2ConstPtr& msg);
  void imageCb(const sensor_msgs::ImageConstPtr& msg);
  void arrivedCb(const std_msgs::Header& header);
  void tfFailureCb(const std_msgs::Header& header, tf2_ros::FilterFailureReason reason);
  // Common path after conversion: TF pose, pairing, CorAl, publishing.
  void processScan(const std_msgs::Header& header, ros_adapters::SensorScan& scan);
  void publishVerdict(PosedScan& ref, const PosedScan& cur);
  void checkDoppler(const std_msgs::Header& header, const ros_adapters::SensorScan& scan,
                    const core::Vec3& velocity);
  void badInput(const std::string& what, const std::string& error);
  bool checkAlignment(CheckAlignment::Request& req, CheckAlignment::Response& res);

  void timerCb(const ros::WallTimerEvent&);
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat);

  ros_adapters::NodeConfig config_;  // guarded by state_mutex_ after onInit
  std::mutex state_mutex_;           // config_, pairing_, reference_, counters_
  online::ScanPairing pairing_;
  std::optional<PosedScan> reference_;
  std::optional<PosedScan> previous_;       // last scan with a pose (velocity for de-skewing)
  std::vector<core::Twist> recent_twists_;  // last <= 3 inter-scan velocities (de-skewing)
  Counters counters_, last_report_;
  ros::WallTime last_report_time_;
  std::string last_error_;
  // Scans waiting for TF: (frame, stamp) -> wall time of arrival (tf_timeout bookkeeping).
  std::map<std::pair<std::string, ros::Time>, ros::WallTime> pending_;

  std::shared_ptr<tf2_ros::Buffer> tf_buffer_;
  std::shared_ptr<tf2_ros::TransformListener> tf_listener_;
  message_filters::Subscriber<sensor_msgs::PointCloud2> cloud_sub_;
  message_filters::Subscriber<sensor_msgs::Image> image_sub_;
  std::shared_ptr<tf2_ros::MessageFilter<sensor_msgs::PointCloud2>> cloud_filter_;
  std::shared_ptr<tf2_ros::MessageFilter<sensor_msgs::Image>> image_filter_;

  std::mutex connect_mutex_;  // held across advertise so connectCb sees the publishers
  bool subscribed_ = false;
  ros::Publisher alignment_pub_, quality_pub_, features_pub_, doppler_pub_;
  ros::ServiceServer service_;
  ros::WallTimer timer_;
  std::shared_ptr<diagnostic_updater::Updater> updater_;
  boost::recursive_mutex reconfigure_mutex_;
  std::shared_ptr<dynamic_reconfigure::Server<ReconfigureConfig>> reconfigure_;
};

}  // namespace coral_introspection
