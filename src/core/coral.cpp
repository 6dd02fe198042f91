#include "coral_introspection/core/coral.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "coral_introspection/core/entropy.hpp"
#include "coral_introspection/core/neighbour_grid.hpp"

namespace coral_introspection {
namespace core {

std::string CoralConfig::validate() const {
  std::ostringstream e;
  if (dimension != 2 && dimension != 3) e << "dimension must be 2 or 3 (got " << dimension << "); ";
  if (!(radius > 0.0)) e << "radius must be > 0 m (got " << radius << "); ";
  if (dynamic_radius) {
    if (!(r_min > 0.0)) e << "r_min must be > 0 m (got " << r_min << "); ";
    if (!(r_min <= r_max)) e << "r_min must be <= r_max (got " << r_min << " > " << r_max << "); ";
    if (!(alpha_deg > 0.0 && alpha_deg < 90.0))
      e << "alpha_deg must be in (0, 90) deg (got " << alpha_deg << "); ";
  }
  if (!(epsilon >= 0.0)) e << "epsilon must be >= 0 (got " << epsilon << "); ";
  if (!(e_reject >= 0.0 && e_reject < 1.0))
    e << "e_reject must be in [0, 1) (got " << e_reject << "); ";
  if (min_neighbours < 2) e << "min_neighbours must be >= 2 (got " << min_neighbours << "); ";
  if (min_neighbours_other < 1)
    e << "min_neighbours_other must be >= 1 (got " << min_neighbours_other << "); ";
  if (!(min_overlap >= 0.0 && min_overlap <= 1.0))
    e << "min_overlap must be in [0, 1] (got " << min_overlap << "); ";
  std::string s = e.str();
  if (!s.empty()) s.resize(s.size() - 2);
  return s;
}

double dynamicRadius(const CoralConfig& cfg, double distance) {
  if (!cfg.dynamic_radius) return cfg.radius;
  const double r = distance * std::sin(cfg.alpha_deg * M_PI / 180.0);  // Sec. III-C (2)
  return std::clamp(r, cfg.r_min, cfg.r_max);
}

namespace {

Points finitePoints(const Points& in) {
  Points out;
  out.reserve(in.size());
  for (const Vec3& p : in)
    if (p.allFinite()) out.push_back(p);
  return out;
}

double median(std::vector<double>& v) {
  const std::size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + mid, v.end());
  double m = v[mid];
  if (v.size() % 2 == 0) m = 0.5 * (m + *std::max_element(v.begin(), v.begin() + mid));
  return m;
}

double aggregate(std::vector<double>& v, Aggregation agg) {
  if (v.empty()) return 0.0;
  if (agg == Aggregation::kMedian) return median(v);
  double s = 0.0;
  for (double x : v) s += x;
  return s / static_cast<double>(v.size());
}

// Scores every point of `own` against its own cloud and the other cloud.
void scoreCloud(const Points& own, const Vec3& origin, const NeighbourGrid& own_grid,
                const NeighbourGrid& other_grid, const CoralConfig& cfg,
                std::vector<PointEntropy>& out, std::vector<double>& mme_terms,
                std::size_t& num_overlap) {
  const int dim = cfg.dimension;
  for (const Vec3& p : own) {
    PointEntropy pe;
    const Vec3 rel = p - origin;
    const double d = dim == 2 ? rel.head<2>().norm() : rel.norm();
    pe.radius = static_cast<float>(dynamicRadius(cfg, d));
    Moments m_own, m_other;
    own_grid.forEachWithin(p, pe.radius, [&](const Vec3& x, uint32_t) { m_own.add(x - p); });
    other_grid.forEachWithin(p, pe.radius, [&](const Vec3& x, uint32_t) { m_other.add(x - p); });
    Moments m_joint = m_own;
    m_joint += m_other;
    double h_joint = 0.0;
    const bool joint_ok = m_joint.n >= cfg.min_neighbours &&
                          differentialEntropy(m_joint.covariance(), dim, cfg.epsilon, &h_joint);
    if (joint_ok) mme_terms.push_back(h_joint);
    // A point counts only with enough neighbours in its own and in the other cloud.
    if (m_own.n >= cfg.min_neighbours && m_other.n >= cfg.min_neighbours_other) {
      ++num_overlap;
      double h_sep = 0.0;
      if (joint_ok && differentialEntropy(m_own.covariance(), dim, cfg.epsilon, &h_sep)) {
        pe.h_sep = static_cast<float>(h_sep);
        pe.h_joint = static_cast<float>(h_joint);
        pe.valid = true;
      }
    }
    out.push_back(pe);
  }
}

}  // namespace

CoralResult computeCoral(const Scan& a, const Scan& b, const CoralConfig& cfg) {
  const auto t0 = std::chrono::steady_clock::now();
  CoralResult res;
  const Points pa = finitePoints(a.points), pb = finitePoints(b.points);
  res.num_points_a = pa.size();
  res.num_points_b = pb.size();
  const double cell = cfg.maxRadius();
  const NeighbourGrid grid_a(pa, cell, cfg.dimension), grid_b(pb, cell, cfg.dimension);

  std::vector<PointEntropy> per_point;
  per_point.reserve(pa.size() + pb.size());
  std::vector<double> mme_terms;
  mme_terms.reserve(pa.size() + pb.size());
  scoreCloud(pa, a.origin, grid_a, grid_b, cfg, per_point, mme_terms, res.num_overlap);
  scoreCloud(pb, b.origin, grid_b, grid_a, cfg, per_point, mme_terms, res.num_overlap);

  // Sec. III-C (3): drop the E_reject fraction of valid points with the lowest h_sep.
  std::vector<std::size_t> valid_idx;
  for (std::size_t i = 0; i < per_point.size(); ++i)
    if (per_point[i].valid) valid_idx.push_back(i);
  const auto n_reject =
      static_cast<std::size_t>(std::floor(cfg.e_reject * static_cast<double>(valid_idx.size())));
  if (n_reject > 0) {
    std::nth_element(valid_idx.begin(), valid_idx.begin() + n_reject, valid_idx.end(),
                     [&](std::size_t i, std::size_t j) {
                       return per_point[i].h_sep < per_point[j].h_sep;
                     });
    for (std::size_t k = 0; k < n_reject; ++k) per_point[valid_idx[k]].valid = false;
    valid_idx.erase(valid_idx.begin(), valid_idx.begin() + n_reject);
  }
  res.num_rejected = n_reject;

  std::vector<double> hs, hj;
  hs.reserve(valid_idx.size());
  hj.reserve(valid_idx.size());
  for (std::size_t i : valid_idx) {
    hs.push_back(per_point[i].h_sep);
    hj.push_back(per_point[i].h_joint);
  }
  res.num_valid = valid_idx.size();
  res.h_sep = aggregate(hs, cfg.aggregation);    // Eq. 4 (or its median)
  res.h_joint = aggregate(hj, cfg.aggregation);  // Eq. 3 (or its median)
  res.quality = res.h_joint - res.h_sep;         // Eq. 5
  res.mme = aggregate(mme_terms, Aggregation::kMean);
  const std::size_t total = pa.size() + pb.size();
  res.overlap = total > 0 ? static_cast<double>(res.num_overlap) / total : 0.0;
  res.valid = res.num_valid > 0 && res.overlap >= cfg.min_overlap;
  if (cfg.per_point) res.per_point = std::move(per_point);
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

}  // namespace core
}  // namespace coral_introspection
