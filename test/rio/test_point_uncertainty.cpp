// The point covariance and Doppler weight under the ablations of Table I (Sec. IV-B: the
// removed part's sigma set "to a very small value"), checked on a point on the boresight
// where Eq. 8 is diagonal: diag(sigma_r^2, r^2 sigma_az^2, r^2 sigma_el^2).
#include <gtest/gtest.h>

#include "coral_introspection/rio/point_uncertainty.hpp"

namespace rio = coral_introspection::rio;

namespace {

rio::UncertaintyConfig config(rio::UncertaintyMode mode, bool replace = false) {
  rio::UncertaintyConfig c;
  c.mode = mode;
  c.noise = {0.1, 0.01, 0.02};
  c.isotropic_sigma = 0.2;
  c.ablation_replace = replace;
  c.ablation_shrink = 1e-3;
  return c;
}

void expectDiagonal(const rio::Mat3& S, double a, double b, double c) {
  EXPECT_NEAR(S(0, 0), a, 1e-12 + 1e-9 * a);
  EXPECT_NEAR(S(1, 1), b, 1e-12 + 1e-9 * b);
  EXPECT_NEAR(S(2, 2), c, 1e-12 + 1e-9 * c);
  EXPECT_NEAR((S - rio::Mat3(S.diagonal().asDiagonal())).norm(), 0.0, 1e-12);
}

}  // namespace

TEST(PointUncertainty, AblationsFollowTheMeaningOfEachRow) {
  using M = rio::UncertaintyMode;
  const rio::Vec3 p(10, 0, 0);  // r = 10 m on the boresight
  expectDiagonal(rio::pointCovariance(p, config(M::kFull)), 0.01, 0.01, 0.04);
  // The paper: the removed sigma becomes 1e-3 of itself, the other part stays.
  expectDiagonal(rio::pointCovariance(p, config(M::kNoRange)), 1e-8, 0.01, 0.04);
  expectDiagonal(rio::pointCovariance(p, config(M::kNoBearing)), 0.01, 1e-8, 4e-8);
  // The package's variant: the removed part replaced by the isotropic sigma (0.2 m).
  expectDiagonal(rio::pointCovariance(p, config(M::kNoRange, true)), 0.04, 0.01, 0.04);
  expectDiagonal(rio::pointCovariance(p, config(M::kNoBearing, true)), 0.01, 0.04, 0.04);
  expectDiagonal(rio::pointCovariance(p, config(M::kNone)), 0.04, 0.04, 0.04);
  rio::UncertaintyConfig scaled = config(M::kNoRange);
  scaled.covariance_scale = 4.0;  // Table II scales whatever the row uses
  expectDiagonal(rio::pointCovariance(p, scaled), 4e-8, 0.04, 0.16);
}

TEST(PointUncertainty, DopplerWeightDependsOnlyOnTheBearingPart) {
  using M = rio::UncertaintyMode;
  const rio::Vec3 p(10, 0, 0);
  const rio::Vec3 v(1.0, 2.0, 0.0);  // 2 m/s across the beam: bearing noise matters
  const rio::UncertaintyConfig full = config(M::kFull);
  const double sd2 = full.sigma_doppler * full.sigma_doppler;
  // d(d^T v)/d(azimuth) = v_y = 2 m/s: variance sigma_doppler^2 + (2 * 0.01)^2.
  EXPECT_NEAR(rio::dopplerVariance(p, v, full), sd2 + 4e-4, 1e-9);
  // Range noise moves the point along its bearing: no change of the Doppler weight.
  EXPECT_NEAR(rio::dopplerVariance(p, v, config(M::kNoRange)), sd2 + 4e-4, 1e-9);
  // Without the bearing part only the Doppler floor is left (a constant weight).
  EXPECT_NEAR(rio::dopplerVariance(p, v, config(M::kNoBearing)), sd2, 1e-9);
  EXPECT_NEAR(rio::dopplerVariance(p, v, config(M::kNone)), 0.01, 1e-12);
}
