// Pose-graph optimiser on known answers: a drifted square loop closed by one correct loop
// edge returns to the truth (2D and 3D), a Huber loss limits the damage of a wrong loop edge,
// ATE of rigidly moved / locally offset trajectories, TUM / KITTI writer round trips.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "coral_introspection/coral/refinement.hpp"
#include "coral_introspection/eval/cloud_io.hpp"
#include "coral_introspection/eval/log_nodes.hpp"
#include "coral_introspection/eval/pose_graph.hpp"
#include "coral_introspection/eval/trajectory_metrics.hpp"

using namespace coral_introspection::coral;
using namespace coral_introspection::eval;

namespace {

Eigen::Isometry3d pose(const Vec3& p, double yaw, double roll = 0.0) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(yaw, Vec3::UnitZ()) * Eigen::AngleAxisd(roll, Vec3::UnitX()))
                   .toRotationMatrix();
  T.translation() = p;
  return T;
}

// 4 * per_side poses on a square of `side` m, 1 pose per side/per_side m, heading along the
// side; z = z_amp * sin(2 pi k / n), height `z0` added.
Isometries square(int per_side, double side, double z_amp, double z0 = 0.0) {
  const Vec3 corner[4] = {{0, 0, 0}, {side, 0, 0}, {side, side, 0}, {0, side, 0}};
  const Vec3 dir[4] = {{1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}};
  const int n = 4 * per_side;
  Isometries T;
  for (int k = 0; k < n; ++k) {
    const int s = k / per_side;
    Vec3 p = corner[s] + dir[s] * (side * (k % per_side) / per_side);
    p.z() = z0 + z_amp * std::sin(2.0 * M_PI * k / n);
    T.push_back(pose(p, s * M_PI / 2.0));
  }
  return T;
}

// Odometry from the true increments with a yaw (and roll) bias per step and 1 cm noise.
Isometries drift(const Isometries& truth, double yaw_bias, double roll_bias, bool noise_z) {
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0.0, 0.01);
  Isometries odo{truth[0]};
  for (std::size_t k = 1; k < truth.size(); ++k) {
    Eigen::Isometry3d d = truth[k - 1].inverse() * truth[k];
    d = d * pose(Vec3::Zero(), yaw_bias, roll_bias);
    d.translation() += Vec3(n(rng), n(rng), noise_z ? n(rng) : 0.0);
    odo.push_back(odo.back() * d);
  }
  return odo;
}

PoseGraphEdge edge(const Isometries& truth, int from, int to, bool loop) {
  PoseGraphEdge e;
  e.from = from;
  e.to = to;
  e.T_from_to = truth[from].inverse() * truth[to];
  e.sigma_translation = 0.01;
  e.sigma_rotation = 0.002;
  e.loop = loop;
  return e;
}

double angle(const Eigen::Isometry3d& A, const Eigen::Isometry3d& B) {
  return Eigen::AngleAxisd(A.linear().transpose() * B.linear()).angle();
}

// |whitened residual| of an edge at the given poses (translation and angle of the error).
double whitened(const PoseGraphEdge& e, const Isometries& T) {
  const Eigen::Isometry3d E = e.T_from_to.inverse() * T[e.from].inverse() * T[e.to];
  return std::hypot(E.translation().norm() / e.sigma_translation,
                    Eigen::AngleAxisd(E.linear()).angle() / e.sigma_rotation);
}

}  // namespace

TEST(PoseGraph, ValidateRefusesBadConfigs) {
  PoseGraphConfig cfg;
  EXPECT_EQ(cfg.validate(), "");
  cfg.dimension = 4;
  EXPECT_NE(cfg.validate().find("dimension"), std::string::npos);
  cfg = PoseGraphConfig();
  cfg.max_iterations = 0;
  EXPECT_NE(cfg.validate().find("max_iterations"), std::string::npos);
  cfg = PoseGraphConfig();
  cfg.huber_loss = -1.0;
  EXPECT_NE(cfg.validate().find("huber_loss"), std::string::npos);

  // optimizePoseGraph refuses it too, and bad edges, leaving the poses alone.
  const Isometries truth = square(10, 10.0, 0.0);
  Isometries poses = drift(truth, 0.01, 0.0, false);
  const Isometries before = poses;
  PoseGraphResult res;
  cfg.dimension = 4;
  EXPECT_FALSE(optimizePoseGraph(odometryEdges(poses, 0.05, 0.01), cfg, &poses, &res));
  EXPECT_NE(res.error.find("dimension"), std::string::npos);
  std::vector<PoseGraphEdge> bad{edge(truth, 39, 0, true)};
  bad[0].to = 40;  // one past the last pose
  EXPECT_FALSE(optimizePoseGraph(bad, PoseGraphConfig(), &poses, &res));
  EXPECT_NE(res.error.find("edge 0"), std::string::npos) << res.error;
  bad = {edge(truth, 3, 0, true)};
  bad[0].sigma_rotation = 0.0;
  EXPECT_FALSE(optimizePoseGraph(bad, PoseGraphConfig(), &poses, &res));
  EXPECT_NE(res.error.find("sigma"), std::string::npos) << res.error;
  for (std::size_t k = 0; k < poses.size(); ++k) EXPECT_TRUE(poses[k].isApprox(before[k]));
}

TEST(PoseGraph, PlanarSquareLoopRemovesDrift) {
  // 40 poses at 1 m on a 10 m square, 0.01 rad yaw bias per step (0.39 rad at the end); all
  // poses at z = 0.3, which the planar graph must keep.
  const Isometries truth = square(10, 10.0, 0.0, 0.3);
  Isometries poses = drift(truth, 0.01, 0.0, false);
  std::vector<PoseGraphEdge> edges = odometryEdges(poses, 0.05, 0.01);
  ASSERT_EQ(edges.size(), 39u);
  edges.push_back(edge(truth, 39, 0, true));
  const double ate_before = absoluteTrajectoryError(poses, truth, 2);
  const double end_before = (poses.back().translation() - truth.back().translation()).norm();

  PoseGraphConfig cfg;
  cfg.dimension = 2;
  PoseGraphResult res;
  ASSERT_TRUE(optimizePoseGraph(edges, cfg, &poses, &res)) << res.error;
  const double ate_after = absoluteTrajectoryError(poses, truth, 2);
  const double end_after = (poses.back().translation() - truth.back().translation()).norm();
  std::printf("planar: ATE %.3f -> %.3f m, end %.3f -> %.3f m, cost %.1f -> %.3f, %d its\n",
              ate_before, ate_after, end_before, end_after, res.initial_cost, res.final_cost,
              res.iterations);
  EXPECT_TRUE(res.converged);
  EXPECT_LT(res.final_cost, 1e-3 * res.initial_cost);
  EXPECT_GT(ate_before, 0.5);                     // the drift is real
  EXPECT_LT(whitened(edges.back(), poses), 1.0);  // the loop is closed
  EXPECT_LT(ate_after, 0.2 * ate_before);
  EXPECT_LT(ate_after, 0.05);
  EXPECT_LT(end_after, 0.03);
  EXPECT_LT(angle(poses.back(), truth.back()), 0.005);
  EXPECT_TRUE(poses[0].isApprox(truth[0]));  // gauge held
  for (const Eigen::Isometry3d& T : poses) EXPECT_NEAR(T.translation().z(), 0.3, 1e-12);
}

// The continuation (loop sigmas first x100, x30, x10, x3, then as given) ends in the same
// minimum as one solve where one solve finds it (a square whose yaw drifts 1.56 rad, loop
// edges every 8th pose, Huber 1 on them), and its stages count in the iterations. Where it
// matters, a start metres and tens of degrees off (the Intel log's odometry), it is shown by
// coral_loop_eval (doc/loop_closure.md).
TEST(PoseGraph, ContinuationEndsInTheSameMinimumAsOneSolve) {
  const Isometries truth = square(10, 10.0, 0.0);
  const Isometries start = drift(truth, 0.04, 0.0, false);
  std::vector<PoseGraphEdge> edges = odometryEdges(start, 0.05, 0.01);
  for (int k = 8; k < 40; k += 8) {
    edges.push_back(edge(truth, k, 0, true));
    edges.push_back(edge(truth, k, k - 8, true));
  }
  PoseGraphConfig cfg;
  cfg.dimension = 2;
  cfg.huber_loss = 1.0;
  Isometries plain = start, staged = start;
  PoseGraphResult r_plain, r_staged;
  ASSERT_TRUE(optimizePoseGraph(edges, cfg, &plain, &r_plain)) << r_plain.error;
  cfg.loop_sigma_schedule = {100.0, 30.0, 10.0, 3.0};
  ASSERT_TRUE(optimizePoseGraph(edges, cfg, &staged, &r_staged)) << r_staged.error;
  EXPECT_GT(absoluteTrajectoryError(start, truth, 2), 1.0);  // the drift is real
  EXPECT_LT(absoluteTrajectoryError(plain, truth, 2), 0.2);
  for (std::size_t k = 0; k < plain.size(); ++k) {
    EXPECT_LT((plain[k].translation() - staged[k].translation()).norm(), 1e-4) << k;
    EXPECT_LT(angle(plain[k], staged[k]), 1e-5) << k;
  }
  EXPECT_NEAR(r_staged.final_cost, r_plain.final_cost, 1e-6 * r_plain.final_cost);
  EXPECT_GT(r_staged.iterations, r_plain.iterations);  // 5 solves counted
  cfg.loop_sigma_schedule = {0.5};
  EXPECT_NE(cfg.validate().find("loop_sigma_schedule"), std::string::npos);
}

// `laps` times round the square of `square` (the same places, the heading turning on).
Isometries laps(int n_laps, double z0) {
  const Isometries lap = square(10, 10.0, 0.0, z0);
  Isometries T;
  for (int l = 0; l < n_laps; ++l) T.insert(T.end(), lap.begin(), lap.end());
  return T;
}

// Odometry edges of `start` (sigmas 0.05 m, odom_r) and loop edges (exact, from the truth;
// kLoopEdgeSigmaT/R) between the laps, every `every`-th pose of a lap to the same place on
// every earlier lap.
std::vector<PoseGraphEdge> lapGraph(const Isometries& truth, const Isometries& start, int every,
                                    double odom_r) {
  std::vector<PoseGraphEdge> edges = odometryEdges(start, 0.05, odom_r);
  for (int k = 40; k < static_cast<int>(truth.size()); k += every)
    for (int back = k - 40; back >= 0; back -= 40) {
      PoseGraphEdge e = edge(truth, back, k, true);
      e.sigma_translation = kLoopEdgeSigmaT;
      e.sigma_rotation = kLoopEdgeSigmaR;
      edges.push_back(e);
    }
  return edges;
}

// The linear start (chordal rotations, then positions) is exact where the edges agree: three
// laps, so the heading turns by 6 pi and a start that unwrapped angles would have to guess the
// turns; the start's own poses (drifted by 0.2 rad a step) only give node 0, z and roll.
TEST(PoseGraph, LinearStartIsExactOnConsistentEdges) {
  const Isometries truth = laps(3, 0.3);
  Isometries start = drift(truth, 0.2, 0.0, false);
  const std::vector<PoseGraphEdge> edges = lapGraph(truth, truth, 8, 0.01);  // exact odometry
  std::string error;
  ASSERT_TRUE(planarLinearStart(edges, &start, &error)) << error;
  for (std::size_t k = 0; k < truth.size(); ++k) {
    EXPECT_LT((start[k].translation() - truth[k].translation()).norm(), 1e-6) << k;
    EXPECT_LT(angle(start[k], truth[k]), 1e-7) << k;
  }
  // Refused, poses untouched: an edge past the last pose, a config asking for it in 3D.
  std::vector<PoseGraphEdge> bad = edges;
  bad.back().to = static_cast<int>(truth.size());
  const Isometries before = start;
  EXPECT_FALSE(planarLinearStart(bad, &start, &error));
  EXPECT_NE(error.find("out of range"), std::string::npos) << error;
  for (std::size_t k = 0; k < start.size(); ++k) EXPECT_TRUE(start[k].isApprox(before[k]));
  PoseGraphConfig cfg;
  cfg.try_linear_start = true;  // dimension 3
  EXPECT_NE(cfg.validate().find("try_linear_start"), std::string::npos);
  cfg.dimension = 2;
  EXPECT_EQ(cfg.validate(), "");
}

// Five laps of odometry whose heading drifts 0.04 rad a step (1.6 rad a lap), with the 2D
// logs' odometry yaw sigma (0.03 rad) and loop edges every 8th pose: the continuation alone
// stops in a local minimum whose laps are bent against each other (as coral_loop_eval's Intel
// graphs did, doc/loop_closure.md "Intel's graphs were folded"); the linear start ends near the
// truth at a far lower cost. Measured: ATE 1.08 m (cost 2164) against 0.10 m (cost 170).
// try_linear_start solves from both and keeps that one (on ACES graphs holding false edges the
// odometry's start can be the lower: doc/loop_closure.md).
TEST(PoseGraph, LinearStartLeavesTheFoldOfADriftedStart) {
  const Isometries truth = laps(5, 0.0);
  const Isometries odo = drift(truth, 0.04, 0.0, false);
  const std::vector<PoseGraphEdge> edges = lapGraph(truth, odo, 8, kLogOdometrySigmaR);
  PoseGraphConfig cfg = robustContinuationConfig(2);
  Isometries from_odometry = odo, from_linear = odo, from_start = odo;
  PoseGraphResult r_odometry, r_linear, r_start;
  std::string error;
  ASSERT_TRUE(optimizePoseGraph(edges, cfg, &from_odometry, &r_odometry)) << r_odometry.error;
  ASSERT_TRUE(planarLinearStart(edges, &from_linear, &error)) << error;
  ASSERT_TRUE(optimizePoseGraph(edges, cfg, &from_linear, &r_linear)) << r_linear.error;
  cfg.try_linear_start = true;  // both starts, the lower final cost kept
  ASSERT_TRUE(optimizePoseGraph(edges, cfg, &from_start, &r_start)) << r_start.error;
  EXPECT_DOUBLE_EQ(r_start.final_cost, std::min(r_odometry.final_cost, r_linear.final_cost));
  EXPECT_EQ(r_start.iterations, r_odometry.iterations + r_linear.iterations);
  for (std::size_t k = 0; k < from_start.size(); ++k)
    EXPECT_TRUE(from_start[k].isApprox(from_linear[k])) << k;
  const double ate_odometry = absoluteTrajectoryError(from_odometry, truth, 2),
               ate_start = absoluteTrajectoryError(from_start, truth, 2);
  std::printf(
      "five laps, 0.04 rad/step: ATE odometry %.3f, from it %.3f (cost %.1f), from the "
      "linear start %.3f m (cost %.1f)\n",
      absoluteTrajectoryError(odo, truth, 2), ate_odometry, r_odometry.final_cost, ate_start,
      r_start.final_cost);
  EXPECT_GT(ate_odometry, 0.5);  // the fold is real
  EXPECT_LT(ate_start, 0.15);
  EXPECT_LT(r_start.final_cost, 0.25 * r_odometry.final_cost);
  EXPECT_TRUE(from_start[0].isApprox(odo[0]));  // gauge held
}

TEST(PoseGraph, SpatialSquareLoopRemovesDrift) {
  // The square with +-1 m of z and yaw + roll bias, so the drift leaves the plane.
  const Isometries truth = square(10, 10.0, 1.0);
  Isometries poses = drift(truth, 0.01, 0.005, true);
  std::vector<PoseGraphEdge> edges = odometryEdges(poses, 0.05, 0.01);
  edges.push_back(edge(truth, 39, 0, true));
  const double ate_before = absoluteTrajectoryError(poses, truth, 3);

  PoseGraphConfig cfg;  // dimension 3
  PoseGraphResult res;
  ASSERT_TRUE(optimizePoseGraph(edges, cfg, &poses, &res)) << res.error;
  const double ate_after = absoluteTrajectoryError(poses, truth, 3);
  const double end_after = (poses.back().translation() - truth.back().translation()).norm();
  std::printf("spatial: ATE %.3f -> %.3f m, end %.3f m, cost %.1f -> %.3f, %d its\n", ate_before,
              ate_after, end_after, res.initial_cost, res.final_cost, res.iterations);
  EXPECT_TRUE(res.converged);
  EXPECT_GT(ate_before, 0.5);
  EXPECT_LT(whitened(edges.back(), poses), 1.0);
  EXPECT_LT(ate_after, 0.2 * ate_before);
  EXPECT_LT(ate_after, 0.05);
  EXPECT_LT(end_after, 0.03);
  EXPECT_LT(angle(poses.back(), truth.back()), 0.005);
  EXPECT_TRUE(poses[0].isApprox(truth[0]));
}

TEST(PoseGraph, HuberLimitsAWrongLoopEdge) {
  // The correct loop 39 -> 0 plus a wrong one 0 -> 20 that is 5 m off, both as certain as
  // one odometry step. Huber bounds the wrong edge's pull at ~1 sigma of force.
  const Isometries truth = square(10, 10.0, 0.0);
  const Isometries odo = drift(truth, 0.01, 0.0, false);
  std::vector<PoseGraphEdge> edges = odometryEdges(odo, 0.05, 0.01);
  edges.push_back(edge(truth, 39, 0, true));
  PoseGraphEdge wrong = edge(truth, 0, 20, true);
  wrong.T_from_to.translation() += Vec3(0.0, 5.0, 0.0);
  edges.push_back(wrong);
  for (std::size_t k = 39; k < edges.size(); ++k) {
    edges[k].sigma_translation = 0.05;
    edges[k].sigma_rotation = 0.01;
  }

  double ate[2], wrong_residual[2];
  for (int robust = 0; robust < 2; ++robust) {
    PoseGraphConfig cfg;
    cfg.dimension = 2;
    cfg.huber_loss = robust ? 1.0 : 0.0;
    Isometries poses = odo;
    PoseGraphResult res;
    ASSERT_TRUE(optimizePoseGraph(edges, cfg, &poses, &res)) << res.error;
    EXPECT_TRUE(res.converged);
    ate[robust] = absoluteTrajectoryError(poses, truth, 2);
    wrong_residual[robust] = whitened(edges.back(), poses);
  }
  const double ate_before = absoluteTrajectoryError(odo, truth, 2);
  std::printf(
      "wrong loop: ATE drifted %.3f, plain %.3f, huber %.3f m; wrong edge %.1f / %.1f sigma\n",
      ate_before, ate[0], ate[1], wrong_residual[0], wrong_residual[1]);
  EXPECT_GT(ate[0], ate_before);        // least squares is bent by the wrong edge...
  EXPECT_LT(wrong_residual[0], 10.0);   // ...which it mostly accepts,
  EXPECT_GT(wrong_residual[1], 50.0);   // while Huber rejects it
  EXPECT_LT(ate[1], 0.25 * ate[0]);     // and stays far less bent,
  EXPECT_LT(ate[1], 0.5 * ate_before);  // still better than no loop closure at all.
}

TEST(PoseGraph, AteOfRigidlyMovedTrajectoryIsZero) {
  const Isometries truth = square(10, 10.0, 1.0);
  Isometries moved;
  const Eigen::Isometry3d M = pose(Vec3(3.0, -7.0, 2.0), 1.1, 0.4);
  for (const Eigen::Isometry3d& T : truth) moved.push_back(M * T);
  EXPECT_NEAR(absoluteTrajectoryError(moved, truth, 3), 0.0, 1e-9);
  // Planar: a yaw + (x, y) move of a planar trajectory.
  const Isometries flat = square(10, 10.0, 0.0);
  const Eigen::Isometry3d P = pose(Vec3(3.0, -7.0, 0.0), -2.5);
  moved.clear();
  for (const Eigen::Isometry3d& T : flat) moved.push_back(P * T);
  EXPECT_NEAR(absoluteTrajectoryError(moved, flat, 2), 0.0, 1e-9);
  // A mirrored trajectory is not a planar motion: its ATE must not be 0.
  moved.clear();
  for (const Eigen::Isometry3d& T : flat)
    moved.push_back(pose(Vec3(T.translation().x(), -T.translation().y(), 0), 0));
  EXPECT_GT(absoluteTrajectoryError(moved, flat, 2), 1.0);
  EXPECT_TRUE(std::isnan(absoluteTrajectoryError(moved, Isometries(), 2)));
}

TEST(PoseGraph, AteOfOneOffsetPoseIsKnown) {
  // 5 poses on the x axis, the middle one moved 1 m sideways: the alignment can only shift
  // by d/N (no rotation helps by symmetry), so ATE = d sqrt(N - 1) / N = 0.4 m.
  Isometries ref, est;
  for (int k = -2; k <= 2; ++k) ref.push_back(pose(Vec3(k, 0.0, 0.0), 0.0));
  est = ref;
  est[2].translation().y() += 1.0;
  EXPECT_NEAR(absoluteTrajectoryError(est, ref, 2), 0.4, 1e-9);
  EXPECT_NEAR(absoluteTrajectoryError(est, ref, 3), 0.4, 1e-9);
  est = ref;
  est[2].translation().z() += 1.0;
  EXPECT_NEAR(absoluteTrajectoryError(est, ref, 3), 0.4, 1e-9);
  EXPECT_NEAR(absoluteTrajectoryError(est, ref, 2), 0.0, 1e-12);  // planar ignores z
}

TEST(PoseGraph, TumAndKittiWritersRoundTrip) {
  Isometries poses;
  poses.push_back(pose(Vec3(1.5, -2.25, 0.125), 0.3, -0.2));
  poses.push_back(pose(Vec3(-40.0, 7.0, 3.0), -2.9, 1.3));
  poses.push_back(Eigen::Isometry3d::Identity());
  const std::vector<double> stamps{1600000000.25, 1600000000.5, 1600000001.0};
  const std::string dir = ::testing::TempDir();
  std::string err;

  ASSERT_TRUE(writeTumTrajectory(dir + "/pg_traj.tum", stamps, poses, &err)) << err;
  std::vector<StampedPose> tum;
  ASSERT_TRUE(readTum(dir + "/pg_traj.tum", &tum, &err)) << err;
  ASSERT_EQ(tum.size(), poses.size());
  for (std::size_t k = 0; k < poses.size(); ++k) {
    EXPECT_NEAR(tum[k].t, stamps[k], 1e-6);
    EXPECT_LT((tum[k].p - poses[k].translation()).norm(), 1e-6);
    EXPECT_LT((tum[k].q.toRotationMatrix() - poses[k].linear()).norm(), 1e-7);
  }

  ASSERT_TRUE(writeKittiPoses(dir + "/pg_traj.kitti", poses, &err)) << err;
  Isometries kitti;
  ASSERT_TRUE(readKittiPoses(dir + "/pg_traj.kitti", &kitti, &err)) << err;
  ASSERT_EQ(kitti.size(), poses.size());
  for (std::size_t k = 0; k < poses.size(); ++k)
    EXPECT_LT((kitti[k].matrix() - poses[k].matrix()).norm(), 1e-9);

  err.clear();
  EXPECT_FALSE(writeTumTrajectory("/nonexistent_dir_pg/t.tum", stamps, poses, &err));
  EXPECT_FALSE(err.empty());
  err.clear();
  EXPECT_FALSE(writeKittiPoses("/nonexistent_dir_pg/t.kitti", poses, &err));
  EXPECT_FALSE(err.empty());
  err.clear();
  EXPECT_FALSE(writeTumTrajectory(dir + "/pg_bad.tum", {0.0}, poses, &err));  // size mismatch
  EXPECT_FALSE(err.empty());
}

// The back end's check after the gate (optimizePrunedPoseGraph): of three right loop edges and
// one 5 m off, the wrong one is left with the largest residual and removed, and the graph
// solved without it returns to the truth; the right ones stay. With a cap of no removal the
// wrong edge is kept and the graph is reported inconsistent; a bad pruning config is refused.
TEST(PoseGraph, PruningRemovesTheWrongLoopEdgeOnly) {
  const Isometries truth = square(10, 10.0, 0.0);
  const Isometries odo = drift(truth, 0.01, 0.0, false);
  std::vector<PoseGraphEdge> edges = odometryEdges(odo, 0.05, 0.01);
  for (const auto& ft : {std::make_pair(39, 0), std::make_pair(30, 10), std::make_pair(25, 5)})
    edges.push_back(edge(truth, ft.first, ft.second, true));
  PoseGraphEdge wrong = edge(truth, 0, 20, true);
  wrong.T_from_to.translation() += Vec3(0.0, 5.0, 0.0);
  edges.push_back(wrong);
  const int wrong_index = static_cast<int>(edges.size()) - 1;
  for (PoseGraphEdge& e : edges)
    if (e.loop) {
      e.sigma_translation = 0.05;
      e.sigma_rotation = 0.01;
    }
  const PoseGraphConfig cfg = robustContinuationConfig(2);
  ToleranceConfig tol;  // 0.3 m, 2 deg
  LoopPruning pruning;  // 3 tolerances

  Isometries huber = odo;
  ASSERT_TRUE(optimizePoseGraph(edges, cfg, &huber, nullptr));
  Isometries pruned = odo;
  std::vector<int> removed;
  bool consistent = false;
  PoseGraphResult res;
  ASSERT_TRUE(
      optimizePrunedPoseGraph(edges, cfg, tol, pruning, &pruned, &removed, &consistent, &res))
      << res.error;
  const double ate_huber = absoluteTrajectoryError(huber, truth, 2);
  const double ate_pruned = absoluteTrajectoryError(pruned, truth, 2);
  std::printf("pruning: removed %zu edge(s), ATE huber %.3f, pruned %.3f m\n", removed.size(),
              ate_huber, ate_pruned);
  ASSERT_EQ(removed, std::vector<int>{wrong_index});
  EXPECT_TRUE(consistent);
  EXPECT_GT(ate_huber, 3.0 * ate_pruned);  // Huber alone is still bent by the wrong edge
  EXPECT_LT(ate_pruned, 0.05);
  for (const PoseGraphEdge& e : edges)  // every kept loop edge explained within the tolerance
    if (e.loop && &e != &edges.back())
      EXPECT_LT(toleranceSize(e.T_from_to.inverse() * pruned[e.from].inverse() * pruned[e.to], tol),
                1.0);

  pruning.max_removals = 0;  // the cap: nothing removed, the wrong edge reported
  Isometries capped = odo;
  ASSERT_TRUE(
      optimizePrunedPoseGraph(edges, cfg, tol, pruning, &capped, &removed, &consistent, &res));
  EXPECT_TRUE(removed.empty());
  EXPECT_FALSE(consistent);
  EXPECT_NEAR(absoluteTrajectoryError(capped, truth, 2), ate_huber, 1e-9);

  pruning.max_residual = 0.0;
  Isometries untouched = odo;
  EXPECT_FALSE(
      optimizePrunedPoseGraph(edges, cfg, tol, pruning, &untouched, &removed, &consistent, &res));
  EXPECT_NE(res.error.find("max_residual"), std::string::npos) << res.error;
  EXPECT_TRUE(untouched[5].isApprox(odo[5]));
}
