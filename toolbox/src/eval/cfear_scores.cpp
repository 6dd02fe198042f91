#include "coral_introspection/eval/cfear_scores.hpp"

#include "coral_introspection/coral/validation.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "coral_introspection/coral/entropy.hpp"
#include "coral_introspection/coral/neighbour_grid.hpp"

namespace coral_introspection {
namespace eval {

std::string CfearConfig::validate() const {
  return coral::Problems()
      .require(resolution > 0.0, "resolution", "> 0 m", resolution)
      .require(min_points >= 3, "min_points", ">= 3", min_points)
      .require(eigen_floor_ratio > 0.0 && eigen_floor_ratio <= 1.0, "eigen_floor_ratio",
               "in (0, 1]", eigen_floor_ratio)
      .str();
}

namespace {
coral::Points planarFinite(const coral::Points& in) {
  coral::Points out;
  out.reserve(in.size());
  for (const coral::Vec3& p : in)
    if (p.head<2>().allFinite()) out.emplace_back(p.x(), p.y(), 0.0);
  return out;
}
}  // namespace

SurfacePoints computeSurfacePoints(const coral::Points& points, const CfearConfig& cfg) {
  SurfacePoints out;
  if (!cfg.validate().empty()) return out;
  const coral::Points pts = planarFinite(points);
  // Grid downsampling: the mean of the points of each occupied cell.
  const double inv = 1.0 / cfg.resolution;
  struct CellSum {
    coral::Vec3 sum =
        coral::Vec3::Zero();  // explicit: Eigen leaves default-constructed vectors unset
    double n = 0.0;
  };
  std::unordered_map<uint64_t, CellSum> cells;
  for (const coral::Vec3& p : pts) {
    const auto ix = static_cast<int64_t>(std::floor(p.x() * inv));
    const auto iy = static_cast<int64_t>(std::floor(p.y() * inv));
    CellSum& c =
        cells[(static_cast<uint64_t>(ix) << 32) ^ (static_cast<uint64_t>(iy) & 0xffffffffu)];
    c.sum += p;
    c.n += 1.0;
  }
  const coral::NeighbourGrid grid(pts, cfg.resolution, 2);
  for (const auto& kv : cells) {
    const coral::Vec3 centre = kv.second.sum / kv.second.n;
    coral::Moments m;
    grid.forEachWithin(centre, cfg.resolution,
                       [&](const coral::Vec3& x, uint32_t) { m.add(x - centre); });
    if (m.n < cfg.min_points) continue;
    SurfacePoint s;
    s.num_points = static_cast<int>(m.n);
    s.mean = (centre + m.sum / m.n).head<2>();
    const Eigen::Matrix2d cov = m.covariance().topLeftCorner<2, 2>();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(cov);
    Eigen::Vector2d ev = es.eigenvalues();  // ascending
    if (!(ev(1) > 0.0) || !ev.allFinite()) continue;
    ev = ev.cwiseMax(cfg.eigen_floor_ratio * ev(1));
    s.cov = es.eigenvectors() * ev.asDiagonal() * es.eigenvectors().transpose();
    s.normal = es.eigenvectors().col(0);  // across the surface
    out.push_back(s);
  }
  return out;
}

SurfacePoints transformSurfacePoints(const SurfacePoints& s, const Eigen::Isometry3d& T) {
  const Eigen::Matrix2d R = T.linear().topLeftCorner<2, 2>();
  const Eigen::Vector2d t = T.translation().head<2>();
  SurfacePoints out = s;
  for (SurfacePoint& p : out) {
    p.mean = R * p.mean + t;
    p.cov = R * p.cov * R.transpose();
    p.normal = R * p.normal;
  }
  return out;
}

double p2pCost(const SurfacePoint& target, const Eigen::Vector2d& x) {
  return (x - target.mean).squaredNorm();
}

double p2lCost(const SurfacePoint& target, const Eigen::Vector2d& x) {
  const double d = target.normal.dot(x - target.mean);  // distance to the surface line
  return d * d;
}

double p2dCost(const SurfacePoint& target, const Eigen::Vector2d& x) {
  const Eigen::LLT<Eigen::Matrix2d> llt(target.cov.inverse());  // L L^T = Sigma^-1
  const Eigen::Vector2d e = llt.matrixL().transpose() * (x - target.mean);
  return e.squaredNorm();  // = r^T L L^T r = r^T Sigma^-1 r
}

CfearScores computeCfearScores(const SurfacePoints& target, const SurfacePoints& source,
                               const CfearConfig& cfg) {
  CfearScores res;
  if (target.empty() || source.empty() || !cfg.validate().empty()) return res;
  coral::Points means;
  means.reserve(target.size());
  for (const SurfacePoint& s : target) means.emplace_back(s.mean.x(), s.mean.y(), 0.0);
  const coral::NeighbourGrid grid(means, cfg.resolution, 2);
  for (const SurfacePoint& s : source) {
    const coral::Vec3 q(s.mean.x(), s.mean.y(), 0.0);
    double best = std::numeric_limits<double>::infinity();
    int best_i = -1;
    grid.forEachWithin(q, cfg.resolution, [&](const coral::Vec3& x, uint32_t i) {
      const double d2 = (x - q).squaredNorm();
      if (d2 < best) {
        best = d2;
        best_i = static_cast<int>(i);
      }
    });
    if (best_i < 0) continue;
    const SurfacePoint& t = target[best_i];
    res.p2p.sum += p2pCost(t, s.mean);
    res.p2l.sum += p2lCost(t, s.mean);
    res.p2d.sum += p2dCost(t, s.mean);
    res.p2p.count += 1.0;
  }
  res.p2l.count = res.p2d.count = res.p2p.count;
  res.valid = res.p2p.count > 0.0;
  for (CfearScore* sc : {&res.p2p, &res.p2l, &res.p2d})
    sc->normalized = res.valid ? sc->sum / sc->count : 0.0;
  return res;
}

}  // namespace eval
}  // namespace coral_introspection
