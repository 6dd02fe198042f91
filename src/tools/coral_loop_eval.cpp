// coral_loop_eval: loop-closure candidates of a real sequence (eval/loop_candidates.hpp)
// judged by the preset's verdict and its parts, one CSV row per candidate.
//   rosrun coral_introspection coral_loop_eval --config PRESET.yaml
//       (--keyframes DIR | --carmen LOG.clf.bz2 --corrected POSES.csv) [--out FILE.csv]
// Keyframes: DIR/optimized_poses.txt is the reference, DIR/odom_poses.txt the odometry.
// CARMEN: the corrected poses are the reference, the log's raw odometry the odometry, and
// every benchmark relation (LOG's .relations) joining scans more than 30 log lines apart is
// a true candidate as it is ("relation").
// Exit 0 on success, 2 with a message for bad arguments or unreadable data.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "coral_introspection/eval/carmen_log.hpp"
#include "coral_introspection/eval/cloud_io.hpp"
#include "coral_introspection/eval/keyframe_sequence.hpp"
#include "coral_introspection/eval/loop_candidates.hpp"
#include "coral_introspection/online/introspector.hpp"
#include "coral_introspection/ros_eval/preset_file.hpp"

using namespace coral_introspection;

namespace {

constexpr const char* kUsage =
    "usage: coral_loop_eval --config PRESET.yaml (--keyframes DIR | --carmen LOG.clf.bz2 "
    "--corrected POSES.csv) [--out FILE.csv]";

int fail(const std::string& msg) {
  std::fprintf(stderr, "coral_loop_eval: %s\n%s\n", msg.c_str(), kUsage);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::string config, keyframes, carmen, corrected, out_path;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "-h" || arg == "--help") {
      std::printf("%s\n", kUsage);
      return 0;
    }
    if (i + 1 >= argc) return fail("missing value after " + arg);
    const std::string val = argv[++i];
    if (arg == "--config")
      config = val;
    else if (arg == "--keyframes")
      keyframes = val;
    else if (arg == "--carmen")
      carmen = val;
    else if (arg == "--corrected")
      corrected = val;
    else if (arg == "--out")
      out_path = val;
    else
      return fail("unknown argument " + arg);
  }
  if (config.empty() || keyframes.empty() == carmen.empty() || carmen.empty() != corrected.empty())
    return fail("--config and either --keyframes or --carmen with --corrected are required");
  ros_adapters::NodeConfig node;
  core::VerdictConfig verdict;
  std::string err;
  if (!ros_adapters::loadPresetFile(config, &node, &verdict, &err))
    return fail(config + ": " + err);
  online::IntrospectorConfig judge_cfg = node.online;
  judge_cfg.verdict.method = core::VerdictMethod::kBoth;  // every term of the verdict

  core::LoopCandidateConfig lc;
  lc.dimension = node.online.coral.dimension;
  lc.tolerance = verdict.tolerance;
  std::vector<core::TrainingScan> scans;
  core::Isometries ref, odom;
  std::vector<core::LoopCandidate> candidates;
  std::vector<core::TrainingScan> rel_scans;
  std::vector<core::ScanPair> rel_pairs;
  if (!keyframes.empty()) {
    core::KeyframeSequenceConfig kc;
    if (!core::loadKeyframeSequence(keyframes, kc, nullptr, &scans, &ref, &err)) return fail(err);
    kc.poses_file = "odom_poses.txt";
    if (!core::readKittiPoses(keyframes + "/" + kc.poses_file, &odom, &err)) return fail(err);
    odom.resize(scans.size());
  } else {
    std::vector<core::CarmenLaserScan> log;
    core::LaserGeometry geometry;
    std::vector<int> raw;
    if (!core::readCarmenLog(carmen, &log, &err) ||
        !core::correctedSequence(log, corrected, geometry, &scans, &ref, &odom, &raw, &err))
      return fail(err);
    lc.min_index_gap = 30;
    std::string rel = carmen;
    for (const char* ext : {".bz2", ".clf"})
      if (rel.size() > 4 && rel.compare(rel.size() - 4, 4, ext) == 0) rel.resize(rel.size() - 4);
    std::vector<core::Relation> relations, loops;
    if (!core::readRelations(rel + ".relations", &relations, &err)) return fail(err);
    // Loop relations: more than 30 log lines apart (by stamp order in the log).
    std::vector<double> stamps;
    for (const auto& l : log) stamps.push_back(l.stamp);
    auto line = [&](double t) {
      return static_cast<int>(std::lower_bound(stamps.begin(), stamps.end(), t - 1e-4) -
                              stamps.begin());
    };
    for (const core::Relation& r : relations)
      if (std::abs(line(r.t1) - line(r.t2)) > 30) loops.push_back(r);
    int unmatched = 0;
    if (!core::relationPairs(log, loops, geometry, &rel_scans, &rel_pairs, &unmatched, &err))
      return fail(err);
    std::cerr << loops.size() << " loop relations (" << unmatched << " unmatched)\n";
  }
  if (!core::buildLoopCandidates(scans, ref, odom, lc, &candidates, &err)) return fail(err);

  std::ofstream file;
  if (!out_path.empty()) {
    file.open(out_path);
    if (!file) return fail("cannot write " + out_path);
  }
  std::ostream& out = out_path.empty() ? std::cout : file;
  out << "a,b,source,init_yaw,is_true,error_t,error_r,converged,fitness,valid,classifier_p,"
         "relative_score,relative_misaligned,q,h_joint,h_sep,overlap\n";
  auto row = [&](const core::Scan& a, const core::Scan& b, const core::LoopCandidate& c) {
    const core::AlignmentVerdict v = online::judgePair(a, b, c.T_a_b, judge_cfg, false).verdict;
    out << c.a << ',' << c.b << ',' << c.source << ',' << c.init_yaw_deg << ',' << c.is_true << ','
        << c.error_translation << ',' << c.error_rotation_deg << ',' << c.converged << ','
        << c.fitness << ',' << v.valid << ',' << v.classifier.probability << ',' << v.relative.score
        << ',' << v.relative.misaligned << ',' << v.coral.quality << ',' << v.coral.h_joint << ','
        << v.coral.h_sep << ',' << v.coral.overlap << "\n";
  };
  for (const core::LoopCandidate& c : candidates) row(scans[c.a].scan, scans[c.b].scan, c);
  for (const core::ScanPair& p : rel_pairs) {
    core::LoopCandidate c;
    c.a = p.a;
    c.b = p.b;
    c.source = "relation";
    c.T_a_b = p.T_a_b;
    c.is_true = true;
    c.converged = true;
    row(rel_scans[p.a].scan, rel_scans[p.b].scan, c);
  }
  int t = 0, f = 0;
  for (const auto& c : candidates) (c.is_true ? t : f)++;
  std::cerr << "candidates: " << t << " true, " << f << " false (registered), " << rel_pairs.size()
            << " relations\n";
  return 0;
}
