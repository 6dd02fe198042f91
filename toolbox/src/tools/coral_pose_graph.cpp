// coral_pose_graph: the consumer of the loop verdict on a keyframe sequence or a 2D laser log of
// one's own, with no reference poses: what a SLAM back end does with it, small enough to read
// and copy (coral_loop_eval is the evaluation, which needs reference poses to label candidates).
//   1. keyframes DIR/Scans/NNNNNN.pcd (or .bin) and their odometry DIR/odom_poses.txt (KITTI
//      layout, world_T_body; DIR/times.txt optional), as FAST-LIO / scan-context pose graphs
//      write them (eval/keyframe_sequence.hpp); under a 2D preset a PCD with fields x and y
//      only is a planar scan (z = 0); or (--carmen, 2D presets) the FLASER scans of a CARMEN
//      log taken as keyframes every --keyframe_distance metres or --keyframe_angle degrees of
//      its raw odometry (eval::logKeyframes);
//   2. loop candidates proposed as LIO-SAM and hdl_graph_slam propose them: keyframes at least
//      --min_gap apart within --radius metres, registered by PCL (GICP, NDT or LIO-SAM's
//      point-to-point ICP; point-to-point or point-to-line ICP in 2D) from the relative pose
//      there. --proposal odometry (keyframes' default): every such pair of the odometry, at
//      most --max_candidates (eval::proposeLoopCandidates); --proposal estimate (CARMEN's
//      default: wheel odometry drifts by metres between revisits): keyframe by keyframe, the
//      nearest one in the graph's current estimate, the graph optimised again after an accepted
//      edge it disagrees with (eval::closeLoopsIncrementally, LIO-SAM's loop thread). With
//      --lookalikes N, also N pairs far apart in the odometry registered from four headings (what a
//      place recognizer's false matches hand over);
//   3. each candidate asked the preset's loop verdict exactly as check_alignment with
//      loop_closure answers it (online::judgePair with coral::loopClosureVerdict); --gate
//      fitness instead accepts PCL's fitness score <= --max_fitness (LIO-SAM's 0.3), --gate
//      none every candidate, for comparison; --front_end scan_matching first replaces each odometry
//      step by its registration where the stream verdict accepts it (or by the pose the
//      verdict's own registration reached, ros_eval::streamVerdictDecision), --front_end
//      calibrated keeps the odometry with its yaw calibrated on those steps
//      (eval::calibratedOdometry); either writes every step as OUT_DIR/front_end.csv;
//   4. a pose graph of the odometry edges and the accepted loop edges (the pose the verdict
//      offers when it accepts a registered one, else the candidate's), optimised with Ceres
//      (eval/pose_graph.hpp), written as OUT_DIR/trajectory.tum and trajectory.kitti, and every
//      candidate with its verdict as OUT_DIR/candidates.csv.
// With --pcm PROBABILITY the back end checks the accepted loop edges (PCM, Mangelson et al. 2018;
// eval/pairwise_consistency.hpp): each must close a cycle with the odometry between its ends
// within the chi-square bound of that probability (with --proposal estimate before it enters
// the running graph), and of those only the largest pairwise consistent set is kept; the graph
// is solved from the odometry with them. It catches an edge the gate let through where the
// odometry is as good as its sigmas (not on Intel's wheel odometry: doc/loop_closure.md).
// With --reference FILE (KITTI layout, one pose per keyframe) it also prints the ATE of the
// odometry and of the graph against it; with --relations FILE (CARMEN) the benchmark's relation
// error of both (Kuemmerle et al. 2009, eval/log_nodes.hpp).
//   rosrun coral_introspection coral_pose_graph --config PRESET.yaml [--classifier FILE.yaml]
//       (--keyframes DIR | --carmen LOG [--keyframe_distance M] [--keyframe_angle DEG])
//       --out_dir DIR [--front_end odometry|scan_matching|calibrated] [--proposal
//       odometry|estimate]
//       [--registration R] [--radius M] [--min_gap N] [--max_candidates N] [--lookalikes N]
//       [--gate verdict|fitness|none] [--max_fitness F] [--pcm PROBABILITY]
//       [--reference FILE | --relations FILE]
// Exit 0 on success, 2 with a message for bad arguments or unreadable data.
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "coral_introspection/coral/types.hpp"
#include "coral_introspection/eval/carmen_log.hpp"
#include "coral_introspection/eval/cloud_io.hpp"
#include "coral_introspection/eval/incremental_loops.hpp"
#include "coral_introspection/eval/keyframe_sequence.hpp"
#include "coral_introspection/eval/log_nodes.hpp"
#include "coral_introspection/eval/loop_candidates.hpp"
#include "coral_introspection/eval/pairwise_consistency.hpp"
#include "coral_introspection/eval/pose_graph.hpp"
#include "coral_introspection/eval/tool_args.hpp"
#include "coral_introspection/online/introspector.hpp"
#include "coral_introspection/ros_eval/preset_file.hpp"
#include "coral_introspection/ros_eval/stream_decision.hpp"

using namespace coral_introspection;

namespace {

constexpr const char* kUsage =
    "usage: coral_pose_graph --config PRESET.yaml [--classifier FILE.yaml] (--keyframes DIR | "
    "--carmen LOG.clf[.bz2] [--keyframe_distance M (default 1)] [--keyframe_angle DEG (default "
    "30)]) --out_dir DIR [--front_end odometry|scan_matching|calibrated (default odometry)] "
    "[--proposal "
    "odometry|estimate (default: odometry for --keyframes, estimate for --carmen)] "
    "[--registration gicp|ndt|icp (3D, default gicp) | icp|point_to_line (2D, default icp)] "
    "[--radius M (default 3)] [--min_gap N (keyframes, default 50; 30 for --carmen)] "
    "[--max_candidates N (--proposal odometry, default 60)] [--lookalikes N (default 0)] "
    "[--gate verdict|fitness|none (default verdict)] [--max_fitness F (default 0.3, --gate "
    "fitness)] [--pcm PROBABILITY (e.g. 0.99; default off)] [--reference FILE (KITTI poses: ATE) | "
    "--relations FILE (--carmen: benchmark "
    "relation error)]";

int fail(const std::string& msg) { return eval::toolError("coral_pose_graph", msg, kUsage); }

// How the front end measured a step: its registration as the stream verdict accepted it, the
// pose the verdict's own registration reached, or not at all (the odometry's step stays).
struct FrontEndStep {
  const char* source = "odometry";
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();  // b in a's frame, as measured
};

// OUT_DIR/front_end.csv: one row per odometry step (keyframe b - 1 to b).
bool writeFrontEndSteps(const std::string& path, const std::vector<eval::TrainingScan>& scans,
                        const std::vector<FrontEndStep>& steps, std::string* error) {
  std::ofstream out(path);
  if (!out) {
    *error = "cannot write " + path;
    return false;
  }
  out << "a,b,stamp_a,stamp_b,source,x,y,z,yaw_deg\n";
  for (std::size_t k = 0; k < steps.size(); ++k) {
    const Eigen::Vector3d t = steps[k].T.translation();
    out << k << ',' << k + 1 << ',' << std::to_string(scans[k].stamp) << ','
        << std::to_string(scans[k + 1].stamp) << ',' << steps[k].source << ',' << t.x() << ','
        << t.y() << ',' << t.z() << ',' << coral::yawOf(steps[k].T.rotation()) * 180.0 / M_PI
        << '\n';
  }
  return static_cast<bool>(out);
}

// Keyframe odometry (lidar-inertial) is good to a few cm per keyframe; a registered loop edge
// to about the tolerance's tenth (coral_loop_eval's settings). A CARMEN log's wheel odometry:
// eval::kLogOdometrySigmaT/R.
constexpr double kOdomSigmaT = 0.05, kOdomSigmaR = 0.01;
// How far (log lines) a relation's scan may lie from a keyframe to be measured through the raw
// odometry between them (eval::LogNodes): no bound. Keyframes are taken by the odometry's motion
// (eval::logKeyframes), so a scan lies within about --keyframe_distance / --keyframe_angle of
// odometry of its nearest keyframe however many lines apart they are (a robot standing still
// adds lines, not motion). (Intel's 639 unmeasured relations of before came from
// eval::logLineAt, not from the former bound of 200 lines.)
constexpr int kAttachLines = std::numeric_limits<int>::max();

// The verdict and the reason only: a PairJudgement also holds the prepared pair (grids,
// filtered clouds, a few MB per dense pair), which is not kept for every candidate.
struct Decided {
  eval::LoopCandidate c;
  coral::AlignmentVerdict v;  // --gate verdict only
  std::string reason;         // why there is no verdict (empty when v.valid)
  bool accepted = false;
  bool inconsistent = false;                                 // accepted, then left out by --pcm
  Eigen::Isometry3d T_edge = Eigen::Isometry3d::Identity();  // the loop edge when accepted
};

}  // namespace

int main(int argc, char** argv) {
  eval::ToolArgs args;
  if (const auto exit = eval::readCommandLine(
          "coral_pose_graph", kUsage, argc, argv,
          {"--config", "--classifier", "--keyframes", "--carmen", "--keyframe_distance",
           "--keyframe_angle", "--out_dir", "--proposal", "--registration", "--radius", "--min_gap",
           "--max_candidates", "--lookalikes", "--gate", "--max_fitness", "--reference",
           "--relations", "--front_end", "--pcm"},
          {}, &args))
    return *exit;
  const std::string config = args.get("--config"), classifier = args.get("--classifier"),
                    keyframes = args.get("--keyframes"), carmen = args.get("--carmen"),
                    out_dir = args.get("--out_dir"), reference = args.get("--reference"),
                    relations_path = args.get("--relations");
  if (config.empty() || keyframes.empty() == carmen.empty() || out_dir.empty())
    return fail("--config, --out_dir and one of --keyframes or --carmen are required");
  const std::string input = carmen.empty() ? keyframes : carmen;
  if (carmen.empty() &&
      (args.has("--keyframe_distance") || args.has("--keyframe_angle") || !relations_path.empty()))
    return fail("--keyframe_distance, --keyframe_angle and --relations go with --carmen");
  if (!carmen.empty() && !reference.empty())
    return fail("--reference goes with --keyframes (a CARMEN log is measured by --relations)");
  std::string err, gate, proposal, front_end;
  if (!eval::choiceOption(args, "--gate", {"verdict", "fitness", "none"}, &gate, &err) ||
      !eval::choiceOption(args, "--front_end", {"odometry", "scan_matching", "calibrated"},
                          &front_end, &err) ||
      !eval::choiceOption(args, "--proposal",
                          carmen.empty() ? std::vector<std::string>{"odometry", "estimate"}
                                         : std::vector<std::string>{"estimate", "odometry"},
                          &proposal, &err))
    return fail(err);
  if (front_end == "calibrated" && carmen.empty())
    return fail("--front_end calibrated needs --carmen (it calibrates a planar wheel odometry)");
  if (proposal == "estimate" && args.has("--max_candidates"))
    return fail(
        "--max_candidates goes with --proposal odometry (estimate proposes one "
        "candidate per keyframe)");
  double max_fitness = 0.3;  // LIO-SAM's historyFitnessScoreThreshold
  if (!eval::numberOption(args, "--max_fitness", max_fitness, &max_fitness, &err)) return fail(err);
  if (!(max_fitness > 0.0)) return fail("--max_fitness must be > 0 (m^2)");
  eval::PairwiseConsistencyConfig pcm;
  const bool use_pcm = args.has("--pcm");
  if (!eval::numberOption(args, "--pcm", pcm.probability, &pcm.probability, &err)) return fail(err);
  if (const std::string e = pcm.validate(); use_pcm && !e.empty()) return fail("--pcm: " + e);
  // gmapping's linearUpdate 1 m; its angularUpdate 0.5 rad, ~30 deg.
  double keyframe_distance = 1.0, keyframe_angle_deg = 30.0;
  if (!eval::numberOption(args, "--keyframe_distance", keyframe_distance, &keyframe_distance,
                          &err) ||
      !eval::numberOption(args, "--keyframe_angle", keyframe_angle_deg, &keyframe_angle_deg, &err))
    return fail(err);
  if (!(keyframe_distance > 0.0) || !(keyframe_angle_deg > 0.0))
    return fail("--keyframe_distance and --keyframe_angle must be > 0 (m, deg)");
  // The preset, then the classifier file over it, key by key (as coral_check).
  std::vector<std::string> presets = {config};
  if (!classifier.empty()) presets.push_back(classifier);
  ros_adapters::NodeConfig node;
  if (!ros_eval::loadPresetFiles(presets, &node, &err)) return fail(err);
  if (node.input_type != ros_adapters::InputType::kPointCloud)
    return fail(config + ": keyframes are point clouds; use a lidar preset");
  const int dim = node.online.coral.dimension;
  if (!carmen.empty() && dim != 2)
    return fail(config + ": a CARMEN log holds 2D laser scans; use a 2D preset (lidar_2d.yaml)");
  online::IntrospectorConfig loop = node.online;
  loop.verdict = coral::loopClosureVerdict(node.online.verdict);

  // Candidates: the evaluation's keyframe settings (3 m, 50 keyframes, 60 revisits; 30 keyframes
  // of a log), changed by the options; no look-alike places unless asked for.
  eval::LoopCandidateConfig cand = eval::evaluationCandidates(3, node.online.verdict.tolerance);
  cand.dimension = dim;
  if (dim == 2) cand.registration = "icp";
  if (!carmen.empty()) cand.min_index_gap = 30;
  cand.max_lookalike_pairs = 0;
  if (args.has("--registration")) cand.registration = args.get("--registration");
  if (!eval::numberOption(args, "--radius", cand.radius, &cand.radius, &err) ||
      !eval::intOption(args, "--min_gap", cand.min_index_gap, 1, 1000000, &cand.min_index_gap,
                       &err) ||
      !eval::intOption(args, "--max_candidates", cand.max_radius_candidates, 1, 1000000,
                       &cand.max_radius_candidates, &err) ||
      !eval::intOption(args, "--lookalikes", 0, 0, 1000000, &cand.max_lookalike_pairs, &err))
    return fail(err);
  if (!(cand.radius > 0.0)) return fail("--radius must be > 0 (m)");
  // Look-alikes: pairs farther apart than the radius by a margin (the evaluation's 8 m for 3 m).
  cand.lookalike_min_distance = std::max(cand.lookalike_min_distance, cand.radius + 5.0);
  if (const std::string e = cand.validate(); !e.empty()) return fail("--registration: " + e);

  // 1. Keyframes and their odometry.
  std::vector<eval::TrainingScan> scans;
  coral::Isometries odom, ref;
  std::vector<eval::CarmenLaserScan> log;
  std::vector<int> log_lines;  // --carmen: each keyframe's FLASER line
  std::vector<eval::Relation> relations;
  if (carmen.empty()) {
    eval::KeyframeSequenceConfig seq;
    seq.poses_file = "odom_poses.txt";
    seq.planar_ok = dim == 2;  // a 2D preset reads PCDs with x and y only as planar scans
    if (!eval::loadKeyframeSequence(keyframes, seq, nullptr, &scans, &odom, &err)) return fail(err);
    if (scans.size() < 2) return fail(keyframes + ": fewer than two keyframes");
  } else if (!eval::readCarmenLog(carmen, &log, &err) ||
             !eval::logKeyframes(log, eval::LaserGeometry{}, keyframe_distance,
                                 keyframe_angle_deg * M_PI / 180.0, &scans, &odom, &log_lines,
                                 &err)) {
    return fail(carmen + ": " + err);
  }
  if (!reference.empty()) {
    if (!eval::readKittiPoses(reference, &ref, &err)) return fail(err);
    if (ref.size() < scans.size()) return fail(reference + ": fewer poses than keyframes");
    ref.resize(scans.size());
  }
  if (!relations_path.empty() && !eval::readRelations(relations_path, &relations, &err))
    return fail(err);
  // Written before the work, so that a wrong folder fails at once.
  const std::string csv_path = out_dir + "/candidates.csv";
  std::ofstream csv(csv_path);
  if (!csv) return fail("cannot write " + csv_path + " (does --out_dir exist?)");

  // The front end: each step of the odometry registered and put to the stream verdict (the
  // package's use for odometry); an accepted registration replaces the step (scan_matching), or
  // the accepted ones calibrate the odometry's yaw (calibrated).
  int steps_matched = 0;
  eval::OdometryYawModel yaw_model;
  std::vector<FrontEndStep> fe_steps;
  for (std::size_t k = 1; k < odom.size(); ++k)
    fe_steps.push_back({"odometry", odom[k - 1].inverse() * odom[k]});
  const eval::LoopDecision verdict = ros_eval::streamVerdictDecision(scans, node.online);
  const eval::LoopDecision stream = [&](const eval::LoopCandidate& c, Eigen::Isometry3d* T) {
    if (!verdict(c, T)) return false;
    fe_steps[c.a] = {T->isApprox(c.T_a_b) ? "registration" : "verdict_registration", *T};
    return true;
  };
  if (front_end == "scan_matching")
    odom = eval::scanMatchedOdometry(scans, odom, cand, stream, &steps_matched);
  if (front_end == "calibrated" &&
      !eval::calibratedOdometry(scans, odom, cand, stream, &odom, &yaw_model, &err))
    return fail(err);
  if (front_end != "odometry" &&
      !writeFrontEndSteps(out_dir + "/front_end.csv", scans, fe_steps, &err))
    return fail(err);

  // 3. The gate, asked about one registered candidate.
  auto decide = [&](const eval::LoopCandidate& c) {
    Decided d;
    d.c = c;
    d.T_edge = c.T_a_b;
    if (gate == "verdict") {
      online::PairJudgement j =
          online::judgePair(scans[c.a].scan, scans[c.b].scan, c.T_a_b, loop, false);
      d.v = std::move(j.verdict);
      d.reason = std::move(j.reason);
      d.accepted = d.v.valid && d.v.aligned;
      // Accepted registered from the pose: the verdict offers that pose (refined_transform).
      if (d.accepted && d.v.refined) d.T_edge = c.T_a_b * d.v.refinement.delta;
    } else {
      d.accepted = gate == "none" || (c.converged && c.fitness <= max_fitness);
    }
    return d;
  };
  auto loopEdge = [](const Decided& d) {
    return eval::PoseGraphEdge{d.c.a, d.c.b, d.T_edge, eval::kLoopEdgeSigmaT, eval::kLoopEdgeSigmaR,
                               true};
  };

  // 2. Candidates and 3. their verdicts; 4. the pose graph.
  const bool log_odometry = !carmen.empty();
  const std::vector<eval::PoseGraphEdge> odom_edges =
      eval::odometryEdges(odom, log_odometry ? eval::kLogOdometrySigmaT : kOdomSigmaT,
                          log_odometry ? eval::kLogOdometrySigmaR : kOdomSigmaR);
  const eval::PoseGraphConfig graph_cfg = eval::robustContinuationConfig(dim);
  std::vector<Decided> decided;
  eval::LoopCandidateConfig batch = cand;  // --proposal estimate: the look-alikes only
  if (proposal == "estimate") batch.max_radius_candidates = 0;
  std::vector<eval::LoopCandidate> proposed;
  if (!eval::proposeLoopCandidates(scans, odom, batch, &proposed, &err)) return fail(err);
  for (const eval::LoopCandidate& c : proposed) decided.push_back(decide(c));
  std::vector<eval::PoseGraphEdge> loop_edges;
  std::vector<std::size_t> owner;  // loop_edges[s] is decided[owner[s]]'s
  for (std::size_t i = 0; i < decided.size(); ++i)
    if (decided[i].accepted) {
      loop_edges.push_back(loopEdge(decided[i]));
      owner.push_back(i);
    }
  // --pcm, first part: a loop edge enters the graph only when it agrees with the odometry between
  // its ends (eval::odometryInconsistentLoops); in estimate mode before it can bend the estimate
  // that later proposals start from.
  if (use_pcm) pcm.dimension = dim;
  std::string check_error;
  auto odometryConsistent = [&](const eval::PoseGraphEdge& e) {
    std::vector<eval::PoseGraphEdge> edges = odom_edges;
    edges.push_back(e);
    std::vector<int> off;
    if (!eval::odometryInconsistentLoops(edges, pcm, &off, &check_error)) return false;
    return off.empty();
  };
  coral::Isometries poses = odom;
  eval::PoseGraphResult res;
  int solves = 1;
  if (proposal == "estimate") {
    eval::IncrementalLoops inc;
    auto backEnd = [&](const eval::LoopCandidate& c, Eigen::Isometry3d* T_edge) {
      decided.push_back(decide(c));
      *T_edge = decided.back().T_edge;
      return decided.back().accepted;
    };
    auto admit = [&](const eval::PoseGraphEdge& e, int seed) {
      const bool ok = odometryConsistent(e);
      decided[seed < 0 ? decided.size() - 1 : owner[seed]].inconsistent = !ok;
      return ok;
    };
    if (!eval::closeLoopsIncrementally(scans, odom, cand, odom_edges, loop_edges, graph_cfg,
                                       backEnd, &poses, &inc, &err,
                                       use_pcm ? eval::EdgeCheck(admit) : eval::EdgeCheck()))
      return fail("pose graph: " + err);
    if (!check_error.empty()) return fail(check_error);
    solves = inc.solves;
    res = inc.last;
  } else if (!use_pcm) {  // with --pcm the graph is solved once, after the check (5.)
    std::vector<eval::PoseGraphEdge> edges = odom_edges;
    edges.insert(edges.end(), loop_edges.begin(), loop_edges.end());
    if (!eval::optimizePoseGraph(edges, graph_cfg, &poses, &res))
      return fail("pose graph: " + res.error);
  }
  // 5. --pcm, second part: the loop edges in the graph checked against each other (PCM's largest
  // pairwise consistent set; in odometry mode the odometry check too); the graph solved from the
  // odometry with the rest (estimate mode solved it as it went: again only when some are out).
  int odometry_out = 0, pairwise_out = 0;
  if (use_pcm) {
    std::vector<eval::PoseGraphEdge> edges = odom_edges;
    std::vector<std::size_t> in_graph;  // edges[odom_edges.size() + i] is decided[in_graph[i]]'s
    for (std::size_t i = 0; i < decided.size(); ++i) {
      odometry_out += decided[i].inconsistent ? 1 : 0;  // estimate mode: refused on arrival
      if (decided[i].accepted && !decided[i].inconsistent) {
        edges.push_back(loopEdge(decided[i]));
        in_graph.push_back(i);
      }
    }
    std::vector<int> removed;
    int by_odometry = 0;
    if (!eval::inconsistentLoopEdges(edges, pcm, &removed, &by_odometry, &err)) return fail(err);
    for (const int r : removed) decided[in_graph[r - odom_edges.size()]].inconsistent = true;
    odometry_out += by_odometry;
    pairwise_out = static_cast<int>(removed.size()) - by_odometry;
    if (proposal != "estimate" || !removed.empty()) {
      poses = odom;
      if (!eval::optimizePoseGraph(eval::keptEdges(edges, removed), graph_cfg, &poses, &res))
        return fail("pose graph (pcm): " + res.error);
      if (proposal == "estimate") ++solves;
    }
  }
  const int left_out = odometry_out + pairwise_out;
  int accepted = 0, revisits = 0;
  for (const Decided& d : decided) {
    accepted += d.accepted ? 1 : 0;
    revisits += d.c.source == "radius" ? 1 : 0;
  }

  std::vector<double> stamps;
  for (const eval::TrainingScan& s : scans) stamps.push_back(s.stamp);
  if (!eval::writeTumTrajectory(out_dir + "/trajectory.tum", stamps, poses, &err) ||
      !eval::writeKittiPoses(out_dir + "/trajectory.kitti", poses, &err))
    return fail(err);
  csv << "a,b,source,init_yaw_deg,fitness,converged,accepted,rejected_by,reason,refined,x,y,z,"
         "yaw_deg,pcm_inconsistent\n";
  auto field = [](std::string text) {  // a sentence as one CSV cell
    for (char& ch : text) ch = ch == ',' || ch == '\n' ? ';' : ch;
    return text;
  };
  for (const Decided& d : decided) {
    const coral::AlignmentVerdict& v = d.v;
    const Eigen::Vector3d t = d.c.T_a_b.translation();
    csv << d.c.a << ',' << d.c.b << ',' << d.c.source << ',' << d.c.init_yaw_deg << ','
        << eval::fitnessCell(d.c.fitness) << ',' << d.c.converged << ',' << d.accepted << ','
        << field(v.rejected_by) << ',' << field(d.reason) << ',' << (d.accepted && v.refined) << ','
        << t.x() << ',' << t.y() << ',' << t.z() << ','
        << coral::yawOf(d.c.T_a_b.rotation()) * 180.0 / M_PI << ',' << d.inconsistent << '\n';
  }
  if (!csv.flush()) return fail("cannot write " + csv_path);

  std::printf(
      "%s: %zu keyframes; %zu loop candidates (%d within %.1f m of the %s, %zu look-alike "
      "registrations), %d accepted by gate %s\n",
      input.c_str(), scans.size(), decided.size(), revisits, cand.radius,
      proposal == "estimate" ? "graph's estimate" : "odometry",
      decided.size() - static_cast<std::size_t>(revisits), accepted, gate.c_str());
  if (decided.empty())
    std::printf("no loop candidates: the trajectory is the odometry's (try a larger --radius)\n");
  std::printf(
      "pose graph: %zu odometry and %d loop edges, Ceres %s (%d solve%s); %s/trajectory.tum, "
      ".kitti, candidates.csv written\n",
      scans.size() - 1, accepted - left_out,
      res.converged ? "converged" : "stopped at its iteration cap", solves, solves == 1 ? "" : "s",
      out_dir.c_str());
  if (use_pcm)
    std::printf(
        "pcm (chi-square %.3g): of %d accepted loop edges, %d left out as they disagree with the "
        "odometry between their ends, %d more as they are not in the largest pairwise "
        "consistent set\n",
        pcm.probability, accepted, odometry_out, pairwise_out);
  const auto second_tries = std::count_if(
      fe_steps.begin(), fe_steps.end(),
      [](const FrontEndStep& f) { return std::string(f.source) == "verdict_registration"; });
  if (front_end == "scan_matching")
    std::printf(
        "front end: %d of %zu odometry steps replaced by their registration (the stream "
        "verdict accepted it; %td at the pose the verdict's own registration reached)\n",
        steps_matched, scans.size() - 1, second_tries);
  if (front_end == "calibrated")
    std::printf(
        "front end: odometry yaw calibrated on %d of %zu steps (registered, accepted by the "
        "stream verdict; %td at the pose the verdict's own registration reached): %.4f rad "
        "per rad turned %+.4f rad per m; step yaw rms %.4f -> %.4f rad\n",
        yaw_model.steps, scans.size() - 1, second_tries, yaw_model.gain, yaw_model.bias_per_m,
        yaw_model.rms_before, yaw_model.rms_after);
  if (front_end != "odometry")
    std::printf("front end: every step in %s/front_end.csv\n", out_dir.c_str());
  if (!ref.empty())
    std::printf("ATE against %s: odometry %.3f m, graph %.3f m\n", reference.c_str(),
                eval::absoluteTrajectoryError(odom, ref, dim),
                eval::absoluteTrajectoryError(poses, ref, dim));
  if (!relations.empty()) {
    const eval::LogNodes nodes(log, log_lines);
    const eval::RelationError o = eval::relationError(nodes, odom, relations, kAttachLines);
    const eval::RelationError g = eval::relationError(nodes, poses, relations, kAttachLines);
    std::printf(
        "relation error against %s (%d of %zu relations): odometry %.3f m / %.2f deg, graph "
        "%.3f m / %.2f deg\n",
        relations_path.c_str(), g.n, relations.size(), o.translation, o.rotation_deg, g.translation,
        g.rotation_deg);
  }
  return 0;
}
