// coral_pose_graph: the consumer of the loop verdict on a keyframe sequence of one's own, with
// no reference poses: what a SLAM back end does with it, small enough to read and copy
// (coral_loop_eval is the evaluation, which needs reference poses to label candidates).
//   1. keyframes DIR/Scans/NNNNNN.pcd (or .bin) and their odometry DIR/odom_poses.txt (KITTI
//      layout, world_T_body; DIR/times.txt optional), as FAST-LIO / scan-context pose graphs
//      write them (eval/keyframe_sequence.hpp); under a 2D preset a PCD with fields x and y
//      only is a planar scan (z = 0);
//   2. loop candidates proposed as LIO-SAM and hdl_graph_slam propose them: keyframes at least
//      --min_gap apart whose odometry poses lie within --radius metres, registered by PCL (GICP,
//      NDT or LIO-SAM's point-to-point ICP) from the odometry's relative pose; with
//      --lookalikes N, also N pairs far apart in the odometry registered from four headings
//      (what a place recognizer's false matches hand over) (eval::proposeLoopCandidates);
//   3. each candidate asked the preset's loop verdict exactly as check_alignment with
//      loop_closure answers it (online::judgePair with coral::loopClosureVerdict); --gate
//      fitness instead accepts PCL's fitness score <= --max_fitness (LIO-SAM's 0.3), --gate
//      none every candidate, for comparison;
//   4. a pose graph of the odometry edges and the accepted loop edges (the pose the verdict
//      offers when it accepts a registered one, else the candidate's), optimised with Ceres
//      (eval/pose_graph.hpp), written as OUT_DIR/trajectory.tum and trajectory.kitti, and every
//      candidate with its verdict as OUT_DIR/candidates.csv.
// With --reference FILE (KITTI layout, one pose per keyframe) it also prints the ATE of the
// odometry and of the graph against it.
//   rosrun coral_introspection coral_pose_graph --config PRESET.yaml [--classifier FILE.yaml]
//       --keyframes DIR --out_dir DIR [--registration gicp|ndt|icp] [--radius M] [--min_gap N]
//       [--max_candidates N] [--lookalikes N] [--gate verdict|fitness|none] [--max_fitness F]
//       [--reference FILE]
// Exit 0 on success, 2 with a message for bad arguments or unreadable data.
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "coral_introspection/coral/types.hpp"
#include "coral_introspection/eval/cloud_io.hpp"
#include "coral_introspection/eval/keyframe_sequence.hpp"
#include "coral_introspection/eval/loop_candidates.hpp"
#include "coral_introspection/eval/pose_graph.hpp"
#include "coral_introspection/eval/tool_args.hpp"
#include "coral_introspection/online/introspector.hpp"
#include "coral_introspection/ros_eval/preset_file.hpp"

using namespace coral_introspection;

namespace {

constexpr const char* kUsage =
    "usage: coral_pose_graph --config PRESET.yaml [--classifier FILE.yaml] --keyframes DIR "
    "--out_dir DIR [--registration gicp|ndt|icp (default gicp)] [--radius M (default 3)] "
    "[--min_gap N (keyframes, default 50)] [--max_candidates N (default 60)] [--lookalikes N "
    "(default 0)] [--gate verdict|fitness|none (default verdict)] [--max_fitness F (default "
    "0.3, --gate fitness)] [--reference FILE (KITTI poses: ATE)]";

int fail(const std::string& msg) { return eval::toolError("coral_pose_graph", msg, kUsage); }

// Keyframe odometry (lidar-inertial) is good to a few cm per keyframe; a registered loop edge
// to about the tolerance's tenth (coral_loop_eval's settings).
constexpr double kOdomSigmaT = 0.05, kOdomSigmaR = 0.01;

// The verdict and the reason only: a PairJudgement also holds the prepared pair (grids,
// filtered clouds, a few MB per dense pair), which is not kept for every candidate.
struct Decided {
  eval::LoopCandidate c;
  coral::AlignmentVerdict v;  // --gate verdict only
  std::string reason;         // why there is no verdict (empty when v.valid)
  bool accepted = false;
  Eigen::Isometry3d T_edge = Eigen::Isometry3d::Identity();  // the loop edge when accepted
};

}  // namespace

int main(int argc, char** argv) {
  eval::ToolArgs args;
  if (const auto exit =
          eval::readCommandLine("coral_pose_graph", kUsage, argc, argv,
                                {"--config", "--classifier", "--keyframes", "--out_dir",
                                 "--registration", "--radius", "--min_gap", "--max_candidates",
                                 "--lookalikes", "--gate", "--max_fitness", "--reference"},
                                {}, &args))
    return *exit;
  const std::string config = args.get("--config"), classifier = args.get("--classifier"),
                    keyframes = args.get("--keyframes"), out_dir = args.get("--out_dir"),
                    reference = args.get("--reference");
  if (config.empty() || keyframes.empty() || out_dir.empty())
    return fail("--config, --keyframes and --out_dir are required");
  std::string err, gate;
  if (!eval::choiceOption(args, "--gate", {"verdict", "fitness", "none"}, &gate, &err))
    return fail(err);
  double max_fitness = 0.3;  // LIO-SAM's historyFitnessScoreThreshold
  if (!eval::numberOption(args, "--max_fitness", max_fitness, &max_fitness, &err)) return fail(err);
  if (!(max_fitness > 0.0)) return fail("--max_fitness must be > 0 (m^2)");
  // The preset, then the classifier file over it, key by key (as coral_check).
  std::vector<std::string> presets = {config};
  if (!classifier.empty()) presets.push_back(classifier);
  ros_adapters::NodeConfig node;
  if (!ros_eval::loadPresetFiles(presets, &node, &err)) return fail(err);
  if (node.input_type != ros_adapters::InputType::kPointCloud)
    return fail(config + ": keyframes are point clouds; use a lidar preset");
  const int dim = node.online.coral.dimension;
  online::IntrospectorConfig loop = node.online;
  loop.verdict = coral::loopClosureVerdict(node.online.verdict);

  // Candidates: the evaluation's keyframe settings (3 m, 50 keyframes, 60 revisits), changed by
  // the options; no look-alike places unless asked for.
  eval::LoopCandidateConfig cand = eval::evaluationCandidates(3, node.online.verdict.tolerance);
  cand.dimension = dim;
  if (dim == 2) cand.registration = "icp";
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
  eval::KeyframeSequenceConfig seq;
  seq.poses_file = "odom_poses.txt";
  seq.planar_ok = dim == 2;  // a 2D preset reads PCDs with x and y only as planar scans
  if (!eval::loadKeyframeSequence(keyframes, seq, nullptr, &scans, &odom, &err)) return fail(err);
  if (scans.size() < 2) return fail(keyframes + ": fewer than two keyframes");
  if (!reference.empty()) {
    if (!eval::readKittiPoses(reference, &ref, &err)) return fail(err);
    if (ref.size() < scans.size()) return fail(reference + ": fewer poses than keyframes");
    ref.resize(scans.size());
  }
  // Written before the work, so that a wrong folder fails at once.
  const std::string csv_path = out_dir + "/candidates.csv";
  std::ofstream csv(csv_path);
  if (!csv) return fail("cannot write " + csv_path + " (does --out_dir exist?)");

  // 2. Candidates, 3. the gate.
  std::vector<eval::LoopCandidate> proposed;
  if (!eval::proposeLoopCandidates(scans, odom, cand, &proposed, &err)) return fail(err);
  std::vector<Decided> decided;
  int accepted = 0;
  for (const eval::LoopCandidate& c : proposed) {
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
    accepted += d.accepted ? 1 : 0;
    decided.push_back(d);
  }

  // 4. The pose graph.
  std::vector<eval::PoseGraphEdge> edges = eval::odometryEdges(odom, kOdomSigmaT, kOdomSigmaR);
  for (const Decided& d : decided)
    if (d.accepted)
      edges.push_back({d.c.a, d.c.b, d.T_edge, eval::kLoopEdgeSigmaT, eval::kLoopEdgeSigmaR, true});
  coral::Isometries poses = odom;
  eval::PoseGraphResult res;
  if (!eval::optimizePoseGraph(edges, eval::robustContinuationConfig(dim), &poses, &res))
    return fail("pose graph: " + res.error);
  std::vector<double> stamps;
  for (const eval::TrainingScan& s : scans) stamps.push_back(s.stamp);
  if (!eval::writeTumTrajectory(out_dir + "/trajectory.tum", stamps, poses, &err) ||
      !eval::writeKittiPoses(out_dir + "/trajectory.kitti", poses, &err))
    return fail(err);
  csv << "a,b,source,init_yaw_deg,fitness,converged,accepted,rejected_by,reason,refined,x,y,z,"
         "yaw_deg\n";
  auto field = [](std::string text) {  // a sentence as one CSV cell
    for (char& ch : text) ch = ch == ',' || ch == '\n' ? ';' : ch;
    return text;
  };
  for (const Decided& d : decided) {
    const coral::AlignmentVerdict& v = d.v;
    const Eigen::Vector3d t = d.c.T_a_b.translation();
    csv << d.c.a << ',' << d.c.b << ',' << d.c.source << ',' << d.c.init_yaw_deg << ','
        << d.c.fitness << ',' << d.c.converged << ',' << d.accepted << ',' << field(v.rejected_by)
        << ',' << field(d.reason) << ',' << (d.accepted && v.refined) << ',' << t.x() << ','
        << t.y() << ',' << t.z() << ',' << coral::yawOf(d.c.T_a_b.rotation()) * 180.0 / M_PI
        << '\n';
  }
  if (!csv.flush()) return fail("cannot write " + csv_path);

  int revisits = 0;
  for (const eval::LoopCandidate& c : proposed) revisits += c.source == "radius" ? 1 : 0;
  std::printf(
      "%s: %zu keyframes; %zu loop candidates (%d within %.1f m of the odometry, %zu "
      "look-alike registrations), %d accepted by gate %s\n",
      keyframes.c_str(), scans.size(), proposed.size(), revisits, cand.radius,
      proposed.size() - revisits, accepted, gate.c_str());
  if (proposed.empty())
    std::printf("no loop candidates: the trajectory is the odometry's (try a larger --radius)\n");
  std::printf(
      "pose graph: %zu odometry and %d loop edges, Ceres %s; %s/trajectory.tum, .kitti, "
      "candidates.csv written\n",
      scans.size() - 1, accepted, res.converged ? "converged" : "stopped at its iteration cap",
      out_dir.c_str());
  if (!ref.empty())
    std::printf("ATE against %s: odometry %.3f m, graph %.3f m\n", reference.c_str(),
                eval::absoluteTrajectoryError(odom, ref, dim),
                eval::absoluteTrajectoryError(poses, ref, dim));
  return 0;
}
