#include "coral_introspection/eval/log_nodes.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "coral_introspection/coral/types.hpp"
#include "coral_introspection/eval/pose_graph.hpp"

namespace coral_introspection {
namespace eval {

LogNodes::LogNodes(const std::vector<CarmenLaserScan>& log, const std::vector<int>& raw_index)
    : log_(log), raw_index_(raw_index) {}

bool LogNodes::attach(double stamp, int max_lines, int* node,
                      Eigen::Isometry3d* T_node_scan) const {
  const int line = logLineAt(log_, stamp);
  if (line == static_cast<int>(log_.size()) || std::abs(log_[line].stamp - stamp) > 1e-4 ||
      raw_index_.empty())
    return false;
  const auto n = std::lower_bound(raw_index_.begin(), raw_index_.end(), line);
  int k = static_cast<int>(n - raw_index_.begin());
  if (k == static_cast<int>(raw_index_.size()) ||
      (k > 0 && line - raw_index_[k - 1] < raw_index_[k] - line))
    --k;  // the nearer of the two nodes around the line
  if (std::abs(raw_index_[k] - line) > max_lines) return false;
  auto odom = [&](int l) {
    const Eigen::Vector3d& p = log_[static_cast<std::size_t>(l)].laser_pose;
    return coral::se2(p.x(), p.y(), p.z());
  };
  *node = k;
  *T_node_scan = odom(raw_index_[k]).inverse() * odom(line);
  return true;
}

bool LogNodes::edge(double stamp_a, double stamp_b, const Eigen::Isometry3d& T_a_b, int max_lines,
                    int* node_a, int* node_b, Eigen::Isometry3d* T_from_to) const {
  Eigen::Isometry3d A, B;
  if (!attach(stamp_a, max_lines, node_a, &A) || !attach(stamp_b, max_lines, node_b, &B) ||
      *node_a == *node_b)
    return false;
  *T_from_to = A * T_a_b * B.inverse();
  return true;
}

RelationError relationError(const LogNodes& nodes, const coral::Isometries& T_world_node,
                            const std::vector<Relation>& relations, int max_lines) {
  RelationError e;
  for (const Relation& r : relations) {
    int k1, k2;
    Eigen::Isometry3d A1, A2;
    if (!nodes.attach(r.t1, max_lines, &k1, &A1) || !nodes.attach(r.t2, max_lines, &k2, &A2))
      continue;
    const Eigen::Isometry3d est = (T_world_node[k1] * A1).inverse() * (T_world_node[k2] * A2);
    const Eigen::Isometry3d d = r.T_1_2.inverse() * est;
    const double t = d.translation().head<2>().norm();
    const double a = std::abs(coral::yawOf(d.linear())) * 180.0 / M_PI;
    ++e.n;
    e.translation += t;
    e.rotation_deg += a;
    e.translation_sq += t * t;
    e.rotation_sq += a * a;
  }
  if (e.n > 0) {
    e.translation /= e.n;
    e.rotation_deg /= e.n;
    e.translation_sq /= e.n;
    e.rotation_sq /= e.n;
  }
  return e;
}

bool relationGraph(const LogNodes& nodes, const coral::Isometries& T_world_odom,
                   const std::vector<Relation>& relations, int max_lines, coral::Isometries* poses,
                   RelationGraphFigures* figures, std::string* error) {
  figures->corrected = relationError(nodes, *poses, relations, max_lines);
  std::vector<PoseGraphEdge> edges =
      odometryEdges(T_world_odom, kLogOdometrySigmaT, kLogOdometrySigmaR);
  for (const Relation& r : relations) {
    PoseGraphEdge e;
    if (!nodes.edge(r.t1, r.t2, r.T_1_2, max_lines, &e.from, &e.to, &e.T_from_to)) continue;
    e.sigma_translation = kLoopEdgeSigmaT;
    e.sigma_rotation = kLoopEdgeSigmaR;
    e.loop = true;
    edges.push_back(e);
    ++figures->edges;
  }
  *poses = T_world_odom;
  PoseGraphConfig cfg = robustContinuationConfig(2);
  cfg.try_linear_start = true;  // from the odometry alone the Intel graph folds (pose_graph.hpp)
  PoseGraphResult res;
  if (!optimizePoseGraph(edges, cfg, poses, &res)) {
    if (error) *error = "relation graph: " + res.error;
    return false;
  }
  figures->own = relationError(nodes, *poses, relations, max_lines);
  return true;
}

}  // namespace eval
}  // namespace coral_introspection
