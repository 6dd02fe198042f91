#include "coral_introspection/coral/coral.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <iterator>
#include <random>

#include "coral_detail.hpp"
#include "coral_introspection/coral/beam_spacing.hpp"
#include "coral_introspection/coral/entropy.hpp"
#include "coral_introspection/coral/moments_kernel.hpp"
#include "coral_introspection/coral/neighbour_grid.hpp"
#include "coral_introspection/coral/parallel.hpp"
#include "coral_introspection/coral/point_filter.hpp"
#include "coral_introspection/coral/statistics.hpp"
#include "coral_introspection/coral/validation.hpp"
#include "coral_introspection/coral/voxel_filter.hpp"

namespace coral_introspection {
namespace coral {

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
      .require(voxel_leaf >= 0.0 && std::isfinite(voxel_leaf), "voxel_leaf", ">= 0 m (0 = off)",
               voxel_leaf)
      .require(max_queries >= 0, "max_queries", ">= 0 (0 = every point)", max_queries)
      .require(threads >= 1 && threads <= 64, "threads", "in [1, 64]", threads)
      // Scored points leave as float (PointEntropy::position, the float32 quality cloud):
      // a wider limit would accept points whose position becomes inf.
      .require(max_abs_coordinate > 0.0 && max_abs_coordinate <= kMaxAbsCoordinate,
               "max_abs_coordinate", "in (0, 1e38] m (float range of scored positions)",
               max_abs_coordinate)
      .require(max_range >= 0.0 && max_range <= kMaxAbsCoordinate, "max_range",
               "in [0, 1e38] m (0 = off)", max_range)
      .require(beam_step_deg >= 0.0 && beam_step_deg <= 90.0, "beam_step_deg",
               "in [0, 90] deg (0 = off)", beam_step_deg)
      .require(max_points >= 1, "max_points", ">= 1", max_points)
      .require(merge_distance >= 0.0 && merge_distance < 1.0, "merge_distance", "in [0, 1) m",
               merge_distance)
      .require(max_degenerate_fraction >= 0.0 && max_degenerate_fraction <= 1.0,
               "max_degenerate_fraction", "in [0, 1]", max_degenerate_fraction)
      .str();
}

CoralConfig CoralConfig::radarPaper() {
  CoralConfig c;
  c.dimension = 2;
  c.radius = 1.0;  // r_min = r_max = 1 m
  c.dynamic_radius = false;
  c.epsilon = 0.0;
  c.e_reject = 0.0;
  // RIP keeps at most one peak per azimuth and range bin beyond 2.5 m: features never
  // coincide, so the merge pass would only cost instructions.
  c.merge_distance = 0.0;
  return c;
}

double dynamicRadius(const CoralConfig& cfg, double distance) {
  if (!cfg.dynamic_radius) return cfg.radius;
  const double r = distance * std::sin(cfg.alpha_deg * M_PI / 180.0);  // Sec. III-C (2)
  return std::clamp(r, cfg.r_min, cfg.r_max);
}

namespace {

using detail::pointRadius;
using detail::setPoint;

// Takes v by value: the median reorders it (callers pass std::move(v)).
double aggregate(std::vector<double> v, Aggregation agg) {
  if (v.empty()) return 0.0;
  if (agg == Aggregation::kMedian) return median(std::move(v));
  double s = 0.0;
  for (double x : v) s += x;
  return s / static_cast<double>(v.size());
}

// Scores every point of both clouds (the grid's cell size is the largest radius). Cells are
// processed one at a time so the 3^N neighbour cells are looked up once per cell for all of
// its points, of a and of b; out[i] belongs to original index i.
template <int Dim>
std::size_t scoreAll(const NeighbourGrid& grid, std::size_t num_a, const Vec3& origin_a,
                     const Vec3& origin_b, const CoralConfig& cfg, std::vector<PointEntropy>& out) {
  std::atomic<std::size_t> tests{0};
  parallelChunks(grid.numCells(), cfg.threads, [&](std::size_t c0, std::size_t c1) {
    NeighbourGrid::Span spans[2][NeighbourGrid::kBlockCells];  // the block's points of a, b
    int num_spans[2];
    std::size_t chunk_tests = 0;
    for (std::size_t c = c0; c < c1; ++c) {
      // Every radius <= cell size: the 3^N block around the cell holds every neighbour.
      grid.neighbourSpans(c, spans[0], &num_spans[0], spans[1], &num_spans[1]);
      const NeighbourGrid::Range pts = grid.cellPoints(c);
      std::size_t candidates = 0;  // each point of the cell tests all of them
      for (int s = 0; s < 2; ++s)
        for (int k = 0; k < num_spans[s]; ++k) candidates += spans[s][k].end - spans[s][k].begin;
      chunk_tests += candidates * static_cast<std::size_t>(pts.end - pts.begin);
      const uint32_t* idx = grid.cellIndices(c);
      for (const Vec3* p = pts.begin; p != pts.end; ++p, ++idx) {
        const bool in_a = *idx < num_a;
        PointEntropy& pe = out[*idx];
        const double radius = pointRadius<Dim>(cfg, *p, in_a ? origin_a : origin_b);
        const double r2 = radius * radius;
        setPoint(pe, *p, in_a, radius);
        MomentsN<Dim> m_own, m_other;
        const int own = in_a ? 0 : 1, other = 1 - own;
        addWithin<Dim>(grid, spans[own], num_spans[own], *p, r2, &m_own);
        addWithin<Dim>(grid, spans[other], num_spans[other], *p, r2, &m_other);
        scorePoint(m_own, m_other, cfg, &pe);
      }
    }
    tests += chunk_tests;
  });
  return tests;
}

// Scores the points at the given positions of the grid's sorted points; out[k] belongs to
// queries[k]. Each query visits only the cells that intersect its own ball.
template <int Dim>
std::size_t scoreQueries(const NeighbourGrid& grid, const std::vector<uint32_t>& queries,
                         std::size_t num_a, const Vec3& origin_a, const Vec3& origin_b,
                         const CoralConfig& cfg, std::vector<PointEntropy>& out) {
  const Points& pts = grid.sortedPoints();
  const std::vector<uint32_t>& idx = grid.sortedIndices();
  std::atomic<std::size_t> tests{0};
  parallelChunks(queries.size(), cfg.threads, [&](std::size_t k0, std::size_t k1) {
    std::size_t chunk_tests = 0;
    for (std::size_t k = k0; k < k1; ++k) {
      const Vec3& p = pts[queries[k]];
      const bool in_a = idx[queries[k]] < num_a;
      const double radius = pointRadius<Dim>(cfg, p, in_a ? origin_a : origin_b);
      setPoint(out[k], p, in_a, radius);
      MomentsN<Dim> m_a, m_b;  // a's and b's points near p
      chunk_tests += momentsNear<Dim>(grid, p, radius, &m_a, &m_b);
      const MomentsN<Dim>& m_own = in_a ? m_a : m_b;
      const MomentsN<Dim>& m_other = in_a ? m_b : m_a;
      scorePoint(m_own, m_other, cfg, &out[k]);
    }
    tests += chunk_tests;
  });
  return tests;
}

// Standard error of the mean of v as an estimate of the mean over a population of n_pop
// (finite-population correction; 0 when the whole population was scored).
double standardError(const std::vector<double>& v, double sample_fraction, Aggregation agg) {
  if (v.size() < 2 || sample_fraction >= 1.0) return 0.0;
  double mean = 0.0, ss = 0.0;
  for (double x : v) mean += x;
  mean /= static_cast<double>(v.size());
  for (double x : v) ss += (x - mean) * (x - mean);
  const double var = ss / static_cast<double>(v.size() - 1);
  const double se = std::sqrt((1.0 - sample_fraction) * var / static_cast<double>(v.size()));
  return agg == Aggregation::kMedian ? se * std::sqrt(M_PI / 2.0) : se;  // normal approx.
}

}  // namespace

// Stratified subset of each scan: its points in grid order (cells in order of appearance,
// so spatially grouped) are split into max_queries equal strata and one point is taken at
// the same seeded offset in each (systematic sampling: every point has the inclusion
// probability max_queries / n). Returns positions in the grid's sorted points, a's first.
std::vector<uint32_t> detail::selectQueries(const NeighbourGrid& grid, const CoralConfig& cfg) {
  std::vector<uint32_t> in_grid[2];
  for (std::size_t c = 0; c < grid.numCells(); ++c) {
    const NeighbourGrid::Range r = grid.cellPoints(c);
    const auto first = static_cast<uint32_t>(r.begin - grid.sortedPoints().data());
    const auto mid = static_cast<uint32_t>(r.mid - r.begin) + first;
    const auto end = static_cast<uint32_t>(r.end - r.begin) + first;
    for (uint32_t i = first; i < mid; ++i) in_grid[0].push_back(i);
    for (uint32_t i = mid; i < end; ++i) in_grid[1].push_back(i);
  }
  std::vector<uint32_t> out;
  const auto m = static_cast<std::size_t>(cfg.max_queries);
  for (int s = 0; s < 2; ++s) {
    const std::vector<uint32_t>& all = in_grid[s];
    if (all.size() <= m) {
      out.insert(out.end(), all.begin(), all.end());
      continue;
    }
    // Seeded offset in [0, 1) from the top 53 bits (the same on every standard library).
    std::mt19937_64 rng(static_cast<uint64_t>(cfg.query_seed) * 2 + static_cast<uint64_t>(s));
    const double u = static_cast<double>(rng() >> 11) * 0x1.0p-53;
    const double stride = static_cast<double>(all.size()) / static_cast<double>(m);
    for (std::size_t k = 0; k < m; ++k)
      out.push_back(all[std::min(all.size() - 1, static_cast<std::size_t>((k + u) * stride))]);
  }
  return out;
}

// Grid cell for the subset path. Each query visits only the cells that intersect its own
// ball, so with the dynamic radius a query of radius r_min does not pay for r_max. Cells
// much finer than the radius cost more in hash lookups than they save in distance tests
// (measured on 64-beam clouds voxelised to r / 5: r / 2 cells took 1.2x the instructions of
// r cells), hence about the radius.
double detail::queryCellSize(const CoralConfig& cfg) {
  return cfg.dynamic_radius ? std::max(cfg.r_min, 0.5 * cfg.r_max) : cfg.radius;
}

void finalizeCoral(const CoralConfig& cfg, std::vector<PointEntropy> per_point, CoralResult* res) {
  // Sec. III-C (3): drop the E_reject fraction of valid points with the lowest h_sep.
  std::vector<std::size_t> valid_idx;
  std::vector<double> mme_terms;
  std::size_t num_overlap = 0;
  for (std::size_t i = 0; i < per_point.size(); ++i) {
    const PointEntropy& pe = per_point[i];
    if (pe.valid) valid_idx.push_back(i);
    if (pe.joint_ok) mme_terms.push_back(pe.h_joint);
    num_overlap += pe.overlap ? 1 : 0;
    res->num_degenerate += pe.degenerate ? 1 : 0;
  }
  const auto n_reject =
      static_cast<std::size_t>(std::floor(cfg.e_reject * static_cast<double>(valid_idx.size())));
  if (n_reject > 0) {
    std::vector<std::size_t> order = valid_idx;
    std::nth_element(order.begin(), order.begin() + n_reject, order.end(),
                     [&](std::size_t i, std::size_t j) {
                       return per_point[i].h_sep < per_point[j].h_sep ||
                              (per_point[i].h_sep == per_point[j].h_sep && i < j);
                     });
    for (std::size_t k = 0; k < n_reject; ++k) per_point[order[k]].valid = false;
    valid_idx.erase(std::remove_if(valid_idx.begin(), valid_idx.end(),
                                   [&](std::size_t i) { return !per_point[i].valid; }),
                    valid_idx.end());
  }
  res->num_rejected = n_reject;

  std::vector<double> hs, hj, q;
  hs.reserve(valid_idx.size());
  hj.reserve(valid_idx.size());
  q.reserve(valid_idx.size());
  for (std::size_t i : valid_idx) {  // index order: sums never depend on threads
    hs.push_back(per_point[i].h_sep);
    hj.push_back(per_point[i].h_joint);
    q.push_back(per_point[i].q());
  }
  res->num_queries = per_point.size();
  res->num_overlap = num_overlap;
  res->num_valid = valid_idx.size();
  const std::size_t population = std::max(res->num_used_a + res->num_used_b, per_point.size());
  const double fraction =
      population > 0 ? static_cast<double>(per_point.size()) / static_cast<double>(population)
                     : 1.0;
  res->h_sep_stderr = standardError(hs, fraction, cfg.aggregation);
  res->h_joint_stderr = standardError(hj, fraction, cfg.aggregation);
  res->quality_stderr = standardError(q, fraction, cfg.aggregation);
  res->h_sep = aggregate(std::move(hs), cfg.aggregation);    // Eq. 4 (or its median)
  res->h_joint = aggregate(std::move(hj), cfg.aggregation);  // Eq. 3 (or its median)
  res->quality = res->h_joint - res->h_sep;                  // Eq. 5
  res->mme = aggregate(std::move(mme_terms), Aggregation::kMean);
  res->overlap = per_point.empty()
                     ? 0.0
                     : static_cast<double>(num_overlap) / static_cast<double>(per_point.size());
  res->valid = false;
  if (per_point.empty())
    res->reason = "no usable points";
  else if (num_overlap == 0)
    res->reason = "the scans do not overlap";
  else if (res->overlap < cfg.min_overlap)
    res->reason = "overlap " + std::to_string(res->overlap) + " below min_overlap " +
                  std::to_string(cfg.min_overlap);
  else if (res->num_valid == 0)
    res->reason =
        "no overlapping point has a usable covariance (coincident or degenerate "
        "neighbourhoods)";
  else if (static_cast<double>(res->num_degenerate) >
           cfg.max_degenerate_fraction * static_cast<double>(num_overlap))
    res->reason = std::to_string(res->num_degenerate) + " of " + std::to_string(num_overlap) +
                  " overlapping neighbourhoods are degenerate (more than max_degenerate_fraction)";
  else
    res->valid = true;
  if (cfg.per_point) res->per_point = std::move(per_point);
}

bool detail::prepareClouds(const Scan& a, const Scan& b, const CoralConfig& cfg,
                           PreparedClouds* out, CoralResult* res) {
  // Input hygiene, then the voxel filter: every step counts what it removed.
  Points* storage = out->storage;
  Points* thinned = out->thinned;
  Points* merged = out->merged;
  Points* voxels = out->voxels;
  const Points** clouds = out->cloud;
  const Scan* scans[2] = {&a, &b};
  std::size_t usable[2] = {0, 0};
  for (int s = 0; s < 2; ++s) {
    std::size_t non_finite = 0, out_of_range = 0, beyond = 0;
    clouds[s] = &usablePoints(scans[s]->points, cfg.max_abs_coordinate, &storage[s], &non_finite,
                              &out_of_range);
    clouds[s] = &pointsWithinRange(*clouds[s], scans[s]->origin, cfg.max_range, cfg.dimension,
                                   &out->ranged[s], &beyond);
    res->num_non_finite += non_finite;
    res->num_out_of_range += out_of_range;
    res->num_beyond_max_range += beyond;
    // A planar scan finer than the spacing the preset's bounds were chosen at, thinned to it.
    if (cfg.dimension == 2)
      clouds[s] = &thinToBeamStep(*clouds[s], scans[s]->origin, cfg.beam_step_deg, &out->beamed[s],
                                  &res->num_beam_thinned);
    usable[s] = clouds[s]->size();
  }
  res->num_points_a = usable[0];
  res->num_points_b = usable[1];
  const auto max_points = static_cast<std::size_t>(cfg.max_points);
  if (usable[0] > max_points || usable[1] > max_points) {
    if (cfg.refuse_over_max_points) {
      res->reason = "a scan has " + std::to_string(std::max(usable[0], usable[1])) +
                    " points, more than max_points " + std::to_string(max_points) + " (refused)";
      return false;
    }
    for (int s = 0; s < 2; ++s) {
      if (usable[s] <= max_points) continue;
      thinned[s] = strideSubsample(*clouds[s], max_points);
      res->num_thinned += usable[s] - max_points;
      clouds[s] = &thinned[s];
    }
  }
  // The voxel filter merges coincident points itself (one centroid per voxel).
  const bool merge = cfg.merge_distance > 0.0 && cfg.voxel_leaf < cfg.merge_distance;
  const bool voxel = cfg.voxel_leaf > 0.0;
  if (merge || voxel) {
    std::size_t removed[2] = {0, 0};
    parallelChunks(2, cfg.threads, [&](std::size_t s0, std::size_t s1) {
      for (std::size_t s = s0; s < s1; ++s) {
        if (merge) {
          removed[s] = mergeCoincident(*clouds[s], cfg.merge_distance, cfg.dimension, &merged[s]);
          clouds[s] = &merged[s];
        }
        if (voxel) {
          voxels[s] = voxelFilter(*clouds[s], cfg.voxel_leaf, cfg.dimension);
          clouds[s] = &voxels[s];
        }
      }
    });
    res->num_merged = removed[0] + removed[1];
  }
  res->num_used_a = clouds[0]->size();
  res->num_used_b = clouds[1]->size();
  return true;
}

CoralResult computeCoral(const Scan& a, const Scan& b, const CoralConfig& cfg) {
  const auto t0 = std::chrono::steady_clock::now();
  CoralResult res;
  detail::PreparedClouds prepared;
  if (!detail::prepareClouds(a, b, cfg, &prepared, &res)) {
    res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return res;
  }
  const Points& pa = *prepared.cloud[0];
  const Points& pb = *prepared.cloud[1];
  const auto m = static_cast<std::size_t>(cfg.max_queries);
  const bool subset = m > 0 && (pa.size() > m || pb.size() > m);
  // scoreAll searches the 3^N cells around each point's cell: cells slightly larger than the
  // largest radius keep a neighbour exactly at the radius (a tie the rounded distance test
  // accepts) within them, as CoralPair's searches do (NeighbourGrid::forEachCellNear).
  const NeighbourGrid grid(
      pa, pb, subset ? detail::queryCellSize(cfg) : cfg.maxRadius() * (1.0 + 1e-6), cfg.dimension);
  std::vector<PointEntropy> per_point;
  if (subset) {
    const std::vector<uint32_t> queries = detail::selectQueries(grid, cfg);
    per_point.resize(queries.size());
    auto score = cfg.dimension == 2 ? scoreQueries<2> : scoreQueries<3>;
    res.num_distance_tests = score(grid, queries, pa.size(), a.origin, b.origin, cfg, per_point);
  } else {
    per_point.resize(pa.size() + pb.size());
    auto score = cfg.dimension == 2 ? scoreAll<2> : scoreAll<3>;
    res.num_distance_tests = score(grid, pa.size(), a.origin, b.origin, cfg, per_point);
  }
  finalizeCoral(cfg, std::move(per_point), &res);
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

}  // namespace coral
}  // namespace coral_introspection
