#include "coral_introspection/coral/coral.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "coral_introspection/coral/entropy.hpp"
#include "coral_introspection/coral/neighbour_grid.hpp"
#include "coral_introspection/coral/validation.hpp"

namespace coral_introspection {
namespace core {

std::string CoralConfig::validate() const {
  // Radii in [0.01, 10] m (also the dynamic_reconfigure range of coral_radius, cfg/Coral.cfg):
  // below 1 cm no lidar/radar neighbourhood holds min_neighbours points, and the hash grid
  // (cell = largest radius) would need a cell per point; above 10 m a neighbourhood spans
  // whole structures and the per-point cost grows with the square/cube of r.
  auto radiusOk = [](double r) { return r >= 0.01 && r <= 10.0; };
  Problems p;
  p.require(dimension == 2 || dimension == 3, "dimension", "2 or 3", dimension)
      .require(radiusOk(radius), "radius", "in [0.01, 10] m", radius);
  if (dynamic_radius) {
    p.require(radiusOk(r_min), "r_min", "in [0.01, 10] m", r_min)
        .require(radiusOk(r_max), "r_max", "in [0.01, 10] m", r_max)
        .require(r_min <= r_max, "r_min", "<= r_max", r_min)
        .require(alpha_deg > 0.0 && alpha_deg < 90.0, "alpha_deg", "in (0, 90) deg", alpha_deg);
  }
  return p.require(epsilon >= 0.0, "epsilon", ">= 0", epsilon)
      .require(e_reject >= 0.0 && e_reject < 1.0, "e_reject", "in [0, 1)", e_reject)
      .require(min_neighbours >= 2, "min_neighbours", ">= 2", min_neighbours)
      .require(min_neighbours_other >= 1, "min_neighbours_other", ">= 1", min_neighbours_other)
      .require(min_overlap >= 0.0 && min_overlap <= 1.0, "min_overlap", "in [0, 1]", min_overlap)
      .str();
}

CoralConfig CoralConfig::radarPaper() {
  CoralConfig c;
  c.dimension = 2;
  c.radius = 1.0;  // r_min = r_max = 1 m
  c.dynamic_radius = false;
  c.epsilon = 0.0;
  c.e_reject = 0.0;
  return c;
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

// Adds the points of [begin, end) within sqrt(r2) of p to m, centred on p.
template <int Dim>
void addWithin(const Vec3* begin, const Vec3* end, const Vec3& p, double r2, MomentsN<Dim>& m) {
  for (const Vec3* x = begin; x != end; ++x) {
    const typename MomentsN<Dim>::V d = (*x - p).template head<Dim>();
    if (d.squaredNorm() <= r2) m.add(d);
  }
}

// Scores every point of both clouds against its own cloud and the other cloud. The grid
// holds both clouds; cells are processed one at a time so the 3^N neighbour cells are
// looked up once per cell for all of its points, of a and of b.
template <int Dim>
void scoreClouds(const NeighbourGrid& grid, std::size_t num_a, const Vec3& origin_a,
                 const Vec3& origin_b, const CoralConfig& cfg, std::vector<PointEntropy>& out,
                 std::vector<double>& mme_terms, std::size_t& num_overlap) {
  std::vector<NeighbourGrid::Range> ranges;
  for (std::size_t c = 0; c < grid.numCells(); ++c) {
    grid.neighbourRanges(c, 1, &ranges);  // every radius <= cell size
    const NeighbourGrid::Range pts = grid.cellPoints(c);
    const uint32_t* idx = grid.cellIndices(c);
    for (const Vec3* p = pts.begin; p != pts.end; ++p, ++idx) {
      const bool in_a = *idx < num_a;
      PointEntropy& pe = out[*idx];
      const double d = (*p - (in_a ? origin_a : origin_b)).template head<Dim>().norm();
      const double radius = dynamicRadius(cfg, d);
      const double r2 = radius * radius;
      pe.radius = static_cast<float>(radius);
      MomentsN<Dim> m_own, m_other;
      for (const NeighbourGrid::Range& rg : ranges) {
        addWithin(in_a ? rg.begin : rg.mid, in_a ? rg.mid : rg.end, *p, r2, m_own);
        addWithin(in_a ? rg.mid : rg.begin, in_a ? rg.end : rg.mid, *p, r2, m_other);
      }
      scorePoint(m_own, m_other, cfg, &pe, &mme_terms, &num_overlap);
    }
  }
}

}  // namespace

void finalizeCoral(const CoralConfig& cfg, std::vector<PointEntropy> per_point,
                   std::vector<double> mme_terms, CoralResult* res) {
  // Sec. III-C (3): drop the E_reject fraction of valid points with the lowest h_sep.
  std::vector<std::size_t> valid_idx;
  for (std::size_t i = 0; i < per_point.size(); ++i)
    if (per_point[i].valid) valid_idx.push_back(i);
  const auto n_reject =
      static_cast<std::size_t>(std::floor(cfg.e_reject * static_cast<double>(valid_idx.size())));
  if (n_reject > 0) {
    std::nth_element(
        valid_idx.begin(), valid_idx.begin() + n_reject, valid_idx.end(),
        [&](std::size_t i, std::size_t j) { return per_point[i].h_sep < per_point[j].h_sep; });
    for (std::size_t k = 0; k < n_reject; ++k) per_point[valid_idx[k]].valid = false;
    valid_idx.erase(valid_idx.begin(), valid_idx.begin() + n_reject);
  }
  res->num_rejected = n_reject;

  std::vector<double> hs, hj;
  hs.reserve(valid_idx.size());
  hj.reserve(valid_idx.size());
  for (std::size_t i : valid_idx) {
    hs.push_back(per_point[i].h_sep);
    hj.push_back(per_point[i].h_joint);
  }
  res->num_valid = valid_idx.size();
  res->h_sep = aggregate(hs, cfg.aggregation);    // Eq. 4 (or its median)
  res->h_joint = aggregate(hj, cfg.aggregation);  // Eq. 3 (or its median)
  res->quality = res->h_joint - res->h_sep;       // Eq. 5
  res->mme = aggregate(mme_terms, Aggregation::kMean);
  const std::size_t total = res->num_points_a + res->num_points_b;
  res->overlap = total > 0 ? static_cast<double>(res->num_overlap) / total : 0.0;
  res->valid = res->num_valid > 0 && res->overlap >= cfg.min_overlap;
  if (cfg.per_point) res->per_point = std::move(per_point);
}

CoralResult computeCoral(const Scan& a, const Scan& b, const CoralConfig& cfg) {
  const auto t0 = std::chrono::steady_clock::now();
  CoralResult res;
  const Points pa = finitePoints(a.points), pb = finitePoints(b.points);
  res.num_points_a = pa.size();
  res.num_points_b = pb.size();
  const NeighbourGrid grid(pa, pb, cfg.maxRadius(), cfg.dimension);

  std::vector<PointEntropy> per_point(pa.size() + pb.size());
  std::vector<double> mme_terms;
  mme_terms.reserve(per_point.size());
  auto score = cfg.dimension == 2 ? scoreClouds<2> : scoreClouds<3>;
  score(grid, pa.size(), a.origin, b.origin, cfg, per_point, mme_terms, res.num_overlap);

  finalizeCoral(cfg, std::move(per_point), std::move(mme_terms), &res);
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

}  // namespace core
}  // namespace coral_introspection
