#include "coral_introspection/ros/coral_scan_input.hpp"

#include <sensor_msgs/image_encodings.h>

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <sstream>

#include "coral_introspection/coral/validation.hpp"

namespace coral_introspection {
namespace ros_adapters {

namespace {
void setHeader(const std_msgs::Header& h, online::ScanInput* s) {
  s->stamp = h.stamp.toSec();
  s->id = h.stamp.toNSec();
}
}  // namespace

std::string inputKindName(InputType type) {
  switch (type) {
    case InputType::kPolarImage:
      return "polar radar images (input_type polar_image)";
    case InputType::kLaserScan:
      return "laser scans (input_type laser_scan)";
    default:
      return "point clouds (input_type pointcloud)";
  }
}

bool toSensorScan(const sensor_msgs::PointCloud2& cloud, const NodeConfig& cfg, SensorScan* out,
                  std::string* error) {
  *out = SensorScan();
  setHeader(cloud.header, &out->scan);
  const bool doppler = cfg.online.doppler.enabled && hasField(cloud, cfg.velocity_field);
  CloudReadStats stats;
  if (!cloudToPoints(cloud, &out->scan.features.points, error, &stats,
                     doppler ? cfg.velocity_field : std::string(),
                     doppler ? &out->scan.radial_velocity : nullptr))
    return false;
  out->dropped_non_finite = stats.non_finite;
  if (out->scan.features.points.empty())
    return coral::fail(error,
                       stats.non_finite > 0 ? "only NaN/Inf points" : "empty cloud (0 points)");
  return true;
}

bool toSensorScan(const sensor_msgs::LaserScan& scan, const NodeConfig&, SensorScan* out,
                  std::string* error) {
  *out = SensorScan();
  setHeader(scan.header, &out->scan);
  const double a0 = scan.angle_min, da = scan.angle_increment;
  const double lo = scan.range_min, hi = scan.range_max;
  std::ostringstream e;
  if (!std::isfinite(a0) || !std::isfinite(da) || da == 0.0) {
    e << "laser scan angle_min " << a0 << ", angle_increment " << da
      << ": both must be finite and angle_increment non-zero";
    return coral::fail(error, e.str());
  }
  const std::size_t n = scan.ranges.size();
  if (n > 1 && std::abs(da) * static_cast<double>(n - 1) > 2.0 * M_PI + 1e-6) {
    e << "laser scan of " << n << " readings " << da << " rad apart spans more than a full turn";
    return coral::fail(error, e.str());
  }
  if (!(lo >= 0.0 && std::isfinite(hi) && hi > lo)) {
    e << "laser scan range_min " << lo << ", range_max " << hi
      << ": must satisfy 0 <= range_min < range_max, finite";
    return coral::fail(error, e.str());
  }
  coral::Points& p = out->scan.features.points;
  p.reserve(n);
  // Beam i is measured time_increment after beam i - 1, the first at the header's stamp
  // (REP 117's LaserScan): with a time, the beams are de-skewed by the odometry's velocity
  // (a 10 Hz scanner turning at 1 rad/s sweeps 6 deg, more than lidar_2d's tolerance).
  const double dt = scan.time_increment;
  out->scan.point_stamps = std::isfinite(dt) && dt != 0.0;
  std::vector<double>& stamps = out->scan.features.stamps;
  for (std::size_t i = 0; i < n; ++i) {
    const double r = scan.ranges[i];
    if (std::isnan(r)) {
      ++out->dropped_non_finite;
      continue;
    }
    if (!(r >= lo && r < hi)) continue;  // +-Inf, too close, at or past range_max: no return
    const double a = a0 + static_cast<double>(i) * da;
    p.emplace_back(r * std::cos(a), r * std::sin(a), 0.0);
    if (out->scan.point_stamps) stamps.push_back(out->scan.stamp + static_cast<double>(i) * dt);
  }
  if (p.empty()) {
    e << "laser scan of " << n << " readings has none in [range_min, range_max) = [" << lo << ", "
      << hi << ")";
    return coral::fail(error, e.str());
  }
  return true;
}

bool toSensorScan(const sensor_msgs::Image& image, const NodeConfig& cfg, SensorScan* out,
                  std::string* error) {
  *out = SensorScan();
  setHeader(image.header, &out->scan);
  out->scan.is_radar = true;
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
  radar::PolarScan scan;
  const bool ok = cfg.polar_format == PolarFormat::kOxford
                      ? radar::decodeOxfordImage(mat, &scan, error)
                      : radar::decodePolarImage(mat, cfg.polar, stamp, &scan, error);
  if (!ok) return false;
  if (!radar::extractRipFeatures(scan, cfg.rip, &out->scan.features, error)) return false;
  const double shift = stamp - scan.stamp;  // embedded clock -> header clock
  for (double& t : out->scan.features.stamps) t += shift;
  if (out->scan.features.points.empty())
    return coral::fail(error, "no RIP features (check rip/z_min and the image)");
  return true;
}

online::ScanInput noPoseInput(const std_msgs::Header& header, const std::string& fixed_frame,
                              const std::string& error) {
  online::ScanInput s;
  setHeader(header, &s);
  s.pose_error = "no transform " + fixed_frame + " <- '" + header.frame_id +
                 "' at t = " + std::to_string(header.stamp.toSec()) + ": " + error;
  return s;
}

}  // namespace ros_adapters
}  // namespace coral_introspection
