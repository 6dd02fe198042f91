#include "coral_introspection/coral/constraint.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <vector>

#include "coral_introspection/coral/neighbour_grid.hpp"
#include "coral_introspection/coral/point_filter.hpp"

namespace coral_introspection {
namespace coral {

namespace {

// Points per scan whose normals enter the information (a stride over the rest): 2D scans
// (180-1080 beams) are used whole; a dense 3D cloud's weakest direction is estimated from a
// spread subset, which keeps this term a small part of a verdict's cost.
constexpr std::size_t kMaxQueries = 4000;

struct Shared {
  Vec3 p, n;
  double w;  // 1 - lambda_min / lambda_mid of the point's own neighbourhood
};

// Shared surface points of cloud `side` (0: a, 1: b) of the grid over (a, b).
std::vector<Shared> sharedPoints(const NeighbourGrid& grid, const Points& own, int side,
                                 std::size_t size_a, const CoralConfig& coral) {
  std::vector<Shared> out;
  const int dim = coral.dimension;
  const double r = coral.maxRadius();
  const std::size_t stride = strideFor(own.size(), kMaxQueries);
  for (std::size_t i = 0; i < own.size(); i += stride) {
    const Vec3& q = own[i];
    if (!q.allFinite()) continue;
    int n_own = 0, n_other = 0;
    Vec3 sum = Vec3::Zero();
    Eigen::Matrix3d sq = Eigen::Matrix3d::Zero();
    grid.forEachWithin(q, r, [&](const Vec3& p, uint32_t index) {
      const bool is_own = (index < size_a) == (side == 0);
      if (!is_own) {
        ++n_other;
        return;
      }
      const Vec3 d = p - q;
      ++n_own;
      sum += d;
      sq += d * d.transpose();
    });
    if (n_own < coral.min_neighbours || n_other < coral.min_neighbours_other) continue;
    const Vec3 mean = sum / n_own;
    const Eigen::Matrix3d cov = sq / n_own - mean * mean.transpose();
    Shared s{q, Vec3::Zero(), 0.0};
    if (!surfaceNormal(cov, dim, &s.n, &s.w)) continue;
    out.push_back(s);
  }
  return out;
}

// Smallest eigenvalue of sum w J J^T, J = [n, k (p - c) x n] in tolerance units (k = rotation
// tolerance [rad] / translation tolerance [m]); planar: the x, y, yaw rows.
double weakestDirection(const std::vector<Shared>& pts, int dim, double k) {
  if (pts.empty()) return 0.0;
  Vec3 c = Vec3::Zero();
  for (const Shared& s : pts) c += s.p;
  c /= static_cast<double>(pts.size());
  Eigen::Matrix<double, 6, 6> info = Eigen::Matrix<double, 6, 6>::Zero();
  for (const Shared& s : pts) {
    Eigen::Matrix<double, 6, 1> J;
    J << s.n, k * (s.p - c).cross(s.n);
    info += s.w * J * J.transpose();
  }
  if (dim == 2) {
    Eigen::Matrix3d planar;
    const int idx[3] = {0, 1, 5};  // x, y, yaw
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) planar(i, j) = info(idx[i], idx[j]);
    return std::max(0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(planar).eigenvalues()(0));
  }
  return std::max(
      0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>>(info).eigenvalues()(0));
}

}  // namespace

bool surfaceNormal(const Eigen::Matrix3d& cov, int dimension, Vec3* normal, double* weight,
                   double* spread) {
  *normal = Vec3::Zero();
  if (spread) *spread = 1.0;
  if (dimension == 2) {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(cov.topLeftCorner<2, 2>());
    const Eigen::Vector2d ev = es.eigenvalues();
    if (!(ev(1) > 0.0)) return false;
    normal->head<2>() = es.eigenvectors().col(0);
    *weight = 1.0 - std::max(0.0, ev(0)) / ev(1);
    return true;
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
  const Eigen::Vector3d ev = es.eigenvalues();
  if (!(ev(1) > 0.0)) return false;
  *normal = es.eigenvectors().col(0);
  *weight = 1.0 - std::max(0.0, ev(0)) / ev(1);
  if (spread) *spread = ev(1) / ev(2);
  return true;
}

ConstraintResult registrationConstraint(const Points& a, const Points& b,
                                        const Eigen::Isometry3d& T_a_b, const CoralConfig& coral,
                                        const ToleranceConfig& tolerance,
                                        double reference_beam_step_deg) {
  ConstraintResult res;
  Points fa, fb;  // finite points only (the grid's precondition), b's in a's frame
  for (const Vec3& p : a)
    if (p.allFinite()) fa.push_back(p);
  for (const Vec3& p : b)
    if (p.allFinite()) fb.push_back(T_a_b * p);
  const NeighbourGrid grid(fa, fb, coral.maxRadius(), coral.dimension);
  const double k = tolerance.rotation_deg * M_PI / 180.0 / tolerance.translation;
  const std::vector<Shared> sa = sharedPoints(grid, fa, 0, fa.size(), coral);
  const std::vector<Shared> sb = sharedPoints(grid, fb, 1, fa.size(), coral);
  res.valid = true;
  res.points = static_cast<int>(sa.size() + sb.size());
  // 2D: in points at the reference beam spacing (a denser scanner's points count their share).
  const bool planar = coral.dimension == 2;
  const double share_a = planar ? beamSpacingShare(a, reference_beam_step_deg) : 1.0;
  const double share_b = planar ? beamSpacingShare(b, reference_beam_step_deg) : 1.0;
  res.weakest = std::min(share_a * weakestDirection(sa, coral.dimension, k),
                         share_b * weakestDirection(sb, coral.dimension, k));
  return res;
}

}  // namespace coral
}  // namespace coral_introspection
