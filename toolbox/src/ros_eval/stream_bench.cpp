#include "coral_introspection/ros_eval/stream_bench.hpp"

#include <ros/network.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/point_cloud2_iterator.h>
#include <tf2_eigen/tf2_eigen.h>
#include <xmlrpcpp/XmlRpcClient.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "coral_introspection/coral/statistics.hpp"
#include "coral_introspection/radar/motion_compensation.hpp"

namespace coral_introspection {
namespace ros_eval {

CloudStreamer::CloudStreamer(ros::NodeHandle& nh, const coral::Points& world,
                             const StreamOptions& options)
    : opt_(options) {
  const int stride = std::max(1, opt_.stride);
  for (std::size_t i = 0; i < world.size(); i += stride)
    if (world[i].allFinite()) world_.push_back(world[i]);
  std::normal_distribution<float> n(0.f, static_cast<float>(opt_.noise));
  noise_.resize(3 * world_.size() + 4099);
  for (float& v : noise_) v = n(rng_);
  // Queue of 2: a slow subscriber makes the publisher drop (roscpp counts it in header.seq).
  pub_ = nh.advertise<sensor_msgs::PointCloud2>(opt_.topic, 2);
}

bool CloudStreamer::waitForSubscriber(double timeout_s) const {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout_s);
  while (ros::ok() && ros::WallTime::now() < end) {
    if (pub_.getNumSubscribers() > 0) return true;
    ros::WallDuration(0.05).sleep();
  }
  return pub_.getNumSubscribers() > 0;
}

Eigen::Isometry3d CloudStreamer::pose(double t) const {
  radar::Twist v;
  v.linear = coral::Vec3(opt_.speed, 0.0, 0.0);
  v.angular = coral::Vec3(0.0, 0.0, opt_.yaw_rate);
  return radar::constantVelocityPose(v, t);
}

void CloudStreamer::publish(double t, const ros::Time& stamp) {
  const Eigen::Isometry3d T = pose(t);
  geometry_msgs::TransformStamped ts = tf2::eigenToTransform(T);
  ts.header.stamp = stamp;
  ts.header.frame_id = opt_.fixed_frame;
  ts.child_frame_id = opt_.frame;
  tf_.sendTransform(ts);

  sensor_msgs::PointCloud2 c;
  c.header.stamp = stamp;
  c.header.frame_id = opt_.frame;
  sensor_msgs::PointCloud2Modifier mod(c);
  mod.setPointCloud2FieldsByString(1, "xyz");
  mod.resize(world_.size());
  const Eigen::Isometry3d T_sensor_fixed = T.inverse();
  const std::size_t offset = std::uniform_int_distribution<std::size_t>(0, 4096)(rng_);
  const float* noise = noise_.data() + offset;
  sensor_msgs::PointCloud2Iterator<float> it(c, "x");
  for (std::size_t i = 0; i < world_.size(); ++i, ++it) {
    const coral::Vec3 p = T_sensor_fixed * world_[i];
    it[0] = static_cast<float>(p.x()) + noise[3 * i];
    it[1] = static_cast<float>(p.y()) + noise[3 * i + 1];
    it[2] = static_cast<float>(p.z()) + noise[3 * i + 2];
  }
  pub_.publish(c);
}

std::size_t CloudStreamer::run(double duration_s) {
  ros::WallRate rate(opt_.rate);
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(duration_s);
  std::size_t n = 0;
  while (ros::ok() && ros::WallTime::now() < end) {
    publish(t_, ros::Time::now());
    t_ += 1.0 / opt_.rate;
    ++n;
    rate.sleep();
  }
  return n;
}

VerdictMonitor::VerdictMonitor(ros::NodeHandle& nh, const std::string& alignment_topic,
                               const std::string& node)
    : node_(node), since_(ros::WallTime::now()) {
  alignment_sub_ = nh.subscribe<AlignmentQuality>(
      alignment_topic, 1000, [this](const AlignmentQuality::ConstPtr& m) {
        Sample s{*m, (ros::Time::now() - m->stamp_b).toSec(), ros::WallTime::now()};
        std::lock_guard<std::mutex> l(mutex_);
        samples_.push_back(std::move(s));
      });
  diag_sub_ = nh.subscribe<diagnostic_msgs::DiagnosticArray>(
      "/diagnostics", 100, [this](const diagnostic_msgs::DiagnosticArray::ConstPtr& a) {
        for (const auto& st : a->status) {
          if (st.name.find(node_) == std::string::npos) continue;
          std::map<std::string, std::string> d;
          for (const auto& kv : st.values) d[kv.key] = kv.value;
          d["__message"] = st.message;
          d["__level"] = std::to_string(static_cast<int>(st.level));
          std::lock_guard<std::mutex> l(mutex_);
          diag_messages_.push_back(d["__level"] + ": " + st.message);
          diag_ = std::move(d);
        }
      });
}

void VerdictMonitor::reset() {
  std::lock_guard<std::mutex> l(mutex_);
  samples_.clear();
  diag_messages_.clear();
  since_ = ros::WallTime::now();
}

std::size_t VerdictMonitor::size() {
  std::lock_guard<std::mutex> l(mutex_);
  return samples_.size();
}

bool VerdictMonitor::waitFor(std::size_t n, double timeout_s) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout_s);
  while (ros::ok() && ros::WallTime::now() < end) {
    if (size() >= n) return true;
    ros::WallDuration(0.01).sleep();
  }
  return size() >= n;
}

std::vector<std::string> VerdictMonitor::diagnosticMessages() {
  std::lock_guard<std::mutex> l(mutex_);
  return diag_messages_;
}

std::map<std::string, std::string> VerdictMonitor::diagnostics() {
  std::lock_guard<std::mutex> l(mutex_);
  return diag_;
}

StreamSummary VerdictMonitor::summary() {
  std::lock_guard<std::mutex> l(mutex_);
  StreamSummary s;
  s.seconds = (ros::WallTime::now() - since_).toSec();
  s.messages = samples_.size();
  std::vector<double> latency, age;
  // A loop starts where stamps jump back by more than 1 s (a replayed bag looping).
  struct Loop {
    std::size_t messages = 0, verdicts = 0;
    double first = 0.0;
  };
  std::vector<Loop> loops(1);
  double last_stamp = -1.0;
  for (const Sample& x : samples_) {
    const AlignmentQuality& m = x.msg;
    ++s.by_status[m.status];
    const bool judged =
        m.status == AlignmentQuality::VERDICT || m.status == AlignmentQuality::INVALID_PAIR;
    if (m.status == AlignmentQuality::VERDICT) ++s.verdicts;
    if (m.status != AlignmentQuality::VERDICT && m.reason.empty()) ++s.without_reason;
    if (judged) {
      ++s.judged;
      age.push_back(x.age);
    }
    if (m.status != AlignmentQuality::DROPPED) latency.push_back(m.latency);
    const double stamp = m.stamp_b.toSec();
    if (last_stamp >= 0.0 && stamp < last_stamp - 1.0) loops.emplace_back();
    if (loops.back().messages == 0) loops.back().first = stamp;
    last_stamp = stamp;
    ++loops.back().messages;
    if (m.status == AlignmentQuality::VERDICT) ++loops.back().verdicts;
  }
  s.verdict_rate = s.seconds > 0.0 ? s.verdicts / s.seconds : 0.0;
  s.latency_median = coral::quantile(latency, 0.5);
  s.latency_p95 = coral::quantile(latency, 0.95);
  s.latency_max = latency.empty() ? 0.0 : *std::max_element(latency.begin(), latency.end());
  s.age_median = coral::quantile(age, 0.5);
  s.age_p95 = coral::quantile(age, 0.95);
  // The first and the last loop may be cut by the measuring window: only those between.
  for (std::size_t k = 1; k + 1 < loops.size(); ++k) {
    ++s.loops;
    if (loops[k].verdicts + 1 == loops[k].messages) {
      ++s.loops_judged;
    } else if (s.worst_loop.empty()) {
      std::ostringstream w;
      w << "loop " << k << " (from t = " << std::fixed << loops[k].first
        << "): " << loops[k].verdicts << " verdicts for " << loops[k].messages << " scans";
      s.worst_loop = w.str();
    }
  }
  return s;
}

std::optional<int> nodePid(const std::string& node) {
  XmlRpc::XmlRpcValue args, result, payload;
  args[0] = ros::this_node::getName();
  args[1] = ros::names::resolve(node);
  if (!ros::master::execute("lookupNode", args, result, payload, false)) return std::nullopt;
  std::string host, path;
  uint32_t port = 0;
  if (!ros::network::splitURI(static_cast<std::string>(payload), host, port)) return std::nullopt;
  const std::string uri = static_cast<std::string>(payload);
  const std::size_t slash = uri.find('/', uri.find("://") + 3);
  path = slash == std::string::npos ? "/" : uri.substr(slash);
  XmlRpc::XmlRpcClient client(host.c_str(), static_cast<int>(port), path.c_str());
  XmlRpc::XmlRpcValue req, res;
  req[0] = ros::this_node::getName();
  if (!client.execute("getPid", req, res) || res.getType() != XmlRpc::XmlRpcValue::TypeArray ||
      res.size() < 3 || res[2].getType() != XmlRpc::XmlRpcValue::TypeInt)
    return std::nullopt;
  return static_cast<int>(res[2]);
}

double processRssMiB(int pid) {
  std::ifstream f("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(f, line))
    if (line.rfind("VmRSS:", 0) == 0) {
      std::istringstream s(line.substr(6));
      double kib = 0.0;
      s >> kib;
      return kib / 1024.0;
    }
  return 0.0;
}

}  // namespace ros_eval
}  // namespace coral_introspection
