#include "coral_introspection/ros/coral_nodelet.hpp"

#include <tf2_eigen/tf2_eigen.h>
#include <pluginlib/class_list_macros.hpp>

#include <algorithm>
#include <sstream>

#include "coral_introspection/coral/classifier.hpp"
#include "coral_introspection/coral/coral.hpp"
#include "coral_introspection/ros/conversions.hpp"

namespace coral_introspection {

using online::PairAction;
using ros_adapters::InputType;

CoralNodelet::~CoralNodelet() {
  // Disconnect inputs before the filters they feed are destroyed.
  timer_.stop();
  cloud_sub_.unsubscribe();
  image_sub_.unsubscribe();
  cloud_filter_.reset();
  image_filter_.reset();
}

void CoralNodelet::onInit() {
  ros::NodeHandle& nh = getNodeHandle();
  ros::NodeHandle& pnh = getPrivateNodeHandle();

  // Whole private namespace at once: validation sees every key (typos are reported).
  XmlRpc::XmlRpcValue tree;
  pnh.getParam(pnh.getNamespace(), tree);
  std::string error;
  std::vector<std::string> warnings;
  if (!ros_adapters::loadNodeConfig(tree, &config_, &error, &warnings)) {
    NODELET_FATAL("invalid parameters in %s: %s", pnh.getNamespace().c_str(), error.c_str());
    throw std::runtime_error("CoralNodelet: invalid parameters: " + error);  // load fails
  }
  for (const auto& w : warnings) NODELET_WARN("%s", w.c_str());
  pairing_.setConfig(config_.pairing);

  tf_buffer_ = std::make_shared<tf2_ros::Buffer>();
  tf_listener_ = std::make_shared<tf2_ros::TransformListener>(*tf_buffer_, nh);
  const auto queue = static_cast<uint32_t>(config_.queue_size);
  if (config_.input_type == InputType::kPointCloud) {
    cloud_filter_ = std::make_shared<tf2_ros::MessageFilter<sensor_msgs::PointCloud2>>(
        cloud_sub_, *tf_buffer_, config_.fixed_frame, queue, nh);
    cloud_filter_->registerCallback(
        boost::bind(&CoralNodelet::cloudCb, this, boost::placeholders::_1));
    cloud_filter_->registerFailureCallback(
        boost::function<void(const sensor_msgs::PointCloud2ConstPtr&,
                             tf2_ros::FilterFailureReason)>(
            [this](const sensor_msgs::PointCloud2ConstPtr& m, tf2_ros::FilterFailureReason r) {
              tfFailureCb(m->header, r);
            }));
    cloud_sub_.registerCallback(boost::function<void(const sensor_msgs::PointCloud2ConstPtr&)>(
        [this](const sensor_msgs::PointCloud2ConstPtr& m) { arrivedCb(m->header); }));
  } else {
    image_filter_ = std::make_shared<tf2_ros::MessageFilter<sensor_msgs::Image>>(
        image_sub_, *tf_buffer_, config_.fixed_frame, queue, nh);
    image_filter_->registerCallback(
        boost::bind(&CoralNodelet::imageCb, this, boost::placeholders::_1));
    image_filter_->registerFailureCallback(
        boost::function<void(const sensor_msgs::ImageConstPtr&, tf2_ros::FilterFailureReason)>(
            [this](const sensor_msgs::ImageConstPtr& m, tf2_ros::FilterFailureReason r) {
              tfFailureCb(m->header, r);
            }));
    image_sub_.registerCallback(boost::function<void(const sensor_msgs::ImageConstPtr&)>(
        [this](const sensor_msgs::ImageConstPtr& m) { arrivedCb(m->header); }));
  }

  updater_ = std::make_shared<diagnostic_updater::Updater>(nh, pnh, getName());
  updater_->setHardwareID("coral_introspection");
  updater_->add("CorAl alignment", this, &CoralNodelet::diagnose);
  last_report_time_ = ros::WallTime::now();
  timer_ = nh.createWallTimer(ros::WallDuration(1.0), &CoralNodelet::timerCb, this);

  reconfigure_ =
      std::make_shared<dynamic_reconfigure::Server<ReconfigureConfig>>(reconfigure_mutex_, pnh);
  ReconfigureConfig rc;  // start from the YAML values, not the .cfg defaults
  rc.classifier_threshold = config_.classifier.threshold;
  rc.coral_radius = config_.coral.radius;
  rc.coral_min_overlap = config_.coral.min_overlap;
  rc.publish_quality_cloud = config_.publish_quality_cloud;
  rc.publish_features = config_.publish_features;
  reconfigure_->updateConfig(rc);
  reconfigure_->setCallback(boost::bind(&CoralNodelet::reconfigureCb, this, boost::placeholders::_1,
                                        boost::placeholders::_2));

  service_ = nh.advertiseService("check_alignment", &CoralNodelet::checkAlignment, this);
  {
    // Held across advertise: connectCb (run from another thread as soon as a subscriber
    // appears) must see the assigned publishers (pointcloud_to_laserscan pattern).
    std::lock_guard<std::mutex> lock(connect_mutex_);
    const auto cb = boost::bind(&CoralNodelet::connectCb, this);
    alignment_pub_ = nh.advertise<AlignmentQuality>("alignment", 10, cb, cb);
    quality_pub_ = nh.advertise<sensor_msgs::PointCloud2>("quality_cloud", 2, cb, cb);
    features_pub_ = nh.advertise<sensor_msgs::PointCloud2>("features", 2, cb, cb);
    if (config_.doppler.enabled)
      doppler_pub_ = nh.advertise<VelocityConsistency>("velocity_consistency", 10, cb, cb);
  }
  NODELET_INFO(
      "CoralNodelet: input %s on '%s', fixed frame '%s', CorAl %dD r = %.2f m",
      config_.input_type == InputType::kPointCloud ? "pointcloud" : "polar_image",
      nh.resolveName(config_.input_type == InputType::kPointCloud ? "scan" : "polar_image").c_str(),
      config_.fixed_frame.c_str(), config_.coral.dimension, config_.coral.radius);
}

// Input is subscribed only while someone listens to an output (lazy, like
// pointcloud_to_laserscan); the pairing restarts after a gap in subscribers.
void CoralNodelet::connectCb() {
  guarded("connect callback", [&] {
    std::lock_guard<std::mutex> lock(connect_mutex_);
    const bool wanted = alignment_pub_.getNumSubscribers() + quality_pub_.getNumSubscribers() +
                            features_pub_.getNumSubscribers() +
                            (doppler_pub_ ? doppler_pub_.getNumSubscribers() : 0) >
                        0;
    if (wanted == subscribed_) return;
    const auto queue = static_cast<uint32_t>(config_.queue_size);
    if (wanted) {
      if (cloud_filter_) cloud_sub_.subscribe(getNodeHandle(), "scan", queue);
      if (image_filter_) image_sub_.subscribe(getNodeHandle(), "polar_image", queue);
      NODELET_DEBUG("output subscribed: subscribing to input");
    } else {
      cloud_sub_.unsubscribe();
      image_sub_.unsubscribe();
      std::lock_guard<std::mutex> state(state_mutex_);
      pairing_.reset();
      reference_.reset();
      previous_.reset();
      recent_twists_.clear();
    }
    subscribed_ = wanted;
  });
}

void CoralNodelet::reconfigureCb(ReconfigureConfig& rc, uint32_t) {
  guarded("dynamic_reconfigure callback", [&] {
    std::lock_guard<std::mutex> lock(state_mutex_);
    ros_adapters::NodeConfig c = config_;
    c.classifier.threshold = rc.classifier_threshold;
    c.coral.radius = rc.coral_radius;
    c.coral.min_overlap = rc.coral_min_overlap;
    c.publish_quality_cloud = rc.publish_quality_cloud;
    c.publish_features = rc.publish_features;
    const std::string err = c.validate();
    if (!err.empty()) {
      NODELET_WARN("dynamic_reconfigure change rejected: %s", err.c_str());
      return;
    }
    config_ = c;
  });
}

void CoralNodelet::arrivedCb(const std_msgs::Header& header) {
  guarded("arrival callback", [&] {
    std::lock_guard<std::mutex> lock(state_mutex_);
    ++counters_.received;
    pending_.emplace(std::make_pair(header.frame_id, header.stamp), ros::WallTime::now());
  });
}

void CoralNodelet::tfFailureCb(const std_msgs::Header& header,
                               tf2_ros::FilterFailureReason reason) {
  guarded("TF failure callback", [&] {
    std::lock_guard<std::mutex> lock(state_mutex_);
    // A scan that already timed out in timerCb was counted there.
    if (pending_.erase(std::make_pair(header.frame_id, header.stamp)) == 0) return;
    std::ostringstream e;
    if (reason == tf2_ros::filter_failure_reasons::EmptyFrameID) {
      ++counters_.bad_inputs;
      e << "scan at t = " << header.stamp << " has an empty frame_id";
    } else {
      ++counters_.tf_failures;
      e << "no transform " << config_.fixed_frame << " <- '" << header.frame_id
        << "' at t = " << header.stamp
        << (reason == tf2_ros::filter_failure_reasons::OutTheBack
                ? " (older than the TF buffer: extrapolation into the past)"
                : " (dropped from the TF queue while waiting)");
    }
    last_error_ = e.str();
    NODELET_WARN_THROTTLE(5.0, "scan dropped: %s", last_error_.c_str());
  });
}

void CoralNodelet::badInput(const std::string& what, const std::string& error) {
  ++counters_.bad_inputs;
  last_error_ = what + ": " + error;
  NODELET_WARN_THROTTLE(5.0, "bad input dropped: %s", last_error_.c_str());
}

void CoralNodelet::cloudCb(const sensor_msgs::PointCloud2ConstPtr& msg) {
  guarded("cloud callback", [&] {
    std::lock_guard<std::mutex> lock(state_mutex_);
    pending_.erase(std::make_pair(msg->header.frame_id, msg->header.stamp));
    ros_adapters::SensorScan scan;
    std::string error;
    if (!ros_adapters::cloudToSensorScan(*msg, config_, &scan, &error)) {
      badInput("cloud in '" + msg->header.frame_id + "'", error);
      return;
    }
    if (scan.dropped_non_finite > 0) {
      counters_.non_finite_points += scan.dropped_non_finite;
      NODELET_WARN_THROTTLE(10.0, "dropped %zu NaN/Inf points of a cloud", scan.dropped_non_finite);
    }
    if (scan.features.points.empty()) {
      badInput("cloud at t = " + std::to_string(msg->header.stamp.toSec()),
               scan.dropped_non_finite > 0 ? "only NaN/Inf points" : "empty cloud (0 points)");
      return;
    }
    processScan(msg->header, scan);
  });
}

void CoralNodelet::imageCb(const sensor_msgs::ImageConstPtr& msg) {
  guarded("image callback", [&] {
    std::lock_guard<std::mutex> lock(state_mutex_);
    pending_.erase(std::make_pair(msg->header.frame_id, msg->header.stamp));
    ros_adapters::SensorScan scan;
    std::string error;
    if (!ros_adapters::imageToSensorScan(*msg, config_, &scan, &error)) {
      badInput("polar image in '" + msg->header.frame_id + "'", error);
      return;
    }
    if (scan.features.points.empty()) {
      badInput("polar image at t = " + std::to_string(msg->header.stamp.toSec()),
               "no RIP features (check rip/z_min and the image)");
      return;
    }
    processScan(msg->header, scan);
  });
}

// Called with state_mutex_ held.
void CoralNodelet::processScan(const std_msgs::Header& header, ros_adapters::SensorScan& scan) {
  PosedScan cur;
  cur.stamp = header.stamp;
  try {
    cur.T_fixed_sensor = tf2::transformToEigen(
        tf_buffer_->lookupTransform(config_.fixed_frame, header.frame_id, header.stamp));
  } catch (const tf2::TransformException& e) {
    ++counters_.tf_failures;
    last_error_ = e.what();
    NODELET_WARN_THROTTLE(5.0, "TF lookup failed: %s", e.what());
    return;
  }
  const PairAction action = pairing_.offer(cur.stamp.toSec(), cur.T_fixed_sensor.translation());
  const bool reset = action == PairAction::kFirst || action == PairAction::kGapReset ||
                     action == PairAction::kBackwardsReset || action == PairAction::kDuplicateReset;
  // Sensor velocity over the last interval, only within one unbroken sequence.
  core::Twist twist;
  const bool have_twist =
      !reset && previous_ && cur.stamp > previous_->stamp &&
      ros_adapters::twistBetween(previous_->T_fixed_sensor, cur.T_fixed_sensor,
                                 (cur.stamp - previous_->stamp).toSec(), &twist);
  // Radar: de-skew with the velocity of the last interval (paper Sec. V-A). The first scan
  // of a sequence is de-skewed later, with the velocity towards the scan it is paired with.
  if (reset) recent_twists_.clear();
  if (have_twist) {
    recent_twists_.push_back(twist);
    if (recent_twists_.size() > 3) recent_twists_.erase(recent_twists_.begin());
  }
  if (scan.is_radar && config_.motion_compensation) {
    if (have_twist)
      core::compensateMotion(ros_adapters::robustTwist(recent_twists_), cur.stamp.toSec(),
                             &scan.features);
    else
      cur.needs_deskew = true;
  }
  // Doppler (4D radar clouds): the odometry's velocity must explain the radial velocities.
  if (config_.doppler.enabled && have_twist && !scan.radial_velocity.empty())
    checkDoppler(header, scan, twist.linear);
  if (scan.is_radar && config_.publish_features && features_pub_.getNumSubscribers() > 0)
    features_pub_.publish(
        ros_adapters::pointsToCloud(scan.features.points, header, &scan.features.intensity));
  ++counters_.processed;
  counters_.latency_sum += std::max(0.0, (ros::Time::now() - header.stamp).toSec());

  cur.features = std::move(scan.features);
  switch (action) {
    case PairAction::kPair:
      publishVerdict(*reference_, cur);
      break;
    case PairAction::kBackwardsReset:
      ++counters_.time_resets;
      NODELET_WARN_THROTTLE(5.0,
                            "time jumped backwards (%.3f s -> %.3f s, looping bag?): "
                            "pairing restarts",
                            reference_->stamp.toSec(), cur.stamp.toSec());
      break;
    case PairAction::kDuplicateReset:
      ++counters_.duplicate_stamps;
      NODELET_WARN_THROTTLE(5.0, "two scans with stamp %.6f s: pairing restarts",
                            cur.stamp.toSec());
      break;
    case PairAction::kGapReset:
      ++counters_.gap_resets;
      NODELET_INFO_THROTTLE(10.0,
                            "reference scan older than pairing/max_time_gap = %.2f s: "
                            "restarting pairing",
                            config_.pairing.max_time_gap);
      break;
    default:
      break;
  }
  if (action != PairAction::kTooClose) reference_ = cur;
  previous_ = std::move(cur);
}

// Called with state_mutex_ held.
void CoralNodelet::publishVerdict(PosedScan& ref, const PosedScan& cur) {
  if (ref.needs_deskew) {  // first radar scan of a sequence: velocity towards cur
    core::Twist twist;
    if (ros_adapters::twistBetween(ref.T_fixed_sensor, cur.T_fixed_sensor,
                                   (cur.stamp - ref.stamp).toSec(), &twist))
      core::compensateMotion(twist, ref.stamp.toSec(), &ref.features);
    ref.needs_deskew = false;
  }
  core::Scan a, b;
  a.points = ref.features.points;
  b.points = cur.features.points;
  a = core::transformScan(a, ref.T_fixed_sensor);  // origin = sensor position (fixed frame)
  b = core::transformScan(b, cur.T_fixed_sensor);
  const bool want_cloud = config_.publish_quality_cloud && quality_pub_.getNumSubscribers() > 0;
  core::CoralConfig cc = config_.coral;
  cc.per_point = want_cloud;
  const core::CoralResult result = core::computeCoral(a, b, cc);
  core::Verdict verdict;
  if (result.valid) verdict = core::classify(config_.classifier, result.h_joint, result.h_sep);
  std_msgs::Header header;
  header.stamp = cur.stamp;
  header.frame_id = config_.fixed_frame;
  alignment_pub_.publish(ros_adapters::toMessage(result, verdict, header, ref.stamp, cur.stamp));
  ++counters_.pairs;
  counters_.processing_sum += result.seconds;
  if (result.valid) {
    ++counters_.valid_pairs;
    if (!verdict.aligned) ++counters_.misaligned;
  }
  if (want_cloud) quality_pub_.publish(ros_adapters::buildQualityCloud(a, b, result, header));
}

// Called with state_mutex_ held. velocity: sensor velocity from TF, current sensor frame.
void CoralNodelet::checkDoppler(const std_msgs::Header& header,
                                const ros_adapters::SensorScan& scan, const core::Vec3& velocity) {
  const core::ConsistencyResult r = core::checkVelocityConsistency(
      scan.features.points, scan.radial_velocity, velocity, config_.doppler.check);
  VelocityConsistency m;
  m.header = header;
  m.valid = r.valid;
  m.consistent = r.valid && r.consistent;
  m.chi2 = r.chi2;
  m.threshold = r.threshold;
  m.dof = static_cast<uint32_t>(std::max(0, r.dof));
  m.velocity_odometry.x = velocity.x();
  m.velocity_odometry.y = velocity.y();
  m.velocity_odometry.z = velocity.z();
  m.velocity_doppler.x = r.velocity_doppler.x();
  m.velocity_doppler.y = r.velocity_doppler.y();
  m.velocity_doppler.z = r.velocity_doppler.z();
  m.num_points = static_cast<uint32_t>(scan.radial_velocity.size());
  m.num_inliers = static_cast<uint32_t>(r.num_inliers);
  m.inlier_ratio = m.num_points > 0 ? static_cast<double>(m.num_inliers) / m.num_points : 0.0;
  doppler_pub_.publish(m);
  ++counters_.doppler_checks;
  if (r.valid && !r.consistent) ++counters_.doppler_inconsistent;
  if (!r.valid) NODELET_DEBUG("Doppler check invalid: %s", r.error.c_str());
}

bool CoralNodelet::checkAlignment(CheckAlignment::Request& req, CheckAlignment::Response& res) {
  bool answered = false;  // false fails the call: malformed request or internal error
  guarded("check_alignment", [&] {
    ros_adapters::NodeConfig cfg;
    {
      std::lock_guard<std::mutex> lock(state_mutex_);
      cfg = config_;
    }
    const bool clouds = !req.cloud_a.fields.empty() || !req.cloud_b.fields.empty();
    ros_adapters::SensorScan sa, sb;
    std::string error;
    Eigen::Isometry3d T_a_b;
    bool ok = clouds ? ros_adapters::cloudToSensorScan(req.cloud_a, cfg, &sa, &error) &&
                           ros_adapters::cloudToSensorScan(req.cloud_b, cfg, &sb, &error)
                     : ros_adapters::imageToSensorScan(req.image_a, cfg, &sa, &error) &&
                           ros_adapters::imageToSensorScan(req.image_b, cfg, &sb, &error);
    ok = ok && ros_adapters::toEigen(req.transform_a_b, &T_a_b, &error);
    if (!ok) {
      std::lock_guard<std::mutex> lock(state_mutex_);
      badInput("check_alignment request", error);
      return;
    }
    core::Scan a, b;
    a.points = std::move(sa.features.points);
    b.points = std::move(sb.features.points);
    b = core::transformScan(b, T_a_b);  // into a's sensor frame; origin = b's sensor position
    core::CoralConfig cc = cfg.coral;
    cc.per_point = false;
    const core::CoralResult result = core::computeCoral(a, b, cc);
    core::Verdict verdict;
    if (result.valid) verdict = core::classify(cfg.classifier, result.h_joint, result.h_sep);
    std_msgs::Header header = clouds ? req.cloud_a.header : req.image_a.header;
    res.result =
        ros_adapters::toMessage(result, verdict, header, header.stamp,
                                clouds ? req.cloud_b.header.stamp : req.image_b.header.stamp);
    answered = true;
  });
  return answered;
}

void CoralNodelet::timerCb(const ros::WallTimerEvent&) {
  guarded("diagnostics timer", [&] {
    {
      std::lock_guard<std::mutex> lock(state_mutex_);
      const ros::WallTime now = ros::WallTime::now();
      for (auto it = pending_.begin(); it != pending_.end();) {
        if ((now - it->second).toSec() <= config_.tf_timeout) {
          ++it;
          continue;
        }
        ++counters_.tf_failures;
        std::ostringstream e;
        e << "no transform " << config_.fixed_frame << " <- '" << it->first.first
          << "' at t = " << it->first.second << " within tf_timeout = " << config_.tf_timeout
          << " s";
        last_error_ = e.str();
        NODELET_WARN_THROTTLE(5.0, "%s", last_error_.c_str());
        it = pending_.erase(it);
      }
    }
    updater_->force_update();
  });
}

void CoralNodelet::diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  std::lock_guard<std::mutex> lock(state_mutex_);
  const Counters& c = counters_;
  const Counters& l = last_report_;
  const ros::WallTime now = ros::WallTime::now();
  const double dt = std::max(1e-3, (now - last_report_time_).toSec());
  const uint64_t processed = c.processed - l.processed, pairs = c.pairs - l.pairs;
  const uint64_t new_problems = (c.tf_failures - l.tf_failures) + (c.bad_inputs - l.bad_inputs) +
                                (c.errors - l.errors) + (c.time_resets - l.time_resets) +
                                (c.duplicate_stamps - l.duplicate_stamps);
  const double frac = c.valid_pairs > 0 ? static_cast<double>(c.misaligned) / c.valid_pairs : 0.0;
  if (new_problems > 0)
    stat.summaryf(diagnostic_msgs::DiagnosticStatus::WARN, "%lu input problem(s): %s",
                  static_cast<unsigned long>(new_problems), last_error_.c_str());
  else if (c.received == 0)
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "waiting for scans");
  else
    stat.summaryf(diagnostic_msgs::DiagnosticStatus::OK, "%.1f %% of pairs misaligned",
                  100.0 * frac);
  stat.add("rate [scans/s]", processed / dt);
  stat.add("latency [s]", processed > 0 ? (c.latency_sum - l.latency_sum) / processed : 0.0);
  stat.add("processing time [s]", pairs > 0 ? (c.processing_sum - l.processing_sum) / pairs : 0.0);
  stat.add("scans received", c.received);
  stat.add("scans processed", c.processed);
  stat.add("pairs", c.pairs);
  stat.add("valid pairs", c.valid_pairs);
  stat.add("misaligned pairs", c.misaligned);
  stat.add("fraction misaligned", frac);
  stat.add("tf failures", c.tf_failures);
  stat.add("bad inputs", c.bad_inputs);
  stat.add("non-finite points dropped", c.non_finite_points);
  stat.add("time jumps backwards", c.time_resets);
  stat.add("duplicate stamps", c.duplicate_stamps);
  stat.add("reference too old", c.gap_resets);
  stat.add("callback errors", c.errors);
  if (config_.doppler.enabled) {
    stat.add("doppler checks", c.doppler_checks);
    stat.add("doppler inconsistent", c.doppler_inconsistent);
  }
  stat.add("last error", last_error_);
  last_report_ = c;
  last_report_time_ = now;
}

}  // namespace coral_introspection

PLUGINLIB_EXPORT_CLASS(coral_introspection::CoralNodelet, nodelet::Nodelet)
