// The raw scans of a CARMEN log placed on the pose graph of its corrected subset (the graph's
// nodes, coral_loop_eval): a raw scan hangs off the node nearest to it in log lines through
// the raw odometry between the two (locally good: the nodes are ~10 lines, ~1 m, apart).
// This lets the benchmark relations, which join raw scans, be loop edges of that graph and be
// measured on it: the relation error of Kümmerle et al. (2009), "On measuring the accuracy of
// SLAM algorithms", the metric the Radish logs' relations were published for.
#pragma once

#include <string>
#include <vector>

#include "coral_introspection/coral/types.hpp"
#include "coral_introspection/eval/carmen_log.hpp"

namespace coral_introspection {
namespace eval {

class LogNodes {
 public:
  // raw_index[k]: the log line of graph node k (correctedSequence), increasing.
  LogNodes(const std::vector<CarmenLaserScan>& log, const std::vector<int>& raw_index);

  // The node nearest (in log lines) to the scan stamped `stamp` (matched to 1e-4 s) and the
  // scan's pose in that node's frame by the raw odometry. False when no scan has the stamp or
  // the nearest node is more than max_lines away.
  bool attach(double stamp, int max_lines, int* node, Eigen::Isometry3d* T_node_scan) const;

  // A measurement T_a_b between the raw scans stamped stamp_a and stamp_b as an edge between
  // the nodes they hang off: *T_from_to = T_node_a_a * T_a_b * T_node_b_b^-1. False when
  // either scan does not attach within max_lines or both attach to the same node.
  bool edge(double stamp_a, double stamp_b, const Eigen::Isometry3d& T_a_b, int max_lines,
            int* node_a, int* node_b, Eigen::Isometry3d* T_from_to) const;

 private:
  const std::vector<CarmenLaserScan>& log_;
  std::vector<int> raw_index_;
};

struct RelationError {
  int n = 0;                    // relations whose two scans attach to nodes
  double translation = 0.0;     // mean |t| of the error transform [m]
  double rotation_deg = 0.0;    // mean |angle| [deg]
  double translation_sq = 0.0;  // mean t^2 [m^2] (the benchmark's squared form)
  double rotation_sq = 0.0;     // mean angle^2 [deg^2]
};

// For each relation (t1, t2, T_1_2): the estimate's relative pose P(t1)^-1 P(t2), with
// P(t) = T_world_node[node] * T_node_scan, against T_1_2. Relations whose scans do not attach
// within max_lines are skipped (counted out of n).
RelationError relationError(const LogNodes& nodes, const coral::Isometries& T_world_node,
                            const std::vector<Relation>& relations, int max_lines);

// Sigmas of the raw wheel odometry between consecutive graph nodes (~1 m apart) [m], [rad]:
// the relation graph's and coral_loop_eval's odometry edges on CARMEN logs.
constexpr double kLogOdometrySigmaT = 0.1, kLogOdometrySigmaR = 0.03;

// The benchmark's ground truth as a trajectory of the graph nodes: the raw odometry between
// consecutive nodes (kLogOdometrySigmaT/R) and every relation whose scans attach within max_lines
// as an edge (0.05 m, 0.01 rad), optimised with robustContinuationConfig from the odometry and
// from the planar linear start, the lower cost kept (PoseGraphConfig::try_linear_start; from the
// raw odometry alone the Intel graph stopped in a folded local minimum 9 m ATE from the
// corrected poses, at 2.4x the cost; now 0.48 m). The corrected poses of the Radish logs are one
// SLAM result: they reproduce the relations to 3-5 cm median but disagree with them by
// decimetres in places; labels and ATE against this graph measure against the relations. False
// with *error when the optimisation fails.
struct RelationGraphFigures {
  int edges = 0;            // relations used as edges
  RelationError own;        // relation error of the result
  RelationError corrected;  // relation error of the given reference (the corrected poses)
};
bool relationGraph(const LogNodes& nodes, const coral::Isometries& T_world_odom,
                   const std::vector<Relation>& relations, int max_lines, coral::Isometries* poses,
                   RelationGraphFigures* figures, std::string* error);

}  // namespace eval
}  // namespace coral_introspection
