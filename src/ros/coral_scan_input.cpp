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
  return type == InputType::kPointCloud ? "point clouds (input_type pointcloud)"
                                        : "polar radar images (input_type polar_image)";
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
