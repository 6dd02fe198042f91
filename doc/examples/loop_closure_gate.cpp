// Template: a SLAM back end that asks CorAl before it adds a loop-closure edge (roscpp).
//
// Copy LoopClosureBackEnd::onLoopCandidate into your back end's loop-closure callback: after
// your matcher (ICP, GICP, ...) registered keyframe b against keyframe a, it sends both
// scans (sensor_msgs/PointCloud2, or sensor_msgs/LaserScan for a 2D back end such as
// slam_karto) and T_a_b to the `check_alignment` service of a running coral_node /
// CoralNodelet with loop_closure = true and adds the edge only on an aligned verdict.
//
// Demo (coral_node running, e.g. `rosrun coral_introspection coral_node` with a preset loaded):
//   rosrun coral_introspection coral_loop_closure_example --a 000109.pcd --b 000161.pcd
//       --transform_file T.txt [--service check_alignment] [--laser_scan]
// prints `edge added` or `edge rejected: <why>` and exits 0 (2 on bad arguments or input).
// With --laser_scan the two files are planar scans (z = 0, in the scanner's frame) sent as the
// LaserScans of their readings, to a node with config/lidar_2d.yaml and input_type laser_scan.
#include <pcl/io/pcd_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl_conversions/pcl_conversions.h>
#include <ros/ros.h>

#include <sensor_msgs/LaserScan.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "coral_introspection/CheckAlignment.h"

namespace {

// Minimal back end: a list of edges (a, b, T_a_b); yours would be a pose graph.
class LoopClosureBackEnd {
 public:
  explicit LoopClosureBackEnd(const std::string& service = "check_alignment", double timeout = 10.0)
      : client_(nh_.serviceClient<coral_introspection::CheckAlignment>(service)),
        timeout_(timeout) {}

  // cloud_a, cloud_b: in their own sensor frames; T_a_b maps points of b into a's frame
  // (p_a = T_a_b p_b), from your matcher. Returns true when the edge was added.
  bool onLoopCandidate(const sensor_msgs::PointCloud2& cloud_a,
                       const sensor_msgs::PointCloud2& cloud_b, const Eigen::Isometry3d& T_a_b) {
    coral_introspection::CheckAlignment srv;
    srv.request.cloud_a = cloud_a;
    srv.request.cloud_b = cloud_b;
    return ask(&srv, cloud_a.header.frame_id, cloud_b.header.frame_id, T_a_b);
  }
  // A 2D back end's two LaserScans go in scan_a / scan_b (a node with input_type laser_scan);
  // a request holding both kinds is refused.
  bool onLoopCandidate(const sensor_msgs::LaserScan& scan_a, const sensor_msgs::LaserScan& scan_b,
                       const Eigen::Isometry3d& T_a_b) {
    coral_introspection::CheckAlignment srv;
    srv.request.scan_a = scan_a;
    srv.request.scan_b = scan_b;
    return ask(&srv, scan_a.header.frame_id, scan_b.header.frame_id, T_a_b);
  }

  const std::string& lastRejection() const { return last_rejection_; }

 private:
  struct Edge {
    std::string a, b;
    Eigen::Isometry3d T_a_b;
  };

  // The call and the decision, for either kind of scan in srv.
  bool ask(coral_introspection::CheckAlignment* request, const std::string& frame_a,
           const std::string& frame_b, const Eigen::Isometry3d& T_a_b) {
    coral_introspection::CheckAlignment& srv = *request;
    srv.request.transform_a_b = toTransformMsg(T_a_b);
    srv.request.loop_closure = true;  // judged with the preset's loop_closure/ gate
    // roscpp has no per-call timeout: bound the wait for the service instead. Without a
    // verdict, do not add an unchecked loop (a wrong loop ruins the whole graph).
    if (!client_.waitForExistence(ros::Duration(timeout_)) || !client_.call(srv))
      return reject("service " + client_.getService() + " unavailable");
    const coral_introspection::AlignmentQuality& r = srv.response.result;
    if (r.valid && r.aligned) {
      edges_.push_back({frame_a, frame_b, T_a_b});
      return true;
    }
    // Judged and misaligned: rejected_by names the term that said so. With correction_hint
    // "refined" (loop_closure/max_refinement or restarts) the pose transform_a_b * correction
    // passes: register again from there with your matcher and ask again, rather than adding it
    // as is. No verdict (refused request, too little overlap, ...): reason / error say why.
    if (r.valid) return reject(r.rejected_by);
    return reject(r.reason.empty() ? srv.response.error : r.reason);
  }

  static geometry_msgs::Transform toTransformMsg(const Eigen::Isometry3d& T) {
    geometry_msgs::Transform m;
    m.translation.x = T.translation().x();
    m.translation.y = T.translation().y();
    m.translation.z = T.translation().z();
    // Normalised: the service refuses a quaternion that is not of unit length.
    const Eigen::Quaterniond q = Eigen::Quaterniond(T.linear()).normalized();
    m.rotation.x = q.x();
    m.rotation.y = q.y();
    m.rotation.z = q.z();
    m.rotation.w = q.w();
    return m;
  }

  bool reject(const std::string& why) {
    last_rejection_ = why;
    ROS_WARN("loop closure rejected: %s", why.c_str());
    return false;
  }

  ros::NodeHandle nh_;
  ros::ServiceClient client_;
  double timeout_;  // [s] to wait for the service
  std::vector<Edge> edges_;
  std::string last_rejection_;
};

// 4x4 or 3x4 row-major matrix (the last row of a 4x4 is ignored).
bool readTransform(const std::string& path, Eigen::Isometry3d* T) {
  std::ifstream in(path);
  std::vector<double> v;
  for (double x; v.size() < 12 && in >> x;) v.push_back(x);
  if (v.size() < 12) return false;
  T->setIdentity();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) T->matrix()(r, c) = v[4 * r + c];
  return true;
}

// A PCD file (every field kept: the service reads x, y, z) as a PointCloud2.
bool readPcd(const std::string& path, const std::string& frame, sensor_msgs::PointCloud2* msg) {
  pcl::PCLPointCloud2 pc;
  if (pcl::io::loadPCDFile(path, pc) != 0) return false;
  pcl_conversions::moveFromPCL(pc, *msg);
  msg->header.frame_id = frame;
  msg->header.stamp = ros::Time::now();
  return true;
}

// The LaserScan of a planar cloud in the scanner's frame (z ignored): bearings at the median step
// between the sorted bearings, beams without a point written as +inf (no return), range_max
// above the farthest point. A 2D back end holds its LaserScans already; this only rebuilds them
// from the demo's files. False when the cloud has fewer than two distinct bearings.
bool laserScanFromPlanar(const sensor_msgs::PointCloud2& cloud, sensor_msgs::LaserScan* scan) {
  pcl::PointCloud<pcl::PointXYZ> pts;
  pcl::fromROSMsg(cloud, pts);
  std::vector<std::pair<double, double>> beams;  // (bearing, range)
  for (const auto& p : pts)
    if (std::isfinite(p.x) && std::isfinite(p.y))
      beams.emplace_back(std::atan2(p.y, p.x), std::hypot(p.x, p.y));
  std::sort(beams.begin(), beams.end());
  std::vector<double> steps;
  for (std::size_t i = 1; i < beams.size(); ++i)
    if (beams[i].first - beams[i - 1].first > 1e-6)
      steps.push_back(beams[i].first - beams[i - 1].first);
  if (steps.empty()) return false;
  std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
  const double inc = steps[steps.size() / 2], first = beams.front().first;
  const auto beam = [&](double bearing) { return std::lround((bearing - first) / inc); };
  scan->header = cloud.header;
  scan->angle_min = first;
  scan->angle_increment = inc;
  scan->angle_max = first + beam(beams.back().first) * inc;
  scan->range_min = 0.0;
  scan->range_max = 0.0;
  scan->ranges.assign(beam(beams.back().first) + 1, std::numeric_limits<float>::infinity());
  for (const auto& [bearing, range] : beams) {
    scan->ranges[beam(bearing)] = range;
    scan->range_max = std::max<float>(scan->range_max, range + 1.0);
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "loop_closure_gate", ros::init_options::AnonymousName);
  std::string a, b, transform_file, service = "check_alignment";
  bool laser_scan = false;
  for (int i = 1; i < argc; i += 2) {
    const std::string arg = argv[i];
    if (arg == "--laser_scan") {
      laser_scan = true;
      --i;  // a flag: no value
    } else if (i + 1 == argc) {
      break;
    } else if (arg == "--a")
      a = argv[i + 1];
    else if (arg == "--b")
      b = argv[i + 1];
    else if (arg == "--transform_file")
      transform_file = argv[i + 1];
    else if (arg == "--service")
      service = argv[i + 1];
  }
  if (a.empty() || b.empty() || transform_file.empty()) {
    std::fprintf(stderr,
                 "usage: %s --a A.pcd --b B.pcd --transform_file T.txt [--service S] "
                 "[--laser_scan]\n",
                 argv[0]);
    return 2;
  }
  ros::NodeHandle nh;  // starts the node (ros::Time::now() below needs it)
  Eigen::Isometry3d T_a_b;
  sensor_msgs::PointCloud2 cloud_a, cloud_b;
  if (!readTransform(transform_file, &T_a_b) || !readPcd(a, "keyframe_a", &cloud_a) ||
      !readPcd(b, "keyframe_b", &cloud_b)) {
    std::fprintf(stderr, "could not read %s, %s or %s\n", a.c_str(), b.c_str(),
                 transform_file.c_str());
    return 2;
  }
  LoopClosureBackEnd back_end(service);
  sensor_msgs::LaserScan scan_a, scan_b;
  if (laser_scan &&
      (!laserScanFromPlanar(cloud_a, &scan_a) || !laserScanFromPlanar(cloud_b, &scan_b))) {
    std::fprintf(stderr, "%s or %s: fewer than two distinct bearings, not a planar scan\n",
                 a.c_str(), b.c_str());
    return 2;
  }
  if (laser_scan ? back_end.onLoopCandidate(scan_a, scan_b, T_a_b)
                 : back_end.onLoopCandidate(cloud_a, cloud_b, T_a_b))
    std::printf("edge added\n");
  else
    std::printf("edge rejected: %s\n", back_end.lastRejection().c_str());
  return 0;
}
