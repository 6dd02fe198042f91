// coral_loop_eval: loop closure end to end on a real sequence with reference poses, the
// evaluation of doc/loop_closure.md and a template of the consumer:
//   1. loop candidates (eval/loop_candidates.hpp): revisits and look-alike places, registered
//      by PCL (GICP or NDT in 3D; point-to-point or point-to-line ICP in 2D), labelled true
//      or false against the reference;
//   2. each gate of eval/loop_gates.hpp decides every candidate (one CorAl evaluation each);
//   3. per gate, a keyframe pose graph (odometry edges + the accepted loop edges) optimised
//      with Ceres (eval/pose_graph.hpp, loop sigmas by continuation); ATE against the
//      reference poses and, for CARMEN logs, the benchmark's relation error; trajectories
//      written as TUM and KITTI files with --out_dir;
//   4. with --prune TOLERANCES, per gate, the same graph after a back end's consistency check
//      (eval::optimizePrunedPoseGraph: loop edges the optimum leaves more than TOLERANCES off
//      removed, worst first), its ATE and relation error (--out_dir: GATE_pruned.tum / .kitti);
//   5. with --pcm PROBABILITY, per gate, the graph of the loop edges that agree with the
//      odometry between their ends and, of those, the largest set of pairwise consistent ones
//      (eval::inconsistentLoopEdges: PCM's cycles through the odometry under a chi-square bound
//      of that probability, as coral_pose_graph --pcm) (--out_dir: GATE_pcm.tum / .kitti);
//   6. with --timing, the preset's loop verdict run once more per candidate as a back end
//      gets it (online::judgePair with coral::loopClosureVerdict: coral_check --loop_closure,
//      check_alignment with loop_closure), timed: median, 90th percentile and largest time per
//      kind of candidate (true / false, accepted / rejected), and the candidates whose verdict
//      there differs from the table's gate "verdict" (which step 2 combines from one
//      evaluation with every term; none expected);
// The verdict gates include the loop gate's restart check when the preset turns it on
// (loop_closure/restarts, coral/restart_check.hpp), as coral_check --loop_closure does; a
// better alignment it finds is the candidate's refined pose (gate `refined`).
//   rosrun coral_introspection coral_loop_eval --config PRESET.yaml
//       (--keyframes DIR | --carmen LOG.clf.bz2 --corrected POSES.csv)
//       [--rows all|even|odd] [--registration gicp|ndt|icp (3D) | icp|point_to_line (2D)]
//       [--out FILE.csv] [--out_dir DIR] [--prune TOLERANCES] [--pcm PROBABILITY]
//       [--lookalikes N] [--timing] [--calibrate_odometry]
// Keyframes: DIR/optimized_poses.txt is the reference, DIR/odom_poses.txt the odometry.
// CARMEN (eval/carmen_loops.hpp): the graph nodes are the scans with corrected poses, the
// log's raw odometry the odometry, the reference the graph of the benchmark relations; the
// relations joining scans more than 30 log lines apart are the revisits, as they are and
// registered again from a perturbed pose (labelled against the relation), edges between the
// graph nodes their raw scans hang off (eval/log_nodes.hpp).
// --rows even|odd: only every other candidate (tuning / held-out halves of the gate table).
// --calibrate_odometry (CARMEN): the graph nodes' odometry steps registered again and judged by
// the preset's stream verdict (eval::scanMatchedSteps); the odometry's yaw gain and yaw bias per
// metre fitted on the steps it accepts (eval::fitOdometryYaw) and corrected on every step before
// the graphs, the odometry check of --pcm included, as a back end calibrates its odometry. The
// reference (the relation graph) keeps the raw odometry.
// --lookalikes N: look-alike scan pairs, each registered from every heading (default 40 in 3D,
// 60 in 2D: eval::evaluationCandidates). They are spread evenly over the qualifying pairs, so
// a multiple of the default holds the default's pairs and new ones (a larger false set).
// Exit 0 on success, 2 with a message for bad arguments or unreadable data.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "coral_introspection/coral/statistics.hpp"
#include "coral_introspection/coral/types.hpp"
#include "coral_introspection/eval/carmen_loops.hpp"
#include "coral_introspection/eval/cloud_io.hpp"
#include "coral_introspection/eval/incremental_loops.hpp"
#include "coral_introspection/eval/keyframe_sequence.hpp"
#include "coral_introspection/eval/loop_gates.hpp"
#include "coral_introspection/eval/pairwise_consistency.hpp"
#include "coral_introspection/eval/pose_graph.hpp"
#include "coral_introspection/eval/tool_args.hpp"
#include "coral_introspection/online/introspector.hpp"
#include "coral_introspection/ros_eval/preset_file.hpp"
#include "coral_introspection/ros_eval/stream_decision.hpp"

using namespace coral_introspection;

namespace {

constexpr const char* kUsage =
    "usage: coral_loop_eval --config PRESET.yaml (--keyframes DIR | --carmen LOG.clf.bz2 "
    "--corrected POSES.csv) [--rows all|even|odd] [--registration gicp|ndt|icp (3D, default "
    "gicp) | icp|point_to_line (2D, default icp)] [--out FILE.csv] [--out_dir DIR] "
    "[--prune TOLERANCES (e.g. 3)] [--pcm PROBABILITY (e.g. 0.99)] [--lookalikes N] [--timing] "
    "[--calibrate_odometry (--carmen)]";

int fail(const std::string& msg) { return eval::toolError("coral_loop_eval", msg, kUsage); }

// Edge uncertainties of the graph [m], [rad]: keyframe odometry (lidar-inertial) is good to a
// few cm per keyframe; wheel odometry between corrected CARMEN scans (~1 m apart):
// kLogOdometrySigmaT/R; a registered loop edge to about the tolerance's tenth. Huber on loop
// edges and the continuation: eval::robustContinuationConfig.
struct GraphSettings {
  double odom_t = 0.05, odom_r = 0.01;
  double loop_t = eval::kLoopEdgeSigmaT, loop_r = eval::kLoopEdgeSigmaR;
};

// A candidate and the one CorAl evaluation every CorAl gate decides from.
struct Judged {
  eval::LoopCandidate c;
  coral::AlignmentVerdict v;   // method kBoth
  bool in_graph = false;       // an edge of the graph: between graph nodes, or attached to them
  int node_a = 0, node_b = 0;  // its graph nodes
  Eigen::Isometry3d T_edge = Eigen::Isometry3d::Identity();  // node_b in node_a's frame
  // The loop verdict rejected at the pose and the gate refines (loop_closure/max_refinement),
  // or accepted there and the restart check found a better alignment (loop_closure/restarts,
  // in v.restart), or accepted at the pose registered from the given one
  // (loop_closure/max_registered_offset, in v.nearby): the evaluation at that pose (method
  // kBoth) and the edge through it.
  bool has_refined = false;
  coral::AlignmentVerdict v_refined;
  Eigen::Isometry3d T_edge_refined = Eigen::Isometry3d::Identity();
  // --timing: the preset's loop verdict as a back end gets it, its time [s] (< 0: not run).
  double seconds = -1.0;
  bool timed_accepted = false;
};

// --timing: the preset's loop verdict of candidate c (scans a, b) as coral_check --loop_closure
// runs it, into j->seconds and j->timed_accepted.
void timeVerdict(const coral::Scan& a, const coral::Scan& b, const online::IntrospectorConfig& loop,
                 Judged* j) {
  const auto t0 = std::chrono::steady_clock::now();
  const coral::AlignmentVerdict v = online::judgePair(a, b, j->c.T_a_b, loop, false).verdict;
  j->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  j->timed_accepted = v.valid && v.aligned;
}

// --timing's report: per kind of candidate, the verdict's time; the candidates whose timed
// verdict differs from the table's gate "verdict".
void printTiming(const std::vector<const Judged*>& table, const coral::VerdictConfig& verdict) {
  std::map<std::string, std::vector<double>> by_kind;
  int differ = 0;
  for (const Judged* j : table) {
    const bool table_accepted = eval::loopGateAccepts("verdict", j->c, j->v, verdict);
    by_kind[std::string(j->c.is_true ? "true" : "false") +
            (j->timed_accepted ? ", accepted" : ", rejected")]
        .push_back(j->seconds);
    if (table_accepted != j->timed_accepted) {
      ++differ;
      std::printf("timing: candidate %d-%d (%s): the verdict %s it, the table's gate %s it\n",
                  j->c.a, j->c.b, j->c.source.c_str(), j->timed_accepted ? "accepts" : "rejects",
                  table_accepted ? "accepts" : "rejects");
    }
  }
  // 0.1 s: the bound for a loop verdict on a 64-beam pair.
  std::printf(
      "loop verdict time per candidate [s] (one thread; --timing)\n%-16s %6s %8s %8s %8s %8s\n",
      "candidates", "n", "median", "p90", "max", ">0.1 s");
  for (const auto& [kind, t] : by_kind) {
    const auto over = std::count_if(t.begin(), t.end(), [](double x) { return x > 0.1; });
    std::printf("%-16s %6zu %8.4f %8.4f %8.4f %8ld\n", kind.c_str(), t.size(), coral::median(t),
                coral::quantile(t, 0.9), *std::max_element(t.begin(), t.end()),
                static_cast<long>(over));
  }
  std::printf("timing: the verdict differs from the table's gate on %d of %zu candidates\n", differ,
              table.size());
}

// One evaluation of candidate c of scans (a, b) (method kBoth, every gate term), and, as
// coral::judgeAlignment does for the loop verdict: when the verdict accepts it there and the
// loop gate restarts, the restart check (in j.v.restart) and the evaluation at the better
// alignment it found; when the verdict rejects it there, the registration from the pose
// (loop_closure/max_registered_offset, in j.v.nearby; the evaluation at the registered pose
// when the verdict accepts it there) and else the evaluation at the pose coral::refinePose
// reaches (loop_closure/max_refinement).
Judged judgeCandidate(const eval::LoopCandidate& c, const coral::Scan& a, const coral::Scan& b,
                      const online::IntrospectorConfig& judge_cfg,
                      const coral::VerdictConfig& verdict) {
  Judged j;
  j.c = c;
  const online::PairJudgement pj = online::judgePair(a, b, c.T_a_b, judge_cfg, false);
  j.v = pj.verdict;
  if (!pj.prepared || !j.v.valid) return j;
  const coral::GateConfig& gate = verdict.loop_closure;
  auto judgeAt = [&](const Eigen::Isometry3d& T) {
    return coral::judgeAlignment(*pj.prepared, T, judge_cfg.verdict);
  };
  // The restart check of a pose the loop verdict accepts, judged there as w.
  auto restartCheck = [&](const Eigen::Isometry3d& T, const coral::AlignmentVerdict& w) {
    return coral::betterAlignmentElsewhere(
        *pj.prepared, T, {true, w.coral.quality, w.coral.overlap}, verdict.tolerance,
        verdict.restart, [&](const Eigen::Isometry3d& T2) {
          const coral::AlignmentVerdict w2 = judgeAt(T2);
          return coral::JudgedPose{eval::loopGateAccepts("verdict", c, w2, verdict),
                                   w2.coral.quality, w2.coral.overlap};
        });
  };
  // Which pose is refined: delta from the candidate's pose and its size [tolerances].
  auto refineTo = [&](const Eigen::Isometry3d& T, double size) {
    j.has_refined = true;
    j.v_refined = judgeAt(T);
    j.v_refined.refinement.delta = c.T_a_b.inverse() * T;
    j.v_refined.refinement.size = size;
  };
  if (eval::loopGateAccepts("verdict", c, j.v, verdict)) {
    if (!gate.restarts) return j;
    j.v.restart = restartCheck(c.T_a_b, j.v);
    if (j.v.restart.better_elsewhere) refineTo(j.v.restart.T_a_b, j.v.restart.distance);
    return j;
  }
  if (gate.max_registered_offset > 0.0) {
    j.v.nearby = coral::registeredNearby(
        *pj.prepared, c.T_a_b, verdict.tolerance, verdict.restart, gate.max_registered_offset,
        [&](const Eigen::Isometry3d& T) {
          const coral::AlignmentVerdict w = judgeAt(T);
          return eval::loopGateAccepts("verdict", c, w, verdict) &&
                 w.classifier.probability >= gate.registered_min_probability &&
                 !(gate.restarts && restartCheck(T, w).better_elsewhere);
        });
    if (j.v.nearby.accepted) {
      refineTo(j.v.nearby.T_a_b, j.v.nearby.size);
      return j;
    }
  }
  if (gate.max_refinement <= 0.0) return j;
  const coral::PoseRefinement r = coral::refinePose(
      *pj.prepared, c.T_a_b, judge_cfg.coral.dimension, verdict.tolerance, gate.max_refinement);
  if (!(r.size > 0.0)) return j;
  j.has_refined = true;
  j.v_refined = judgeAt(c.T_a_b * r.delta);
  j.v_refined.refinement = r;
  return j;
}

// A benchmark relation's raw scans hang off the graph node at most this many log lines away
// (the corrected scans are ~9 lines apart).
constexpr int kAttachLines = 10;

}  // namespace

int main(int argc, char** argv) {
  eval::ToolArgs args;
  std::string err;
  if (!eval::parseToolArgs(
          argc, argv,
          {"--config", "--keyframes", "--carmen", "--corrected", "--out", "--out_dir", "--rows",
           "--registration", "--prune", "--pcm", "--lookalikes"},
          {"--timing", "--calibrate_odometry"}, &args, &err))
    return fail(err);
  if (args.help) {
    std::printf("%s\n", kUsage);
    return 0;
  }
  const std::string config = args.get("--config"), keyframes = args.get("--keyframes"),
                    carmen = args.get("--carmen"), corrected = args.get("--corrected"),
                    out_path = args.get("--out"), out_dir = args.get("--out_dir"),
                    registration = args.get("--registration");
  if (config.empty() || keyframes.empty() == carmen.empty() || carmen.empty() != corrected.empty())
    return fail("--config and either --keyframes or --carmen with --corrected are required");
  std::string rows;
  if (!eval::choiceOption(args, "--rows", {"all", "even", "odd"}, &rows, &err)) return fail(err);
  const bool calibrate_odometry = args.flag("--calibrate_odometry");
  if (calibrate_odometry && carmen.empty())
    return fail("--calibrate_odometry needs --carmen (it calibrates a log's wheel odometry)");
  // An optional number whose config validates it (absent: that back-end check is not run).
  auto checked = [&](const char* name, double* value,
                     const std::function<std::string()>& problems) {
    err.clear();
    if (!eval::numberOption(args, name, *value, value, &err)) return false;
    if (const std::string e = problems(); !e.empty()) err = std::string(name) + ": " + e;
    return err.empty();
  };
  eval::LoopPruning pruning;            // --prune: max_residual
  eval::PairwiseConsistencyConfig pcm;  // --pcm: probability
  const bool prune = args.has("--prune"), use_pcm = args.has("--pcm");
  if ((prune && !checked("--prune", &pruning.max_residual, [&] { return pruning.validate(); })) ||
      (use_pcm && !checked("--pcm", &pcm.probability, [&] { return pcm.validate(); })))
    return fail(err);
  ros_adapters::NodeConfig node;
  coral::VerdictConfig verdict;
  if (!ros_eval::loadPresetFile(config, &node, &verdict, &err))
    return fail(err);  // names the file (and line)
  online::IntrospectorConfig judge_cfg = node.online;
  judge_cfg.verdict.method = coral::VerdictMethod::kBoth;  // every term of the verdict
  // The loop gate as `gate` (loop_gates.hpp); every gate term measured for the CSV even when
  // the preset's loop gate does not use it.
  judge_cfg.verdict.gate = verdict.loop_closure;
  judge_cfg.verdict.measure_gate_terms = true;
  const int dim = node.online.coral.dimension;

  eval::CarmenLoopSet set;  // keyframes: scans, ref, odom and the candidates; CARMEN: all of it
  std::vector<double> stamps;
  GraphSettings graph;
  eval::LoopCandidateConfig cand_cfg = eval::evaluationCandidates(dim, verdict.tolerance);
  if (!registration.empty()) cand_cfg.registration = registration;  // else the dimension's
  if (!eval::positiveInt(args, "--lookalikes", cand_cfg.max_lookalike_pairs,
                         &cand_cfg.max_lookalike_pairs, &err))
    return fail(err);
  if (const std::string e = cand_cfg.validate(); !e.empty()) return fail("--registration: " + e);
  if (!keyframes.empty()) {
    if (!eval::loadKeyframeSequence(keyframes, eval::KeyframeSequenceConfig(), nullptr, &set.scans,
                                    &set.ref, &err) ||
        !eval::readKittiPoses(keyframes + "/odom_poses.txt", &set.odom, &err))
      return fail(err);
    if (set.odom.size() < set.scans.size()) return fail("fewer odometry poses than keyframes");
    set.odom.resize(set.scans.size());
    // 1. Candidates: revisits near the odometry pose and look-alike places.
    if (!eval::buildLoopCandidates(set.scans, set.ref, set.odom, cand_cfg, &set.lookalikes, &err))
      return fail(err);
  } else {
    // 1. Candidates: the loop relations as they are and registered again, look-alike places.
    if (!eval::loadCarmenLoopSet(carmen, corrected, eval::relationsPath(carmen), cand_cfg, 30,
                                 kAttachLines, &set, &err))
      return fail(err);
    graph.odom_t = eval::kLogOdometrySigmaT;
    graph.odom_r = eval::kLogOdometrySigmaR;
    const eval::RelationGraphFigures& f = set.figures;
    std::printf(
        "reference: odometry + %d benchmark relations (relation error %.3f m / %.2f deg; the "
        "corrected poses' %.3f m / %.2f deg; ATE between the two %.3f m)\n",
        f.edges, f.own.translation, f.own.rotation_deg, f.corrected.translation,
        f.corrected.rotation_deg, set.ate_reference_corrected);
  }
  if (calibrate_odometry) {
    const eval::LoopDecision stream = ros_eval::streamVerdictDecision(set.scans, node.online);
    eval::OdometryYawModel m;
    if (!eval::calibratedOdometry(set.scans, set.odom, cand_cfg, stream, &set.odom, &m, &err))
      return fail(err);
    std::printf(
        "odometry calibrated on %d of %zu steps (scan matched, accepted by the stream verdict): "
        "yaw error %.4f rad per rad turned %+.4f rad per m; step yaw rms %.4f -> %.4f rad\n",
        m.steps, set.scans.size() - 1, m.gain, m.bias_per_m, m.rms_before, m.rms_after);
  }
  const std::vector<eval::TrainingScan>& scans = set.scans;
  const coral::Isometries &ref = set.ref, &odom = set.odom;
  for (const auto& s : scans) stamps.push_back(s.stamp);

  // 2. One evaluation each (and with --timing the preset's loop verdict, timed).
  const bool timing = args.flag("--timing");
  online::IntrospectorConfig loop_cfg = node.online;
  loop_cfg.verdict = coral::loopClosureVerdict(node.online.verdict);
  std::vector<Judged> judged;
  for (const eval::LoopCandidate& c : set.lookalikes) {
    Judged j = judgeCandidate(c, scans[c.a].scan, scans[c.b].scan, judge_cfg, verdict);
    if (timing) timeVerdict(scans[c.a].scan, scans[c.b].scan, loop_cfg, &j);
    j.in_graph = true;
    j.node_a = c.a;
    j.node_b = c.b;
    j.T_edge = c.T_a_b;
    j.T_edge_refined = c.T_a_b * j.v_refined.refinement.delta;
    judged.push_back(j);
  }
  const eval::LogNodes nodes(set.log, set.raw);
  for (const eval::LoopCandidate& c : set.revisits) {
    const std::vector<eval::TrainingScan>& rs = set.rel_scans;
    Judged j = judgeCandidate(c, rs[c.a].scan, rs[c.b].scan, judge_cfg, verdict);
    if (timing) timeVerdict(rs[c.a].scan, rs[c.b].scan, loop_cfg, &j);
    // An edge between the nodes its scans hang off.
    j.in_graph = nodes.edge(rs[c.a].stamp, rs[c.b].stamp, c.T_a_b, kAttachLines, &j.node_a,
                            &j.node_b, &j.T_edge) &&
                 nodes.edge(rs[c.a].stamp, rs[c.b].stamp, c.T_a_b * j.v_refined.refinement.delta,
                            kAttachLines, &j.node_a, &j.node_b, &j.T_edge_refined);
    judged.push_back(j);
  }
  std::vector<const Judged*> table;  // the rows of the gate table
  for (std::size_t k = 0; k < judged.size(); ++k)
    if (rows == "all" || (rows == "even") == (k % 2 == 0)) table.push_back(&judged[k]);

  if (!out_path.empty()) {
    std::ofstream out(out_path);
    if (!out) return fail("cannot write " + out_path);
    out << "a,b,source,init_yaw,is_true,error_t,error_r,converged,fitness,valid,classifier_p,"
           "relative_score,relative_misaligned,q,h_joint,h_sep,overlap,flat_axes,free_space,"
           "constraint,refinement,refined_accepted,refined_classifier_p,refined_relative_score,"
           "refined_q,refined_overlap,refined_constraint,refined_free_space,restart_better,"
           "restart_distance,restart_q,nearby_size,nearby_accepted,coarse_drop,verdict_accepted,x,"
           "y,z,yaw_deg,restart_starts,restart_usable,restart_back\n";
    for (const Judged* j : table) {
      const eval::LoopCandidate& c = j->c;
      const coral::AlignmentVerdict& v = j->v;
      out << c.a << ',' << c.b << ',' << c.source << ',' << c.init_yaw_deg << ',' << c.is_true
          << ',' << c.error_translation << ',' << c.error_rotation_deg << ',' << c.converged << ','
          << eval::fitnessCell(c.fitness) << ',' << v.valid << ',' << v.classifier.probability
          << ',' << v.relative.score << ',' << v.relative.misaligned << ',' << v.coral.quality
          << ',' << v.coral.h_joint << ',' << v.coral.h_sep << ',' << v.coral.overlap << ','
          << v.relative.flat_axes.size() << ',' << v.free_space.conflict << ','
          << v.constraint.weakest << ',' << (j->has_refined ? j->v_refined.refinement.size : 0.0)
          << ','
          << (j->has_refined && eval::loopGateAccepts("refined", c, v, verdict, &j->v_refined))
          << ',';
      const coral::AlignmentVerdict& w = j->v_refined;  // zeros when not refined
      out << w.classifier.probability << ',' << w.relative.score << ',' << w.coral.quality << ','
          << w.coral.overlap << ',' << w.constraint.weakest << ',' << w.free_space.conflict << ',';
      const coral::RestartResult& r = j->v.restart;  // zeros when not run
      out << r.better_elsewhere << ',' << r.distance << ',' << r.q << ',';
      const coral::NearbyAlignment& n = j->v.nearby;  // zeros when not run
      out << n.size << ',' << n.accepted << ',' << v.coarse.drop() << ','
          << eval::loopGateAccepts("verdict", c, v, verdict) << ',';
      // The candidate's transform (b in a's frame) as judged: coral_check --transform_file.
      const Eigen::Vector3d t = c.T_a_b.translation();
      const Eigen::Matrix3d R = c.T_a_b.rotation();
      out << t.x() << ',' << t.y() << ',' << t.z() << ',' << coral::yawOf(R) * 180.0 / M_PI << ','
          << r.starts << ',' << r.usable << ',' << r.back << "\n";
    }
  }

  // The gate table, then 3. a pose graph per gate.
  int n_true = 0, n_false = 0;
  for (const Judged* j : table) (j->c.is_true ? n_true : n_false)++;
  std::printf("%s: %zu scans; %d true and %d false loop candidates (%s rows)\n",
              keyframes.empty() ? carmen.c_str() : keyframes.c_str(), scans.size(), n_true, n_false,
              rows.c_str());
  // Continuation: the CARMEN logs' raw odometry starts the graph metres and tens of degrees off;
  // planar graphs are solved from the linear start too, the lower cost kept (from the odometry
  // alone Intel's graphs fold).
  eval::PoseGraphConfig pg = eval::robustContinuationConfig(dim);
  pg.try_linear_start = dim == 2;
  const auto odom_edges = eval::odometryEdges(odom, graph.odom_t, graph.odom_r);
  const double ate_odom = eval::absoluteTrajectoryError(odom, ref, dim);
  // CARMEN: the benchmark's relation error of the graph too (every relation of the log, loop
  // relations included: they are edges of the graphs whose gate accepts them).
  auto relErr = [&](const coral::Isometries& poses) {
    if (set.relations.empty()) return std::string();
    const eval::RelationError e = eval::relationError(nodes, poses, set.relations, kAttachLines);
    char buf[64];
    std::snprintf(buf, sizeof buf, " %9.3f %8.2f", e.translation, e.rotation_deg);
    return std::string(buf);
  };
  std::printf("%-14s %14s %14s %10s %10s%s\n", "gate", "true accepted", "false accepted", "ATE [m]",
              "edges", set.relations.empty() ? "" : "  rel [m]  rel [deg]");
  std::printf("%-14s %14s %14s %10.3f %10d%s\n", "odometry", "-", "-", ate_odom, 0,
              relErr(odom).c_str());
  // Per gate, the graph after a back end's check of the accepted loop edges: --prune
  // (eval::optimizePrunedPoseGraph) and --pcm (eval::inconsistentLoopEdges).
  struct Checked {
    std::string gate;
    coral::Isometries poses;
    int removed_true = 0, removed_false = 0;
    bool consistent = true;  // --prune: every remaining loop edge within its bound
  };
  std::vector<Checked> pruned, pcm_checked;
  if (use_pcm) pcm.dimension = dim;
  std::vector<std::string> gates = eval::loopGateNames();
  // Gate `refined`: the poses it adds in place of candidates' own, labelled by their own error
  // against the candidate's reference (the table labels by the candidate): [candidate false,
  // true] x [offered pose off, within the tolerance].
  int offered[2][2] = {{0, 0}, {0, 0}};
  for (const std::string& gate : gates) {
    int ta = 0, fa = 0;
    std::vector<eval::PoseGraphEdge> edges = odom_edges;
    std::vector<bool> edge_true;  // per loop edge
    for (const Judged* j : table) {
      bool refined = false;
      const bool accepted = eval::loopGateAccepts(
          gate, j->c, j->v, verdict, j->has_refined ? &j->v_refined : nullptr, &refined);
      if (!accepted) continue;
      (j->c.is_true ? ta : fa)++;
      if (refined) {
        double t = 0.0, r = 0.0;
        eval::relativeError(j->c.T_a_b * j->v_refined.refinement.delta, j->c.T_ref, &t, &r);
        ++offered[j->c.is_true][eval::withinTolerance(t, r, cand_cfg.tolerance)];
      }
      if (!j->in_graph) continue;  // the rows' candidates between scans of the graph
      edges.push_back({j->node_a, j->node_b, refined ? j->T_edge_refined : j->T_edge,  // refined:
                       graph.loop_t, graph.loop_r, true});                             // that pose
      edge_true.push_back(j->c.is_true);
    }
    coral::Isometries poses = odom;
    eval::PoseGraphResult res;
    if (!eval::optimizePoseGraph(edges, pg, &poses, &res)) return fail(gate + ": " + res.error);
    const double ate = eval::absoluteTrajectoryError(poses, ref, dim);
    // Back-end checks after the gate, same edges (printed below).
    auto count = [&](const std::vector<int>& removed, Checked* c) {
      for (int k : removed)
        (edge_true[k - odom_edges.size()] ? c->removed_true : c->removed_false)++;
    };
    Checked p{gate, odom};
    std::vector<int> removed;
    if (prune && !eval::optimizePrunedPoseGraph(edges, pg, verdict.tolerance, pruning, &p.poses,
                                                &removed, &p.consistent, &res))
      return fail(gate + " (pruned): " + res.error);
    count(removed, &p);
    if (prune) pruned.push_back(p);
    Checked q{gate, odom};
    if (use_pcm) {
      if (!eval::inconsistentLoopEdges(edges, pcm, &removed, nullptr, &err))
        return fail(gate + ": " + err);
      count(removed, &q);
      if (!eval::optimizePoseGraph(eval::keptEdges(edges, removed), pg, &q.poses, &res))
        return fail(gate + " (pcm): " + res.error);
      pcm_checked.push_back(q);
    }
    std::printf("%-14s %8d / %-4d %8d / %-4d %10.3f %10zu%s\n", gate.c_str(), ta, n_true, fa,
                n_false, ate, edges.size() - odom_edges.size(), relErr(poses).c_str());
    if (!out_dir.empty()) {
      std::string name = gate;
      std::replace(name.begin(), name.end(), '<', '_');
      std::replace(name.begin(), name.end(), '=', '_');
      // OUT_DIR/GATE[suffix].tum and .kitti.
      auto write = [&](const std::string& suffix, const coral::Isometries& T) {
        const std::string base = out_dir + "/" + name + suffix;
        return eval::writeTumTrajectory(base + ".tum", stamps, T, &err) &&
               eval::writeKittiPoses(base + ".kitti", T, &err);
      };
      if (!write("", poses) || (prune && !write("_pruned", p.poses)) ||
          (use_pcm && !write("_pcm", q.poses)))
        return fail(err);
    }
  }
  std::printf(
      "gate refined, its offered poses by their own error: for true candidates %d within the "
      "tolerance, %d off; for false candidates %d within, %d off\n",
      offered[1][1], offered[1][0], offered[0][1], offered[0][0]);
  auto table_of = [&](const std::vector<Checked>& checked) {
    std::printf("%-14s %14s %14s %10s%s\n", "gate", "removed true", "removed false", "ATE [m]",
                set.relations.empty() ? "" : "  rel [m]  rel [deg]");
    for (const Checked& c : checked)
      std::printf("%-14s %14d %14d %10.3f%s%s\n", c.gate.c_str(), c.removed_true, c.removed_false,
                  eval::absoluteTrajectoryError(c.poses, ref, dim), relErr(c.poses).c_str(),
                  c.consistent ? "" : "  (stopped at the cap: still inconsistent)");
  };
  if (prune) {
    std::printf(
        "\nafter a back end's consistency check (loop edges the optimum leaves more than %.1f "
        "tolerances off removed, worst first, at most %d; the edges above):\n",
        pruning.max_residual, pruning.max_removals);
    table_of(pruned);
  }
  if (use_pcm) {
    std::printf(
        "\nafter the odometry and pairwise consistency checks (PCM: the loop edges whose cycle "
        "with the odometry, and of those the largest set whose cycles with each other, close "
        "within the chi-square bound of probability %.4g; the edges above):\n",
        pcm.probability);
    table_of(pcm_checked);
  }
  if (timing) printTiming(table, verdict);
  return 0;
}
