#include "coral_introspection/coral/coral_pair.hpp"

#include <atomic>
#include <chrono>

#include "coral_detail.hpp"
#include "coral_introspection/coral/moments_kernel.hpp"
#include "coral_introspection/coral/neighbour_grid.hpp"
#include "coral_introspection/coral/parallel.hpp"

namespace coral_introspection {
namespace coral {

namespace {

// The queries of one scan: positions in its own grid, their radii and own-cloud moments
// (pose-independent, computed once).
struct Side {
  std::unique_ptr<NeighbourGrid> grid;  // the scan in its own frame
  std::vector<uint32_t> queries;        // positions in grid->sortedPoints()
  std::vector<uint32_t> probe;          // indices into queries
  std::vector<double> radius;           // per query [m]
  std::vector<MomentsN<2>> own2;        // per query, dimension 2
  std::vector<MomentsN<3>> own3;        // per query, dimension 3
  std::vector<OwnEntropy> h_own;        // per query: h_i (Eq. 1) in its own cloud
  std::size_t own_tests = 0;            // distance tests of the own-cloud searches
};

template <int Dim, class S>
auto& own(S& side, std::size_t k) {  // Side or const Side
  if constexpr (Dim == 2)
    return side.own2[k];
  else
    return side.own3[k];
}

// m's deviations (taken in the other cloud's frame) expressed in the query's frame by R.
// Only the upper triangle of sum2 is meaningful (MomentsN::add), so it is mirrored first.
template <int Dim>
void rotate(const Eigen::Matrix3d& R3, MomentsN<Dim>* m) {
  const Eigen::Matrix<double, Dim, Dim> R = R3.topLeftCorner<Dim, Dim>();
  const Eigen::Matrix<double, Dim, Dim> s2 = m->sum2.template selfadjointView<Eigen::Upper>();
  m->sum = R * m->sum;
  m->sum2 = R * s2 * R.transpose();
}

}  // namespace

struct CoralPair::Impl {
  CoralConfig cfg;
  CoralResult base;  // input counts, or the refusal
  bool refused = false;
  Side side[2];
  Vec3 origin[2];  // each scan's sensor in its own frame (dynamic radius)

  template <int Dim>
  void prepareSide(int s) {
    Side& sd = side[s];
    const std::size_t nq = sd.queries.size();
    sd.radius.resize(nq);
    if (Dim == 2) sd.own2.resize(nq);
    if (Dim == 3) sd.own3.resize(nq);
    sd.h_own.resize(nq);
    const Points& pts = sd.grid->sortedPoints();
    std::atomic<std::size_t> tests{0};
    parallelChunks(nq, cfg.threads, [&](std::size_t k0, std::size_t k1) {
      std::size_t t = 0;
      for (std::size_t k = k0; k < k1; ++k) {
        const Vec3& p = pts[sd.queries[k]];
        sd.radius[k] = detail::pointRadius<Dim>(cfg, p, origin[s]);
        MomentsN<Dim>& m = own<Dim>(sd, k);
        t += momentsNear<Dim>(*sd.grid, p, sd.radius[k], &m);
        sd.h_own[k].ok =
            m.n >= cfg.min_neighbours &&
            differentialEntropy(m.covariance(), cfg.dimension, cfg.epsilon, &sd.h_own[k].h);
      }
      tests += t;
    });
    sd.own_tests = tests;
  }

  // Scores queries[subset[i]] of side s (all queries when subset is null) with the other
  // scan moved by T_a_b; out[i] in a's frame. Returns the other-cloud distance tests.
  template <int Dim>
  std::size_t score(int s, const Eigen::Isometry3d& T_a_b, const std::vector<uint32_t>* subset,
                    PointEntropy* out) const {
    const Side& sd = side[s];
    const NeighbourGrid& other = *side[1 - s].grid;
    // M: this side's frame -> the other scan's frame; a's frame is the common one.
    const Eigen::Isometry3d M = s == 0 ? T_a_b.inverse() : T_a_b;
    const Eigen::Matrix3d R_back = M.linear().transpose();  // other's frame -> this side's
    const Points& pts = sd.grid->sortedPoints();
    const std::size_t n = subset ? subset->size() : sd.queries.size();
    std::atomic<std::size_t> tests{0};
    parallelChunks(n, cfg.threads, [&](std::size_t i0, std::size_t i1) {
      std::size_t t = 0;
      for (std::size_t i = i0; i < i1; ++i) {
        const std::size_t k = subset ? (*subset)[i] : i;
        const Vec3& q = pts[sd.queries[k]];
        MomentsN<Dim> m_other;
        t += momentsNear<Dim>(other, M * q, sd.radius[k], &m_other);
        rotate(R_back, &m_other);
        detail::setPoint(out[i], s == 0 ? q : Vec3(T_a_b * q), s == 0, sd.radius[k]);
        const OwnEntropy& h_own = sd.h_own[k];
        scorePoint(own<Dim>(sd, k), m_other, cfg, &out[i], [&](double* h) {  // Eq. 1, 6
          *h = h_own.h;
          return h_own.ok;
        });
      }
      tests += t;
    });
    return tests;
  }

  template <int Dim>
  CoralResult evaluate(const Eigen::Isometry3d& T_a_b, bool probe_only, bool per_point,
                       CoralResult* probe) const {
    CoralResult res = base;
    if (refused) return res;
    std::vector<PointEntropy> pp;
    if (probe_only) {
      pp.resize(side[0].probe.size() + side[1].probe.size());
      res.num_distance_tests = score<Dim>(0, T_a_b, &side[0].probe, pp.data());
      res.num_distance_tests +=
          score<Dim>(1, T_a_b, &side[1].probe, pp.data() + side[0].probe.size());
    } else {
      const std::size_t na = side[0].queries.size();
      pp.resize(na + side[1].queries.size());
      res.num_distance_tests = side[0].own_tests + side[1].own_tests;
      res.num_distance_tests += score<Dim>(0, T_a_b, nullptr, pp.data());
      res.num_distance_tests += score<Dim>(1, T_a_b, nullptr, pp.data() + na);
      if (probe) {
        std::vector<PointEntropy> sub;
        for (uint32_t k : side[0].probe) sub.push_back(pp[k]);
        for (uint32_t k : side[1].probe) sub.push_back(pp[na + k]);
        *probe = base;
        CoralConfig c = cfg;
        c.per_point = false;
        finalizeCoral(c, std::move(sub), probe);
      }
    }
    CoralConfig c = cfg;
    c.per_point = cfg.per_point && per_point && !probe_only;
    finalizeCoral(c, std::move(pp), &res);
    return res;
  }
};

CoralPair::CoralPair(const Scan& a, const Scan& b, const CoralConfig& cfg, int probe_queries)
    : impl_(std::make_unique<Impl>()) {
  Impl& im = *impl_;
  im.cfg = cfg;
  im.origin[0] = a.origin;
  im.origin[1] = b.origin;
  detail::PreparedClouds prepared;
  if (!detail::prepareClouds(a, b, cfg, &prepared, &im.base)) {
    im.refused = true;
    return;
  }
  const auto m = static_cast<std::size_t>(cfg.max_queries);
  for (int s = 0; s < 2; ++s) {
    Side& sd = im.side[s];
    const Points& pts = *prepared.cloud[s];
    const bool subset = m > 0 && pts.size() > m;
    sd.grid = std::make_unique<NeighbourGrid>(pts, detail::queryCellSize(cfg), cfg.dimension);
    if (subset) {
      sd.queries = detail::selectQueries(*sd.grid, cfg);
    } else {
      sd.queries.resize(pts.size());
      for (std::size_t i = 0; i < pts.size(); ++i) sd.queries[i] = static_cast<uint32_t>(i);
    }
    // Probe queries: the middle of each of probe_queries equal strata of the (spatially
    // ordered) queries, so the probe is itself a systematic sample.
    const std::size_t nq = sd.queries.size();
    const auto np = static_cast<std::size_t>(probe_queries);
    for (std::size_t k = 0; k < (np > 0 && nq > np ? np : nq); ++k)
      sd.probe.push_back(np > 0 && nq > np ? static_cast<uint32_t>((2 * k + 1) * nq / (2 * np))
                                           : static_cast<uint32_t>(k));
    if (cfg.dimension == 2)
      im.prepareSide<2>(s);
    else
      im.prepareSide<3>(s);
  }
}

CoralPair::~CoralPair() = default;

CoralResult CoralPair::evaluate(const Eigen::Isometry3d& T_a_b, CoralResult* probe,
                                bool per_point) const {
  const auto t0 = std::chrono::steady_clock::now();
  CoralResult r = impl_->cfg.dimension == 2 ? impl_->evaluate<2>(T_a_b, false, per_point, probe)
                                            : impl_->evaluate<3>(T_a_b, false, per_point, probe);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

CoralResult CoralPair::evaluateProbe(const Eigen::Isometry3d& T_a_b) const {
  const auto t0 = std::chrono::steady_clock::now();
  CoralResult r = impl_->cfg.dimension == 2 ? impl_->evaluate<2>(T_a_b, true, false, nullptr)
                                            : impl_->evaluate<3>(T_a_b, true, false, nullptr);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

const CoralConfig& CoralPair::config() const { return impl_->cfg; }

const Points& CoralPair::points(int side) const {
  static const Points kNone;
  const Side& sd = impl_->side[side == 0 ? 0 : 1];
  return sd.grid ? sd.grid->sortedPoints() : kNone;
}

const Vec3& CoralPair::origin(int side) const { return impl_->origin[side == 0 ? 0 : 1]; }

}  // namespace coral
}  // namespace coral_introspection
