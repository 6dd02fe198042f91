#include "coral_introspection/ros/check_alignment.hpp"

#include "coral_introspection/online/introspector.hpp"
#include "coral_introspection/ros/conversions.hpp"
#include "coral_introspection/ros/scan_input.hpp"

namespace coral_introspection {
namespace ros_adapters {

bool answerCheckAlignment(const CheckAlignment::Request& req, const NodeConfig& cfg,
                          CheckAlignment::Response* res) {
  const bool clouds = !req.cloud_a.fields.empty() || !req.cloud_b.fields.empty();
  const std_msgs::Header& ha = clouds ? req.cloud_a.header : req.image_a.header;
  const ros::Time stamp_b = clouds ? req.cloud_b.header.stamp : req.image_b.header.stamp;
  SensorScan sa, sb;
  std::string error;
  auto convert = [&](const auto& msg, const char* name, SensorScan* s) {
    if (toSensorScan(msg, cfg, s, &error)) return true;
    error = std::string(name) + ": " + error;
    return false;
  };
  Eigen::Isometry3d T_a_b;
  const bool ok =
      (clouds ? convert(req.cloud_a, "cloud_a", &sa) && convert(req.cloud_b, "cloud_b", &sb)
              : convert(req.image_a, "image_a", &sa) && convert(req.image_b, "image_b", &sb)) &&
      toEigen(req.transform_a_b, &T_a_b, &error);
  if (!ok) {
    res->result = toMessage(core::AlignmentVerdict(), cfg.online.verdict, ha, ha.stamp, stamp_b);
    res->error = "request refused: " + error;
    res->result.status = AlignmentQuality::REFUSED;
    res->result.reason = res->error;
    return false;
  }
  core::Scan a, b;
  a.points = std::move(sa.scan.features.points);
  b.points = std::move(sb.scan.features.points);
  // A loop-closure candidate: the gated verdict with the loop gate (coral/verdict.hpp).
  online::IntrospectorConfig judge = cfg.online;
  if (req.loop_closure) judge.verdict = core::loopClosureVerdict(cfg.online.verdict);
  const online::PairJudgement j = online::judgePair(std::move(a), b, T_a_b, judge, false);
  res->result = toMessage(j.verdict, judge.verdict, ha, ha.stamp, stamp_b);
  res->result.loop_closure = req.loop_closure;
  res->result.reason = j.reason;
  res->error = j.reason;
  return true;
}

}  // namespace ros_adapters
}  // namespace coral_introspection
