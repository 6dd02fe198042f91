#include "coral_introspection/ros/coral_check_alignment.hpp"

#include "coral_introspection/online/introspector.hpp"
#include "coral_introspection/ros/conversions.hpp"
#include "coral_introspection/ros/coral_scan_input.hpp"

namespace coral_introspection {
namespace ros_adapters {

namespace {

// A message of the request counts as given when anything beyond its header is set (a
// layout, a size or data): an unfilled field of the request is a default-constructed one.
bool given(const sensor_msgs::PointCloud2& c) {
  return !c.fields.empty() || c.width > 0 || c.height > 0 || !c.data.empty();
}
bool given(const sensor_msgs::Image& i) {
  return !i.encoding.empty() || i.width > 0 || i.height > 0 || !i.data.empty();
}

}  // namespace

std::string requestKindError(const CheckAlignment::Request& req, InputType type) {
  const bool ca = given(req.cloud_a), cb = given(req.cloud_b);
  const bool ia = given(req.image_a), ib = given(req.image_b);
  std::string held;  // the given fields, e.g. "cloud_a, image_b"
  for (const auto& [set, name] : {std::pair<bool, const char*>{ca, "cloud_a"},
                                  {cb, "cloud_b"},
                                  {ia, "image_a"},
                                  {ib, "image_b"}})
    if (set) held += std::string(held.empty() ? "" : ", ") + name;
  // A laser-scan nodelet judges requests of planar point clouds (the service has no LaserScan
  // fields; a client converts them as it sends them).
  const bool clouds_wanted = type != InputType::kPolarImage;
  const std::string wanted = clouds_wanted ? "cloud_a and cloud_b" : "image_a and image_b";
  const std::string self = "this nodelet is configured for " + inputKindName(type);
  if (held.empty())
    return "the request holds no scan (cloud_a, cloud_b, image_a and image_b are all empty); " +
           self + ": fill " + wanted;
  // Clouds and images in one request: which pair was meant cannot be told (the image
  // fields of a cloud request are not leftovers to be ignored).
  if ((ca || cb) && (ia || ib))
    return "the request mixes point clouds and polar images (" + held + "); " + self + ": fill " +
           wanted + " only";
  const std::string kind = clouds_wanted ? "point clouds" : "polar images";
  if ((ca || cb) != clouds_wanted)
    return self + "; the request holds " + (clouds_wanted ? "polar images" : "point clouds") +
           " (" + held + "): send them to a nodelet with input_type " +
           (clouds_wanted ? "polar_image" : "pointcloud");
  if (clouds_wanted ? !(ca && cb) : !(ia && ib))
    return std::string(clouds_wanted ? (ca ? "cloud_b" : "cloud_a")
                                     : (ia ? "image_b" : "image_a")) +
           " is empty: the request needs two " + kind + " (" + wanted + ")";
  return "";
}

bool answerCheckAlignment(const CheckAlignment::Request& req, const NodeConfig& cfg,
                          CheckAlignment::Response* res) {
  const bool clouds = given(req.cloud_a) || given(req.cloud_b);
  const std_msgs::Header& ha = clouds ? req.cloud_a.header : req.image_a.header;
  const ros::Time stamp_b = clouds ? req.cloud_b.header.stamp : req.image_b.header.stamp;
  SensorScan sa, sb;
  std::string error = requestKindError(req, cfg.input_type);
  auto convert = [&](const auto& msg, const char* name, SensorScan* s) {
    if (toSensorScan(msg, cfg, s, &error)) return true;
    error = std::string(name) + ": " + error;
    return false;
  };
  Eigen::Isometry3d T_a_b;
  const bool ok =
      error.empty() &&
      (clouds ? convert(req.cloud_a, "cloud_a", &sa) && convert(req.cloud_b, "cloud_b", &sb)
              : convert(req.image_a, "image_a", &sa) && convert(req.image_b, "image_b", &sb)) &&
      toEigen(req.transform_a_b, &T_a_b, &error);
  if (!ok) {
    res->result = toMessage(coral::AlignmentVerdict(), cfg.online.verdict, ha, ha.stamp, stamp_b);
    res->error = "request refused: " + error;
    res->result.status = AlignmentQuality::REFUSED;
    res->result.reason = res->error;
    return false;
  }
  coral::Scan a, b;
  a.points = std::move(sa.scan.features.points);
  b.points = std::move(sb.scan.features.points);
  // A loop-closure candidate: the gated verdict with the loop gate (coral/verdict.hpp).
  online::IntrospectorConfig judge = cfg.online;
  if (req.loop_closure) judge.verdict = coral::loopClosureVerdict(cfg.online.verdict);
  const online::PairJudgement j = online::judgePair(std::move(a), b, T_a_b, judge, false);
  res->result = toMessage(j.verdict, judge.verdict, ha, ha.stamp, stamp_b);
  res->result.loop_closure = req.loop_closure;
  res->result.reason = j.reason;
  res->error = j.reason;
  return true;
}

}  // namespace ros_adapters
}  // namespace coral_introspection
