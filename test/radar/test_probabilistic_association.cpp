// Probability-guided association (Eq. 13-14) versus Euclidean nearest neighbour.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "coral_introspection/radar/probabilistic_association.hpp"
#include "coral_introspection/radar/radar_uncertainty.hpp"

using namespace coral_introspection::coral;
using namespace coral_introspection::radar;

namespace {
RadarNoiseConfig noise(double sigma_range, double sigma_azimuth) {
  RadarNoiseConfig c;
  c.sigma_range = sigma_range;
  c.sigma_azimuth = sigma_azimuth;
  return c;
}
}  // namespace

// Figure 3: p_k at 10 m on the x axis; its ellipse is thin along the beam (x) and wide
// across it (y). l_q is closer but along the beam, l_p farther but across it.
TEST(ProbabilisticAssociation, Figure3FartherPointAlongHighUncertaintyAxisWins) {
  const Vec3 p(10.0, 0.0, 0.0);
  const Mat3 S = pointCovariance(p, noise(0.1, 0.02), 2);  // sigma 0.1 m along, 0.2 m across
  const Points landmarks = {Vec3(10.25, 0.0, 0.0),         // l_q: 0.25 m, 2.5 sigma
                            Vec3(10.0, 0.4, 0.0)};         // l_p: 0.40 m, 2.0 sigma
  ASSERT_LT((landmarks[0] - p).norm(), (landmarks[1] - p).norm());  // Euclidean: l_q
  ProbabilisticAssociationConfig cfg;
  const ProbabilisticMatcher matcher(landmarks, cfg);
  const ProbabilisticMatch m = matcher.match(p, S);
  EXPECT_EQ(m.target, 1);
  EXPECT_NEAR(m.mahalanobis2, 4.0, 1e-9);
  // Both candidates pass the gate here; the density of l_p is the larger one (Eq. 14).
  double m2_q = 0.0;
  const double ld_q = gaussianLogDensity(landmarks[0], p, S, 2, cfg.min_variance, &m2_q);
  EXPECT_NEAR(m2_q, 6.25, 1e-9);
  EXPECT_GT(m.log_density, ld_q);
  EXPECT_NEAR(m.log_density, gaussianLogDensity(landmarks[1], p, S, 2, cfg.min_variance), 1e-12);
}

TEST(ProbabilisticAssociation, ThreeSigmaGateRejectsOutliers) {
  const Vec3 p(0.0, 20.0, 0.0);                             // beam along y now
  const Mat3 S = pointCovariance(p, noise(0.05, 0.01), 2);  // 0.05 m along, 0.2 m across
  ProbabilisticAssociationConfig cfg;
  std::string err;
  // 0.2 m along the beam is 4 sigma: outside the gate although it is the only candidate.
  auto m = associateProbabilistic({p}, {S}, {Vec3(0.0, 20.2, 0.0)}, cfg, &err);
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].target, -1);
  // 0.5 m across is 2.5 sigma: accepted.
  m = associateProbabilistic({p}, {S}, {Vec3(0.5, 20.0, 0.0)}, cfg, &err);
  EXPECT_EQ(m[0].target, 0);
}

TEST(ProbabilisticAssociation, ThreeDimensionalAndNonFiniteLandmarks) {
  RadarNoiseConfig c = noise(0.05, 0.01);
  c.sigma_elevation = 0.03;
  const Vec3 p(5.0, 5.0, 2.0);
  const Mat3 S = pointCovariance(p, c, 3);
  const Vec3 beam = p.normalized();
  const Vec3 across = beam.cross(Vec3::UnitZ()).normalized();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Points landmarks = {Vec3(nan, 0, 0), p + 0.12 * beam, p + 0.15 * across};
  ProbabilisticAssociationConfig cfg;
  cfg.dimension = 3;
  std::string err;
  const auto m = associateProbabilistic({p}, {S}, landmarks, cfg, &err);
  ASSERT_EQ(m.size(), 1u) << err;
  EXPECT_EQ(m[0].target, 2);  // original index kept despite the NaN landmark
}

TEST(ProbabilisticAssociation, RefusesBadInput) {
  ProbabilisticAssociationConfig cfg;
  std::string err;
  EXPECT_TRUE(associateProbabilistic({Vec3::Zero()}, {}, {Vec3::Zero()}, cfg, &err).empty());
  EXPECT_NE(err.find("covariances"), std::string::npos);
  cfg.gate_sigma = -1.0;
  EXPECT_NE(cfg.validate().find("gate_sigma"), std::string::npos);
}
