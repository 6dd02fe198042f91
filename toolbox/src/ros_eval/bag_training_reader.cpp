#include "coral_introspection/ros_eval/bag_training_reader.hpp"

#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2/buffer_core.h>
#include <tf2/exceptions.h>
#include <tf2_msgs/TFMessage.h>

#include <sstream>

#include "coral_introspection/eval/oxford_training.hpp"
#include "coral_introspection/radar/deskew.hpp"
#include "coral_introspection/ros/conversions.hpp"
#include "coral_introspection/ros/coral_scan_input.hpp"

namespace coral_introspection {
namespace ros_eval {

std::string BagTrainingOptions::validate() const {
  std::ostringstream e;
  if (scan_topic.empty()) e << "scan_topic must not be empty; ";
  if (fixed_frame.empty()) e << "fixed_frame must not be empty; ";
  if (cfear_k < 1) e << "cfear_k must be >= 1 (got " << cfear_k << "); ";
  if (max_scans < 0) e << "max_scans must be >= 0 (got " << max_scans << "); ";
  if (const std::string n = node.validate(); !n.empty()) e << n << "; ";
  std::string s = e.str();
  if (!s.empty()) s.resize(s.size() - 2);
  return s;
}

namespace {

struct RawScan {
  eval::TrainingScan scan;
  radar::RadarFeatures rip, kstrong;  // radar images: features with per-point stamps
  double kstrong_ref = 0.0;           // reference stamp of kstrong (embedded clock)
  bool is_image = false;
  Eigen::Isometry3d T_fixed_sensor = Eigen::Isometry3d::Identity();
};

// Pass 1: every transform (tf, tf_static, odometry) into one buffer spanning the bag.
void fillBuffer(rosbag::Bag& bag, const BagTrainingOptions& o, tf2::BufferCore* buffer) {
  rosbag::View view(
      bag, rosbag::TopicQuery(std::vector<std::string>{"/tf", "/tf_static", o.odom_topic}));
  for (const rosbag::MessageInstance& m : view) {
    if (auto tf = m.instantiate<tf2_msgs::TFMessage>()) {
      const bool is_static = m.getTopic() == "/tf_static";
      for (const auto& t : tf->transforms) buffer->setTransform(t, "bag", is_static);
    } else if (auto od = m.instantiate<nav_msgs::Odometry>()) {
      geometry_msgs::TransformStamped t;
      t.header = od->header;
      t.child_frame_id = od->child_frame_id;
      t.transform.translation.x = od->pose.pose.position.x;
      t.transform.translation.y = od->pose.pose.position.y;
      t.transform.translation.z = od->pose.pose.position.z;
      t.transform.rotation = od->pose.pose.orientation;
      buffer->setTransform(t, "odometry", false);
    }
  }
}

bool readScan(const rosbag::MessageInstance& m, const BagTrainingOptions& o, RawScan* out,
              std::string* frame, ros::Time* stamp, std::string* error) {
  if (auto cloud = m.instantiate<sensor_msgs::PointCloud2>()) {
    *frame = cloud->header.frame_id;
    *stamp = cloud->header.stamp;
    return ros_adapters::cloudToPoints(*cloud, &out->scan.scan.points, error);
  }
  auto image = m.instantiate<sensor_msgs::Image>();
  if (!image) {
    *error = "scan topic message is neither PointCloud2 nor Image (" + m.getDataType() + ")";
    return false;
  }
  *frame = image->header.frame_id;
  *stamp = image->header.stamp;
  out->is_image = true;
  ros_adapters::SensorScan ss;
  if (!ros_adapters::toSensorScan(*image, o.node, &ss, error)) return false;  // RIP front end
  out->rip = std::move(ss.scan.features);
  if (o.with_cfear) {
    const cv::Mat mat(static_cast<int>(image->height), static_cast<int>(image->width), CV_8UC1,
                      const_cast<uint8_t*>(image->data.data()), image->step);
    radar::PolarScan polar;
    const bool ok = o.node.polar_format == ros_adapters::PolarFormat::kOxford
                        ? radar::decodeOxfordImage(mat, &polar, error)
                        : radar::decodePolarImage(mat, o.node.polar, stamp->toSec(), &polar, error);
    if (!ok) return false;
    out->kstrong = eval::kStrongestPoints(polar, o.cfear_k, o.cfear_z_min, o.node.rip.min_range,
                                          o.node.rip.max_range);
    out->kstrong_ref = polar.stamp;
  }
  return true;
}

}  // namespace

std::string bagTopicType(const std::string& bag_path, const std::string& topic) {
  try {
    rosbag::Bag bag(bag_path, rosbag::bagmode::Read);
    rosbag::View view(bag, rosbag::TopicQuery(topic));
    for (const rosbag::ConnectionInfo* c : view.getConnections()) return c->datatype;
  } catch (const std::exception&) {
  }
  return "";
}

bool loadBagTrainingScans(const std::string& bag_path, const BagTrainingOptions& o,
                          const eval::Progress& progress, std::vector<eval::TrainingScan>* scans,
                          coral::Isometries* T_fixed_sensor, BagTrainingSummary* summary,
                          std::string* error) {
  auto fail = [&](const std::string& msg) {
    if (error) *error = msg;
    return false;
  };
  if (const std::string e = o.validate(); !e.empty()) return fail(e);
  *summary = BagTrainingSummary();
  std::vector<RawScan> raw;
  try {
    rosbag::Bag bag(bag_path, rosbag::bagmode::Read);
    rosbag::View all(bag);
    const double span = (all.getEndTime() - all.getBeginTime()).toSec();
    tf2::BufferCore buffer(ros::Duration(span + 10.0));  // keep the whole bag
    fillBuffer(bag, o, &buffer);
    rosbag::View view(bag, rosbag::TopicQuery(o.scan_topic));
    const std::size_t total = view.size();
    for (const rosbag::MessageInstance& m : view) {
      ++summary->scan_messages;
      RawScan r;
      std::string frame, err;
      ros::Time stamp;
      if (!readScan(m, o, &r, &frame, &stamp, &err)) {
        if (summary->first_error.empty()) summary->first_error = err;
        ++summary->bad_message;
        continue;
      }
      summary->radar_images = summary->radar_images || r.is_image;
      try {
        const auto t = buffer.lookupTransform(o.fixed_frame, frame, stamp);
        if (!ros_adapters::toEigen(t.transform, &r.T_fixed_sensor, &err))
          throw tf2::TransformException(err);
      } catch (const tf2::TransformException& e) {
        if (summary->first_error.empty()) summary->first_error = e.what();
        ++summary->no_pose;
        continue;
      }
      r.scan.stamp = stamp.toSec();
      raw.push_back(std::move(r));
      if (progress) progress(summary->scan_messages, total);
      if (o.max_scans > 0 && static_cast<int>(raw.size()) >= o.max_scans) break;
    }
  } catch (const std::exception& e) {  // rosbag::BagException and friends
    return fail(bag_path + ": " + e.what());
  }
  if (raw.size() < 2)
    return fail(
        "fewer than 2 scans with a pose on " + o.scan_topic + " in " + bag_path +
        (summary->first_error.empty() ? "" : " (first problem: " + summary->first_error + ")"));

  scans->clear();
  T_fixed_sensor->clear();
  // The online de-skew policy (radar/deskew.hpp) on the bag's poses.
  std::vector<double> stamps;
  coral::Isometries poses;
  for (const RawScan& r : raw) {
    stamps.push_back(r.scan.stamp);
    poses.push_back(r.T_fixed_sensor);
  }
  const auto velocities = radar::deskewVelocities(stamps, poses);
  for (std::size_t i = 0; i < raw.size(); ++i) {
    RawScan& r = raw[i];
    if (summary->radar_images) {
      if (o.motion_compensation && velocities[i]) {
        radar::compensateMotion(*velocities[i], r.scan.stamp, &r.rip);
        radar::compensateMotion(*velocities[i], r.kstrong_ref, &r.kstrong);
      }
      r.scan.scan.points = std::move(r.rip.points);
      r.scan.cfear_points = std::move(r.kstrong.points);
    }
    scans->push_back(std::move(r.scan));
    T_fixed_sensor->push_back(r.T_fixed_sensor);
  }
  return true;
}

}  // namespace ros_eval
}  // namespace coral_introspection
