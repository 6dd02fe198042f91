#include "coral_introspection/ros/rio_nodelet.hpp"

#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Odometry.h>
#include <pluginlib/class_list_macros.hpp>

#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "coral_introspection/config/yaml_tree.hpp"
#include "coral_introspection/rio/config_yaml.hpp"
#include "coral_introspection/ros/conversions.hpp"
#include "coral_introspection/ros/xmlrpc_tree.hpp"

namespace coral_introspection {

template <class F>
void RioNodelet::guarded(const char* what, F&& f) noexcept {
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
    std::lock_guard<std::mutex> lock(mutex_);
    ++counters_.errors;
    last_problem_ = std::string(what) + " failed: " + error;
    NODELET_ERROR_THROTTLE(5.0, "%s", last_problem_.c_str());
  } catch (...) {
  }
}

std::string RioNodelet::readParameters(const ros::NodeHandle& pnh, std::string* config_file,
                                       std::string* time_source, bool* publish_extrinsics_tf) {
  XmlRpc::XmlRpcValue params;
  pnh.getParam(pnh.getNamespace(), params);
  config::ParamTree tree;
  std::string err;
  if (!ros_adapters::fromXmlRpc(params, &tree, &err)) return err;
  // Not ours but legitimately here: diagnostic_updater's ~diagnostic_period, and
  // nodelet::Loader's ~num_worker_threads (`nodelet standalone` shares the namespace).
  tree.accept("diagnostic_period");
  tree.accept("num_worker_threads");
  std::string imu_frame;  // default: base_frame
  const bool ok =
      tree.get("config_file", config_file) && tree.get("odom_frame", &odom_frame_) &&
      tree.get("base_frame", &base_frame_) && tree.get("radar_frame", &radar_frame_) &&
      tree.get("publish_tf", &publish_tf_) && tree.get("max_path_length", &max_path_length_) &&
      tree.get("extrinsics_source", &extrinsics_source_) && tree.get("imu_frame", &imu_frame) &&
      tree.get("heap_release_interval", &heap_release_interval_) &&
      tree.get("publish_extrinsics_tf", publish_extrinsics_tf) &&
      tree.get("time_source", time_source);
  imu_frame_ = tree.has("imu_frame") ? imu_frame : base_frame_;
  return ok ? tree.unknownKeysMessage() : tree.error();
}

std::string RioNodelet::loadConfig(const std::string& config_file, const std::string& time_source,
                                   bool publish_extrinsics_tf, rio::RioConfig* cfg,
                                   ros_adapters::RioInputConfig* in_cfg) {
  if (config_file.empty()) return "parameter ~config_file is required (a rio YAML file)";
  config::ParamTree tree;
  std::string err;
  // With extrinsics from TF the file need not (and should not) give them.
  rio::RioConfigRules rules{{"ros"}, extrinsics_source_ == "config"};
  // The messages rio_offline prints, naming file and line ("file:line: unknown group ...").
  if (!(config::loadYamlFile(config_file, &tree, &err) &&
        rio::loadRioConfig(tree, cfg, &err, rules) &&
        ros_adapters::loadRioInputConfig(tree, in_cfg, &err)))
    return "invalid config_file: " + err;
  if (!time_source.empty()) {  // optional override of the config's ros/time_source
    in_cfg->time_source = time_source;
    if (!(err = in_cfg->validate()).empty()) return "~time_source: " + err;
  }
  if (odom_frame_.empty() || base_frame_.empty() || max_path_length_ < 1)
    return "odom_frame and base_frame must be set and max_path_length >= 1";
  if (extrinsics_source_ != "config" && extrinsics_source_ != "tf")
    return "extrinsics_source must be config or tf, got '" + extrinsics_source_ + "'";
  if (imu_frame_.empty() || radar_frame_.empty()) return "imu_frame and radar_frame must be set";
  if (extrinsics_source_ == "tf" && publish_extrinsics_tf)
    return "publish_extrinsics_tf needs extrinsics_source config (with tf they come from TF)";
  if (extrinsics_source_ == "tf" && tree.has("extrinsics"))
    NODELET_WARN("extrinsics_source tf: the extrinsics of %s are not used", config_file.c_str());
  if (!(heap_release_interval_ >= 0.0 && heap_release_interval_ <= 3600.0))
    return "heap_release_interval must be in [0, 3600] s, 0 = off (got " +
           std::to_string(heap_release_interval_) + ")";
  return "";
}

void RioNodelet::onInit() {
  ros::NodeHandle& nh = getNodeHandle();
  ros::NodeHandle& pnh = getPrivateNodeHandle();
  std::string config_file, time_source;
  bool publish_extrinsics_tf = false;
  rio::RioConfig cfg;
  ros_adapters::RioInputConfig in_cfg;
  std::string err = readParameters(pnh, &config_file, &time_source, &publish_extrinsics_tf);
  if (err.empty()) err = loadConfig(config_file, time_source, publish_extrinsics_tf, &cfg, &in_cfg);
  if (!err.empty()) {
    // As CoralNodelet: a configuration error fails the load (the manager reports it), rather
    // than a loaded nodelet that does nothing.
    NODELET_FATAL("%s", err.c_str());
    throw std::runtime_error("RioNodelet: " + err);
  }
  updater_ = std::make_shared<diagnostic_updater::Updater>(nh, pnh);
  updater_->setHardwareID("rio");
  // Several nodelets share the manager's node name: the task name says which one.
  updater_->add(getName() + ": radar-inertial odometry", this, &RioNodelet::diagnose);
  timer_ = pnh.createWallTimer(ros::WallDuration(1.0),
                               [this](const ros::WallTimerEvent&) { updater_->update(); });
  cfg_ = cfg;
  if (extrinsics_source_ == "config") {
    extrinsics_from_ = "config file";
    startEstimator();
    if (publish_extrinsics_tf) {
      geometry_msgs::TransformStamped t;
      t.header.stamp = ros::Time::now();
      t.header.frame_id = imu_frame_;
      t.child_frame_id = radar_frame_;
      t.transform.translation.x = cfg_.extrinsics.t.x();
      t.transform.translation.y = cfg_.extrinsics.t.y();
      t.transform.translation.z = cfg_.extrinsics.t.z();
      const Eigen::Quaterniond q(cfg_.extrinsics.R);
      t.transform.rotation.x = q.x();
      t.transform.rotation.y = q.y();
      t.transform.rotation.z = q.z();
      t.transform.rotation.w = q.w();
      static_tf_ = std::make_unique<tf2_ros::StaticTransformBroadcaster>();
      static_tf_->sendTransform(t);
    }
  } else {
    tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
    tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_);
  }
  input_ = std::make_unique<ros_adapters::RioInput>(in_cfg);
  path_.header.frame_id = odom_frame_;
  velocity_field_ = in_cfg.velocity_field;
  radar_time_offset_ = cfg.radar_time_offset;
  tf_ = std::make_unique<tf2_ros::TransformBroadcaster>();

  odom_pub_ = nh.advertise<nav_msgs::Odometry>("odometry", 50);
  path_pub_ = nh.advertise<nav_msgs::Path>("path", 1);
  landmarks_pub_ = nh.advertise<sensor_msgs::PointCloud2>("landmarks", 1);
  stamped_pub_ = nh.advertise<sensor_msgs::PointCloud2>("radar_stamped", 10);
  // The odometry needs every input from the start: no lazy subscription of the inputs.
  imu_sub_ =
      nh.subscribe("imu", 2000, &RioNodelet::imuCb, this, ros::TransportHints().tcpNoDelay());
  radar_sub_ = nh.subscribe("radar", 50, &RioNodelet::radarCb, this);
  if (input_->usesTrigger())
    trigger_sub_ = nh.subscribe("trigger", 50, &RioNodelet::triggerCb, this);
  if (cfg.barometer.enabled)  // remap "baro" (the config's ros/baro_topic names the bag's)
    baro_sub_ = nh.subscribe("baro", 500, &RioNodelet::baroCb, this);
  NODELET_INFO("rio: config %s, radar time from %s, extrinsics from %s", config_file.c_str(),
               in_cfg.time_source.c_str(), extrinsics_source_.c_str());
}

void RioNodelet::startEstimator() {
  estimator_ = std::make_unique<rio::Estimator>(cfg_);
  estimator_->setComputeCovariance(true);
}

void RioNodelet::lookupExtrinsics(const std::string& radar_frame) {
  geometry_msgs::TransformStamped t;
  try {
    // Latest available: the mounting is rigid (a static transform in practice).
    t = tf_buffer_->lookupTransform(imu_frame_, radar_frame, ros::Time(0));
  } catch (const tf2::TransformException& e) {
    last_problem_ = "waiting for TF " + imu_frame_ + " <- " + radar_frame +
                    " (radar-to-IMU extrinsics; extrinsics_source tf): " + e.what();
    NODELET_WARN_THROTTLE(5.0, "%s", last_problem_.c_str());
    return;
  }
  std::string err;
  if (!ros_adapters::extrinsicsFromTransform(t.transform, &cfg_.extrinsics, &err) ||
      !(err = cfg_.validate()).empty()) {
    last_problem_ = "TF " + imu_frame_ + " <- " + radar_frame + ": " + err;
    NODELET_ERROR_THROTTLE(5.0, "%s", last_problem_.c_str());
    return;
  }
  extrinsics_from_ = "TF " + imu_frame_ + " <- " + radar_frame;
  NODELET_INFO("rio: extrinsics from %s: t = (%.4f, %.4f, %.4f) m", extrinsics_from_.c_str(),
               cfg_.extrinsics.t.x(), cfg_.extrinsics.t.y(), cfg_.extrinsics.t.z());
  startEstimator();
}

void RioNodelet::imuCb(const sensor_msgs::ImuConstPtr& msg) {
  guarded("IMU callback", [&] {
    std::lock_guard<std::mutex> lock(mutex_);
    ++counters_.imu;
    rio::ImuSample s;
    std::string err;
    if (!input_->imu(*msg, &s, &err)) {
      last_problem_ = err;
      NODELET_WARN_THROTTLE(5.0, "%s", err.c_str());
      return;
    }
    if (estimator_) handle(estimator_->addImu(s));
  });
}

void RioNodelet::baroCb(const sensor_msgs::FluidPressureConstPtr& msg) {
  guarded("barometer callback", [&] {
    std::lock_guard<std::mutex> lock(mutex_);
    ++counters_.baro;
    rio::BaroSample s;
    std::string err;
    if (!input_->baro(*msg, &s, &err)) {
      last_problem_ = err;
      NODELET_WARN_THROTTLE(5.0, "%s", err.c_str());
      return;
    }
    if (estimator_) estimator_->addBaro(s);
  });
}

void RioNodelet::radarCb(const sensor_msgs::PointCloud2ConstPtr& msg) {
  bool release_heap = false;
  guarded("radar callback", [&] {
    std::lock_guard<std::mutex> lock(mutex_);
    ++counters_.scans;
    std::string err;
    const long without_velocity = input_->counters().no_velocity_field;
    std::vector<rio::RadarFrame> frames = input_->radar(*msg, &err);
    // The newest scan says whether the radar input is refused (diagnostics: ERROR).
    scan_error_ = input_->counters().no_velocity_field > without_velocity ? err : "";
    if (!scan_error_.empty()) {
      last_problem_ = err;
      NODELET_ERROR_THROTTLE(5.0, "%s", err.c_str());
    } else if (!err.empty()) {
      last_problem_ = err;
      NODELET_WARN_THROTTLE(5.0, "%s", err.c_str());
    }
    if (!msg->header.frame_id.empty()) radar_frame_ = msg->header.frame_id;
    if (!estimator_) lookupExtrinsics(radar_frame_);
    for (rio::RadarFrame& f : frames) feedRadar(std::move(f));
    // Rate-limited, after the frame's solve (the large allocations: clouds, Ceres problems).
    release_heap = heap_release_.due(ros::SteadyTime::now().toSec(), heap_release_interval_);
  });
  // Outside the lock: the IMU callback does not wait for it (heap_release.hpp says why).
  if (release_heap) {
    const ros::SteadyTime start = ros::SteadyTime::now();
    const bool released = ros_adapters::releaseFreeHeap();
    NODELET_DEBUG("heap release (%s): %.3f ms", released ? "malloc_trim" : "unavailable",
                  (ros::SteadyTime::now() - start).toSec() * 1e3);
  }
}

void RioNodelet::triggerCb(const std_msgs::HeaderConstPtr& msg) {
  guarded("trigger callback", [&] {
    std::lock_guard<std::mutex> lock(mutex_);
    ++counters_.triggers;
    for (rio::RadarFrame& f : input_->trigger(*msg)) feedRadar(std::move(f));
  });
}

void RioNodelet::feedRadar(rio::RadarFrame f) {
  if (f.points.empty()) NODELET_WARN_THROTTLE(5.0, "empty radar scan at %.3f s", f.t);
  if (stamped_pub_.getNumSubscribers() > 0 && f.t + radar_time_offset_ > 0.0) {
    std_msgs::Header h;
    h.stamp = ros::Time(f.t + radar_time_offset_);
    h.frame_id = radar_frame_;
    stamped_pub_.publish(ros_adapters::radarFrameToCloud(f, h, velocity_field_));
  }
  if (!estimator_) {
    ++counters_.waiting_for_extrinsics;
    return;
  }
  handle(estimator_->addRadar(std::move(f)));
}

void RioNodelet::handle(const std::vector<rio::FrameReport>& reports) {
  if (estimator_->counters().time_jumps != time_jumps_seen_) {
    // The estimator restarted on a new sequence (time jumped back): so does the path, whose
    // poses would be of another time line (and would fill up to max_path_length).
    time_jumps_seen_ = estimator_->counters().time_jumps;
    path_.poses.clear();
  }
  for (const rio::FrameReport& r : reports) {
    ++counters_.frames;
    last_status_ = r.status;
    if (!r.message.empty()) {
      last_message_ = r.message;
      if (r.message == estimator_->inputError())  // refused input (IMU units)
        NODELET_ERROR_THROTTLE(5.0, "rio: %s: no odometry", r.message.c_str());
      else if (r.status == rio::FrameStatus::kReset || r.status == rio::FrameStatus::kRejected)
        NODELET_WARN_THROTTLE(2.0, "rio %s: %s", rio::toString(r.status), r.message.c_str());
    }
    if (r.status == rio::FrameStatus::kTracking || r.status == rio::FrameStatus::kReset) {
      ++counters_.tracked;
      publish(r);
    }
  }
}

void RioNodelet::publish(const rio::FrameReport& r) {
  const rio::NavState& s = r.state;
  const ros::Time stamp(s.t);
  const Eigen::Matrix3d R = s.q.toRotationMatrix();
  geometry_msgs::Pose pose;
  pose.position.x = s.p.x();
  pose.position.y = s.p.y();
  pose.position.z = s.p.z();
  pose.orientation.x = s.q.x();
  pose.orientation.y = s.q.y();
  pose.orientation.z = s.q.z();
  pose.orientation.w = s.q.w();
  if (publish_tf_) {
    geometry_msgs::TransformStamped t;
    t.header.stamp = stamp;
    t.header.frame_id = odom_frame_;
    t.child_frame_id = base_frame_;
    t.transform.translation.x = s.p.x();
    t.transform.translation.y = s.p.y();
    t.transform.translation.z = s.p.z();
    t.transform.rotation = pose.orientation;
    tf_->sendTransform(t);
  }
  if (odom_pub_.getNumSubscribers() > 0) {
    nav_msgs::Odometry o;
    o.header.stamp = stamp;
    o.header.frame_id = odom_frame_;
    o.child_frame_id = base_frame_;
    o.pose.pose = pose;
    const Eigen::Vector3d v_body = R.transpose() * s.v;  // ROS: twist in the child frame
    o.twist.twist.linear.x = v_body.x();
    o.twist.twist.linear.y = v_body.y();
    o.twist.twist.linear.z = v_body.z();
    if (r.has_covariance) {
      // Estimator order [dp (world), dtheta (body), dv (world), ...]; ROS wants the pose
      // covariance with the rotation about the parent's axes: dtheta_world = R dtheta_body.
      Eigen::Matrix<double, 6, 6> J = Eigen::Matrix<double, 6, 6>::Identity();
      J.bottomRightCorner<3, 3>() = R;
      const Eigen::Matrix<double, 6, 6> P = J * r.covariance.topLeftCorner<6, 6>() * J.transpose();
      const Eigen::Matrix3d V = R.transpose() * r.covariance.block<3, 3>(6, 6) * R;
      for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j) o.pose.covariance[6 * i + j] = P(i, j);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) o.twist.covariance[6 * i + j] = V(i, j);
      for (int i = 3; i < 6; ++i) o.twist.covariance[7 * i] = -1.0;  // angular rate: not given
    } else {
      o.pose.covariance[0] = -1.0;  // REP 145-style "unknown"
    }
    odom_pub_.publish(o);
  }
  geometry_msgs::PoseStamped ps;
  ps.header.stamp = stamp;
  ps.header.frame_id = odom_frame_;
  ps.pose = pose;
  path_.poses.push_back(ps);
  if (static_cast<int>(path_.poses.size()) > max_path_length_)
    path_.poses.erase(path_.poses.begin());
  if (path_pub_.getNumSubscribers() > 0) {
    path_.header.stamp = stamp;
    path_pub_.publish(path_);
  }
  if (landmarks_pub_.getNumSubscribers() > 0) {
    std_msgs::Header h;
    h.stamp = stamp;
    h.frame_id = odom_frame_;
    landmarks_pub_.publish(ros_adapters::pointsToCloud(estimator_->landmarkPositions(), h));
  }
}

void RioNodelet::diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  std::lock_guard<std::mutex> lock(mutex_);
  stat.add("extrinsics source", extrinsics_source_);
  stat.add("radar frames waiting for extrinsics", counters_.waiting_for_extrinsics);
  if (!estimator_) {
    if (!scan_error_.empty())
      stat.summary(diagnostic_msgs::DiagnosticStatus::ERROR, "input refused: " + scan_error_);
    else
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN,
                   "waiting for TF " + imu_frame_ + " <- " + radar_frame_ +
                       " (radar-to-IMU extrinsics): the odometry starts when it appears");
    stat.add("imu messages", counters_.imu);
    stat.add("radar messages", counters_.scans);
    stat.add("last problem", last_problem_);
    return;
  }
  {
    const Eigen::Quaterniond q(cfg_.extrinsics.R);
    std::ostringstream ts, qs;
    ts << std::setprecision(6) << cfg_.extrinsics.t.x() << ' ' << cfg_.extrinsics.t.y() << ' '
       << cfg_.extrinsics.t.z();
    qs << std::setprecision(6) << q.x() << ' ' << q.y() << ' ' << q.z() << ' ' << q.w();
    stat.add("extrinsics from", extrinsics_from_);
    stat.add("extrinsics translation [m]", ts.str());
    stat.add("extrinsics rotation [qx qy qz qw]", qs.str());
  }
  const rio::RioCounters& c = estimator_->counters();
  const ros_adapters::RioInputCounters& ic = input_->counters();
  // Refused input first: nothing else the odometry says is worth reading then.
  if (!estimator_->inputError().empty())
    stat.summary(diagnostic_msgs::DiagnosticStatus::ERROR,
                 "input refused, no odometry: " + estimator_->inputError());
  else if (!scan_error_.empty())
    stat.summary(diagnostic_msgs::DiagnosticStatus::ERROR, "input refused: " + scan_error_);
  else if (counters_.imu == 0 || counters_.scans == 0)
    stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "waiting for IMU and radar input");
  else if (last_status_ == rio::FrameStatus::kInitializing)
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "initialising: " + last_message_);
  else if (last_status_ == rio::FrameStatus::kReset || last_status_ == rio::FrameStatus::kRejected)
    stat.summary(diagnostic_msgs::DiagnosticStatus::WARN,
                 std::string(rio::toString(last_status_)) + ": " + last_message_);
  else
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "tracking");
  stat.add("imu messages", counters_.imu);
  stat.add("radar messages", counters_.scans);
  stat.add("trigger messages", counters_.triggers);
  stat.add("barometer messages", counters_.baro);
  stat.add("frames with a barometer residual", c.baro_frames);
  stat.add("bad barometer messages", ic.bad_baro + c.bad_baro);
  stat.add("frames", counters_.frames);
  stat.add("tracked frames", counters_.tracked);
  stat.add("resets", c.resets);
  stat.add("failed solves", c.failed_solves);
  stat.add("rejected frames", c.rejected_frames);
  stat.add("imu gaps", c.imu_gaps);
  stat.add("imu gaps bridged with Doppler", c.gap_bridged);
  stat.add("time jumps back", c.time_jumps);
  stat.add("imu out of order", c.imu_out_of_order);
  stat.add("empty scans", c.empty_scans);
  stat.add("scans without radial velocity", ic.no_velocity_field);
  stat.add("bad clouds", ic.bad_clouds);
  stat.add("bad imu messages", ic.bad_imu);
  stat.add("scans without trigger", ic.unmatched_scans);
  stat.add("trigger sequence restarts", input_->triggerRestarts());
  stat.add("standing frames", c.standing_frames);
  // t_d: the estimate (time_offset/estimate) or the configured radar_time_offset.
  stat.add("radar time offset [s]", estimator_->timeOffset());
  stat.add("radar time offset", estimator_->config().time_offset.estimate
                                    ? "estimated (prior: radar_time_offset)"
                                    : "configured (radar_time_offset)");
  stat.add("frames with the time offset at its bound", c.offset_at_bound);
  stat.add("callback errors", counters_.errors);
  stat.add("input error", estimator_->inputError());
  stat.add("last problem", last_problem_);
}

}  // namespace coral_introspection

PLUGINLIB_EXPORT_CLASS(coral_introspection::RioNodelet, nodelet::Nodelet)
