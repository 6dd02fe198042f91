// libFuzzer harness: two small point sets and a CorAl config -> computeCoral (Eq. 1-6).
// Each point starts with a control byte choosing how its coordinates are read: small
// quantised values (clusters with neighbours), raw float32 or float64 (NaN, Inf, denormals,
// huge values), or a cluster point shifted by a special value (1e10, 9.3e18, 1e30, -1e300,
// denormal, ...). The config covers the input hygiene (coordinate limit up to the float
// range of scored positions, max_points, merging), the voxel filter and the query subset.
// The result must be defined whatever the input: finite aggregates, counts that add up, and no
// verdict without overlapping points or with a reason.
#include <cmath>
#include <limits>

#include "coral_introspection/coral/coral.hpp"
#include "fuzz_input.hpp"

using namespace coral_introspection::core;
using coral_fuzz::FuzzInput;

namespace {

constexpr std::size_t kMaxPoints = 256;  // per cloud: keeps one execution well under 1 ms

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
  return c;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  FuzzInput in(data, size);
  const CoralConfig cfg = readConfig(in);
  if (!cfg.validate().empty()) return 0;  // precondition of computeCoral
  Scan a, b;
  for (Scan* s : {&a, &b})
    for (int i = 0; i < 2; ++i) s->origin[i] = in.take<int8_t>();
  while (in.remaining() > 0) {
    const uint8_t ctrl = in.byte();
    Scan& s = ctrl & 1 ? b : a;
    const Vec3 p = readPoint(in, ctrl);
    if (s.points.size() < kMaxPoints) s.points.push_back(p);
  }
  const CoralResult r = computeCoral(a, b, cfg);
  // Every input point is usable or counted as dropped.
  std::size_t finite = 0;
  for (const Scan* s : {&a, &b})
    for (const Vec3& p : s->points) finite += p.allFinite();
  CORAL_FUZZ_CHECK(r.num_non_finite == a.points.size() + b.points.size() - finite);
  CORAL_FUZZ_CHECK(r.num_points_a + r.num_points_b + r.num_out_of_range == finite);
  CORAL_FUZZ_CHECK(std::isfinite(r.h_joint) && std::isfinite(r.h_sep) && std::isfinite(r.quality) &&
                   std::isfinite(r.mme) && std::isfinite(r.quality_stderr));
  CORAL_FUZZ_CHECK(r.valid == r.reason.empty());
  if (!r.reason.empty() && r.reason.find("refused") != std::string::npos) {
    CORAL_FUZZ_CHECK(cfg.refuse_over_max_points && !r.valid);
    return 0;
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
  return 0;
}
