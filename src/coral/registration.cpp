#include "coral_introspection/coral/registration.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "coral_introspection/coral/constraint.hpp"
#include "coral_introspection/coral/neighbour_grid.hpp"
#include "coral_introspection/coral/point_filter.hpp"
#include "coral_introspection/coral/validation.hpp"

namespace coral_introspection {
namespace coral {

std::string RegistrationConfig::validate() const {
  return Problems()
      .require(max_correspondence > 0.0 && max_correspondence <= 100.0, "max_correspondence",
               "in (0, 100] m", max_correspondence)
      .require(max_iterations >= 1 && max_iterations <= 1000, "max_iterations", "in [1, 1000]",
               max_iterations)
      .require(std::isfinite(min_step) && min_step > 0.0, "min_step", "> 0", min_step)
      .require(min_correspondences >= 3, "min_correspondences", ">= 3", min_correspondences)
      .require(normal_radius >= 0.0 && normal_radius <= 10.0, "normal_radius",
               "in [0, 10] m (0 = CorAl's radius)", normal_radius)
      .require(std::isfinite(robust_scale) && robust_scale >= 0.0, "robust_scale",
               ">= 0 m (0 = least squares)", robust_scale)
      .str();
}

// 3D target points whose neighbourhood spreads less than this in its second direction
// (surfaceNormal's spread, lambda_mid / lambda_max) get no normal.
constexpr double kMinSpread = 0.1;

struct SurfaceTarget::Impl {
  int dimension = 3;
  RegistrationConfig cfg;
  Points points, normals;
  // The nearest target point is searched within `near` first (near_grid, of that cell size),
  // then within max_correspondence (wide_grid, of that cell size; none when near reaches it):
  // most correspondences are close, and a wide search visits many points of a dense cloud.
  // Exact either way: a point found within `near` is the nearest of all.
  double near = 0.0;
  std::unique_ptr<NeighbourGrid> near_grid, wide_grid;

  // Index of the nearest target point to q within `radius` in `grid`, -1 when none.
  int nearestIn(const NeighbourGrid& grid, const Vec3& q, double radius) const {
    int best = -1;
    double best_d2 = std::numeric_limits<double>::infinity();
    grid.forEachWithin(q, radius, [&](const Vec3& p, uint32_t index) {
      const Vec3 d = p - q;
      const double d2 = dimension == 2 ? d.head<2>().squaredNorm() : d.squaredNorm();
      if (d2 < best_d2) {
        best_d2 = d2;
        best = static_cast<int>(index);
      }
    });
    return best;
  }
  // Index of the nearest target point to q within max_correspondence, -1 when none.
  int nearest(const Vec3& q) const {
    const int k = nearestIn(*near_grid, q, near);
    return k >= 0 || !wide_grid ? k : nearestIn(*wide_grid, q, cfg.max_correspondence);
  }
};

SurfaceTarget::SurfaceTarget(const Points& a, const CoralConfig& coral,
                             const RegistrationConfig& cfg)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.dimension = coral.dimension;
  m.cfg = cfg;
  Points finite;
  for (const Vec3& p : a)
    if (p.allFinite()) finite.push_back(p);
  const double r = cfg.normal_radius > 0.0 ? cfg.normal_radius : coral.maxRadius();
  const NeighbourGrid own(finite, r, coral.dimension);
  const std::size_t stride = strideFor(finite.size(), kMaxTargetPoints);
  for (std::size_t i = 0; i < finite.size(); i += stride) {
    const Vec3& q = finite[i];
    int n = 0;
    Vec3 sum = Vec3::Zero();
    Eigen::Matrix3d sq = Eigen::Matrix3d::Zero();
    own.forEachWithin(q, r, [&](const Vec3& p, uint32_t) {
      const Vec3 d = p - q;
      ++n;
      sum += d;
      sq += d * d.transpose();
    });
    if (n < coral.min_neighbours) continue;
    const Vec3 mean = sum / n;
    Vec3 normal;
    // 3D: a neighbourhood along one ring of a spinning lidar (a ring on the ground, a wall
    // seen by one ring) is a line, whose least direction is no surface normal: a ring's arc on
    // flat ground gets a horizontal "normal" and pulls the other scan's rings (at other radii)
    // onto its own. Only patches spread in two directions are used.
    double likeness = 0.0, spread = 0.0;
    if (!surfaceNormal(sq / n - mean * mean.transpose(), coral.dimension, &normal, &likeness,
                       &spread) ||
        spread < kMinSpread)
      continue;
    m.points.push_back(q);
    m.normals.push_back(normal);
  }
  m.near = std::min(cfg.max_correspondence, 0.25 * r);
  m.near_grid = std::make_unique<NeighbourGrid>(m.points, m.near, coral.dimension);
  if (m.near < cfg.max_correspondence)
    m.wide_grid =
        std::make_unique<NeighbourGrid>(m.points, cfg.max_correspondence, coral.dimension);
}

SurfaceTarget::~SurfaceTarget() = default;

std::size_t SurfaceTarget::size() const { return impl_->points.size(); }

RegistrationResult SurfaceTarget::align(
    const Points& b, const Eigen::Isometry3d& T_init, std::size_t max_points, double min_step,
    const std::function<bool(const Eigen::Isometry3d&)>& stop) const {
  const Impl& m = *impl_;
  RegistrationResult res;
  res.T_a_b = T_init;
  Points source;
  const std::size_t stride = strideFor(b.size(), std::max<std::size_t>(max_points, 1));
  const double step_done = min_step > 0.0 ? min_step : m.cfg.min_step;
  for (std::size_t i = 0; i < b.size(); i += stride)
    if (b[i].allFinite()) source.push_back(b[i]);
  if (m.points.empty()) return res;
  using Vec6 = Eigen::Matrix<double, 6, 1>;
  using Mat6 = Eigen::Matrix<double, 6, 6>;
  const double scale2 = m.cfg.robust_scale * m.cfg.robust_scale;
  for (int it = 1; it <= m.cfg.max_iterations; ++it) {
    res.iterations = it;
    Mat6 H = Mat6::Zero();
    Vec6 g = Vec6::Zero();
    int count = 0;
    for (const Vec3& p : source) {
      const Vec3 q = res.T_a_b * p;
      const int k = m.nearest(q);
      if (k < 0) continue;
      const Vec3& n = m.normals[k];
      // Residual n . (q - t) and its Jacobian for q moved by exp(delta): [n; q x n].
      const double r = n.dot(q - m.points[k]);
      Vec6 J;
      J << n, q.cross(n);
      // Cauchy weight (iteratively reweighted least squares): structure seen in one scan
      // only pulls little once its residuals exceed the scale.
      const double w = scale2 > 0.0 ? 1.0 / (1.0 + r * r / scale2) : 1.0;
      H += w * J * J.transpose();
      g += w * r * J;
      ++count;
    }
    res.correspondences = count;
    if (count < m.cfg.min_correspondences) return res;
    Vec6 delta = Vec6::Zero();
    if (m.dimension == 2) {  // x, y, yaw only
      const int idx[3] = {0, 1, 5};
      Eigen::Matrix3d h;
      Eigen::Vector3d gg;
      for (int i = 0; i < 3; ++i) {
        gg(i) = g(idx[i]);
        for (int j = 0; j < 3; ++j) h(i, j) = H(idx[i], idx[j]);
      }
      const Eigen::Vector3d d = h.ldlt().solve(-gg);
      for (int i = 0; i < 3; ++i) delta(idx[i]) = d(i);
    } else {
      delta = H.ldlt().solve(-g);
    }
    if (!delta.allFinite()) return res;  // degenerate (a single line or plane)
    const Vec3 w = delta.tail<3>();
    Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
    if (w.norm() > 0.0) step.linear() = Eigen::AngleAxisd(w.norm(), w.normalized()).matrix();
    step.translation() = delta.head<3>();
    res.T_a_b = step * res.T_a_b;
    if (delta.head<3>().norm() < step_done && w.norm() < step_done) {
      res.converged = true;
      return res;
    }
    if (stop && stop(res.T_a_b)) {
      res.stopped = true;
      return res;
    }
  }
  return res;
}

}  // namespace coral
}  // namespace coral_introspection
