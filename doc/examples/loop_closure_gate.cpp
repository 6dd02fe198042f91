// Template: a SLAM back end that asks CorAl before it adds a loop-closure edge (roscpp).
//
// Copy LoopClosureBackEnd::onLoopCandidate into your back end's loop-closure callback: after
// your matcher (ICP, GICP, ...) registered keyframe b against keyframe a, it sends both
// clouds and T_a_b to the `check_alignment` service of a running coral_node / CoralNodelet
// with loop_closure = true and adds the edge only on an aligned verdict.
//
// Demo (coral_node running, e.g. `rosrun coral_introspection coral_node` with a preset loaded):
//   rosrun coral_introspection coral_loop_closure_example --a 000109.pcd --b 000161.pcd
//       --transform_file T.txt [--service check_alignment]
// prints `edge added` or `edge rejected: <why>` and exits 0 (2 on bad arguments or input).
#include <pcl/io/pcd_io.h>
#include <pcl_conversions/pcl_conversions.h>
#include <ros/ros.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <fstream>
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
    srv.request.transform_a_b = toTransformMsg(T_a_b);
    srv.request.loop_closure = true;  // judged with the preset's loop_closure/ gate
    // roscpp has no per-call timeout: bound the wait for the service instead. Without a
    // verdict, do not add an unchecked loop (a wrong loop ruins the whole graph).
    if (!client_.waitForExistence(ros::Duration(timeout_)) || !client_.call(srv))
      return reject("service " + client_.getService() + " unavailable");
    const coral_introspection::AlignmentQuality& r = srv.response.result;
    if (r.valid && r.aligned) {
      edges_.push_back({cloud_a.header.frame_id, cloud_b.header.frame_id, T_a_b});
      return true;
    }
    // Judged and misaligned: rejected_by names the term that said so. With correction_hint
    // "refined" (loop_closure/max_refinement or restarts) the pose transform_a_b * correction
    // passes: register again from there with your matcher and ask again, rather than adding it
    // as is. No verdict (refused request, too little overlap, ...): reason / error say why.
    if (r.valid) return reject(r.rejected_by);
    return reject(r.reason.empty() ? srv.response.error : r.reason);
  }

  const std::string& lastRejection() const { return last_rejection_; }

 private:
  struct Edge {
    std::string a, b;
    Eigen::Isometry3d T_a_b;
  };

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

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "loop_closure_gate", ros::init_options::AnonymousName);
  std::string a, b, transform_file, service = "check_alignment";
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string arg = argv[i];
    if (arg == "--a")
      a = argv[i + 1];
    else if (arg == "--b")
      b = argv[i + 1];
    else if (arg == "--transform_file")
      transform_file = argv[i + 1];
    else if (arg == "--service")
      service = argv[i + 1];
  }
  if (a.empty() || b.empty() || transform_file.empty()) {
    std::fprintf(stderr, "usage: %s --a A.pcd --b B.pcd --transform_file T.txt [--service S]\n",
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
  if (back_end.onLoopCandidate(cloud_a, cloud_b, T_a_b))
    std::printf("edge added\n");
  else
    std::printf("edge rejected: %s\n", back_end.lastRejection().c_str());
  return 0;
}
