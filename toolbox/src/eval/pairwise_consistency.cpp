#include "coral_introspection/eval/pairwise_consistency.hpp"

#include <algorithm>
#include <boost/math/distributions/chi_squared.hpp>
#include <cmath>
#include <cstdint>

#include "coral_introspection/coral/types.hpp"
#include "coral_introspection/coral/validation.hpp"
#include "coral_introspection/rio/so3.hpp"

namespace coral_introspection {
namespace eval {

namespace {

// Pieces of a cycle in the tangent space of the pose graph's residual (pose_graph.hpp:
// T_noisy = T Exp(xi), xi = (translation, rotation vector); planar: (x, y, yaw)). N = 3 or 6.
template <int N>
struct Tangent {
  using Mat = Eigen::Matrix<double, N, N>;
  using Vec = Eigen::Matrix<double, N, 1>;

  // Ad_T: moves a perturbation from before T to after it, T Exp(xi) = Exp(Ad_T xi) T
  // ([[R, [t]x R], [0, R]]; planar [[R, (t_y, -t_x)^T], [0, 1]]).
  static Mat adjoint(const Eigen::Isometry3d& T) {
    Mat A = Mat::Zero();
    const Eigen::Vector3d t = T.translation();
    if constexpr (N == 3) {
      A.template topLeftCorner<2, 2>() = T.linear().topLeftCorner<2, 2>();
      A(0, 2) = t.y();
      A(1, 2) = -t.x();
      A(2, 2) = 1.0;
    } else {
      const Eigen::Matrix3d R = T.linear();
      A.template topLeftCorner<3, 3>() = R;
      A.template topRightCorner<3, 3>() = rio::skew(t) * R;
      A.template bottomRightCorner<3, 3>() = R;
    }
    return A;
  }

  // The residual of pose_graph.cpp for a cycle T that should be the identity.
  static Vec error(const Eigen::Isometry3d& T) {
    Vec e;
    if constexpr (N == 3) {
      e << T.translation().x(), T.translation().y(), coral::yawOf(T.linear());
    } else {
      e << T.translation(), rio::logQ(Eigen::Quaterniond(T.linear()));
    }
    return e;
  }

  static Mat covariance(double sigma_t, double sigma_r) {
    Vec d;
    if constexpr (N == 3)
      d << sigma_t * sigma_t, sigma_t * sigma_t, sigma_r * sigma_r;
    else
      d << Eigen::Vector3d::Constant(sigma_t * sigma_t),
          Eigen::Vector3d::Constant(sigma_r * sigma_r);
    return d.asDiagonal();
  }
};

// Symmetric consistency graph as bit rows; the greedy largest clique of the header's comment.
struct BitGraph {
  int n = 0, words = 0;
  std::vector<std::uint64_t> bits;  // row-major n x words
  explicit BitGraph(int n_) : n(n_), words((n_ + 63) / 64), bits(std::size_t(n_) * words, 0) {}
  std::uint64_t* row(int i) { return &bits[std::size_t(i) * words]; }
  void link(int i, int j) {
    row(i)[j / 64] |= std::uint64_t(1) << (j % 64);
    row(j)[i / 64] |= std::uint64_t(1) << (i % 64);
  }
};

int popcount(const std::uint64_t* a, const std::uint64_t* b, int words) {
  int c = 0;
  for (int w = 0; w < words; ++w) c += __builtin_popcountll(a[w] & b[w]);
  return c;
}

std::vector<int> greedyLargestClique(BitGraph& g, int max_starts) {
  std::vector<int> degree(g.n), order(g.n);
  for (int i = 0; i < g.n; ++i) {
    degree[i] = popcount(g.row(i), g.row(i), g.words);
    order[i] = i;
  }
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return degree[a] > degree[b]; });
  std::vector<int> best;
  for (int s = 0; s < std::min<int>(max_starts, g.n); ++s) {
    const int v = order[s];
    if (degree[v] + 1 <= static_cast<int>(best.size())) break;  // cannot beat the best
    std::vector<int> clique{v};
    std::vector<std::uint64_t> cand(g.row(v), g.row(v) + g.words);
    for (;;) {
      int pick = -1, pick_links = -1;
      for (int u = 0; u < g.n; ++u) {
        if (!(cand[u / 64] >> (u % 64) & 1)) continue;
        const int links = popcount(cand.data(), g.row(u), g.words);
        if (links > pick_links) pick = u, pick_links = links;
      }
      if (pick < 0) break;
      clique.push_back(pick);
      for (int w = 0; w < g.words; ++w) cand[w] &= g.row(pick)[w];
    }
    if (clique.size() > best.size()) best = clique;
  }
  return best;
}

// pairwise: PCM's test of every two loop edges and the largest consistent set; otherwise each
// loop edge against the odometry alone (the pair test with an identity edge at its end).
template <int N>
bool inconsistentLoops(const std::vector<PoseGraphEdge>& edges,
                       const PairwiseConsistencyConfig& cfg, bool pairwise,
                       std::vector<int>* rejected, std::string* error) {
  const std::string what = pairwise ? "pairwise consistency: " : "odometry consistency: ";
  using TS = Tangent<N>;
  using Mat = typename TS::Mat;
  // The odometry chain: poses P_k (P_0 = I) and prefix sums G_k = sum_{m<k} Ad_{P_(m+1)}
  // Sigma_m Ad_{P_(m+1)}^T, so that the covariance of a segment's steps is a difference of two
  // (O_kl = P_k^-1 P_l, k < l: Ad_{P_l}^-1 (G_l - G_k) Ad_{P_l}^-T).
  std::vector<Eigen::Isometry3d> P{Eigen::Isometry3d::Identity()};
  std::vector<Mat> G{Mat::Zero()};
  std::vector<int> loops;
  for (std::size_t k = 0; k < edges.size(); ++k) {
    const PoseGraphEdge& e = edges[k];
    if (e.loop) {
      loops.push_back(static_cast<int>(k));
      continue;
    }
    if (e.from != static_cast<int>(P.size()) - 1 || e.to != e.from + 1)
      return coral::fail(error, what +
                                    "the odometry edges are not the chain 0 -> "
                                    "1 -> ... in order (edge " +
                                    std::to_string(k) + ": " + std::to_string(e.from) + " -> " +
                                    std::to_string(e.to) + ")");
    P.push_back(P.back() * e.T_from_to);
    const Mat A = TS::adjoint(P.back());
    G.push_back(G.back() +
                A * TS::covariance(e.sigma_translation, e.sigma_rotation) * A.transpose());
  }
  const int nodes = static_cast<int>(P.size());
  std::vector<Mat> ad_inv(nodes);  // Ad_(P_k^-1), used by every pair
  for (int k = 0; k < nodes; ++k) ad_inv[k] = TS::adjoint(P[k].inverse());
  for (int k : loops)
    if (std::min(edges[k].from, edges[k].to) < 0 || std::max(edges[k].from, edges[k].to) >= nodes)
      return coral::fail(error, what + "loop edge " + std::to_string(k) +
                                    " joins a node the odometry chain does not reach");
  boost::math::chi_squared chi2(N);
  const double bound = boost::math::quantile(chi2, cfg.probability);
  const int n = static_cast<int>(loops.size());
  // Per loop edge, the covariance of its noise and of its inverse's noise:
  // (Zb Exp(beta))^-1 = Zb^-1 Exp(-Ad_Zb beta).
  std::vector<Mat> cov(n), inverse_cov(n);
  for (int x = 0; x < n; ++x) {
    const PoseGraphEdge& e = edges[loops[x]];
    const Mat Ad = TS::adjoint(e.T_from_to);
    cov[x] = TS::covariance(e.sigma_translation, e.sigma_rotation);
    inverse_cov[x] = Ad * cov[x] * Ad.transpose();
  }
  // The squared Mahalanobis distance of the cycle closed by loop edge a (index x) and b (index y,
  // covariance of b's inverse inverse_cov_b).
  auto distance2 = [&](const PoseGraphEdge& a, int x, const PoseGraphEdge& b,
                       const Mat& inverse_cov_b) {
    // The cycle i -Za-> k -odom-> l -Zb^-1-> j -odom-> i of loops a (i -> k) and b (j -> l):
    // E = A B C D = identity when both are right. First order: E Exp(Ad_(BCD)^-1 a +
    // Ad_(CD)^-1 b + Ad_D^-1 c + d), b and d the odometry segments' noise.
    const int i = a.from, k = a.to, j = b.from, l = b.to;
    const Eigen::Isometry3d B = P[k].inverse() * P[l], D = P[j].inverse() * P[i];
    const Eigen::Isometry3d C = b.T_from_to.inverse(), CD = C * D, BCD = B * CD;
    const Mat A1 = TS::adjoint(BCD.inverse()), A3 = TS::adjoint(D.inverse());
    Mat S = A1 * cov[x] * A1.transpose() + A3 * inverse_cov_b * A3.transpose();
    // Odometry step m's noise n_m in a segment from u to v, moved to the segment's end, is
    // +-Ad_(P_v^-1) Ad_(P_(m+1)) n_m (+ forward, - when the segment runs back along the
    // chain), then moved past the rest of the cycle. Steps both segments run over (nested
    // loops) enter twice, correlated: their matrices are summed before the covariance.
    const Mat MB = (k <= l ? 1.0 : -1.0) * TS::adjoint(CD.inverse()) * ad_inv[l];
    const Mat MD = (j <= i ? 1.0 : -1.0) * ad_inv[i];
    const int b0 = std::min(k, l), b1 = std::max(k, l), d0 = std::min(j, i), d1 = std::max(j, i);
    const int o0 = std::max(b0, d0), o1 = std::max(o0, std::min(b1, d1));  // shared steps
    const Mat Go = G[o1] - G[o0];
    S += MB * (G[b1] - G[b0] - Go) * MB.transpose() + MD * (G[d1] - G[d0] - Go) * MD.transpose() +
         (MB + MD) * Go * (MB + MD).transpose();
    const typename TS::Vec e = TS::error(a.T_from_to * BCD);
    return e.dot(S.ldlt().solve(e));
  };
  if (!pairwise) {
    // b: the identity at a's end (k -> k, no noise): the cycle is a against the odometry's
    // segment from i to k.
    for (int x = 0; x < n; ++x) {
      const PoseGraphEdge& a = edges[loops[x]];
      const PoseGraphEdge at_end{a.to, a.to, Eigen::Isometry3d::Identity(), 0.0, 0.0, true};
      const double d2 = distance2(a, x, at_end, Mat::Zero());
      if (!(std::isfinite(d2) && d2 <= bound)) rejected->push_back(loops[x]);
    }
    return true;
  }
  BitGraph g(n);
  for (int x = 0; x < n; ++x)
    for (int y = x + 1; y < n; ++y) {
      const double d2 = distance2(edges[loops[x]], x, edges[loops[y]], inverse_cov[y]);
      if (std::isfinite(d2) && d2 <= bound) g.link(x, y);
    }
  std::vector<bool> kept(n, false);
  for (int x : greedyLargestClique(g, cfg.max_starts)) kept[x] = true;
  for (int x = 0; x < n; ++x)
    if (!kept[x]) rejected->push_back(loops[x]);
  return true;
}

}  // namespace

std::string PairwiseConsistencyConfig::validate() const {
  return coral::Problems()
      .require(std::isfinite(probability) && probability > 0.0 && probability < 1.0, "probability",
               "in (0, 1)", probability)
      .require(dimension == 2 || dimension == 3, "dimension", "2 or 3", dimension)
      .require(max_starts >= 1, "max_starts", ">= 1", max_starts)
      .str();
}

namespace {
bool checkLoops(const std::vector<PoseGraphEdge>& edges, const PairwiseConsistencyConfig& cfg,
                bool pairwise, std::vector<int>* rejected, std::string* error) {
  const std::string what = pairwise ? "pairwise consistency: " : "odometry consistency: ";
  if (const std::string problems = cfg.validate(); !problems.empty())
    return coral::fail(error, what + problems);
  if (!rejected) return coral::fail(error, what + "no output");
  rejected->clear();
  return cfg.dimension == 2 ? inconsistentLoops<3>(edges, cfg, pairwise, rejected, error)
                            : inconsistentLoops<6>(edges, cfg, pairwise, rejected, error);
}
}  // namespace

bool pairwiseInconsistentLoops(const std::vector<PoseGraphEdge>& edges,
                               const PairwiseConsistencyConfig& cfg, std::vector<int>* rejected,
                               std::string* error) {
  return checkLoops(edges, cfg, true, rejected, error);
}

bool odometryInconsistentLoops(const std::vector<PoseGraphEdge>& edges,
                               const PairwiseConsistencyConfig& cfg, std::vector<int>* rejected,
                               std::string* error) {
  return checkLoops(edges, cfg, false, rejected, error);
}

bool inconsistentLoopEdges(const std::vector<PoseGraphEdge>& edges,
                           const PairwiseConsistencyConfig& cfg, std::vector<int>* rejected,
                           int* by_odometry, std::string* error) {
  std::vector<int> off_odometry, off_pairwise;
  if (!odometryInconsistentLoops(edges, cfg, &off_odometry, error)) return false;
  // The pairwise test runs on the edges the odometry check kept; its indices map back.
  std::vector<int> index;  // kept[m] is edges[index[m]]
  std::vector<PoseGraphEdge> kept;
  for (std::size_t k = 0; k < edges.size(); ++k)
    if (!std::binary_search(off_odometry.begin(), off_odometry.end(), static_cast<int>(k))) {
      kept.push_back(edges[k]);
      index.push_back(static_cast<int>(k));
    }
  if (!pairwiseInconsistentLoops(kept, cfg, &off_pairwise, error)) return false;
  *rejected = off_odometry;
  for (int m : off_pairwise) rejected->push_back(index[m]);
  std::sort(rejected->begin(), rejected->end());
  if (by_odometry) *by_odometry = static_cast<int>(off_odometry.size());
  return true;
}

std::vector<PoseGraphEdge> keptEdges(const std::vector<PoseGraphEdge>& edges,
                                     const std::vector<int>& rejected) {
  std::vector<PoseGraphEdge> kept;
  for (std::size_t k = 0; k < edges.size(); ++k)
    if (!std::binary_search(rejected.begin(), rejected.end(), static_cast<int>(k)))
      kept.push_back(edges[k]);
  return kept;
}

}  // namespace eval
}  // namespace coral_introspection
