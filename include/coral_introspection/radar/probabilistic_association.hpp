// Probability-guided point association (paper: radar_point_uncertainty_slam, Sec. III-D,
// Eq. 13-14): a measured point p_k with covariance Sigma_k (Eq. 8) is paired with the
// candidate landmark of highest Gaussian density N(l; p_k, Sigma_k), not with the
// Euclidean-nearest one, and only if it lies within the 3-sigma gate.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "coral_introspection/coral/neighbour_grid.hpp"
#include "coral_introspection/coral/types.hpp"

namespace coral_introspection {
namespace radar {

struct ProbabilisticAssociationConfig {
  int dimension = 2;               // 2 (spinning radar, x-y only) or 3
  double gate_sigma = 3.0;         // Mahalanobis gate: sqrt(m^2) <= gate_sigma (3-sigma rule)
  double max_search_radius = 3.0;  // [m] Euclidean cap of the candidate search
  double min_variance = 1e-6;      // [m^2] eigenvalue floor so Sigma_k stays invertible
  // associateOneToOne only: a query whose second-best candidate has at least this fraction
  // of the best candidate's density is left unmatched as ambiguous (0 = off, the paper).
  double ambiguity_ratio = 0.0;
  std::string validate() const;  // empty when valid
};

struct ProbabilisticMatch {
  int target = -1;  // index into the landmarks, -1 = none within the gate
  double mahalanobis2 = std::numeric_limits<double>::infinity();  // (l - p)^T Sigma^-1 (l - p)
  double log_density = -std::numeric_limits<double>::infinity();  // ln P_k(l) (Eq. 13)
  bool ambiguous = false;  // associateOneToOne: rejected by the ambiguity ratio
};

// ln N(x; mean, sigma) over the first dim coordinates (Eq. 13), eigenvalues floored at
// min_variance. *mahalanobis2 (optional) receives (x - mean)^T sigma^-1 (x - mean).
double gaussianLogDensity(const coral::Vec3& x, const coral::Vec3& mean, const coral::Mat3& sigma,
                          int dim, double min_variance, double* mahalanobis2 = nullptr);

// Landmarks indexed once, queried per measured point. Landmarks and queries share a frame;
// Sigma must be expressed in that frame (transformScan rotates covariances).
class ProbabilisticMatcher {
 public:
  // Precondition: cfg.validate() is empty. Non-finite landmarks are never matched.
  ProbabilisticMatcher(const coral::Points& landmarks, const ProbabilisticAssociationConfig& cfg);
  // Eq. 14: argmax over landmarks within the gate of P_k(l); target -1 when none.
  ProbabilisticMatch match(const coral::Vec3& p, const coral::Mat3& sigma) const;
  // Every landmark within the gate of p (Eq. 13 density each), in no particular order.
  std::vector<ProbabilisticMatch> candidates(const coral::Vec3& p, const coral::Mat3& sigma) const;

 private:
  // Calls fn(landmark index, m^2, ln P_k) for each landmark inside the gate of p.
  template <class Fn>
  void forEachInGate(const coral::Vec3& p, const coral::Mat3& sigma, Fn&& fn) const;

  ProbabilisticAssociationConfig cfg_;
  std::vector<uint32_t> original_;  // landmark index of each finite (gridded) landmark
  coral::NeighbourGrid grid_;
};

// Convenience: one match per query (queries[i] with covariances[i]). Returns an empty
// vector and sets *error on a size mismatch or invalid config; never throws.
std::vector<ProbabilisticMatch> associateProbabilistic(const coral::Points& queries,
                                                       const coral::Covariances& covariances,
                                                       const coral::Points& landmarks,
                                                       const ProbabilisticAssociationConfig& cfg,
                                                       std::string* error);

// One-to-one association (Eq. 13-14 with each landmark used once): all query-landmark
// pairs within the gate, taken in order of decreasing density; a pair is kept when
// neither its query nor its landmark is taken yet. One result per query (target -1 when
// it got none). With cfg.ambiguity_ratio > 0, queries with two similarly dense candidates
// are left out first (ambiguous = true). Empty result and *error on a size mismatch or
// invalid config.
std::vector<ProbabilisticMatch> associateOneToOne(const coral::Points& queries,
                                                  const coral::Covariances& covariances,
                                                  const coral::Points& landmarks,
                                                  const ProbabilisticAssociationConfig& cfg,
                                                  std::string* error);

}  // namespace radar
}  // namespace coral_introspection
