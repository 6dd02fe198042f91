// Loop-closure candidates of the shared real sequences (eval/loop_candidates.hpp: revisits
// registered from the odometry, look-alike places registered by ICP from four headings, and
// on Intel the benchmark's loop relations) judged by the presets' loop-closure verdict
// (coral::loopClosureVerdict: relative check + the loop gate). The figures asserted are the
// ones doc/loop_closure.md reports (coral_loop_eval on the same candidates); the relative
// check alone accepts several times more false candidates on the same data. On ACES registered
// point-to-line, the pose graph of the accepted candidates after a back end's consistency check
// (eval::optimizePrunedPoseGraph, or pairwise consistency: eval::pairwiseInconsistentLoops)
// matches the oracle's. The lidar_2d loop gate's restart check (coral/restart_check.hpp)
// rejects the ACES relation registered 1.3 m off, one look-alike and an Intel relation
// registered 1 m off, and no true candidate; lidar_3d's the two Livox candidates GICP left
// off the revisit among ten times the look-alike places.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <random>

#include "coral_introspection/eval/carmen_loops.hpp"
#include "coral_introspection/eval/cloud_io.hpp"
#include "coral_introspection/eval/keyframe_sequence.hpp"
#include "coral_introspection/eval/log_nodes.hpp"
#include "coral_introspection/eval/loop_candidates.hpp"
#include "coral_introspection/eval/pairwise_consistency.hpp"
#include "coral_introspection/eval/pose_graph.hpp"
#include "coral_introspection/online/introspector.hpp"
#include "coral_introspection/ros_eval/preset_file.hpp"
#include "support/preset.hpp"
#include "support/test_data.hpp"

using namespace coral_introspection;

namespace {

struct LoopTally {
  int true_total = 0, true_accepted = 0, false_total = 0, false_accepted = 0;
  int false_accepted_relative = 0;  // the relative check alone
  // Accepted at the pose, then rejected by the loop gate's restart check: [false, true].
  int restart_rejected[2] = {0, 0};
};

// True when the loop verdict accepts.
bool judge(const ros_adapters::NodeConfig& node, const coral::Scan& a, const coral::Scan& b,
           const Eigen::Isometry3d& T_a_b, bool is_true, LoopTally* t) {
  online::IntrospectorConfig loop = node.online, rel = node.online;
  loop.verdict = coral::loopClosureVerdict(node.online.verdict);
  rel.verdict.method = coral::VerdictMethod::kRelative;
  const coral::AlignmentVerdict v = online::judgePair(a, b, T_a_b, loop, false).verdict;
  const bool accepted = v.valid && v.aligned;
  t->restart_rejected[is_true] += v.restart.better_elsewhere;
  (is_true ? t->true_total : t->false_total) += 1;
  (is_true ? t->true_accepted : t->false_accepted) += accepted;
  if (!is_true) {
    const coral::AlignmentVerdict r = online::judgePair(a, b, T_a_b, rel, false).verdict;
    t->false_accepted_relative += r.valid && r.aligned;
  }
  return accepted;
}

// What a test asserts: at least these many candidates, this share of true ones accepted, at
// most max_false false ones, the relative check alone accepting at least relative_factor
// times as many false ones (the gate's worth), and exactly restart_false false candidates and
// restart_true true ones rejected by the restart check after the verdict accepted them at the
// pose.
struct Expected {
  int min_true, min_false, true_percent, max_false, relative_factor, restart_false;
  int restart_true = 0;
};
// Under coral_test::pairStride() > 1 (sanitizers) a few candidates only: the bounds that hold
// for any subset (no more false accepted than measured on all).
void expectTally(const LoopTally& t, const Expected& e) {
  EXPECT_LE(t.false_accepted, e.max_false);
  EXPECT_LE(t.restart_rejected[1], e.restart_true);
  if (coral_test::pairStride() > 1) return;
  EXPECT_EQ(t.restart_rejected[0], e.restart_false);
  EXPECT_EQ(t.restart_rejected[1], e.restart_true);
  EXPECT_GE(t.true_total, e.min_true);
  EXPECT_GE(t.false_total, e.min_false);
  EXPECT_GE(t.true_accepted, t.true_total * e.true_percent / 100);
  EXPECT_GE(t.false_accepted_relative, e.relative_factor * std::max(1, t.false_accepted));
}

// The evaluation's candidate settings, with `lookalikes` look-alike pairs when > 0
// (coral_loop_eval --lookalikes); under the sanitizers' stride, that many times fewer.
eval::LoopCandidateConfig candidateConfig(int dimension, const coral::ToleranceConfig& tol,
                                          int lookalikes = 0) {
  eval::LoopCandidateConfig c = eval::evaluationCandidates(dimension, tol);
  if (lookalikes > 0) c.max_lookalike_pairs = lookalikes;
  const int s = static_cast<int>(coral_test::pairStride());
  c.max_radius_candidates = std::max(2, c.max_radius_candidates / s);
  c.max_lookalike_pairs = std::max(1, c.max_lookalike_pairs / s);
  return c;
}

// The preset `name` into *node and the evaluation's candidate settings with its tolerance.
eval::LoopCandidateConfig presetCandidates(const char* name, int dimension,
                                           ros_adapters::NodeConfig* node) {
  coral_test::loadPreset(name, node);
  return candidateConfig(dimension, node->online.verdict.tolerance);
}

// The hku1 Livox keyframes (scans, reference and odometry poses) and the loop candidates
// eval::buildLoopCandidates builds from them with `lc`.
struct LivoxLoop {
  std::vector<eval::TrainingScan> scans;
  coral::Isometries ref, odom;
  std::vector<eval::LoopCandidate> cands;
};
bool loadLivoxLoop(const std::string& dir, const eval::LoopCandidateConfig& lc, LivoxLoop* l,
                   std::string* err) {
  if (!eval::loadKeyframeSequence(dir, eval::KeyframeSequenceConfig(), nullptr, &l->scans, &l->ref,
                                  err) ||
      !eval::readKittiPoses(dir + "/odom_poses.txt", &l->odom, err))
    return false;
  l->odom.resize(l->scans.size());
  return eval::buildLoopCandidates(l->scans, l->ref, l->odom, lc, &l->cands, err);
}

void print(const char* name, const LoopTally& t) {
  std::cout << name << ": true accepted " << t.true_accepted << " / " << t.true_total
            << ", false accepted " << t.false_accepted << " / " << t.false_total
            << " (relative check alone: " << t.false_accepted_relative
            << "); rejected by the restart check " << t.restart_rejected[1] << " true, "
            << t.restart_rejected[0] << " false\n";
}

}  // namespace

TEST(LoopClosure, Lidar3dOnTheLivoxLoop) {
  CORAL_REQUIRE_DATA("hku1_livox_keyframes");
  ros_adapters::NodeConfig node;
  coral_test::loadPreset("lidar_3d", &node);
  LivoxLoop l;
  std::string err;
  ASSERT_TRUE(
      loadLivoxLoop(coral_data, candidateConfig(3, node.online.verdict.tolerance), &l, &err))
      << err;
  LoopTally t;
  for (const eval::LoopCandidate& c : l.cands)
    judge(node, l.scans[c.a].scan, l.scans[c.b].scan, c.T_a_b, c.is_true, &t);
  print("lidar_3d, hku1 Livox", t);
  // Measured (doc/loop_closure.md): 39 true, 164 false; loop verdict 39 true, 0 false
  // accepted; the relative check alone 17 false. The restart check rejects none of them (the
  // two it rejects are among ten times the look-alike places, test below).
  expectTally(t, {30, 120, 95, 0, 10, 0});
}

// A revisit seen from the same viewpoint, as a robot driving the same path sees it: every 4th
// pair of consecutive Livox keyframes at its reference pose, judged by the loop verdict. The
// Livox's narrow field of view leaves y and roll flat at many of them (Q rises along x, z,
// pitch and yaw); lidar_3d's loop gate counts flat axes among x, y and yaw only
// (loop_closure/max_flat_axes 1). Measured on all 313 (coral_check --loop_closure): 312
// accepted, 1 refused for y and yaw flat; counting all six axes refused 45 (y and roll, 2 of
// them with yaw too), 268 accepted.
TEST(LoopClosure, Lidar3dSameViewpointRevisitsWithAWeakRollAreAccepted) {
  CORAL_REQUIRE_DATA("hku1_livox_keyframes");
  ros_adapters::NodeConfig node;
  coral_test::loadPreset("lidar_3d", &node);
  std::vector<eval::TrainingScan> scans;
  coral::Isometries ref;
  std::string err;
  ASSERT_TRUE(eval::loadKeyframeSequence(coral_data, eval::KeyframeSequenceConfig(), nullptr,
                                         &scans, &ref, &err))
      << err;
  online::IntrospectorConfig loop = node.online;
  loop.verdict = coral::loopClosureVerdict(node.online.verdict);
  ASSERT_EQ(loop.verdict.gate.max_flat_axes, 1);
  int pairs = 0, accepted = 0, weak_roll = 0;
  for (std::size_t k = 0; k + 1 < scans.size(); k += 4 * coral_test::pairStride()) {
    const coral::AlignmentVerdict v = online::judgePair(scans[k].scan, scans[k + 1].scan,
                                                        ref[k].inverse() * ref[k + 1], loop, false)
                                          .verdict;
    ++pairs;
    accepted += v.valid && v.aligned;
    const auto& flat = v.relative.flat_axes;
    weak_roll +=
        flat.size() >= 2 && std::find(flat.begin(), flat.end(), coral::Axis::kRoll) != flat.end();
    if (!(v.valid && v.aligned))
      std::cout << "pair " << k << " refused: " << (v.valid ? v.rejected_by : v.reason) << "\n";
  }
  std::cout << pairs << " consecutive pairs: " << accepted << " accepted, " << weak_roll
            << " with roll and another axis flat\n";
  EXPECT_GE(accepted * 100, pairs * 97);
  if (coral_test::pairStride() > 1) return;
  EXPECT_GE(weak_roll, 6);  // counted over all six axes, these would be refused
}

// Ten times the look-alike places (coral_loop_eval --lookalikes 400), registered by NDT: the
// registration nothing in lidar_3d's loop gate was chosen on (its bounds were chosen on GICP
// candidates; doc/loop_closure.md "Ten times the look-alike places"). Measured: 41 of 42 true
// and 0 of 1600 false accepted (coral_loop_eval --registration ndt --lookalikes 400, and here:
// the same candidates judged by the preset as a back end's request is); the relative check
// alone accepts 4 false ones (NDT's false candidates are mostly far from any alignment). The
// restart check rejects none of them. ~1 min in Release; under the sanitizers' stride 25
// look-alike pairs.
TEST(LoopClosure, Lidar3dTenTimesTheLookAlikesRegisteredByNdt) {
  CORAL_REQUIRE_DATA("hku1_livox_keyframes");
  ros_adapters::NodeConfig node;
  coral_test::loadPreset("lidar_3d", &node);
  eval::LoopCandidateConfig lc = candidateConfig(3, node.online.verdict.tolerance, 400);
  lc.registration = "ndt";
  LivoxLoop l;
  std::string err;
  ASSERT_TRUE(loadLivoxLoop(coral_data, lc, &l, &err)) << err;
  LoopTally t;
  for (const eval::LoopCandidate& c : l.cands)
    judge(node, l.scans[c.a].scan, l.scans[c.b].scan, c.T_a_b, c.is_true, &t);
  print("lidar_3d, hku1 Livox, NDT, ten times the look-alikes", t);
  expectTally(t, {40, 1500, 95, 0, 4, 0});
}

// The loop set of a shared CARMEN log ("intel" or "aces"; eval/carmen_loops.hpp, as
// coral_loop_eval builds it): look-alike places between the corrected scans, the benchmark
// loop relations as they are and registered again from a perturbed pose (labelled against
// the relation). Both logs' corrected poses are shipped with the Intel data.
bool loadCarmenLoops(const std::string& log, const eval::LoopCandidateConfig& cfg,
                     eval::CarmenLoopSet* set, std::string* err) {
  const std::string dir = coral_test::dataDir(), log_dir = dir + "/radish_" + log + "/";
  return eval::loadCarmenLoopSet(log_dir + log + ".clf.bz2",
                                 dir + "/radish_intel/" + log + "_corrected_poses_on_raw.csv",
                                 log_dir + log + ".relations", cfg, 30, 10, set, err);
}

// A loop set and which of its candidates the loop verdict accepted (revisits: every
// pairStride()-th judged, the others not accepted).
struct JudgedLoops {
  eval::CarmenLoopSet set;
  std::vector<bool> lookalike_accepted, revisit_accepted;
};

// The lidar_2d loop verdict on every candidate of a log's loop set, its candidates registered
// again by `registration` (eval::LoopCandidateConfig); *median_error (optional): the median
// translation error of the true re-registrations; *judged (optional): the set and the
// verdicts; lookalikes > 0: that many look-alike pairs (coral_loop_eval --lookalikes; under the
// sanitizers' stride that many times fewer) instead of the evaluation's 60. Unreadable data fails
// the test.
void checkCarmenLoops(const std::string& log, const std::string& registration,
                      const Expected& expected, double* median_error = nullptr,
                      JudgedLoops* judged = nullptr, int lookalikes = 0) {
  ros_adapters::NodeConfig node;
  coral_test::loadPreset("lidar_2d", &node);
  eval::LoopCandidateConfig cfg = candidateConfig(2, node.online.verdict.tolerance, lookalikes);
  cfg.registration = registration;
  eval::CarmenLoopSet set;
  std::string err;
  ASSERT_TRUE(loadCarmenLoops(log, cfg, &set, &err)) << err;
  // Each candidate carries the reference it is labelled against (coral_loop_eval measures the
  // poses the verdict offers against it): its errors are the distance to it.
  for (const std::vector<eval::LoopCandidate>* cands : {&set.lookalikes, &set.revisits})
    for (const eval::LoopCandidate& c : *cands) {
      double t_err = 0.0, r_err = 0.0;
      eval::relativeError(c.T_a_b, c.T_ref, &t_err, &r_err);
      ASSERT_NEAR(t_err, c.error_translation, 1e-9) << c.source << " " << c.a << "-" << c.b;
      ASSERT_NEAR(r_err, c.error_rotation_deg, 1e-9) << c.source << " " << c.a << "-" << c.b;
    }
  LoopTally t;
  std::vector<bool> lookalike_accepted, revisit_accepted(set.revisits.size(), false);
  for (const eval::LoopCandidate& c : set.lookalikes)
    lookalike_accepted.push_back(
        judge(node, set.scans[c.a].scan, set.scans[c.b].scan, c.T_a_b, c.is_true, &t));
  for (std::size_t k = 0; k < set.revisits.size(); k += coral_test::pairStride()) {
    const eval::LoopCandidate& c = set.revisits[k];
    revisit_accepted[k] =
        judge(node, set.rel_scans[c.a].scan, set.rel_scans[c.b].scan, c.T_a_b, c.is_true, &t);
  }
  if (judged) {
    judged->lookalike_accepted = lookalike_accepted;
    judged->revisit_accepted = revisit_accepted;
  }
  print(("lidar_2d, " + log + ", " + registration + " registration").c_str(), t);
  expectTally(t, expected);
  if (median_error) {
    std::vector<double> errors;  // of every true re-registration (judged or not)
    for (const eval::LoopCandidate& c : set.revisits)
      if (c.source == "relation_icp" && c.is_true) errors.push_back(c.error_translation);
    ASSERT_FALSE(errors.empty()) << registration;
    std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
    *median_error = errors[errors.size() / 2];
    std::cout << "median error of the true registrations " << *median_error << " m\n";
  }
  if (judged) judged->set = std::move(set);
}

// The keyframe pose graph of a judged loop set (as coral_loop_eval builds it): raw odometry
// edges and, as loop edges, the candidates `use` selects (look-alikes between their nodes,
// revisits between the nodes their scans hang off); *edge_true: per loop edge, its label.
std::vector<eval::PoseGraphEdge> loopGraph(
    const JudgedLoops& j, const std::function<bool(const eval::LoopCandidate&, bool)>& use,
    std::vector<bool>* edge_true) {
  std::vector<eval::PoseGraphEdge> edges =
      eval::odometryEdges(j.set.odom, eval::kLogOdometrySigmaT, eval::kLogOdometrySigmaR);
  const eval::LogNodes nodes(j.set.log, j.set.raw);
  auto add = [&](const eval::LoopCandidate& c, bool accepted, bool revisit) {
    if (!use(c, accepted)) return;
    eval::PoseGraphEdge e{c.a, c.b, c.T_a_b, eval::kLoopEdgeSigmaT, eval::kLoopEdgeSigmaR, true};
    if (revisit && !nodes.edge(j.set.rel_scans[c.a].stamp, j.set.rel_scans[c.b].stamp, c.T_a_b, 10,
                               &e.from, &e.to, &e.T_from_to))
      return;
    edges.push_back(e);
    edge_true->push_back(c.is_true);
  };
  for (std::size_t k = 0; k < j.set.lookalikes.size(); ++k)
    add(j.set.lookalikes[k], j.lookalike_accepted[k], false);
  for (std::size_t k = 0; k < j.set.revisits.size(); ++k)
    add(j.set.revisits[k], j.revisit_accepted[k], true);
  return edges;
}

// Measured (doc/loop_closure.md, all rows, 2026-12-07 after eval::logLineAt found the stamps of
// the Intel log's lines out of time order): 1521 true (1245 relations, 276 registered again
// within the tolerance), 346 false (106 registered 2+ tolerances off, 240 look-alikes); loop
// verdict 1404 true (1378 at their pose, 26 more registered back within half a tolerance,
// loop_closure/max_registered_offset), 0 false accepted (of the relations registered about 1 m
// off that pass the local terms, the registration from the pose rejects one,
// loop_closure/coarse_registration since 2026-12-07: the restart check did before); the relative
// check alone 30 false (41 with the look-alikes chosen on the folded reference before 2026-12-07's
// third session: doc/loop_closure.md "Intel's graphs were folded"). The restart check also rejects
// one true candidate: relation 130-680 registered again 0.05 m / 1.4 deg from the relation (Q
// 0.102), for an alignment 8.7 tolerances away with Q 0.058 (the cubicle rows repeat). The
// classifier of lidar_2d was trained on ACES: this is a cross-data-set figure. The graphs, as
// coral_loop_eval solves them (from the odometry and from the linear start, the lower cost kept):
// measured ATE against the relation graph, oracle 0.141 m, verdict 0.165 m (every right candidate
// an edge, against the verdict's accepted ones). From the raw odometry alone both stop in a folded
// local minimum, on the odd rows 9.4 and 9.1 m from the relation graph (doc/loop_closure.md
// "Intel's graphs were folded").
TEST(LoopClosure, Lidar2dOnTheIntelLoops) {
  CORAL_REQUIRE_DATA("radish_intel");
  JudgedLoops judged;
  checkCarmenLoops("intel", "icp", {1450, 300, 92, 0, 10, 0, 1}, nullptr, &judged);
  if (coral_test::pairStride() > 1) return;  // the graphs below need every candidate
  eval::PoseGraphConfig pg = eval::robustContinuationConfig(2);
  pg.try_linear_start = true;
  std::vector<bool> edge_true;
  const auto oracle_edges = loopGraph(
      judged, [](const eval::LoopCandidate& c, bool) { return c.is_true; }, &edge_true);
  const auto verdict_edges = loopGraph(
      judged, [](const eval::LoopCandidate&, bool accepted) { return accepted; }, &edge_true);
  coral::Isometries oracle = judged.set.odom, verdict = judged.set.odom;
  eval::PoseGraphResult res;
  ASSERT_TRUE(eval::optimizePoseGraph(oracle_edges, pg, &oracle, &res)) << res.error;
  ASSERT_TRUE(eval::optimizePoseGraph(verdict_edges, pg, &verdict, &res)) << res.error;
  const double ate_oracle = eval::absoluteTrajectoryError(oracle, judged.set.ref, 2);
  const double ate_verdict = eval::absoluteTrajectoryError(verdict, judged.set.ref, 2);
  std::cout << "Intel graphs: ATE oracle " << ate_oracle << ", verdict " << ate_verdict << " m\n";
  EXPECT_LT(ate_oracle, 0.3);
  EXPECT_LT(ate_verdict, 0.3);
  EXPECT_LT(ate_verdict, 1.5 * ate_oracle);
}

// ACES (corridors: errors along them are unobservable, doc/verdict_pairs.md), its relations
// registered again by point-to-point ICP and by point-to-line ICP (PL-ICP, as ROS's
// laser_scan_matcher registers scans; coral_loop_eval --registration point_to_line).
// Measured (doc/loop_closure.md, all rows):
// - point-to-point: 197 true, 280 false; loop verdict 163 true (149 at their pose, 15 more
//   registered back within half a tolerance; since 2026-12-07 the registration from the pose
//   rejects 47-27, accepted at its pose 0.27 m from its relation), 0 false; the relative check
//   alone 36 false. Median error of the true registrations 0.128 m.
// - point-to-line: the true registrations end closer to the relations (median 0.059 m), and
//   the look-alike places ICP converges on are better fitted too: 189 true, 290 false; loop
//   verdict 161 true (153 at their pose), 3 false accepted (look-alikes 22-32 m apart; 6 pass the
//   local terms: 5 look-alikes and a relation registered 1.3 m off; max_quality rejects two
//   look-alikes at Q 0.21 and 0.25, the restart check the relation. The verdict's 0 false holds for
//   the point-to-point registration only); the relative check alone 49 false.
TEST(LoopClosure, Lidar2dOnTheAcesLoops) {
  CORAL_REQUIRE_DATA("radish_aces");
  double point_to_point = 0.0, point_to_line = 0.0;
  checkCarmenLoops("aces", "icp", {180, 250, 83, 0, 10, 0}, &point_to_point);
  JudgedLoops judged;
  checkCarmenLoops("aces", "point_to_line", {180, 250, 85, 3, 10, 1}, &point_to_line, &judged);
  if (coral_test::pairStride() > 1) return;  // the graphs below need every candidate
  EXPECT_LT(point_to_line, 0.7 * point_to_point);

  // The back end's consistency check after the verdict (eval::optimizePrunedPoseGraph): the
  // false edges the verdict let through bend the graph (ATE 4.2 m against the oracle's 0.25 m);
  // each is left the worst explained and removed, no true edge is, and the graph ends within
  // 10 % of the oracle's (measured: 3 false removed, ATE 0.245 m; coral_loop_eval --prune 3).
  eval::PoseGraphConfig pg = eval::robustContinuationConfig(2);
  pg.try_linear_start = true;  // as coral_loop_eval solves planar graphs
  std::vector<bool> verdict_true, oracle_true;
  const auto verdict_edges = loopGraph(
      judged, [](const eval::LoopCandidate&, bool accepted) { return accepted; }, &verdict_true);
  const auto oracle_edges = loopGraph(
      judged, [](const eval::LoopCandidate& c, bool) { return c.is_true; }, &oracle_true);
  const coral::Isometries& odom = judged.set.odom;
  coral::Isometries oracle = odom, bent = odom, pruned = odom;
  eval::PoseGraphResult res;
  ASSERT_TRUE(eval::optimizePoseGraph(oracle_edges, pg, &oracle, &res)) << res.error;
  ASSERT_TRUE(eval::optimizePoseGraph(verdict_edges, pg, &bent, &res)) << res.error;
  std::vector<int> removed;
  bool consistent = false;
  ros_adapters::NodeConfig node;
  coral_test::loadPreset("lidar_2d", &node);
  ASSERT_TRUE(eval::optimizePrunedPoseGraph(verdict_edges, pg, node.online.verdict.tolerance,
                                            eval::LoopPruning(), &pruned, &removed, &consistent,
                                            &res))
      << res.error;
  const std::size_t n_odom = odom.size() - 1;
  const int false_edges =
      static_cast<int>(std::count(verdict_true.begin(), verdict_true.end(), false));
  int removed_true = 0, removed_false = 0;
  for (int k : removed) (verdict_true[k - n_odom] ? removed_true : removed_false)++;
  const double ate_oracle = eval::absoluteTrajectoryError(oracle, judged.set.ref, 2);
  const double ate_bent = eval::absoluteTrajectoryError(bent, judged.set.ref, 2);
  const double ate_pruned = eval::absoluteTrajectoryError(pruned, judged.set.ref, 2);
  std::cout << "point-to-line graph: " << false_edges << " false edges; ATE oracle " << ate_oracle
            << ", verdict " << ate_bent << ", after the consistency check " << ate_pruned
            << " m (removed " << removed_true << " true, " << removed_false << " false)\n";
  EXPECT_GE(false_edges, 1);
  EXPECT_GT(ate_bent, 5.0 * ate_oracle);
  EXPECT_TRUE(consistent);
  EXPECT_EQ(removed_true, 0);
  EXPECT_EQ(removed_false, false_edges);
  EXPECT_LT(ate_pruned, 1.1 * ate_oracle);

  // The odometry and pairwise consistency checks (PCM, the chi-square 99 % bound, not tuned;
  // eval::inconsistentLoopEdges, coral_loop_eval --pcm): the cycles of the false edges with the
  // odometry and the others through ACES's odometry do not close; what is kept holds none of
  // them and 12 true edges fewer (measured 2026-12-07: ATE 0.228 m, oracle 0.251).
  eval::PairwiseConsistencyConfig pcm;
  pcm.dimension = 2;
  std::string error;
  ASSERT_TRUE(eval::inconsistentLoopEdges(verdict_edges, pcm, &removed, nullptr, &error)) << error;
  removed_true = removed_false = 0;
  for (int k : removed) (verdict_true[k - n_odom] ? removed_true : removed_false)++;
  coral::Isometries consistent_graph = odom;
  ASSERT_TRUE(
      eval::optimizePoseGraph(eval::keptEdges(verdict_edges, removed), pg, &consistent_graph, &res))
      << res.error;
  const double ate_pcm = eval::absoluteTrajectoryError(consistent_graph, judged.set.ref, 2);
  std::cout << "odometry and pairwise consistency: removed " << removed_true << " true, "
            << removed_false << " false; ATE " << ate_pcm << " m\n";
  EXPECT_EQ(removed_false, false_edges);
  EXPECT_LE(removed_true, 15);
  EXPECT_LT(ate_pcm, 1.1 * ate_oracle);
}

// Ten times the ACES look-alike places (coral_loop_eval --lookalikes 600, point-to-point): the
// evaluation's 60 pairs and 540 that nothing in lidar_2d's loop gate was chosen on, each
// registered from four headings (doc/loop_closure.md "Ten times the look-alike places").
// Measured: 164 of 197 true and 1 of 2440 false accepted (a look-alike pair of the 540); the
// relative check alone 248 false; the restart check rejects none. ~45 s in Release; under the
// sanitizers' stride 37 pairs.
TEST(LoopClosure, Lidar2dTenTimesTheLookAlikesOnAces) {
  CORAL_REQUIRE_DATA("radish_aces");
  checkCarmenLoops("aces", "icp", {180, 2400, 83, 1, 100, 0}, nullptr, nullptr, 600);
}

// No-return readings written at the scanner's maximum range: 2.8 % of the Intel log's readings
// are 81.83 m. A converter that writes every reading as a point (coral_check scores what it is
// given) hands the verdict walls that are not there, and the free-space term rejects right loop
// relations whose other scan saw a wall in front of them. lidar_2d's coral/max_range (49.9 m)
// drops them: every verdict equals that of the scans read without them, while with max_range 0
// the loop verdict loses right relations to the free-space term. Every 4th of Intel's 1245 loop
// relations, those with a no-return reading in either scan (measured 2026-12-07: 201 judged,
// 192 accepted, 25 of them rejected with max_range 0, all by the free-space term).
TEST(LoopClosure, Lidar2dNoReturnReadingsAtTheMaximumRangeAreDropped) {
  CORAL_REQUIRE_DATA("radish_intel");
  const std::string log_path = coral_data + "/intel.clf.bz2";
  std::vector<eval::CarmenLaserScan> log;
  std::string err;
  ASSERT_TRUE(eval::readCarmenLog(log_path, &log, &err)) << err;
  eval::LaserGeometry every_reading;
  every_reading.max_range = 1000.0;  // 81.83 m readings become points
  std::vector<eval::TrainingScan> scans, raw_scans;
  std::vector<eval::ScanPair> pairs, raw_pairs;
  ASSERT_TRUE(eval::loopRelationPairs(log, eval::relationsPath(log_path), eval::LaserGeometry(), 30,
                                      &scans, &pairs, &err))
      << err;
  ASSERT_TRUE(eval::loopRelationPairs(log, eval::relationsPath(log_path), every_reading, 30,
                                      &raw_scans, &raw_pairs, &err))
      << err;
  ASSERT_EQ(pairs.size(), raw_pairs.size());
  ros_adapters::NodeConfig node;
  coral_test::loadPreset("lidar_2d", &node);
  ASSERT_GT(node.online.coral.max_range, 0.0);
  online::IntrospectorConfig loop = node.online;
  loop.verdict = coral::loopClosureVerdict(node.online.verdict);
  online::IntrospectorConfig off = loop;
  off.coral.max_range = 0.0;
  int judged = 0, accepted = 0, lost_without = 0, named_free_space = 0;
  std::size_t dropped = 0;
  for (std::size_t k = 0; k < pairs.size(); k += 4 * coral_test::pairStride()) {
    const coral::Scan &a = scans[pairs[k].a].scan, &b = scans[pairs[k].b].scan;
    const coral::Scan &ra = raw_scans[raw_pairs[k].a].scan, &rb = raw_scans[raw_pairs[k].b].scan;
    if (ra.points.size() == a.points.size() && rb.points.size() == b.points.size()) continue;
    ++judged;
    const online::PairJudgement clean = online::judgePair(a, b, pairs[k].T_a_b, loop, false);
    const online::PairJudgement raw = online::judgePair(ra, rb, pairs[k].T_a_b, loop, false);
    EXPECT_EQ(raw.verdict.valid, clean.verdict.valid) << "relation " << k;
    EXPECT_EQ(raw.verdict.aligned, clean.verdict.aligned) << "relation " << k;
    EXPECT_EQ(raw.verdict.probability, clean.verdict.probability) << "relation " << k;
    EXPECT_EQ(raw.verdict.rejected_by, clean.verdict.rejected_by) << "relation " << k;
    dropped += raw.verdict.coral.num_beyond_max_range;
    if (!(clean.verdict.valid && clean.verdict.aligned)) continue;
    ++accepted;
    const coral::AlignmentVerdict kept =
        online::judgePair(ra, rb, pairs[k].T_a_b, off, false).verdict;
    if (kept.valid && kept.aligned) continue;
    ++lost_without;
    named_free_space += kept.rejected_by.find("free-space") != std::string::npos;
  }
  std::cout << judged << " relations with no-return readings (" << dropped
            << " points dropped); accepted " << accepted
            << ", of them rejected with max_range 0: " << lost_without << " (" << named_free_space
            << " by the free-space term)\n";
  EXPECT_GT(dropped, 0u);
  if (coral_test::pairStride() > 1) return;
  EXPECT_GE(judged, 150);
  EXPECT_GE(lost_without, accepted / 20);
  EXPECT_EQ(named_free_space, lost_without);
}

// A scanner of finer beam spacing than the 1 deg logs lidar_2d's bounds were chosen on. Every
// ACES FLASER line rewritten as 361 beams of 0.5 deg (the readings at the even beams, at each
// odd beam the range where the line through its neighbours' points meets it plus 1 cm of noise,
// or no return across a depth edge; scripts/experiments/resample_carmen_beams.py writes the same
// as a log): read by the beam count (CARMEN's rule), thinned back to 1 deg by the preset's
// coral/beam_step_deg, every loop relation as it is and moved a tolerance along x is judged as
// at 1 deg. Without the thinning the verdict sees twice the points and some verdicts change
// (printed; measured 2026-12-07: doc/loop_closure.md "Another beam spacing").
TEST(LoopClosure, Lidar2dAFinerScannerIsJudgedAtThePresetsSpacing) {
  CORAL_REQUIRE_DATA("radish_aces");
  const std::string log_path = coral_data + "/aces.clf.bz2";
  std::vector<eval::CarmenLaserScan> log;
  std::string err;
  ASSERT_TRUE(eval::readCarmenLog(log_path, &log, &err)) << err;
  std::vector<eval::CarmenLaserScan> fine = log;
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.01);
  const eval::LaserGeometry g;
  auto valid = [&](double r) { return r >= g.min_range && r < g.max_range; };
  for (eval::CarmenLaserScan& l : fine) {
    const std::vector<double>& r = l.ranges;
    ASSERT_EQ(r.size(), 180u);
    std::vector<double> out(361, 81.83);
    for (std::size_t i = 0; i < 180; ++i) {
      out[2 * i] = r[i];
      if (i + 1 < 180 && valid(r[i]) && valid(r[i + 1]) &&
          std::abs(r[i] - r[i + 1]) <= 0.05 + 0.05 * std::min(r[i], r[i + 1]))
        out[2 * i + 1] =
            2.0 * r[i] * r[i + 1] * std::cos(0.5 * M_PI / 180.0) / (r[i] + r[i + 1]) + noise(rng);
    }
    l.ranges = out;
  }
  std::vector<eval::TrainingScan> scans, fine_scans;
  std::vector<eval::ScanPair> pairs, fine_pairs;
  ASSERT_TRUE(
      eval::loopRelationPairs(log, eval::relationsPath(log_path), g, 30, &scans, &pairs, &err))
      << err;
  ASSERT_TRUE(eval::loopRelationPairs(fine, eval::relationsPath(log_path), g, 30, &fine_scans,
                                      &fine_pairs, &err))
      << err;
  ASSERT_EQ(pairs.size(), fine_pairs.size());
  ros_adapters::NodeConfig node;
  coral_test::loadPreset("lidar_2d", &node);
  ASSERT_EQ(node.online.coral.beam_step_deg, 1.0);
  online::IntrospectorConfig loop = node.online;
  loop.verdict = coral::loopClosureVerdict(node.online.verdict);
  online::IntrospectorConfig off = loop;
  off.coral.beam_step_deg = 0.0;
  int judged = 0, accepted = 0, changed_without = 0;
  for (std::size_t k = 0; k < pairs.size(); k += coral_test::pairStride())
    for (const double dx : {0.0, node.online.verdict.tolerance.translation}) {
      const Eigen::Isometry3d T = pairs[k].T_a_b * coral::se2(dx, 0.0, 0.0);
      const coral::Scan &a = scans[pairs[k].a].scan, &b = scans[pairs[k].b].scan;
      const coral::Scan &fa = fine_scans[fine_pairs[k].a].scan,
                        &fb = fine_scans[fine_pairs[k].b].scan;
      ASSERT_GT(fa.points.size(), a.points.size() + a.points.size() / 2);
      const online::PairJudgement at_1deg = online::judgePair(a, b, T, loop, false);
      const online::PairJudgement thinned = online::judgePair(fa, fb, T, loop, false);
      ++judged;
      accepted += at_1deg.verdict.valid && at_1deg.verdict.aligned;
      EXPECT_EQ(thinned.verdict.valid, at_1deg.verdict.valid) << "relation " << k << " dx " << dx;
      EXPECT_EQ(thinned.verdict.aligned, at_1deg.verdict.aligned)
          << "relation " << k << " dx " << dx << ": " << thinned.verdict.rejected_by << " / "
          << at_1deg.verdict.rejected_by;
      EXPECT_NEAR(thinned.verdict.probability, at_1deg.verdict.probability, 1e-6)
          << "relation " << k << " dx " << dx;
      EXPECT_EQ(thinned.verdict.coral.num_beam_thinned,
                fa.points.size() + fb.points.size() - a.points.size() - b.points.size());
      const coral::AlignmentVerdict raw = online::judgePair(fa, fb, T, off, false).verdict;
      changed_without +=
          (raw.valid && raw.aligned) != (at_1deg.verdict.valid && at_1deg.verdict.aligned);
    }
  std::cout << judged
            << " ACES loop relations as they are and moved a tolerance, at 0.5 deg: " << accepted
            << " accepted, as at 1 deg; without the thinning " << changed_without
            << " verdicts change\n";
  EXPECT_GE(judged, 2 * 100 / static_cast<int>(coral_test::pairStride()));
}

// The loop gate's refinement (lidar_2d loop_closure/max_refinement 0.5, coral/refinement.hpp)
// on the exact ACES loop relations: moved 0.2 m (2/3 of the tolerance) along x or y of b's
// frame, as a registration that stopped short of the revisit, and moved by 1, 2, 4, 8
// tolerances along +-x, +-y and 10, 20 deg of yaw both ways. The verdict is the given pose's
// with or without refinement (never "aligned" because a better pose lies nearby); the refined
// pose is offered for most of the 0.2 m ones and lies closer to the relation; for errors of
// a tolerance or more it is offered for few, and from 4 tolerances on for (almost) none. The
// preset's verdict, which also accepts a candidate registered back within half a tolerance
// (loop_closure/max_registered_offset), accepts a few more of the 0.2 m ones and no more than
// 2 % of those moved by a tolerance, none from 4 tolerances or 20 deg on.
TEST(LoopClosure, Lidar2dRefinementOffersThePoseOfRelationsLeftShort) {
  CORAL_REQUIRE_DATA("radish_aces");
  ros_adapters::NodeConfig node;
  eval::LoopCandidateConfig cfg = presetCandidates("lidar_2d", 2, &node);
  ASSERT_GT(node.online.verdict.loop_closure.max_refinement, 0.0);
  cfg.max_radius_candidates = 0;  // the relations as they are; no registrations needed here
  eval::CarmenLoopSet set;
  std::string err;
  ASSERT_TRUE(loadCarmenLoops("aces", cfg, &set, &err)) << err;
  // The preset's loop verdict (with its restart check), and that verdict without the restart
  // check (refine) and without both (plain): the refinement on its own.
  online::IntrospectorConfig preset = node.online, refine = node.online, plain = node.online;
  preset.verdict = coral::loopClosureVerdict(node.online.verdict);
  refine.verdict = preset.verdict;
  refine.verdict.gate.restarts = false;
  refine.verdict.gate.max_registered_offset = 0.0;
  plain.verdict = refine.verdict;
  plain.verdict.gate.max_refinement = 0.0;
  const double tol = node.online.verdict.tolerance.translation;
  std::vector<std::pair<std::string, Eigen::Isometry3d>> errors;  // name, offset in b's frame
  for (int axis : {0, 1}) {
    Eigen::Isometry3d d = Eigen::Isometry3d::Identity();
    d.translation()[axis] = 0.2;
    errors.push_back({"0.2 m", d});
  }
  for (double k : {1.0, 2.0, 4.0, 8.0})
    for (int axis : {0, 1})
      for (double sign : {1.0, -1.0}) {
        Eigen::Isometry3d d = Eigen::Isometry3d::Identity();
        d.translation()[axis] = sign * k * tol;
        errors.push_back({std::to_string(static_cast<int>(k)) + " tol", d});
      }
  for (double deg : {10.0, 20.0})
    for (double sign : {1.0, -1.0})
      errors.push_back({std::to_string(static_cast<int>(deg)) + " deg",
                        coral::se2(0.0, 0.0, sign * deg * M_PI / 180.0)});
  struct Tally {
    int n = 0, accepted = 0, offered = 0, closer = 0;
    int restart_rejected = 0, restart_closer = 0;  // the preset's restart check
    // The preset's verdict: accepted, and of those accepted at the pose registered from the
    // given one (loop_closure/max_registered_offset).
    int preset_accepted = 0, nearby_accepted = 0;
  };
  std::map<std::string, Tally> tally;
  for (std::size_t k = 0; k < set.revisits.size(); k += coral_test::pairStride()) {
    const eval::LoopCandidate& c = set.revisits[k];
    if (c.source != "relation") continue;
    const coral::Scan &a = set.rel_scans[c.a].scan, &b = set.rel_scans[c.b].scan;
    for (const auto& e : errors) {
      const Eigen::Isometry3d T = c.T_a_b * e.second;
      const coral::AlignmentVerdict p = online::judgePair(a, b, T, plain, false).verdict;
      const coral::AlignmentVerdict r = online::judgePair(a, b, T, refine, false).verdict;
      Tally& t = tally[e.first];
      ++t.n;
      // The verdict is the given pose's: refinement changes neither it nor its CorAl.
      EXPECT_EQ(r.valid && r.aligned, p.valid && p.aligned) << e.first << ", relation " << k;
      EXPECT_FALSE(p.refined);
      t.accepted += r.valid && r.aligned;
      const double before = (c.T_a_b.inverse() * T).translation().norm();
      const coral::AlignmentVerdict f = online::judgePair(a, b, T, preset, false).verdict;
      t.preset_accepted += f.valid && f.aligned;
      t.nearby_accepted += f.nearby.accepted;
      // Registered from the pose only when rejected there, accepted only within the bound.
      EXPECT_EQ(f.nearby.run, r.valid && !r.aligned);
      if (f.nearby.accepted) {
        EXPECT_LE(f.nearby.size, node.online.verdict.loop_closure.max_registered_offset);
      }
      if (r.valid && r.aligned) {
        EXPECT_EQ(f.valid && f.aligned, !f.restart.better_elsewhere);
        t.restart_rejected += f.restart.better_elsewhere;
        t.restart_closer += f.restart.better_elsewhere &&
                            (c.T_a_b.inverse() * f.restart.T_a_b).translation().norm() < before;
      }
      if (!r.refined) continue;
      EXPECT_FALSE(r.aligned);
      EXPECT_LE(r.refinement.size, node.online.verdict.loop_closure.max_refinement + 1e-9);
      ++t.offered;
      t.closer += (c.T_a_b.inverse() * T * r.refinement.delta).translation().norm() < before;
    }
  }
  for (const auto& t : tally)
    std::cout << "ACES relations moved " << t.first << ": " << t.second.n << " candidates, "
              << t.second.accepted << " accepted, refined pose offered for " << t.second.offered
              << " (" << t.second.closer
              << " of them closer to the relation); restart check: " << t.second.restart_rejected
              << " of the accepted rejected (" << t.second.restart_closer
              << " with its better pose closer to the relation); the preset's verdict accepts "
              << t.second.preset_accepted << " (" << t.second.nearby_accepted
              << " at the pose registered from the given one)\n";
  if (coral_test::pairStride() > 1) return;
  // Measured (doc/loop_closure.md, The refinement): 0.2 m: 220 candidates, 3 accepted, 155
  // offered (149 closer); 1 / 2 / 4 / 8 tolerances: 440 each, 4 / 2 / 0 / 0 accepted, 62 / 16
  // / 0 / 0 offered; 10 / 20 deg: 220 each, 1 / 0 accepted, 2 / 0 offered.
  const Tally& short_ = tally["0.2 m"];
  EXPECT_GE(short_.n, 200);
  EXPECT_GE(short_.offered * 100, 65 * short_.n);
  EXPECT_GE(short_.closer * 10, 9 * short_.offered);
  EXPECT_LE(tally["2 tol"].offered * 100, 5 * tally["2 tol"].n);
  EXPECT_LE(tally["4 tol"].offered, 2);
  EXPECT_EQ(tally["8 tol"].offered, 0);
  EXPECT_EQ(tally["20 deg"].offered, 0);
  // The restart check on the accepted (measured): 0.2 m 1 of 3 rejected (its better pose
  // farther from the relation: a candidate within the tolerance lost), 2 tolerances 1 of 2
  // (its better pose closer to the relation), none of the others.
  EXPECT_LE(tally["0.2 m"].restart_rejected, 1);
  // The preset's verdict (measured): 0.2 m 6 accepted (4 registered back), 1 tolerance 8 (4),
  // 2 tolerances 2 (1), 10 deg 1 (0), none of the others.
  EXPECT_GE(tally["0.2 m"].nearby_accepted, 4);
  EXPECT_GT(tally["0.2 m"].preset_accepted, tally["0.2 m"].accepted);
  EXPECT_LE(tally["1 tol"].preset_accepted * 100, 2 * tally["1 tol"].n);
  EXPECT_LE(tally["2 tol"].preset_accepted, 2);
  for (const char* far : {"4 tol", "8 tol", "20 deg"})
    EXPECT_EQ(tally[far].preset_accepted, 0) << far;
}

// lidar_3d's loop gate registers a candidate it rejects at its pose once from it
// (loop_closure/max_registered_offset 0.5, lidar_2d's value): true Livox revisits moved 0.1 m
// and 0.33 deg (a third of the tolerance, as a registration that stopped short) are rejected
// at their pose more often than not, since a one-tolerance step lands closer to Q's minimum;
// registered back within half a tolerance they are accepted. Moved by a full tolerance (0.3 m
// or 2 deg along each axis, both ways) they are registered back about a tolerance and stay
// rejected.
TEST(LoopClosure, Lidar3dRevisitsLeftShortAreAcceptedRegisteredBack) {
  CORAL_REQUIRE_DATA("hku1_livox_keyframes");
  ros_adapters::NodeConfig node;
  eval::LoopCandidateConfig lc = presetCandidates("lidar_3d", 3, &node);
  ASSERT_GT(node.online.verdict.loop_closure.max_registered_offset, 0.0);
  lc.max_lookalike_pairs = 0;  // the true revisits only
  LivoxLoop l;
  std::string err;
  ASSERT_TRUE(loadLivoxLoop(coral_data, lc, &l, &err)) << err;
  online::IntrospectorConfig preset = node.online, at_pose = node.online;
  preset.verdict = coral::loopClosureVerdict(node.online.verdict);
  at_pose.verdict = preset.verdict;
  at_pose.verdict.gate.max_registered_offset = 0.0;
  const coral::ToleranceConfig& tol = node.online.verdict.tolerance;
  // A third of the tolerance in a direction (mostly horizontal) and a sixth of the rotation
  // tolerance about a tilted axis, both varied with the candidate.
  auto short_of = [&](const eval::LoopCandidate& c) {
    const double th = 2.4 * (c.a + 3 * c.b), ph = 1.1 * (c.a + c.b);
    Eigen::Isometry3d D = Eigen::Isometry3d::Identity();
    D.translation() = tol.translation / 3.0 *
                      Eigen::Vector3d(std::cos(th), std::sin(th), 0.2 * std::sin(ph)).normalized();
    D.linear() = Eigen::AngleAxisd(tol.rotation_deg / 6.0 * M_PI / 180.0,
                                   Eigen::Vector3d(std::sin(ph), std::cos(ph), 0.5).normalized())
                     .toRotationMatrix();
    return D;
  };
  std::vector<Eigen::Isometry3d> one_tolerance;
  for (int axis = 0; axis < 3; ++axis)
    for (double sign : {1.0, -1.0}) {
      Eigen::Isometry3d t = Eigen::Isometry3d::Identity(), r = t;
      t.translation()[axis] = sign * tol.translation;
      r.linear() =
          Eigen::AngleAxisd(sign * tol.rotation_deg * M_PI / 180.0, Eigen::Vector3d::Unit(axis))
              .toRotationMatrix();
      one_tolerance.push_back(t);
      one_tolerance.push_back(r);
    }
  auto accepts = [&](const online::IntrospectorConfig& cfg, const eval::LoopCandidate& c,
                     const Eigen::Isometry3d& T) {
    const coral::AlignmentVerdict v =
        online::judgePair(l.scans[c.a].scan, l.scans[c.b].scan, T, cfg, false).verdict;
    return v.valid && v.aligned;
  };
  int n = 0, short_at_pose = 0, short_preset = 0, one = 0, one_preset = 0;
  for (const eval::LoopCandidate& c : l.cands) {
    if (!c.is_true) continue;
    ++n;
    const Eigen::Isometry3d T = c.T_a_b * short_of(c);
    short_at_pose += accepts(at_pose, c, T);
    short_preset += accepts(preset, c, T);
    for (const Eigen::Isometry3d& D : one_tolerance) {
      ++one;
      one_preset += accepts(preset, c, c.T_a_b * D);
    }
  }
  std::cout << "lidar_3d, hku1 Livox true revisits moved a third of the tolerance: " << n
            << ", accepted at the pose " << short_at_pose << ", by the preset (registered back) "
            << short_preset << "; moved a tolerance: " << one << ", accepted " << one_preset
            << "\n";
  if (coral_test::pairStride() > 1) return;
  // Measured: 39 revisits; a third of the tolerance: 19 accepted at the pose, 35 with the
  // registration back (32 if the registered pose also had to reach p 0.5, lidar_2d's
  // registered_min_probability; lidar_3d leaves it 0); one tolerance: 3 of 468 (3 with 0.5),
  // 2 since the loop gate's coarse probe registers from the pose (2026-12-07).
  EXPECT_GE(n, 30);
  EXPECT_LE(short_at_pose * 100, 60 * n);
  EXPECT_GE(short_preset * 100, 85 * n);
  EXPECT_LE(one_preset * 100, 1 * one);
}

// The Livox loop's scans and poses (no candidates) with lidar_3d's candidate settings, and
// the preset's loop verdict as it is (preset) and with one gate term changed (without).
struct Lidar3dScans {
  ros_adapters::NodeConfig node;
  eval::LoopCandidateConfig lc;
  LivoxLoop l;
  online::IntrospectorConfig preset, without;
};
bool loadLidar3dScans(const std::string& dir, const std::function<void(coral::GateConfig*)>& change,
                      Lidar3dScans* s, std::string* err) {
  s->lc = presetCandidates("lidar_3d", 3, &s->node);
  s->lc.max_radius_candidates = 0;
  s->lc.max_lookalike_pairs = 0;
  s->preset = s->without = s->node.online;
  s->preset.verdict = coral::loopClosureVerdict(s->node.online.verdict);
  s->without.verdict = s->preset.verdict;
  change(&s->without.verdict.gate);
  return loadLivoxLoop(dir, s->lc, &s->l, err);
}

// Scan b of the Livox loop registered onto scan a as coral_loop_eval registers look-alike
// places (eval::registerPair from zero translation at the heading).
eval::LoopCandidate registeredAt(const LivoxLoop& l, const eval::LoopCandidateConfig& lc, int a,
                                 int b, double heading_deg) {
  eval::LoopCandidate c;
  Eigen::Isometry3d init = Eigen::Isometry3d::Identity();
  init.linear() =
      Eigen::AngleAxisd(heading_deg * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  eval::registerPair(l.scans[a].scan.points, l.scans[b].scan.points, init, lc, &c);
  return c;
}

// lidar_3d's loop gate refuses poses the relative check finds flat along more than one axis
// (loop_closure/max_flat_axes 1): of the 1599 false candidates of ten times the Livox
// look-alike places (coral_loop_eval --lookalikes 400, doc/loop_closure.md) the gate without
// the term accepted 11; these 9 are look-alike places GICP registered turned 62-131 deg onto
// another place, with 2-3 flat axes at the pose. Registered here as coral_loop_eval does
// (from zero translation at the heading), each is false against the reference, rejected by
// the preset with the flat axes named, and accepted with the term off (what it adds).
TEST(LoopClosure, Lidar3dTurnedLookAlikesAreRejectedByTheirFlatAxes) {
  CORAL_REQUIRE_DATA("hku1_livox_keyframes");
  Lidar3dScans s;
  std::string err;
  ASSERT_TRUE(loadLidar3dScans(
      coral_data, [](coral::GateConfig* g) { g->max_flat_axes = -1; }, &s, &err))
      << err;
  ASSERT_EQ(s.node.online.verdict.loop_closure.max_flat_axes, 1);
  const eval::LoopCandidateConfig& lc = s.lc;
  const LivoxLoop& l = s.l;
  const online::IntrospectorConfig &preset = s.preset, &no_term = s.without;
  const struct {
    int a, b;
    double heading_deg;
  } pairs[] = {{2, 230, 270},  {42, 205, 270}, {44, 242, 270}, {46, 240, 270}, {47, 216, 270},
               {54, 239, 270}, {190, 298, 90}, {212, 293, 90}, {243, 302, 90}};
  int n = 0;
  for (const auto& p : pairs) {
    if (n++ % coral_test::pairStride() != 0) continue;  // sanitizers: a few only
    SCOPED_TRACE(std::to_string(p.a) + "-" + std::to_string(p.b));
    const eval::LoopCandidate c = registeredAt(l, lc, p.a, p.b, p.heading_deg);
    double t = 0.0, r = 0.0;
    eval::relativeError(c.T_a_b, l.ref[p.a].inverse() * l.ref[p.b], &t, &r);
    EXPECT_GT(t, 8.0) << "registered " << t << " m, " << r << " deg from the reference";
    EXPECT_GT(r, 60.0);
    const coral::Scan &a = l.scans[p.a].scan, &b = l.scans[p.b].scan;
    const coral::AlignmentVerdict v = online::judgePair(a, b, c.T_a_b, preset, false).verdict;
    EXPECT_TRUE(v.valid) << v.reason;
    EXPECT_FALSE(v.aligned);
    EXPECT_NE(v.rejected_by.find("flat axes"), std::string::npos) << v.rejected_by;
    EXPECT_GE(v.relative.flat_axes.size(), 2u);
    const coral::AlignmentVerdict w = online::judgePair(a, b, c.T_a_b, no_term, false).verdict;
    EXPECT_TRUE(w.valid && w.aligned) << w.rejected_by;
  }
}

// lidar_3d's loop gate registers a candidate it accepts at its pose again from 16 starts
// (loop_closure/restarts, coral/restart_check.hpp; coarse to fine for these dense scans). Of
// the 1599 false candidates of ten times the Livox look-alike places (coral_loop_eval
// --lookalikes 400, doc/loop_closure.md) the gate without it accepted these two: GICP left
// them 4.3 m and 0.68 m from the revisit (one axis flat at most). Registered here as
// coral_loop_eval does, each is rejected by the restart check, whose better pose is the
// revisit's (within the tolerance of the reference), and accepted with the check off. Since
// 2026-12-07 the preset's registration from the pose (loop_closure/coarse_registration) rejects
// the one 0.68 m off first (it comes back 2.3 tolerances); the preset rejects both.
TEST(LoopClosure, Lidar3dCandidatesOffTheRevisitAreRejectedByTheRestartCheck) {
  CORAL_REQUIRE_DATA("hku1_livox_keyframes");
  Lidar3dScans s;
  std::string err;
  ASSERT_TRUE(loadLidar3dScans(
      coral_data,
      [](coral::GateConfig* g) {
        g->restarts = false;
        g->coarse_registration = false;
      },
      &s, &err))
      << err;
  ASSERT_TRUE(s.node.online.verdict.loop_closure.restarts);
  ASSERT_TRUE(s.node.online.verdict.loop_closure.coarse_registration);
  const eval::LoopCandidateConfig& lc = s.lc;
  const LivoxLoop& l = s.l;
  const online::IntrospectorConfig &preset = s.preset, &no_check = s.without;
  online::IntrospectorConfig restarts_only = preset;
  restarts_only.verdict.gate.coarse_registration = false;
  const coral::ToleranceConfig& tol = s.node.online.verdict.tolerance;
  const struct {
    int a, b;
    double heading_deg, min_error_m;
  } pairs[] = {{54, 184, 90, 4.0}, {67, 186, 0, 0.6}};
  for (const auto& p : pairs) {
    SCOPED_TRACE(std::to_string(p.a) + "-" + std::to_string(p.b));
    const eval::LoopCandidate c = registeredAt(l, lc, p.a, p.b, p.heading_deg);
    const Eigen::Isometry3d truth = l.ref[p.a].inverse() * l.ref[p.b];
    double t = 0.0, r = 0.0;
    eval::relativeError(c.T_a_b, truth, &t, &r);
    EXPECT_GT(t, p.min_error_m) << "registered " << t << " m, " << r << " deg from the reference";
    const coral::Scan &a = l.scans[p.a].scan, &b = l.scans[p.b].scan;
    const coral::AlignmentVerdict w = online::judgePair(a, b, c.T_a_b, no_check, false).verdict;
    EXPECT_TRUE(w.valid && w.aligned) << w.rejected_by;  // what the checks add
    const coral::AlignmentVerdict u = online::judgePair(a, b, c.T_a_b, preset, false).verdict;
    EXPECT_TRUE(u.valid && !u.aligned) << "the preset accepts it";
    const coral::AlignmentVerdict v =
        online::judgePair(a, b, c.T_a_b, restarts_only, false).verdict;
    EXPECT_TRUE(v.valid) << v.reason;
    EXPECT_FALSE(v.aligned);
    EXPECT_TRUE(v.restart.better_elsewhere);
    EXPECT_NE(v.rejected_by.find("restarts"), std::string::npos) << v.rejected_by;
    eval::relativeError(c.T_a_b * v.refinement.delta, truth, &t, &r);
    EXPECT_LT(t, tol.translation) << "the better pose, " << r << " deg";
    EXPECT_LT(r, tol.rotation_deg);
  }
}
