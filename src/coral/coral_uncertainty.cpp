#include "coral_introspection/coral/coral_uncertainty.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>

#include "coral_introspection/coral/entropy.hpp"
#include "coral_introspection/coral/neighbour_grid.hpp"
#include "coral_introspection/coral/point_filter.hpp"

namespace coral_introspection {
namespace coral {

std::string UncertainCoralConfig::validate() const {
  std::string e = base.validate();
  auto add = [&e](const std::string& m) { e += (e.empty() ? "" : "; ") + m; };
  if (!(gate_sigma > 0.0)) add("gate_sigma must be > 0 (got " + std::to_string(gate_sigma) + ")");
  if (!(base.r_min > 0.0 && base.r_min <= base.r_max))
    add("r_min must be in (0, r_max] m (got " + std::to_string(base.r_min) + ", r_max " +
        std::to_string(base.r_max) + ")");
  return e;
}

namespace {

struct Shape {
  Mat3 inv = Mat3::Zero();  // V diag(1 / a_i^2) V^T over the first dim coordinates
  double reach = 0.0;       // largest semi-axis [m]
};

Shape neighbourhoodShape(const Scan& s, std::size_t i, const UncertainCoralConfig& cfg) {
  const int dim = cfg.base.dimension;
  Shape sh;
  const bool has_cov = s.covariances.size() == s.points.size() && s.covariances[i].allFinite();
  if (!has_cov) {  // isotropic fallback: plain CorAl's (dynamic) radius
    const Vec3 rel = s.points[i] - s.origin;
    sh.reach = dynamicRadius(cfg.base, dim == 2 ? rel.head<2>().norm() : rel.norm());
    sh.inv.topLeftCorner(dim, dim).setIdentity();
    sh.inv /= sh.reach * sh.reach;
    return sh;
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(
      s.covariances[i].topLeftCorner(dim, dim).eval());
  Eigen::VectorXd inv_a2(dim);
  for (int k = 0; k < dim; ++k) {
    const double a = std::clamp(cfg.gate_sigma * std::sqrt(std::max(0.0, es.eigenvalues()(k))),
                                cfg.base.r_min, cfg.base.r_max);
    sh.reach = std::max(sh.reach, a);
    inv_a2(k) = 1.0 / (a * a);
  }
  sh.inv.topLeftCorner(dim, dim) =
      es.eigenvectors() * inv_a2.asDiagonal() * es.eigenvectors().transpose();
  return sh;
}

// Per point of `own`: entropies of its ellipsoidal neighbourhood in its own cloud and in
// the joint cloud (Eq. 1, 3, 4); valid only with enough neighbours in both clouds.
void scoreScan(const Scan& own, const NeighbourGrid& own_grid, const NeighbourGrid& other_grid,
               const UncertainCoralConfig& cfg, uint8_t scan, std::vector<PointEntropy>& out) {
  const CoralConfig& b = cfg.base;
  for (std::size_t i = 0; i < own.points.size(); ++i) {
    const Vec3& p = own.points[i];
    const Shape sh = neighbourhoodShape(own, i, cfg);
    auto inside = [&](const Vec3& x) {
      Vec3 d = x - p;
      if (b.dimension == 2) d.z() = 0.0;
      return d.dot(sh.inv * d) <= 1.0;
    };
    Moments m_own, m_other;
    own_grid.forEachWithin(p, sh.reach, [&](const Vec3& x, uint32_t) {
      if (inside(x)) m_own.add(x - p);
    });
    other_grid.forEachWithin(p, sh.reach, [&](const Vec3& x, uint32_t) {
      if (inside(x)) m_other.add(x - p);
    });
    PointEntropy pe;
    pe.position = p.cast<float>();
    pe.scan = scan;
    pe.radius = static_cast<float>(sh.reach);
    scorePoint(m_own, m_other, b, &pe);
    out.push_back(pe);
  }
}

}  // namespace

CoralResult computeCoralUncertain(const Scan& a_in, const Scan& b_in,
                                  const UncertainCoralConfig& cfg) {
  const auto t0 = std::chrono::steady_clock::now();
  Scan a = a_in, b = b_in;
  CoralResult res;
  // The input hygiene of computeCoral: NaN/Inf, points beyond max_abs_coordinate and beyond
  // max_range of their origin are dropped and counted (covariances follow their points).
  for (Scan* s : {&a, &b}) {
    removeUnusable(*s, cfg.base.max_abs_coordinate, &res.num_non_finite, &res.num_out_of_range);
    removeBeyondRange(*s, cfg.base.max_range, cfg.base.dimension, &res.num_beyond_max_range);
  }
  res.num_points_a = a.points.size();
  res.num_points_b = b.points.size();
  const double cell = std::max(cfg.base.r_max, cfg.base.maxRadius());
  const NeighbourGrid grid_a(a.points, cell, cfg.base.dimension);
  const NeighbourGrid grid_b(b.points, cell, cfg.base.dimension);
  res.num_used_a = a.points.size();
  res.num_used_b = b.points.size();
  std::vector<PointEntropy> per_point;
  per_point.reserve(a.points.size() + b.points.size());
  scoreScan(a, grid_a, grid_b, cfg, 0, per_point);
  scoreScan(b, grid_b, grid_a, cfg, 1, per_point);

  finalizeCoral(cfg.base, std::move(per_point), &res);
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

}  // namespace coral
}  // namespace coral_introspection
