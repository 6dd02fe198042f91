#include "coral_introspection/eval/pose_graph.hpp"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>

#include "coral_introspection/coral/refinement.hpp"
#include "coral_introspection/coral/types.hpp"
#include "coral_introspection/coral/validation.hpp"
#include "coral_introspection/eval/trajectory_metrics.hpp"

namespace coral_introspection {
namespace eval {

namespace {

// SE(3) edge on blocks (p, q) with q in Eigen order (x, y, z, w). Residual: translation and
// rotation vector of T_ij^-1 T_i^-1 T_j (the R^3 x SO(3) log, equal to the SE(3) Log to first
// order). rio::PoseManifold is not reused: it expects hand-written tangent Jacobians, while
// this AutoDiff functor yields ambient ones, which EigenQuaternionManifold maps correctly.
struct EdgeCost {
  Eigen::Vector3d p_ij;
  Eigen::Quaterniond q_ij;
  double inv_sigma_t, inv_sigma_r;

  template <typename T>
  bool operator()(const T* pi, const T* qi, const T* pj, const T* qj, T* r) const {
    using V3 = Eigen::Matrix<T, 3, 1>;
    using Q = Eigen::Quaternion<T>;
    const Eigen::Map<const V3> p_i(pi), p_j(pj);
    const Eigen::Map<const Q> q_i(qi), q_j(qj);
    const Q q_m = q_ij.cast<T>();
    const Q q_err = q_m.conjugate() * (q_i.conjugate() * q_j);
    const V3 p_err = q_m.conjugate() * (q_i.conjugate() * (p_j - p_i) - p_ij.cast<T>());
    const T wxyz[4] = {q_err.w(), q_err.x(), q_err.y(), q_err.z()};
    T rotvec[3];
    ceres::QuaternionToAngleAxis(wxyz, rotvec);  // exact Log, shortest rotation
    for (int k = 0; k < 3; ++k) {
      r[k] = p_err[k] * inv_sigma_t;
      r[3 + k] = rotvec[k] * inv_sigma_r;
    }
    return true;
  }
};

// Planar edge on blocks (x, y, yaw): the same residual restricted to SE(2). The yaw error is
// wrapped to (-pi, pi] so a loop that has turned by 2 pi is not seen as a 2 pi error.
struct PlanarEdgeCost {
  double dx, dy, dyaw;
  double inv_sigma_t, inv_sigma_r;

  template <typename T>
  bool operator()(const T* a, const T* b, T* r) const {
    using std::ceil;  // Jets: ceres::ceil/cos/sin by argument-dependent lookup
    using std::cos;
    using std::sin;
    const T ca = cos(a[2]), sa = sin(a[2]);
    const T ex = b[0] - a[0], ey = b[1] - a[1];
    const T rx = ca * ex + sa * ey - dx, ry = -sa * ex + ca * ey - dy;  // in a's frame
    const double cm = std::cos(dyaw), sm = std::sin(dyaw);              // into the meas. frame
    r[0] = (cm * rx + sm * ry) * inv_sigma_t;
    r[1] = (-sm * rx + cm * ry) * inv_sigma_t;
    const T e = b[2] - a[2] - dyaw;
    // ceil() is piecewise constant, so the Jacobian of the wrap is 1.
    r[2] = (e - 2.0 * M_PI * ceil((e - M_PI) / (2.0 * M_PI))) * inv_sigma_r;
    return true;
  }
};

}  // namespace

PoseGraphConfig robustContinuationConfig(int dimension) {
  PoseGraphConfig c;
  c.dimension = dimension;
  c.huber_loss = 1.0;
  c.loop_sigma_schedule = {100.0, 30.0, 10.0, 3.0};
  return c;
}

std::string PoseGraphConfig::validate() const {
  return coral::Problems()
      .require(dimension == 2 || dimension == 3, "dimension", "2 or 3", dimension)
      .require(max_iterations >= 1, "max_iterations", ">= 1", max_iterations)
      .require(std::isfinite(huber_loss) && huber_loss >= 0.0, "huber_loss",
               ">= 0 (whitened units; 0 = none)", huber_loss)
      .require(std::all_of(loop_sigma_schedule.begin(), loop_sigma_schedule.end(),
                           [](double f) { return std::isfinite(f) && f > 1.0; }),
               "loop_sigma_schedule: every factor must be finite and > 1")
      .require(!try_linear_start || dimension == 2,
               "try_linear_start: planar graphs only (dimension 2)")
      .str();
}

bool optimizePoseGraph(const std::vector<PoseGraphEdge>& edges, const PoseGraphConfig& cfg,
                       coral::Isometries* poses, PoseGraphResult* result) {
  PoseGraphResult local;
  PoseGraphResult& res = result ? *result : local;
  res = PoseGraphResult();
  const std::string problems = cfg.validate();
  if (!problems.empty()) return coral::fail(&res.error, problems);
  if (!poses || poses->empty()) return coral::fail(&res.error, "pose graph without poses");
  if (cfg.try_linear_start) {  // solved from both starts; the lower final cost is kept
    PoseGraphConfig one = cfg;
    one.try_linear_start = false;
    coral::Isometries from_given = *poses, from_linear = *poses;  // *poses untouched on failure
    PoseGraphResult linear;
    if (!optimizePoseGraph(edges, one, &from_given, &res) ||
        !planarLinearStart(edges, &from_linear, &res.error))
      return false;
    if (!optimizePoseGraph(edges, one, &from_linear, &linear))
      return coral::fail(&res.error, linear.error);
    const int iterations = res.iterations + linear.iterations;
    if (linear.final_cost < res.final_cost) {
      res = linear;
      from_given = from_linear;
    }
    res.iterations = iterations;
    *poses = from_given;
    return true;
  }
  if (!cfg.loop_sigma_schedule.empty()) {  // the continuation stages, then the solve below
    PoseGraphConfig stage_cfg = cfg;
    stage_cfg.loop_sigma_schedule.clear();
    coral::Isometries staged = *poses;  // *poses untouched when a stage fails
    int iterations = 0;
    for (double f : cfg.loop_sigma_schedule) {
      std::vector<PoseGraphEdge> soft = edges;
      for (PoseGraphEdge& e : soft)
        if (e.loop) {
          e.sigma_translation *= f;
          e.sigma_rotation *= f;
        }
      if (!optimizePoseGraph(soft, stage_cfg, &staged, &res)) return false;
      iterations += res.iterations;
    }
    if (!optimizePoseGraph(edges, stage_cfg, &staged, &res)) return false;
    res.iterations += iterations;
    *poses = staged;
    return true;
  }
  const int n = static_cast<int>(poses->size());
  for (std::size_t k = 0; k < edges.size(); ++k) {
    const PoseGraphEdge& e = edges[k];
    const std::string name = "edge " + std::to_string(k) + ": ";
    if (e.from < 0 || e.from >= n || e.to < 0 || e.to >= n || e.from == e.to)
      return coral::fail(&res.error, name + "indices " + std::to_string(e.from) + " -> " +
                                         std::to_string(e.to) + " invalid for " +
                                         std::to_string(n) + " poses");
    if (!(e.sigma_translation > 0.0 && e.sigma_rotation > 0.0) ||
        !std::isfinite(e.sigma_translation) || !std::isfinite(e.sigma_rotation))
      return coral::fail(&res.error, name + "sigmas must be finite and > 0");
  }

  const bool planar = cfg.dimension == 2;
  // Per pose: planar (x, y, yaw), else p (3) and q (x, y, z, w). Sized once: stable addresses.
  std::vector<std::array<double, 7>> x(n);
  ceres::Problem problem;
  ceres::Manifold* quaternion = planar ? nullptr : new ceres::EigenQuaternionManifold;
  for (int k = 0; k < n; ++k) {
    const Eigen::Isometry3d& T = (*poses)[k];
    double* b = x[k].data();
    if (planar) {
      b[0] = T.translation().x();
      b[1] = T.translation().y();
      b[2] = coral::yawOf(T.linear());
      problem.AddParameterBlock(b, 3);
      if (k == 0) problem.SetParameterBlockConstant(b);
    } else {
      Eigen::Vector3d::Map(b) = T.translation();
      Eigen::Vector4d::Map(b + 3) = Eigen::Quaterniond(T.linear()).normalized().coeffs();
      problem.AddParameterBlock(b, 3);
      problem.AddParameterBlock(b + 3, 4, quaternion);  // shared; the problem deletes it once
      if (k == 0) {
        problem.SetParameterBlockConstant(b);
        problem.SetParameterBlockConstant(b + 3);
      }
    }
  }
  for (const PoseGraphEdge& e : edges) {
    ceres::LossFunction* loss =
        e.loop && cfg.huber_loss > 0.0 ? new ceres::HuberLoss(cfg.huber_loss) : nullptr;
    const double ist = 1.0 / e.sigma_translation, isr = 1.0 / e.sigma_rotation;
    double *a = x[e.from].data(), *b = x[e.to].data();
    if (planar) {
      auto* c = new PlanarEdgeCost{e.T_from_to.translation().x(), e.T_from_to.translation().y(),
                                   coral::yawOf(e.T_from_to.linear()), ist, isr};
      problem.AddResidualBlock(new ceres::AutoDiffCostFunction<PlanarEdgeCost, 3, 3, 3>(c), loss, a,
                               b);
    } else {
      auto* c = new EdgeCost{e.T_from_to.translation(),
                             Eigen::Quaterniond(e.T_from_to.linear()).normalized(), ist, isr};
      problem.AddResidualBlock(new ceres::AutoDiffCostFunction<EdgeCost, 6, 3, 4, 3, 4>(c), loss, a,
                               a + 3, b, b + 3);
    }
  }

  ceres::Solver::Options opt;
  opt.max_num_iterations = cfg.max_iterations;
  opt.num_threads = 1;
  opt.logging_type = ceres::SILENT;
  // A pose graph is sparse (a chain plus a few loops): sparse Cholesky when Ceres has one.
  opt.linear_solver_type =
      ceres::IsSparseLinearAlgebraLibraryTypeAvailable(opt.sparse_linear_algebra_library_type)
          ? ceres::SPARSE_NORMAL_CHOLESKY
          : ceres::DENSE_QR;
  ceres::Solver::Summary summary;
  ceres::Solve(opt, &problem, &summary);
  res.initial_cost = summary.initial_cost;
  res.final_cost = summary.final_cost;
  res.iterations = summary.num_successful_steps + summary.num_unsuccessful_steps;
  res.converged = summary.termination_type == ceres::CONVERGENCE;
  if (!summary.IsSolutionUsable()) return coral::fail(&res.error, "ceres: " + summary.message);

  for (int k = 1; k < n; ++k) {
    Eigen::Isometry3d& T = (*poses)[k];
    const double* b = x[k].data();
    if (planar) {
      // Keep roll/pitch: R = Rz(yaw) R_rp with R_rp = Rz(yaw0)^T R0; z is kept as well.
      const Eigen::AngleAxisd yaw0(coral::yawOf(T.linear()), Eigen::Vector3d::UnitZ());
      const Eigen::Matrix3d R_rp = yaw0.toRotationMatrix().transpose() * T.linear();
      T.linear() = Eigen::AngleAxisd(b[2], Eigen::Vector3d::UnitZ()).toRotationMatrix() * R_rp;
      T.translation().head<2>() = Eigen::Vector2d(b[0], b[1]);
    } else {
      T.linear() = Eigen::Quaterniond(b[6], b[3], b[4], b[5]).normalized().toRotationMatrix();
      T.translation() = Eigen::Map<const Eigen::Vector3d>(b);
    }
  }
  return true;
}

std::string LoopPruning::validate() const {
  return coral::Problems()
      .require(std::isfinite(max_residual) && max_residual > 0.0, "max_residual",
               "> 0 [tolerances]", max_residual)
      .require(max_removals >= 0, "max_removals", ">= 0", max_removals)
      .str();
}

bool optimizePrunedPoseGraph(std::vector<PoseGraphEdge> edges, const PoseGraphConfig& cfg,
                             const coral::ToleranceConfig& tolerance, const LoopPruning& pruning,
                             coral::Isometries* poses, std::vector<int>* removed, bool* consistent,
                             PoseGraphResult* result) {
  PoseGraphResult local;
  PoseGraphResult& res = result ? *result : local;
  if (removed) removed->clear();
  if (consistent) *consistent = false;
  const std::string problems = coral::Problems()
                                   .nested("pruning", pruning.validate())
                                   .nested("tolerance", tolerance.validate())
                                   .str();
  if (!problems.empty()) return coral::fail(&res.error, problems);
  if (!poses) return coral::fail(&res.error, "pose graph without poses");
  // The loop edge the poses explain worst and its residual [tolerances] (edges.size(), 0 when
  // there is no loop edge).
  auto worstLoopEdge = [&](const std::vector<PoseGraphEdge>& es, const coral::Isometries& T) {
    std::pair<std::size_t, double> worst(es.size(), 0.0);
    for (std::size_t k = 0; k < es.size(); ++k) {
      if (!es[k].loop) continue;
      const double size = coral::toleranceSize(
          es[k].T_from_to.inverse() * T[es[k].from].inverse() * T[es[k].to], tolerance);
      if (size > worst.second) worst = {k, size};
    }
    return worst;
  };
  std::vector<int> index(edges.size());  // position in the caller's `edges`
  for (std::size_t k = 0; k < index.size(); ++k) index[k] = static_cast<int>(k);
  coral::Isometries solved = *poses;
  if (!optimizePoseGraph(edges, cfg, &solved, &res)) return false;
  // Later solves start at the last optimum, without the continuation: the cost starts at the
  // last one less the removed edge's and only falls.
  PoseGraphConfig warm = cfg;
  warm.loop_sigma_schedule.clear();
  warm.try_linear_start = false;
  for (int round = 0;; ++round) {
    const auto [worst, size] = worstLoopEdge(edges, solved);
    const bool strained = size > pruning.max_residual;
    if (!strained || round == pruning.max_removals) {
      if (consistent) *consistent = !strained;
      *poses = solved;
      return true;
    }
    if (removed) removed->push_back(index[worst]);
    edges.erase(edges.begin() + static_cast<std::ptrdiff_t>(worst));
    index.erase(index.begin() + static_cast<std::ptrdiff_t>(worst));
    if (!optimizePoseGraph(edges, warm, &solved, &res)) return false;
  }
}

namespace {

// The linear start's weights on each node's own start: node 0 held (the gauge), the others a
// weak prior that only places nodes no edge reaches.
constexpr double kWeakPrior = 1e-9, kAnchor = 1e12;

// Solves sum_e w_e (u[to] - u[from] - rhs_e)^2 + the start's weights * (u[k] - u0[k])^2 for u.
bool linearChain(const std::vector<PoseGraphEdge>& edges, const std::vector<double>& weight,
                 const std::vector<double>& rhs, const std::vector<double>& u0,
                 std::vector<double>* u) {
  const int n = static_cast<int>(u0.size());
  std::vector<Eigen::Triplet<double>> t;
  Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
  for (int k = 0; k < n; ++k) {
    const double w = k == 0 ? kAnchor : kWeakPrior;
    t.emplace_back(k, k, w);
    b[k] += w * u0[k];
  }
  for (std::size_t e = 0; e < edges.size(); ++e) {
    const int i = edges[e].from, j = edges[e].to;
    const double w = weight[e];
    t.emplace_back(i, i, w);
    t.emplace_back(j, j, w);
    t.emplace_back(i, j, -w);
    t.emplace_back(j, i, -w);
    b[j] += w * rhs[e];
    b[i] -= w * rhs[e];
  }
  Eigen::SparseMatrix<double> A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(A);
  if (solver.info() != Eigen::Success) return false;
  const Eigen::VectorXd x = solver.solve(b);
  if (solver.info() != Eigen::Success || !x.allFinite()) return false;
  u->assign(x.data(), x.data() + n);
  return true;
}

}  // namespace

bool planarLinearStart(const std::vector<PoseGraphEdge>& edges, coral::Isometries* poses,
                       std::string* error) {
  if (!poses || poses->empty()) return coral::fail(error, "pose graph without poses");
  const int n = static_cast<int>(poses->size());
  for (const PoseGraphEdge& e : edges)
    if (e.from < 0 || e.to < 0 || e.from >= n || e.to >= n || e.from == e.to ||
        !(e.sigma_translation > 0.0 && e.sigma_rotation > 0.0))
      return coral::fail(error, "planar linear start: an edge out of range or without sigmas");
  // 1. Orientations by the chordal relaxation: each node's (cos, sin) as free unknowns, every
  // edge's rotation a linear constraint R_j = R_i R_ij between them, solved by linear least
  // squares and then normalised. No angle is unwrapped, so no 2 pi is guessed (the relaxation
  // Carlone et al. 2015 found the most accurate start for rotations).
  std::vector<double> yaw0(n);
  for (int k = 0; k < n; ++k) yaw0[k] = coral::yawOf((*poses)[k].linear());
  std::vector<Eigen::Triplet<double>> t;
  Eigen::VectorXd b = Eigen::VectorXd::Zero(2 * n);
  for (int k = 0; k < n; ++k) {
    const double w = k == 0 ? kAnchor : kWeakPrior;
    for (int r = 0; r < 2; ++r) t.emplace_back(2 * k + r, 2 * k + r, w);
    b[2 * k] += w * std::cos(yaw0[k]);
    b[2 * k + 1] += w * std::sin(yaw0[k]);
  }
  for (const PoseGraphEdge& e : edges) {
    // Residual z_j - M z_i, M the edge's 2D rotation acting on z_i = (cos, sin) of node i.
    const Eigen::Matrix2d M = Eigen::Rotation2Dd(coral::yawOf(e.T_from_to.linear())).matrix();
    const double w = 1.0 / (e.sigma_rotation * e.sigma_rotation);
    const int i = 2 * e.from, j = 2 * e.to;
    for (int r = 0; r < 2; ++r) {
      t.emplace_back(i + r, i + r, w);  // M^T M = I
      t.emplace_back(j + r, j + r, w);
      for (int c = 0; c < 2; ++c) {
        t.emplace_back(j + r, i + c, -w * M(r, c));
        t.emplace_back(i + c, j + r, -w * M(r, c));
      }
    }
  }
  Eigen::SparseMatrix<double> A(2 * n, 2 * n);
  A.setFromTriplets(t.begin(), t.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> rotations(A);
  const Eigen::VectorXd z = rotations.solve(b);
  if (rotations.info() != Eigen::Success || !z.allFinite())
    return coral::fail(error, "planar linear start: the rotation solve failed");
  std::vector<double> yaw(n);
  for (int k = 0; k < n; ++k) yaw[k] = std::atan2(z[2 * k + 1], z[2 * k]);
  // 2. With the orientations fixed the positions are linear (LAGO's second step, Carlone et al.
  // 2014), x and y apart.
  std::vector<double> w_t(edges.size()), dx(edges.size()), dy(edges.size()), x0(n), y0(n), x, y;
  for (std::size_t e = 0; e < edges.size(); ++e) {
    const PoseGraphEdge& g = edges[e];
    const Eigen::Vector2d d = Eigen::Rotation2Dd(yaw[g.from]) * g.T_from_to.translation().head<2>();
    dx[e] = d.x();
    dy[e] = d.y();
    w_t[e] = 1.0 / (g.sigma_translation * g.sigma_translation);
  }
  for (int k = 0; k < n; ++k) {
    x0[k] = (*poses)[k].translation().x();
    y0[k] = (*poses)[k].translation().y();
  }
  if (!linearChain(edges, w_t, dx, x0, &x) || !linearChain(edges, w_t, dy, y0, &y))
    return coral::fail(error, "planar linear start: the position solve failed");
  for (int k = 1; k < n; ++k) {  // node 0 stays (the gauge); z, roll and pitch are kept
    Eigen::Isometry3d& T = (*poses)[k];
    const Eigen::AngleAxisd turn(yaw[k] - yaw0[k], Eigen::Vector3d::UnitZ());
    T.linear() = turn.toRotationMatrix() * T.linear();
    T.translation().head<2>() = Eigen::Vector2d(x[k], y[k]);
  }
  return true;
}

std::vector<PoseGraphEdge> odometryEdges(const coral::Isometries& odom_poses,
                                         double sigma_translation, double sigma_rotation) {
  std::vector<PoseGraphEdge> edges;
  for (std::size_t k = 1; k < odom_poses.size(); ++k) {
    PoseGraphEdge e;
    e.from = static_cast<int>(k - 1);
    e.to = static_cast<int>(k);
    e.T_from_to = odom_poses[k - 1].inverse() * odom_poses[k];
    e.sigma_translation = sigma_translation;
    e.sigma_rotation = sigma_rotation;
    edges.push_back(e);
  }
  return edges;
}

double absoluteTrajectoryError(const coral::Isometries& estimate,
                               const coral::Isometries& reference, int dimension) {
  const std::size_t n = estimate.size();
  if (n == 0 || n != reference.size()) return std::numeric_limits<double>::quiet_NaN();
  if (dimension != 2) {
    // Reuse the evaluation's APE: stamps = indices, so pose k is matched with pose k.
    std::vector<StampedPose> est(n), ref(n);
    for (std::size_t k = 0; k < n; ++k) {
      est[k].t = ref[k].t = static_cast<double>(k);
      est[k].p = estimate[k].translation();
      est[k].q = Eigen::Quaterniond(estimate[k].linear()).normalized();
      ref[k].p = reference[k].translation();
      ref[k].q = Eigen::Quaterniond(reference[k].linear()).normalized();
    }
    return trajectoryErrors(est, ref, 0.25, true).ape_trans;
  }
  // Planar: closed-form yaw + (x, y) alignment. The 3D Umeyama on z = 0 points could return
  // an in-plane reflection (a 180 deg roll costs nothing there), which a planar robot can't do.
  Eigen::Vector2d me = Eigen::Vector2d::Zero(), mr = Eigen::Vector2d::Zero();
  for (std::size_t k = 0; k < n; ++k) {
    me += estimate[k].translation().head<2>();
    mr += reference[k].translation().head<2>();
  }
  me /= static_cast<double>(n);
  mr /= static_cast<double>(n);
  double dot = 0.0, cross = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const Eigen::Vector2d e = estimate[k].translation().head<2>() - me;
    const Eigen::Vector2d r = reference[k].translation().head<2>() - mr;
    dot += e.dot(r);
    cross += e.x() * r.y() - e.y() * r.x();
  }
  const Eigen::Rotation2Dd R(std::atan2(cross, dot));
  double sum = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const Eigen::Vector2d e = estimate[k].translation().head<2>() - me;
    const Eigen::Vector2d r = reference[k].translation().head<2>() - mr;
    sum += (r - R * e).squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(n));
}

bool writeTumTrajectory(const std::string& path, const std::vector<double>& stamps,
                        const coral::Isometries& poses, std::string* error) {
  if (stamps.size() != poses.size())
    return coral::fail(error, path + ": " + std::to_string(stamps.size()) + " stamps for " +
                                  std::to_string(poses.size()) + " poses");
  std::vector<StampedPose> trajectory(poses.size());
  for (std::size_t k = 0; k < poses.size(); ++k) {
    trajectory[k].t = stamps[k];
    trajectory[k].p = poses[k].translation();
    trajectory[k].q = Eigen::Quaterniond(poses[k].linear()).normalized();
  }
  return writeTum(path, trajectory, error) || coral::fail(error, "cannot write " + path);
}

bool writeKittiPoses(const std::string& path, const coral::Isometries& poses, std::string* error) {
  std::ofstream out(path);
  if (!out) return coral::fail(error, "cannot write " + path);
  out << std::setprecision(12);
  for (const Eigen::Isometry3d& T : poses) {
    const Eigen::Matrix<double, 3, 4> M = T.matrix().topRows<3>();
    for (int i = 0; i < 12; ++i) out << M(i / 4, i % 4) << (i == 11 ? '\n' : ' ');
  }
  out.close();
  return !out.fail() || coral::fail(error, "error while writing " + path);
}

}  // namespace eval
}  // namespace coral_introspection
