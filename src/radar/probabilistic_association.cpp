#include "coral_introspection/radar/probabilistic_association.hpp"

#include "coral_introspection/coral/validation.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace coral_introspection {
namespace radar {

std::string ProbabilisticAssociationConfig::validate() const {
  return coral::Problems()
      .require(dimension == 2 || dimension == 3, "dimension", "2 or 3", dimension)
      .require(gate_sigma > 0.0, "gate_sigma", "> 0", gate_sigma)
      .require(max_search_radius > 0.0, "max_search_radius", "> 0 m", max_search_radius)
      .require(min_variance > 0.0, "min_variance", "> 0 m^2", min_variance)
      .require(ambiguity_ratio >= 0.0 && ambiguity_ratio < 1.0, "ambiguity_ratio", "in [0, 1)",
               ambiguity_ratio)
      .str();
}

namespace {
template <int N>
void floorInverse(const coral::Mat3& sigma, double min_variance, coral::Mat3* inv, double* logdet,
                  double* lambda_max) {
  using MatN = Eigen::Matrix<double, N, N>;
  Eigen::SelfAdjointEigenSolver<MatN> es;
  es.computeDirect(sigma.topLeftCorner<N, N>());
  const Eigen::Matrix<double, N, 1> lambda = es.eigenvalues().cwiseMax(min_variance);
  *logdet = lambda.array().log().sum();
  *lambda_max = lambda.maxCoeff();
  inv->setZero();
  inv->topLeftCorner<N, N>() =
      es.eigenvectors() * lambda.cwiseInverse().asDiagonal() * es.eigenvectors().transpose();
}

// Inverse (zero-padded to 3 x 3) and log-determinant of the top-left dim x dim block of
// sigma, eigenvalues floored at min_variance.
void regularisedInverse(const coral::Mat3& sigma, int dim, double min_variance, coral::Mat3* inv,
                        double* logdet, double* lambda_max) {
  if (dim == 2)
    floorInverse<2>(sigma, min_variance, inv, logdet, lambda_max);
  else
    floorInverse<3>(sigma, min_variance, inv, logdet, lambda_max);
}

coral::Points finiteOnly(const coral::Points& in, std::vector<uint32_t>* original) {
  coral::Points out;
  for (std::size_t i = 0; i < in.size(); ++i)
    if (in[i].allFinite()) out.push_back(in[i]), original->push_back(static_cast<uint32_t>(i));
  return out;
}
// Shared precondition of the association entry points: a valid config and one covariance
// per query; the reason goes to *error (when given).
bool inputsValid(const coral::Points& queries, const coral::Covariances& covariances,
                 const ProbabilisticAssociationConfig& cfg, std::string* error) {
  std::string msg = cfg.validate();
  if (msg.empty() && covariances.size() != queries.size())
    msg = "covariances size differs from queries size";
  if (msg.empty()) return true;
  if (error) *error = msg;
  return false;
}

}  // namespace

double gaussianLogDensity(const coral::Vec3& x, const coral::Vec3& mean, const coral::Mat3& sigma,
                          int dim, double min_variance, double* mahalanobis2) {
  coral::Mat3 inv;
  double logdet = 0.0, lambda_max = 0.0;
  regularisedInverse(sigma, dim, min_variance, &inv, &logdet, &lambda_max);
  coral::Vec3 r = x - mean;
  if (dim == 2) r.z() = 0.0;
  const double m2 = r.dot(inv * r);
  if (mahalanobis2) *mahalanobis2 = m2;
  // Eq. 13: ln( (2 pi)^(-N/2) |Sigma|^(-1/2) exp(-m^2 / 2) ).
  return -0.5 * (dim * std::log(2.0 * M_PI) + logdet + m2);
}

ProbabilisticMatcher::ProbabilisticMatcher(const coral::Points& landmarks,
                                           const ProbabilisticAssociationConfig& cfg)
    : cfg_(cfg), grid_(finiteOnly(landmarks, &original_), cfg.max_search_radius, cfg.dimension) {}

template <class Fn>
void ProbabilisticMatcher::forEachInGate(const coral::Vec3& p, const coral::Mat3& sigma,
                                         Fn&& fn) const {
  if (!p.allFinite() || !sigma.allFinite()) return;
  coral::Mat3 inv;
  double logdet = 0.0, lambda_max = 0.0;
  regularisedInverse(sigma, cfg_.dimension, cfg_.min_variance, &inv, &logdet, &lambda_max);
  // Every point inside the gate ellipsoid lies within gate * sqrt(lambda_max) of p.
  const double radius = std::min(cfg_.max_search_radius, cfg_.gate_sigma * std::sqrt(lambda_max));
  const double gate2 = cfg_.gate_sigma * cfg_.gate_sigma;
  const double log_norm = -0.5 * (cfg_.dimension * std::log(2.0 * M_PI) + logdet);
  grid_.forEachWithin(p, radius, [&](const coral::Vec3& l, uint32_t idx) {
    coral::Vec3 r = l - p;
    if (cfg_.dimension == 2) r.z() = 0.0;
    const double m2 = r.dot(inv * r);
    if (m2 <= gate2) fn(static_cast<int>(original_[idx]), m2, log_norm - 0.5 * m2);
  });
}

ProbabilisticMatch ProbabilisticMatcher::match(const coral::Vec3& p,
                                               const coral::Mat3& sigma) const {
  ProbabilisticMatch best;
  // Sigma_k is shared by all candidates of p_k, so the highest density (Eq. 14) is the
  // smallest Mahalanobis distance; the 3-sigma gate removes outliers.
  forEachInGate(p, sigma, [&](int target, double m2, double log_density) {
    if (m2 < best.mahalanobis2) best = {target, m2, log_density};
  });
  return best;
}

std::vector<ProbabilisticMatch> ProbabilisticMatcher::candidates(const coral::Vec3& p,
                                                                 const coral::Mat3& sigma) const {
  std::vector<ProbabilisticMatch> out;
  forEachInGate(p, sigma, [&](int target, double m2, double log_density) {
    out.push_back({target, m2, log_density});
  });
  return out;
}

std::vector<ProbabilisticMatch> associateProbabilistic(const coral::Points& queries,
                                                       const coral::Covariances& covariances,
                                                       const coral::Points& landmarks,
                                                       const ProbabilisticAssociationConfig& cfg,
                                                       std::string* error) {
  if (!inputsValid(queries, covariances, cfg, error)) return {};
  const ProbabilisticMatcher matcher(landmarks, cfg);
  std::vector<ProbabilisticMatch> out;
  out.reserve(queries.size());
  for (std::size_t i = 0; i < queries.size(); ++i)
    out.push_back(matcher.match(queries[i], covariances[i]));
  return out;
}

std::vector<ProbabilisticMatch> associateOneToOne(const coral::Points& queries,
                                                  const coral::Covariances& covariances,
                                                  const coral::Points& landmarks,
                                                  const ProbabilisticAssociationConfig& cfg,
                                                  std::string* error) {
  if (!inputsValid(queries, covariances, cfg, error)) return {};
  const ProbabilisticMatcher matcher(landmarks, cfg);
  struct Pair {
    double log_density;
    int query;
    ProbabilisticMatch match;
  };
  std::vector<Pair> pairs;
  std::vector<ProbabilisticMatch> out(queries.size());
  const double log_ratio = cfg.ambiguity_ratio > 0.0 ? std::log(cfg.ambiguity_ratio) : 0.0;
  for (std::size_t i = 0; i < queries.size(); ++i) {
    const std::vector<ProbabilisticMatch> cands = matcher.candidates(queries[i], covariances[i]);
    if (cfg.ambiguity_ratio > 0.0 && cands.size() >= 2) {
      double best = -std::numeric_limits<double>::infinity(), second = best;
      for (const ProbabilisticMatch& m : cands) {
        if (m.log_density > best)
          second = best, best = m.log_density;
        else if (m.log_density > second)
          second = m.log_density;
      }
      if (second - best >= log_ratio) {
        out[i].ambiguous = true;
        continue;
      }
    }
    for (const ProbabilisticMatch& m : cands)
      pairs.push_back({m.log_density, static_cast<int>(i), m});
  }
  // Highest density first; ties broken by query then landmark index (deterministic).
  std::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) {
    if (a.log_density != b.log_density) return a.log_density > b.log_density;
    if (a.query != b.query) return a.query < b.query;
    return a.match.target < b.match.target;
  });
  std::vector<bool> taken(landmarks.size(), false);
  for (const Pair& p : pairs) {
    if (out[p.query].target >= 0 || taken[p.match.target]) continue;
    out[p.query] = p.match;
    taken[p.match.target] = true;
  }
  return out;
}

}  // namespace radar
}  // namespace coral_introspection
