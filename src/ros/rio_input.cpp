#include "coral_introspection/ros/rio_input.hpp"

#include <sensor_msgs/point_cloud2_iterator.h>

#include <cmath>

#include "coral_introspection/coral/validation.hpp"
#include "coral_introspection/ros/conversions.hpp"

namespace coral_introspection {
namespace ros_adapters {

std::string RioInputConfig::validate() const {
  return coral::Problems()
      .require(time_source == "header" || time_source == "trigger", "time_source",
               "header or trigger", time_source)
      .require(!velocity_field.empty(), "velocity_field", "a field name", velocity_field)
      .require(time_source != "trigger" || !trigger_topic.empty(), "trigger_topic",
               "set when time_source is trigger", trigger_topic)
      .str();
}

bool extrinsicsFromTransform(const geometry_msgs::Transform& body_radar, rio::Extrinsics* out,
                             std::string* error) {
  const geometry_msgs::Vector3& p = body_radar.translation;
  const geometry_msgs::Quaternion& q = body_radar.rotation;
  const Eigen::Quaterniond qq(q.w, q.x, q.y, q.z);
  const Eigen::Vector3d t(p.x, p.y, p.z);
  if (!t.allFinite() || !qq.coeffs().allFinite() || std::abs(qq.norm() - 1.0) > 1e-3) {
    *error =
        "radar-to-IMU transform is not a rigid transform (translation finite, unit "
        "quaternion)";
    return false;
  }
  out->R = qq.normalized().toRotationMatrix();
  out->t = t;
  return true;
}

bool loadRioInputConfig(const config::ParamTree& file, RioInputConfig* cfg, std::string* error) {
  config::ParamTree ros;
  if (!file.subtree("ros", &ros, error)) return false;
  const bool ok =
      ros.get("imu_topic", &cfg->imu_topic) && ros.get("radar_topic", &cfg->radar_topic) &&
      ros.get("trigger_topic", &cfg->trigger_topic) && ros.get("baro_topic", &cfg->baro_topic) &&
      ros.get("time_source", &cfg->time_source) &&
      ros.get("velocity_field", &cfg->velocity_field) &&
      ros.get("trigger_seq_offset", &cfg->trigger_seq_offset);
  if (!ok) return coral::fail(error, ros.error());
  // A misspelt key would leave a topic at its default: an error, as in the estimator's groups.
  if (const std::string unknown = ros.unknownKeysMessage(); !unknown.empty())
    return coral::fail(error, unknown);
  const std::string invalid = cfg->validate();
  return invalid.empty() || coral::fail(error, file.origin() + invalid);
}

bool RioInput::imu(const sensor_msgs::Imu& msg, rio::ImuSample* out, std::string* error) {
  out->t = msg.header.stamp.toSec();
  out->acc =
      rio::Vec3(msg.linear_acceleration.x, msg.linear_acceleration.y, msg.linear_acceleration.z);
  out->gyro = rio::Vec3(msg.angular_velocity.x, msg.angular_velocity.y, msg.angular_velocity.z);
  if (!(out->t > 0.0) || !out->acc.allFinite() || !out->gyro.allFinite()) {
    ++counters_.bad_imu;
    *error = "IMU sample with a zero stamp or a non-finite value dropped";
    return false;
  }
  return true;
}

bool RioInput::baro(const sensor_msgs::FluidPressure& msg, rio::BaroSample* out,
                    std::string* error) {
  out->t = msg.header.stamp.toSec();
  out->pressure = msg.fluid_pressure;  // [Pa] (sensor_msgs/FluidPressure)
  if (!(out->t > 0.0) || !std::isfinite(out->pressure) || !(out->pressure > 0.0)) {
    ++counters_.bad_baro;
    *error = "barometer sample with a zero stamp or a pressure that is not positive dropped";
    return false;
  }
  return true;
}

std::vector<rio::RadarFrame> RioInput::radar(const sensor_msgs::PointCloud2& msg,
                                             std::string* error) {
  error->clear();
  rio::RadarFrame f;
  f.t = msg.header.stamp.toSec();
  if (!hasField(msg, cfg_.velocity_field)) {
    // Without Doppler there are no static points and no ego velocity: the odometry would be
    // the IMU's dead reckoning. Refused (counted) rather than tracked as if it were radar.
    ++counters_.no_velocity_field;
    std::string fields;
    for (const sensor_msgs::PointField& pf : msg.fields)
      fields += (fields.empty() ? "" : ", ") + pf.name;
    *error = "radar cloud has no radial-velocity field '" + cfg_.velocity_field +
             "' (fields: " + (fields.empty() ? "none" : fields) +
             "; set ros/velocity_field): scan dropped";
    return {};
  }
  if (!cloudToPoints(msg, &f.points, error, nullptr, cfg_.velocity_field, &f.radial_velocity)) {
    ++counters_.bad_clouds;
    return {};
  }
  if (!usesTrigger()) {
    if (!(f.t > 0.0)) {
      ++counters_.bad_clouds;
      *error = "radar cloud with a zero stamp (set time_source: trigger?) dropped";
      return {};
    }
    return {std::move(f)};
  }
  const long before = matcher_.dropped();
  std::vector<rio::RadarFrame> out = matcher_.addScan(msg.header.seq, std::move(f));
  counters_.unmatched_scans += matcher_.dropped() - before;
  return out;
}

std::vector<rio::RadarFrame> RioInput::trigger(const std_msgs::Header& msg) {
  const long before = matcher_.dropped();  // a sequence restart drops the old waiting scans
  std::vector<rio::RadarFrame> out = matcher_.addTrigger(msg.seq, msg.stamp.toSec());
  counters_.unmatched_scans += matcher_.dropped() - before;
  return out;
}

sensor_msgs::PointCloud2 radarFrameToCloud(const rio::RadarFrame& frame,
                                           const std_msgs::Header& header,
                                           const std::string& velocity_field) {
  sensor_msgs::PointCloud2 c;
  c.header = header;
  sensor_msgs::PointCloud2Modifier mod(c);
  mod.setPointCloud2Fields(4, "x", 1, sensor_msgs::PointField::FLOAT32, "y", 1,
                           sensor_msgs::PointField::FLOAT32, "z", 1,
                           sensor_msgs::PointField::FLOAT32, velocity_field.c_str(), 1,
                           sensor_msgs::PointField::FLOAT32);
  mod.resize(frame.points.size());
  const bool has_v = frame.radial_velocity.size() == frame.points.size();
  sensor_msgs::PointCloud2Iterator<float> x(c, "x"), y(c, "y"), z(c, "z"), v(c, velocity_field);
  for (std::size_t i = 0; i < frame.points.size(); ++i, ++x, ++y, ++z, ++v) {
    *x = static_cast<float>(frame.points[i].x());
    *y = static_cast<float>(frame.points[i].y());
    *z = static_cast<float>(frame.points[i].z());
    *v = has_v ? static_cast<float>(frame.radial_velocity[i]) : 0.0f;
  }
  return c;
}

}  // namespace ros_adapters
}  // namespace coral_introspection
