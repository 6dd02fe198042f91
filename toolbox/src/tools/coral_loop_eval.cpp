// coral_loop_eval: loop closure end to end on a real sequence with reference poses, the
// evaluation of doc/loop_closure.md and a template of the consumer:
//   1. loop candidates (eval/loop_candidates.hpp): revisits and look-alike places, registered
//      by PCL (GICP or NDT in 3D, planar ICP in 2D), labelled true or false against the
//      reference;
//   2. each gate of eval/loop_gates.hpp decides every candidate (one CorAl evaluation each);
//   3. per gate, a keyframe pose graph (odometry edges + the accepted loop edges) optimised
//      with Ceres (eval/pose_graph.hpp, loop sigmas by continuation); ATE against the
//      reference poses and, for CARMEN logs, the benchmark's relation error; trajectories
//      written as TUM and KITTI files with --out_dir.
//   rosrun coral_introspection coral_loop_eval --config PRESET.yaml
//       (--keyframes DIR | --carmen LOG.clf.bz2 --corrected POSES.csv)
//       [--rows all|even|odd] [--registration gicp|ndt] [--out FILE.csv] [--out_dir DIR]
// Keyframes: DIR/optimized_poses.txt is the reference, DIR/odom_poses.txt the odometry.
// CARMEN: the corrected poses are the reference, the log's raw odometry the odometry; the
// benchmark relations joining scans more than 30 log lines apart are further true candidates,
// edges between the graph nodes their raw scans hang off (eval/log_nodes.hpp).
// --rows even|odd: only every other candidate (tuning / held-out halves of the gate table).
// Exit 0 on success, 2 with a message for bad arguments or unreadable data.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "coral_introspection/eval/carmen_log.hpp"
#include "coral_introspection/eval/cloud_io.hpp"
#include "coral_introspection/eval/keyframe_sequence.hpp"
#include "coral_introspection/eval/log_nodes.hpp"
#include "coral_introspection/eval/loop_gates.hpp"
#include "coral_introspection/eval/pose_graph.hpp"
#include "coral_introspection/eval/tool_args.hpp"
#include "coral_introspection/online/introspector.hpp"
#include "coral_introspection/ros_eval/preset_file.hpp"

using namespace coral_introspection;

namespace {

constexpr const char* kUsage =
    "usage: coral_loop_eval --config PRESET.yaml (--keyframes DIR | --carmen LOG.clf.bz2 "
    "--corrected POSES.csv) [--rows all|even|odd] [--registration gicp|ndt] [--out FILE.csv] "
    "[--out_dir DIR]";

int fail(const std::string& msg) { return eval::toolError("coral_loop_eval", msg, kUsage); }

// Edge uncertainties of the graph [m], [rad]: keyframe odometry (lidar-inertial) is good to a
// few cm per keyframe; wheel odometry between corrected CARMEN scans (~1 m apart) to ~0.1 m
// and a few degrees; a registered loop edge to about the tolerance's tenth. Huber (whitened
// units) on loop edges, as back ends with robust kernels use (hdl_graph_slam's Huber 1.0).
struct GraphSettings {
  double odom_t = 0.05, odom_r = 0.01, loop_t = 0.05, loop_r = 0.01, huber = 1.0;
};

// A candidate and the one CorAl evaluation every CorAl gate decides from.
struct Judged {
  eval::LoopCandidate c;
  coral::AlignmentVerdict v;   // method kBoth
  bool in_graph = false;       // an edge of the graph: between graph nodes, or attached to them
  int node_a = 0, node_b = 0;  // its graph nodes
  Eigen::Isometry3d T_edge = Eigen::Isometry3d::Identity();  // node_b in node_a's frame
};

// A benchmark relation's raw scans hang off the graph node at most this many log lines away
// (the corrected scans are ~9 lines apart).
constexpr int kAttachLines = 10;

}  // namespace

int main(int argc, char** argv) {
  eval::ToolArgs args;
  std::string err;
  if (!eval::parseToolArgs(argc, argv,
                           {"--config", "--keyframes", "--carmen", "--corrected", "--out",
                            "--out_dir", "--rows", "--registration"},
                           {}, &args, &err))
    return fail(err);
  if (args.help) {
    std::printf("%s\n", kUsage);
    return 0;
  }
  const std::string config = args.get("--config"), keyframes = args.get("--keyframes"),
                    carmen = args.get("--carmen"), corrected = args.get("--corrected"),
                    out_path = args.get("--out"), out_dir = args.get("--out_dir"),
                    rows = args.get("--rows", "all"),
                    registration = args.get("--registration", "gicp");
  if (config.empty() || keyframes.empty() == carmen.empty() || carmen.empty() != corrected.empty())
    return fail("--config and either --keyframes or --carmen with --corrected are required");
  if (rows != "all" && rows != "even" && rows != "odd")
    return fail("--rows must be all, even or odd (got '" + rows + "')");
  ros_adapters::NodeConfig node;
  coral::VerdictConfig verdict;
  if (!ros_eval::loadPresetFile(config, &node, &verdict, &err))
    return fail(err);  // names the file (and line)
  online::IntrospectorConfig judge_cfg = node.online;
  judge_cfg.verdict.method = coral::VerdictMethod::kBoth;  // every term of the verdict
  // The loop gate as `gate` (loop_gates.hpp); the free-space conflict measured for the CSV
  // even when the preset's loop gate does not use it (a bound below 1 turns the measurement on).
  judge_cfg.verdict.gate = verdict.loop_closure;
  judge_cfg.verdict.gate.max_free_space =
      std::min(verdict.loop_closure.max_free_space, std::nextafter(1.0, 0.0));
  const int dim = node.online.coral.dimension;

  std::vector<eval::TrainingScan> scans, rel_scans;
  coral::Isometries ref, odom;
  std::vector<double> stamps;
  std::vector<eval::ScanPair> rel_pairs;
  std::vector<eval::CarmenLaserScan> log;
  std::vector<int> raw;
  std::vector<eval::Relation> relations;  // all of them: the relation error of each graph
  GraphSettings graph;
  if (!keyframes.empty()) {
    if (!eval::loadKeyframeSequence(keyframes, eval::KeyframeSequenceConfig(), nullptr, &scans,
                                    &ref, &err) ||
        !eval::readKittiPoses(keyframes + "/odom_poses.txt", &odom, &err))
      return fail(err);
    if (odom.size() < scans.size()) return fail("fewer odometry poses than keyframes");
    odom.resize(scans.size());
  } else {
    eval::LaserGeometry geometry;
    if (!eval::readCarmenLog(carmen, &log, &err) ||
        !eval::correctedSequence(log, corrected, geometry, &scans, &ref, &odom, &raw, &err) ||
        !eval::loopRelationPairs(log, eval::relationsPath(carmen), geometry, 30, &rel_scans,
                                 &rel_pairs, &err) ||
        !eval::readRelations(eval::relationsPath(carmen), &relations, &err))
      return fail(err);
    graph.odom_t = 0.1;
    graph.odom_r = 0.03;
  }
  for (const auto& s : scans) stamps.push_back(s.stamp);

  // 1. Candidates, 2. one evaluation each.
  std::vector<eval::LoopCandidate> cands;
  eval::LoopCandidateConfig cand_cfg = eval::evaluationCandidates(dim, verdict.tolerance);
  cand_cfg.registration = registration;
  if (!eval::buildLoopCandidates(scans, ref, odom, cand_cfg, &cands, &err)) return fail(err);
  std::vector<Judged> judged;
  for (const eval::LoopCandidate& c : cands)
    judged.push_back(
        {c, online::judgePair(scans[c.a].scan, scans[c.b].scan, c.T_a_b, judge_cfg, false).verdict,
         true, c.a, c.b, c.T_a_b});
  const eval::LogNodes nodes(log, raw);
  for (const eval::ScanPair& p : rel_pairs) {
    eval::LoopCandidate c;
    c.a = p.a;
    c.b = p.b;
    c.source = "relation";
    c.T_a_b = p.T_a_b;
    c.is_true = c.converged = true;
    Judged j{c,
             online::judgePair(rel_scans[p.a].scan, rel_scans[p.b].scan, p.T_a_b, judge_cfg, false)
                 .verdict};
    // An edge between the nodes its scans hang off: T_node_a_a * T_a_b * T_node_b_b^-1.
    Eigen::Isometry3d A, B;
    j.in_graph = nodes.attach(rel_scans[p.a].stamp, kAttachLines, &j.node_a, &A) &&
                 nodes.attach(rel_scans[p.b].stamp, kAttachLines, &j.node_b, &B) &&
                 j.node_a != j.node_b;
    if (j.in_graph) j.T_edge = A * p.T_a_b * B.inverse();
    judged.push_back(j);
  }
  std::vector<const Judged*> table;  // the rows of the gate table
  for (std::size_t k = 0; k < judged.size(); ++k)
    if (rows == "all" || (rows == "even") == (k % 2 == 0)) table.push_back(&judged[k]);

  if (!out_path.empty()) {
    std::ofstream out(out_path);
    if (!out) return fail("cannot write " + out_path);
    out << "a,b,source,init_yaw,is_true,error_t,error_r,converged,fitness,valid,classifier_p,"
           "relative_score,relative_misaligned,q,h_joint,h_sep,overlap,flat_axes,free_space\n";
    for (const Judged* j : table) {
      const eval::LoopCandidate& c = j->c;
      const coral::AlignmentVerdict& v = j->v;
      out << c.a << ',' << c.b << ',' << c.source << ',' << c.init_yaw_deg << ',' << c.is_true
          << ',' << c.error_translation << ',' << c.error_rotation_deg << ',' << c.converged << ','
          << c.fitness << ',' << v.valid << ',' << v.classifier.probability << ','
          << v.relative.score << ',' << v.relative.misaligned << ',' << v.coral.quality << ','
          << v.coral.h_joint << ',' << v.coral.h_sep << ',' << v.coral.overlap << ','
          << v.relative.flat_axes.size() << ',' << v.free_space.conflict << "\n";
    }
  }

  // The gate table, then 3. a pose graph per gate.
  int n_true = 0, n_false = 0;
  for (const Judged* j : table) (j->c.is_true ? n_true : n_false)++;
  std::printf("%s: %zu scans; %d true and %d false loop candidates (%s rows)\n",
              keyframes.empty() ? carmen.c_str() : keyframes.c_str(), scans.size(), n_true, n_false,
              rows.c_str());
  eval::PoseGraphConfig pg;
  pg.dimension = dim;
  pg.huber_loss = graph.huber;
  // Continuation: the CARMEN logs' raw odometry starts the graph metres and tens of degrees off.
  pg.loop_sigma_schedule = {100.0, 30.0, 10.0, 3.0};
  const auto odom_edges = eval::odometryEdges(odom, graph.odom_t, graph.odom_r);
  const double ate_odom = eval::absoluteTrajectoryError(odom, ref, dim);
  // CARMEN: the benchmark's relation error of the graph too (every relation of the log, loop
  // relations included: they are edges of the graphs whose gate accepts them).
  auto relErr = [&](const coral::Isometries& poses) {
    if (relations.empty()) return std::string();
    const eval::RelationError e = eval::relationError(nodes, poses, relations, kAttachLines);
    char buf[64];
    std::snprintf(buf, sizeof buf, " %9.3f %8.2f", e.translation, e.rotation_deg);
    return std::string(buf);
  };
  std::printf("%-14s %14s %14s %10s %10s%s\n", "gate", "true accepted", "false accepted", "ATE [m]",
              "edges", relations.empty() ? "" : "  rel [m]  rel [deg]");
  std::printf("%-14s %14s %14s %10.3f %10d%s\n", "odometry", "-", "-", ate_odom, 0,
              relErr(odom).c_str());
  for (const std::string& gate : eval::loopGateNames()) {
    int ta = 0, fa = 0;
    std::vector<eval::PoseGraphEdge> edges = odom_edges;
    for (const Judged* j : table) {
      if (!eval::loopGateAccepts(gate, j->c, j->v, verdict)) continue;
      (j->c.is_true ? ta : fa)++;
      if (j->in_graph)  // the rows' candidates between scans of the graph
        edges.push_back({j->node_a, j->node_b, j->T_edge, graph.loop_t, graph.loop_r, true});
    }
    coral::Isometries poses = odom;
    eval::PoseGraphResult res;
    if (!eval::optimizePoseGraph(edges, pg, &poses, &res)) return fail(gate + ": " + res.error);
    const double ate = eval::absoluteTrajectoryError(poses, ref, dim);
    std::printf("%-14s %8d / %-4d %8d / %-4d %10.3f %10zu%s\n", gate.c_str(), ta, n_true, fa,
                n_false, ate, edges.size() - odom_edges.size(), relErr(poses).c_str());
    if (!out_dir.empty()) {
      std::string name = gate;
      std::replace(name.begin(), name.end(), '<', '_');
      std::replace(name.begin(), name.end(), '=', '_');
      if (!eval::writeTumTrajectory(out_dir + "/" + name + ".tum", stamps, poses, &err) ||
          !eval::writeKittiPoses(out_dir + "/" + name + ".kitti", poses, &err))
        return fail(err);
    }
  }
  return 0;
}
