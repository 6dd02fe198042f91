#include "coral_introspection/ros/scan_input.hpp"

#include <sensor_msgs/image_encodings.h>

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <sstream>

namespace coral_introspection {
namespace ros_adapters {

bool cloudToSensorScan(const sensor_msgs::PointCloud2& cloud, const NodeConfig& cfg,
                       SensorScan* out, std::string* error) {
  *out = SensorScan();
  const bool doppler = cfg.doppler.enabled && hasField(cloud, cfg.doppler.velocity_field);
  CloudReadStats stats;
  if (!cloudToPoints(cloud, &out->features.points, error, &stats,
                     doppler ? cfg.doppler.velocity_field : std::string(),
                     doppler ? &out->radial_velocity : nullptr))
    return false;
  out->dropped_non_finite = stats.non_finite;
  return true;
}

bool imageToSensorScan(const sensor_msgs::Image& image, const NodeConfig& cfg, SensorScan* out,
                       std::string* error) {
  *out = SensorScan();
  out->is_radar = true;
  namespace enc = sensor_msgs::image_encodings;
  if (image.encoding != enc::MONO8 && image.encoding != enc::TYPE_8UC1) {
    *error = "polar image encoding must be mono8 (got '" + image.encoding + "')";
    return false;
  }
  if (image.width == 0 || image.height == 0 || image.step < image.width ||
      image.data.size() < static_cast<std::size_t>(image.step) * image.height) {
    std::ostringstream e;
    e << "polar image " << image.width << " x " << image.height << " (step " << image.step
      << ") does not match its " << image.data.size() << " data bytes";
    *error = e.str();
    return false;
  }
  // Wraps the message buffer without copying; the decoders only read it.
  const cv::Mat mat(static_cast<int>(image.height), static_cast<int>(image.width), CV_8UC1,
                    const_cast<uint8_t*>(image.data.data()), image.step);
  const double stamp = image.header.stamp.toSec();
  core::PolarScan scan;
  const bool ok = cfg.polar_format == PolarFormat::kOxford
                      ? core::decodeOxfordImage(mat, &scan, error)
                      : core::decodePolarImage(mat, cfg.polar, stamp, &scan, error);
  if (!ok) return false;
  if (!core::extractRipFeatures(scan, cfg.rip, &out->features, error)) return false;
  const double shift = stamp - scan.stamp;  // embedded clock -> header clock
  for (double& t : out->features.stamps) t += shift;
  return true;
}

bool twistBetween(const Eigen::Isometry3d& T_fixed_prev, const Eigen::Isometry3d& T_fixed_curr,
                  double dt, core::Twist* twist) {
  if (!(dt > 0.0)) return false;
  *twist = core::twistFromRelativePose(T_fixed_prev.inverse() * T_fixed_curr, dt);  // SE(3) log
  return true;
}

core::Twist robustTwist(const std::vector<core::Twist>& recent) {
  if (recent.empty()) return core::Twist();
  if (recent.size() < 3) return recent.back();
  core::Twist out;
  std::vector<double> v(recent.size());
  for (int k = 0; k < 6; ++k) {
    for (std::size_t i = 0; i < recent.size(); ++i)
      v[i] = k < 3 ? recent[i].linear[k] : recent[i].angular[k - 3];
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    (k < 3 ? out.linear[k] : out.angular[k - 3]) = v[v.size() / 2];
  }
  return out;
}

}  // namespace ros_adapters
}  // namespace coral_introspection
