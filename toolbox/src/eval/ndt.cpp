#include "coral_introspection/eval/ndt.hpp"

#include "coral_introspection/coral/validation.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "coral_introspection/coral/entropy.hpp"

namespace coral_introspection {
namespace eval {

std::string NdtConfig::validate() const {
  return coral::Problems()
      .require(dimension == 2 || dimension == 3, "dimension", "2 or 3", dimension)
      .require(voxel_size > 0.0, "voxel_size", "> 0 m", voxel_size)
      .require(min_points >= dimension + 1, "min_points", ">= dimension + 1", min_points)
      .require(eigen_floor_ratio > 0.0 && eigen_floor_ratio <= 1.0, "eigen_floor_ratio",
               "in (0, 1]", eigen_floor_ratio)
      .str();
}

namespace {

using MatN = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 3, 3>;

struct Cell {
  coral::Vec3 ref =
      coral::Vec3::Zero();  // first point: moments are centred on it (no cancellation)
  coral::Moments m;
  coral::Vec3 mean = coral::Vec3::Zero();
  MatN info;              // Sigma^-1 of the regularized N x N covariance
  double log_norm = 0.0;  // -1/2 ln((2 pi)^N det Sigma)
  double entropy = 0.0;   // Eq. 1 of the regularized Sigma [nats]
  bool gaussian = false;
};

uint64_t voxelKey(int64_t x, int64_t y, int64_t z) {
  constexpr uint64_t m = (1u << 21) - 1;
  return (static_cast<uint64_t>(x) & m) | ((static_cast<uint64_t>(y) & m) << 21) |
         ((static_cast<uint64_t>(z) & m) << 42);
}

// Regularized Gaussian of one voxel (3D-NDT eigenvalue floor); false if degenerate.
bool finalizeCell(Cell& c, const NdtConfig& cfg) {
  const int N = cfg.dimension;
  if (c.m.n < cfg.min_points) return false;
  c.mean = c.ref + c.m.sum / c.m.n;
  const MatN cov = c.m.covariance().topLeftCorner(N, N);
  Eigen::SelfAdjointEigenSolver<MatN> es(cov);
  Eigen::VectorXd ev = es.eigenvalues();
  const double lmax = ev.maxCoeff();
  if (!(lmax > 0.0) || !std::isfinite(lmax)) return false;
  ev = ev.cwiseMax(cfg.eigen_floor_ratio * lmax);
  const MatN V = es.eigenvectors();
  c.info = V * ev.cwiseInverse().asDiagonal() * V.transpose();
  const double log_det = ev.array().log().sum();
  c.log_norm = -0.5 * (N * std::log(2.0 * M_PI) + log_det);
  coral::Mat3 reg = coral::Mat3::Identity();
  reg.topLeftCorner(N, N) = V * ev.asDiagonal() * V.transpose();
  return coral::differentialEntropy(reg, N, 0.0, &c.entropy);  // reuse Eq. 1
}

}  // namespace

NdtResult computeNdtScore(const coral::Points& a, const coral::Points& b, const NdtConfig& cfg) {
  NdtResult res;
  if (!cfg.validate().empty()) return res;
  const int N = cfg.dimension;
  const double inv = 1.0 / cfg.voxel_size;
  auto coord = [&](double v) { return static_cast<int64_t>(std::floor(v * inv)); };

  // NDT representation of P_a: one Gaussian per voxel with enough points [48].
  std::unordered_map<uint64_t, Cell> cells;
  for (const coral::Vec3& p : a) {
    if (!p.allFinite()) continue;
    Cell& c = cells[voxelKey(coord(p.x()), coord(p.y()), N == 3 ? coord(p.z()) : 0)];
    if (c.m.n == 0.0) c.ref = p;
    c.m.add(p - c.ref);
  }
  for (auto& kv : cells) {
    kv.second.gaussian = finalizeCell(kv.second, cfg);
    res.num_cells += kv.second.gaussian ? 1 : 0;
  }

  // Eq. 11: s = 1/n sum p~(p_k) over points of P_b inside an occupied voxel or a direct
  // neighbour of one; p~ is the density of the nearest (by mean) such cell.
  double sum_pdf = 0.0, sum_h = 0.0;
  const int zr = N == 3 ? 1 : 0;
  for (const coral::Vec3& p : b) {
    if (!p.allFinite()) continue;
    ++res.num_points_b;
    const int64_t cx = coord(p.x()), cy = coord(p.y()), cz = N == 3 ? coord(p.z()) : 0;
    const Cell* best = nullptr;
    double best_d2 = std::numeric_limits<double>::infinity();
    for (int64_t ix = cx - 1; ix <= cx + 1; ++ix)
      for (int64_t iy = cy - 1; iy <= cy + 1; ++iy)
        for (int64_t iz = cz - zr; iz <= cz + zr; ++iz) {
          const auto it = cells.find(voxelKey(ix, iy, iz));
          if (it == cells.end() || !it->second.gaussian) continue;
          const double d2 = (it->second.mean - p).head(N).squaredNorm();
          if (d2 < best_d2) {
            best_d2 = d2;
            best = &it->second;
          }
        }
    if (best == nullptr) continue;
    const Eigen::VectorXd d = (p - best->mean).head(N);
    sum_pdf += std::exp(best->log_norm - 0.5 * d.dot(best->info * d));  // Gaussian pdf
    sum_h += best->entropy;
    ++res.num_overlap;
  }
  if (res.num_overlap > 0) {
    res.valid = true;
    res.score = sum_pdf / static_cast<double>(res.num_overlap);
    res.entropy = sum_h / static_cast<double>(res.num_overlap);  // Rel-NDT's NDT-entropy
  }
  return res;
}

}  // namespace eval
}  // namespace coral_introspection
