// CorAl alignment quality of two point clouds already in one frame
// (paper: coral_radar_lidar_introspection, Sec. III-B and III-C).
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "coral_introspection/coral/entropy.hpp"
#include "coral_introspection/coral/types.hpp"

namespace coral_introspection {
namespace coral {

enum class Aggregation { kMean, kMedian };  // CorAl vs CorAl-median (Sec. IV-1c)

// Largest valid CoralConfig::max_abs_coordinate [m]: scored points are stored as float
// (PointEntropy::position, max 3.4e38), also after a rigid motion (CoralPair moves b's
// points by the pose: |R p + t| <= sqrt(3) 1e38 + |t| for |coordinates| <= 1e38).
constexpr double kMaxAbsCoordinate = 1e38;

// Every CorAl default lives here. Units: metres, degrees, nats.
struct CoralConfig {
  int dimension = 3;             // 2 (radar, 2D lidar) or 3
  double radius = 0.3;           // [m] fixed neighbourhood radius r
  bool dynamic_radius = false;   // Sec. III-C (2): r = d sin(alpha) clamped to [r_min, r_max]
  double r_min = 0.3;            // [m]
  double r_max = 0.7;            // [m]
  double alpha_deg = 1.33;       // [deg] angular (vertical) resolution of the sensor
  double epsilon = 1e-8;         // Sec. III-C (1): determinant floor [m^2N], 0 disables
                                 // (1e-8: the paper's lidar value, Fig. 6c)
  double e_reject = 0.0;         // Sec. III-C (3): fraction of lowest H_sep points dropped
  int min_neighbours = 4;        // own-cloud points within r (query point included)
  int min_neighbours_other = 2;  // other-cloud points within r for the point to overlap
  Aggregation aggregation = Aggregation::kMean;
  double min_overlap = 0.05;  // below this fraction of overlapping points: no verdict
  bool per_point = true;      // fill CoralResult::per_point (q_k, Eq. 6)

  // Dense clouds (lidar at sensor rate). The defaults score every input point exactly.
  double voxel_leaf = 0.0;  // [m] input voxel filter, one centroid per voxel; 0 = off
  // Score a stratified subset of at most this many points per scan (0 = every point). Their
  // neighbourhoods still come from the full clouds: H_joint, H_sep and Q are estimates of
  // the full means, with their standard errors in CoralResult.
  int max_queries = 0;
  int query_seed = 1;  // seed of the subset: same seed and input, same subset
  int threads = 1;     // worker threads (std::thread); results do not depend on it

  // Degenerate and unbounded input: named and counted, never scored.
  double max_abs_coordinate = 1e7;  // [m] points with a larger |coordinate| are dropped,
                                    // at most kMaxAbsCoordinate
  // [m] points farther than this from their scan's origin (Scan::origin; in x-y for
  // dimension 2) are dropped and counted; 0 = off. Some scanners and converters write a
  // reading without a return as a point at the maximum range (the Intel log: 2.8 % of its
  // readings at 81.83 m, ACES at 50.0 m). Scored as a return, such a point claims the space
  // in front of it is empty, and the free-space term (free_space.hpp) rejects right pairs
  // whose other scan saw a wall there (doc/loop_closure.md "No-return readings").
  double max_range = 0.0;
  // [deg] dimension 2: the beam spacing the preset's bounds were chosen at (lidar_2d: 1 deg,
  // the Radish logs' 180 beams). A scan whose own spacing (medianBeamStepDeg, beam_spacing.hpp)
  // is finer, k = round(beam_step_deg / spacing) >= 2, keeps every k-th beam (a 0.5 deg scanner
  // becomes a 1 deg one), counted in num_beam_thinned: denser scans give CorAl's neighbourhoods
  // more points and the classifier other entropies (on the 2D logs resampled to 0.5 deg the
  // verdict grew more lenient: doc/loop_closure.md "Another beam spacing"). Coarser scans are
  // used as they are. 0 = off.
  double beam_step_deg = 0.0;
  // [points per scan] of usable input; a larger scan is thinned by a deterministic stride
  // (or, with refuse_over_max_points, the pair is not judged): bounds the work per pair.
  int max_points = 1000000;
  bool refuse_over_max_points = false;
  // [m] points of one scan in the same cube of this edge are merged into their centroid
  // (duplicates, no-returns at the origin); 0 = off. Below any lidar's resolution.
  double merge_distance = 1e-3;
  // Above this fraction of overlapping points without a usable covariance (coincident, or
  // collinear/coplanar with epsilon = 0) the result is not valid.
  double max_degenerate_fraction = 0.5;

  // CorAl-Radar settings of Sec. V-A c: 2D, r = 1 m fixed, epsilon = 0, E_reject = 0.
  static CoralConfig radarPaper();

  // Empty string when valid, otherwise a message naming the bad field and its range.
  std::string validate() const;
  // Largest radius any point can use (grid cell size).
  double maxRadius() const { return dynamic_radius ? r_max : radius; }
};

struct PointEntropy {
  Eigen::Vector3f position = Eigen::Vector3f::Zero();  // the scored point (common frame)
  float h_sep = 0.f;        // h_i(p_k) in its own cloud [nats] (Eq. 1), when valid
  float h_joint = 0.f;      // h_j(p_k) in the joint cloud [nats], when joint_ok
  float radius = 0.f;       // neighbourhood radius used [m]
  uint8_t scan = 0;         // 0: point of scan a, 1: of scan b
  bool joint_ok = false;    // enough joint neighbours and a finite h_joint (enters the MME)
  bool overlap = false;     // min_neighbours in its own and min_neighbours_other in the other
  bool degenerate = false;  // overlaps, but its own or joint covariance is not usable
  bool valid = false;       // entered H_sep / H_joint (overlap, finite entropies, not rejected)
  float q() const { return h_joint - h_sep; }  // Eq. 6
};

struct CoralResult {
  bool valid = false;    // enough overlap, valid points, not mostly degenerate (else: reason)
  double h_joint = 0.0;  // Eq. 3 restricted to valid points [nats]
  double h_sep = 0.0;    // Eq. 4 restricted to valid points [nats]
  double quality = 0.0;  // Q = H_joint - H_sep (Eq. 5)
  double mme = 0.0;      // mean joint entropy over every point with enough joint
                         // neighbours, no overlap requirement (MME baseline, Sec. IV-1a)
  double overlap = 0.0;  // fraction of scored points overlapping the other cloud
  std::size_t num_points_a = 0, num_points_b = 0;  // usable input points (finite, in range)
  std::size_t num_used_a = 0, num_used_b = 0;      // points after the voxel filter
  std::size_t num_queries = 0;                     // points scored (all used points, or the subset)
  std::size_t num_overlap = 0;   // scored points with enough neighbours in own and other cloud
  std::size_t num_valid = 0;     // points aggregated (after E_reject)
  std::size_t num_rejected = 0;  // removed by E_reject
  // Input hygiene, both scans together: dropped (NaN/Inf, beyond max_abs_coordinate),
  // thinned (max_points), merged (coincident), and overlapping points whose covariance
  // was not usable.
  std::size_t num_non_finite = 0, num_out_of_range = 0, num_thinned = 0, num_merged = 0;
  std::size_t num_beyond_max_range = 0;  // dropped by max_range (no-return readings)
  std::size_t num_beam_thinned = 0;      // dropped by beam_step_deg (a finer 2D scanner)
  std::size_t num_degenerate = 0;
  // Work of the neighbour search: candidate points distance-tested, over all queries (own
  // and other cloud). Bounded work is asserted on this, not on time.
  std::size_t num_distance_tests = 0;
  std::string reason;  // why the result is not valid (empty when valid)
  // Standard errors of the subset estimates [nats] (0 when every point is scored): the
  // spread of the sampled per-point values over sqrt(n) with the finite-population
  // correction (times sqrt(pi/2) for the median). quality_stderr uses q_k = h_j - h_i.
  double h_joint_stderr = 0.0, h_sep_stderr = 0.0, quality_stderr = 0.0;
  double seconds = 0.0;  // wall time of computeCoral
  // One entry per scored point: scan a's first, then scan b's. When every input point is
  // scored (no voxel filter, no subset) these are exactly the finite input points in order.
  std::vector<PointEntropy> per_point;
};

// Dynamic radius of Sec. III-C (2) for a point at distance d from its own sensor.
double dynamicRadius(const CoralConfig& cfg, double distance);

// CorAl for scans a and b, both expressed in one common frame (origins too). Non-finite
// points are ignored. Never throws on bad data; an unusable pair gives valid == false
// with finite zero aggregates. Precondition: cfg.validate() is empty.
CoralResult computeCoral(const Scan& a, const Scan& b, const CoralConfig& cfg);

// Building blocks shared by CorAl variants whose neighbourhoods differ (e.g. the
// covariance-shaped one in coral_uncertainty.hpp).
//
// Eq. 1 and 6 for one point from the moments of its neighbours in its own cloud and in the
// other cloud (both centred on the point). Every point with enough joint neighbours feeds
// the MME (joint_ok); it overlaps with min_neighbours in its own and min_neighbours_other
// in the other cloud, and is valid when it overlaps and both entropies are finite.
//
// own_entropy(&h) gives h_i(p) from `own` (true when finite): callers that score one point
// at many poses compute it once (CoralPair); the overload without it computes it here.
struct OwnEntropy {
  bool ok = false;  // finite entropy (own.n >= min_neighbours and a usable covariance)
  double h = 0.0;   // [nats]
};
template <class M, class OwnH>
void scorePoint(const M& own, const M& other, const CoralConfig& cfg, PointEntropy* pe,
                OwnH&& own_entropy) {
  M joint = own;
  joint += other;
  double h_joint = 0.0, h_sep = 0.0;
  pe->joint_ok = joint.n >= cfg.min_neighbours &&
                 differentialEntropy(joint.covariance(), cfg.dimension, cfg.epsilon, &h_joint);
  if (pe->joint_ok) pe->h_joint = static_cast<float>(h_joint);
  pe->overlap = own.n >= cfg.min_neighbours && other.n >= cfg.min_neighbours_other;
  if (pe->overlap && pe->joint_ok && own_entropy(&h_sep)) {
    pe->h_sep = static_cast<float>(h_sep);
    pe->valid = true;
  }
  pe->degenerate = pe->overlap && !pe->valid;
}
template <class M>
void scorePoint(const M& own, const M& other, const CoralConfig& cfg, PointEntropy* pe) {
  scorePoint(own, other, cfg, pe, [&](double* h) {
    return differentialEntropy(own.covariance(), cfg.dimension, cfg.epsilon, h);
  });
}

// E_reject (Sec. III-C (3)), H_sep / H_joint / Q (Eq. 3-5, mean or median), MME, overlap,
// standard errors and validity from the per-point entropies of the scored points (scan a's
// first), summed in their order (so results never depend on threads). Expects
// res->num_used_a/b (the population the scored points were drawn from); fills the rest
// except `seconds` and the input counts.
void finalizeCoral(const CoralConfig& cfg, std::vector<PointEntropy> per_point, CoralResult* res);

}  // namespace coral
}  // namespace coral_introspection
