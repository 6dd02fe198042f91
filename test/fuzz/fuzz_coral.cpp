// libFuzzer harness: two small point sets and a CorAl config -> computeCoral (Eq. 1-6) and
// coral::CoralPair, the verdict path (CorAl of one pair at several poses, probes, the
// relative check).
// Each point starts with a control byte choosing how its coordinates are read: small
// quantised values (clusters with neighbours), raw float32 or float64 (NaN, Inf, denormals,
// huge values), or a cluster point shifted by a special value (1e10, 9.3e18, 1e30, -1e300,
// denormal, ...). The config covers the input hygiene (coordinate limit up to the float
// range of scored positions, max_points, merging), the voxel filter and the query subset.
// The result must be defined whatever the input: finite aggregates, counts that add up, and no
// verdict without overlapping points or with a reason. A block of bytes after the config
// (kPairBlock, all zero in the older corpus inputs = computeCoral only) chooses how
// CoralPair is driven: at two fuzzed poses (translations up to 1e6 m, any rotation, about z
// only in 2D) with the probe of evaluate() equal to evaluateProbe() and a relative check of
// fuzzed tolerance (and the constraint term there), or at the identity, where it must count
// what computeCoral counts.
#include <cmath>
#include <limits>

#include "coral_introspection/coral/constraint.hpp"
#include "coral_introspection/coral/coral.hpp"
#include "coral_introspection/coral/coral_pair.hpp"
#include "coral_introspection/coral/relative_check.hpp"
#include "fuzz_input.hpp"

using namespace coral_introspection::coral;
using coral_fuzz::FuzzInput;

namespace {

// Per cloud: keeps one execution (computeCoral, or a CoralPair and its poses) under ~4 ms
// under the sanitizers.
constexpr std::size_t kMaxPoints = 128;
// Bytes of the CoralPair block read right after the config (fixed length: tools that
// extend corpus inputs insert it at offset 23, after readConfig's bytes).
constexpr std::size_t kPairBlock = 20;

double special(uint8_t k) {
  static const double v[] = {1e10,
                             9.3e18,  // just beyond int64 cells at 1 m
                             -9.3e18,
                             1e30,
                             -1e300,
                             std::numeric_limits<double>::denorm_min(),
                             std::numeric_limits<double>::min(),
                             std::numeric_limits<double>::max(),
                             std::numeric_limits<double>::quiet_NaN(),
                             std::numeric_limits<double>::infinity(),
                             4.5e15,  // integers exactly representable up to here
                             -0.0};
  return v[k % (sizeof(v) / sizeof(v[0]))];
}

// x, y, z read in this order (function arguments would leave the order unspecified).
template <class T>
Vec3 takeVec(FuzzInput& in) {
  Vec3 v;
  for (int i = 0; i < 3; ++i) v[i] = static_cast<double>(in.take<T>());
  return v;
}

Vec3 readPoint(FuzzInput& in, uint8_t ctrl) {
  switch ((ctrl >> 1) & 3) {
    case 0:  // cluster point: 5 cm steps within +-6.4 m
      return takeVec<int8_t>(in) * 0.05;
    case 1:
      return takeVec<float>(in);
    case 2:
      return takeVec<double>(in);
    default: {
      Vec3 p = takeVec<int8_t>(in) * 0.05;
      const int axis = in.byte() % 3;
      p[axis] += special(in.byte());
      return p;
    }
  }
}

CoralConfig readConfig(FuzzInput& in) {
  CoralConfig c;
  c.dimension = in.byte() & 1 ? 3 : 2;
  c.radius = in.range(0, 40) * 0.05;  // 0 is invalid
  c.dynamic_radius = in.byte() & 1;
  c.r_min = in.range(0, 20) * 0.05;
  c.r_max = c.r_min + in.range(-1, 20) * 0.05;
  c.alpha_deg = in.range(0, 30) * 0.5;
  const double eps[] = {0.0, 1e-12, 1e-8, 1e-3, 1.0};
  c.epsilon = eps[in.byte() % 5];
  c.e_reject = in.range(0, 10) * 0.1;  // 1.0 is invalid
  c.min_neighbours = in.range(1, 8);
  c.min_neighbours_other = in.range(0, 4);
  c.aggregation = in.byte() & 1 ? Aggregation::kMedian : Aggregation::kMean;
  c.min_overlap = in.range(0, 10) * 0.1;
  c.per_point = in.byte() & 1;
  const double leaf[] = {0.0, 0.0, 0.1, 0.5};
  c.voxel_leaf = leaf[in.byte() % 4];
  const int queries[] = {0, 0, 3, 40};
  c.max_queries = queries[in.byte() % 4];
  c.query_seed = in.byte();
  c.threads = in.range(1, 2);
  // Up to the widest valid limit (kMaxAbsCoordinate, 1e38 m): the grid must stay defined
  // however far the accepted points are; points at 1e300 are then dropped and counted.
  const double limit[] = {1e7, 1e3, 1e19, 1e30, kMaxAbsCoordinate};
  c.max_abs_coordinate = limit[in.byte() % 5];
  c.max_points = in.range(1, 255) + in.range(0, 1) * 1000;
  c.refuse_over_max_points = in.byte() & 1;
  const double merge[] = {1e-3, 0.0, 0.05};
  c.merge_distance = merge[in.byte() % 3];
  c.max_degenerate_fraction = in.range(0, 10) * 0.1;
  // max_range from the seed's byte (no byte of its own: the corpus keeps its meaning): a
  // quarter of the inputs drop points beyond 2 m or 1e30 m of their scan's origin.
  const double range[] = {0.0, 0.0, 2.0, 1e30};
  c.max_range = range[c.query_seed % 4];
  return c;
}

// 7 bytes: translation (5 cm steps, or 0.5 m steps, or a special offset along x) and roll,
// pitch, yaw in 1.4 degree steps over the whole circle (2D: yaw only, no z).
Eigen::Isometry3d readPose(FuzzInput& in, int dimension) {
  const uint8_t kind = in.byte();
  Vec3 t = takeVec<int8_t>(in) * (kind & 1 ? 0.5 : 0.05);
  if ((kind & 6) == 6) {
    const double far[] = {1e3, -1e6, 1e-300, 4e3};
    t[0] += far[(kind >> 3) & 3];
  }
  Vec3 angle = takeVec<int8_t>(in) * (M_PI / 128.0);
  if (dimension == 2) {
    t[2] = 0.0;
    angle[0] = angle[1] = 0.0;
  }
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() =
      (Eigen::AngleAxisd(angle[2], Vec3::UnitZ()) * Eigen::AngleAxisd(angle[1], Vec3::UnitY()) *
       Eigen::AngleAxisd(angle[0], Vec3::UnitX()))
          .toRotationMatrix();
  T.translation() = t;
  return T;
}

// What every result (computeCoral or CoralPair) must satisfy; `finite`: usable input points.
void checkResult(const CoralResult& r, const CoralConfig& cfg, std::size_t finite,
                 std::size_t total) {
  CORAL_FUZZ_CHECK(r.num_non_finite == total - finite);
  CORAL_FUZZ_CHECK(r.num_points_a + r.num_points_b + r.num_out_of_range + r.num_beyond_max_range ==
                   finite);
  CORAL_FUZZ_CHECK(cfg.max_range > 0.0 || r.num_beyond_max_range == 0);
  CORAL_FUZZ_CHECK(std::isfinite(r.h_joint) && std::isfinite(r.h_sep) && std::isfinite(r.quality) &&
                   std::isfinite(r.mme) && std::isfinite(r.quality_stderr));
  CORAL_FUZZ_CHECK(r.valid == r.reason.empty());
  if (!r.reason.empty() && r.reason.find("refused") != std::string::npos) {
    CORAL_FUZZ_CHECK(cfg.refuse_over_max_points && !r.valid);
    return;
  }
  const auto max_points = static_cast<std::size_t>(cfg.max_points);
  CORAL_FUZZ_CHECK(r.num_points_a - std::min(r.num_points_a, max_points) + r.num_points_b -
                       std::min(r.num_points_b, max_points) ==
                   r.num_thinned);
  CORAL_FUZZ_CHECK(r.num_used_a <= std::min(r.num_points_a, max_points) &&
                   r.num_used_b <= std::min(r.num_points_b, max_points));
  CORAL_FUZZ_CHECK(r.num_queries <= r.num_used_a + r.num_used_b);
  CORAL_FUZZ_CHECK(r.num_valid + r.num_rejected <= r.num_overlap);
  CORAL_FUZZ_CHECK(r.num_overlap <= r.num_queries && r.num_degenerate <= r.num_overlap);
  CORAL_FUZZ_CHECK(r.overlap >= 0.0 && r.overlap <= 1.0);
  CORAL_FUZZ_CHECK(!r.valid || (r.num_valid > 0 && r.overlap >= cfg.min_overlap));
  if (cfg.per_point) {
    CORAL_FUZZ_CHECK(r.per_point.size() == r.num_queries);
    std::size_t valid = 0;
    for (const PointEntropy& pe : r.per_point) {
      valid += pe.valid;
      CORAL_FUZZ_CHECK(pe.position.allFinite());
      CORAL_FUZZ_CHECK(!pe.valid || (std::isfinite(pe.h_sep) && std::isfinite(pe.h_joint)));
    }
    CORAL_FUZZ_CHECK(valid == r.num_valid);
  }
}

// The probe of evaluate() and evaluateProbe() score the same points the same way.
void checkSameAggregate(const CoralResult& x, const CoralResult& y) {
  CORAL_FUZZ_CHECK(x.valid == y.valid && x.reason == y.reason);
  CORAL_FUZZ_CHECK(x.num_queries == y.num_queries && x.num_overlap == y.num_overlap &&
                   x.num_valid == y.num_valid && x.num_rejected == y.num_rejected &&
                   x.num_degenerate == y.num_degenerate);
  CORAL_FUZZ_CHECK(x.h_joint == y.h_joint && x.h_sep == y.h_sep && x.quality == y.quality);
}

// The relative check's decision is consistent with its own numbers (relative_check.hpp).
void checkRelative(const RelativeCheckResult& r, const CoralResult& probe, int dimension,
                   const RelativeCheckConfig& rc) {
  if (!probe.valid) {
    CORAL_FUZZ_CHECK(!r.valid && r.coral_evaluations == 0);
    return;
  }
  const std::size_t axes = toleranceAxes(dimension).size();
  CORAL_FUZZ_CHECK(r.axes.size() == axes && r.coral_evaluations == static_cast<int>(2 * axes));
  CORAL_FUZZ_CHECK(r.q == probe.quality);
  CORAL_FUZZ_CHECK(!r.misaligned || r.valid);
  CORAL_FUZZ_CHECK(r.hint.name.empty() || r.valid);
  if (!r.valid) return;
  // s_k = (Q - min) / mean |Q_neighbour - Q| lies in [-1, 2].
  CORAL_FUZZ_CHECK(r.score >= -1.0 - 1e-9 && r.score <= 2.0 + 1e-9);
  CORAL_FUZZ_CHECK(r.misaligned == (r.score > rc.margin));
  CORAL_FUZZ_CHECK(std::isfinite(r.scale) && r.scale > 0.0);
  for (const AxisProbe& p : r.axes)
    CORAL_FUZZ_CHECK(std::isfinite(p.sensitivity) && p.sensitivity >= 0.0 &&
                     p.sensitivity <= r.scale);
}

// CoralPair driven by the kPairBlock bytes after the mode byte (mode 0: not at all; `plain`
// is computeCoral's result in mode 2).
void fuzzPair(FuzzInput& in, uint8_t mode, const Scan& a, const Scan& b, const CoralConfig& cfg,
              const CoralResult& plain, std::size_t finite) {
  const std::size_t total = a.points.size() + b.points.size();
  // Probe of 1-40 queries per scan; in mode 3 also 0 (every query, 1 in 8). Mode 1's
  // relative check scores the probe at 2 x axes poses: a small probe keeps it cheap.
  const uint8_t probe_choice = in.byte();
  const int probe_queries = mode == 3 && probe_choice % 8 == 0 ? 0 : 1 + probe_choice % 40;
  ToleranceConfig tol;
  tol.translation = in.range(1, 40) * 0.05;
  tol.rotation_deg = in.range(1, 45);
  RelativeCheckConfig rc;
  rc.margin = in.range(0, 19) * 0.1;
  rc.flat_ratio = in.range(0, 9) * 0.1;
  const Eigen::Isometry3d T1 = readPose(in, cfg.dimension);
  const Eigen::Isometry3d T2 = readPose(in, cfg.dimension);
  if (mode == 0) return;
  // The relative check evaluates 2 x axes probe poses, each starting cfg.threads - 1
  // threads (parallelChunks); mode 1 runs single-threaded to stay cheap (results do not
  // depend on threads; modes 0, 2 and 3 keep the fuzzed thread count).
  CoralConfig pc = cfg;
  if (mode == 1) pc.threads = 1;
  const CoralPair pair(a, b, pc, probe_queries);
  if (mode == 2) {
    // At the identity CoralPair finds the same neighbours as computeCoral's joint grid (the
    // moments may differ in summation order, so only counts are compared).
    const CoralResult r = pair.evaluate(Eigen::Isometry3d::Identity());
    checkResult(r, cfg, finite, total);
    CORAL_FUZZ_CHECK(r.num_points_a == plain.num_points_a && r.num_points_b == plain.num_points_b &&
                     r.num_used_a == plain.num_used_a && r.num_used_b == plain.num_used_b &&
                     r.num_thinned == plain.num_thinned && r.num_merged == plain.num_merged);
    if (cfg.max_queries == 0 && plain.reason.find("refused") == std::string::npos) {
      CORAL_FUZZ_CHECK(r.num_queries == plain.num_queries);
      // Neighbours exactly at the radius count alike in both searches as long as rounding
      // of cell coordinates stays far below their 1e-6 cell margin (|coordinate| < 1e6 m).
      bool moderate = true;
      for (const Scan* s : {&a, &b})
        for (const Vec3& p : s->points) moderate = moderate && !(p.cwiseAbs().maxCoeff() >= 1e6);
      if (moderate) CORAL_FUZZ_CHECK(r.num_overlap == plain.num_overlap);
    }
    return;
  }
  CoralResult probe;
  const CoralResult r1 = pair.evaluate(T1, &probe);
  checkResult(r1, cfg, finite, total);
  if (r1.reason.find("refused") != std::string::npos) return;
  checkSameAggregate(probe, pair.evaluateProbe(T1));
  if (mode == 1) {
    checkRelative(relativeCheck(pair, T1, probe, cfg.dimension, tol, rc), probe, cfg.dimension, rc);
    // The loop gate's constraint term on the same filtered points at the same pose: a
    // defined, non-negative number and no more shared points than scored ones.
    const ConstraintResult c = registrationConstraint(pair.points(0), pair.points(1), T1, cfg, tol);
    CORAL_FUZZ_CHECK(c.valid && std::isfinite(c.weakest) && c.weakest >= 0.0 && c.points >= 0 &&
                     static_cast<std::size_t>(c.points) <=
                         pair.points(0).size() + pair.points(1).size());
  } else {
    // Without per-point output when asked (what self-calibration's neighbour poses use).
    const bool per_point = probe_choice & 0x40;
    CoralConfig c2 = cfg;
    c2.per_point = cfg.per_point && per_point;
    checkResult(pair.evaluate(T2, nullptr, per_point), c2, finite, total);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  FuzzInput in(data, size);
  const CoralConfig cfg = readConfig(in);
  if (!cfg.validate().empty()) return 0;  // precondition of computeCoral
  FuzzInput pair_in(in.rest(), std::min(in.remaining(), kPairBlock));
  for (std::size_t i = 0; i < kPairBlock; ++i) in.byte();
  Scan a, b;
  for (Scan* s : {&a, &b})
    for (int i = 0; i < 2; ++i) s->origin[i] = in.take<int8_t>();
  while (in.remaining() > 0) {
    const uint8_t ctrl = in.byte();
    Scan& s = ctrl & 1 ? b : a;
    const Vec3 p = readPoint(in, ctrl);
    if (s.points.size() < kMaxPoints) s.points.push_back(p);
  }
  // Every input point is usable or counted as dropped.
  std::size_t finite = 0;
  for (const Scan* s : {&a, &b})
    for (const Vec3& p : s->points) finite += p.allFinite();
  // computeCoral in modes 0 and 2 (compared with CoralPair there); modes 1 and 3 spend the
  // execution on CoralPair alone.
  const uint8_t mode = pair_in.byte() & 3;
  CoralResult plain;
  if (mode == 0 || mode == 2) {
    plain = computeCoral(a, b, cfg);
    checkResult(plain, cfg, finite, a.points.size() + b.points.size());
  }
  fuzzPair(pair_in, mode, a, b, cfg, plain, finite);
  return 0;
}
