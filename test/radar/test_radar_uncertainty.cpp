// Polar measurement model (Eq. 3-8) against a Monte Carlo propagation of polar noise.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "coral_introspection/coral/entropy.hpp"
#include "coral_introspection/radar/radar_uncertainty.hpp"

using namespace coral_introspection::coral;
using namespace coral_introspection::radar;

namespace {

Vec3 polarToCartesian(double r, double az, double el) {
  return r * Vec3(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
}

// Sample covariance of 1e5 points drawn from Gaussian polar noise around (r, az, el).
Mat3 monteCarlo(double r, double az, double el, const RadarNoiseConfig& c, int dim, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  Moments m;
  const Vec3 p0 = polarToCartesian(r, az, dim == 2 ? 0.0 : el);
  for (int i = 0; i < 100000; ++i) {
    const double de = dim == 2 ? 0.0 : c.sigma_elevation * g(rng);
    m.add(polarToCartesian(r + c.sigma_range * g(rng), az + c.sigma_azimuth * g(rng),
                           (dim == 2 ? 0.0 : el) + de) -
          p0);
  }
  return m.covariance();
}

double relFrobenius(const Mat3& model, const Mat3& mc) { return (model - mc).norm() / mc.norm(); }

RadarNoiseConfig testNoise() {
  RadarNoiseConfig c;
  c.sigma_range = 0.05;
  c.sigma_azimuth = 0.01;
  c.sigma_elevation = 0.02;
  return c;
}

}  // namespace

TEST(RadarUncertainty, Matches3DMonteCarloIncludingOffAxisElevation) {
  const RadarNoiseConfig c = testNoise();
  unsigned seed = 1;
  for (double r : {2.0, 10.0, 40.0})
    for (double az : {0.0, 0.7, 2.5, -1.9})
      for (double el : {0.0, 0.35, -0.6}) {
        const Vec3 p = polarToCartesian(r, az, el);
        const Mat3 mc = monteCarlo(r, az, el, c, 3, seed++);
        EXPECT_LT(relFrobenius(pointCovariance(p, c, 3), mc), 0.03)
            << "r " << r << " az " << az << " el " << el;
      }
}

TEST(RadarUncertainty, Matches2DMonteCarlo) {
  const RadarNoiseConfig c = RadarNoiseConfig::oxfordCts350x();
  unsigned seed = 100;
  for (double r : {3.0, 25.0, 120.0})
    for (double az : {0.0, 1.2, -2.8}) {
      const Mat3 model = pointCovariance(polarToCartesian(r, az, 0.0), c, 2);
      const Mat3 mc = monteCarlo(r, az, 0.0, c, 2, seed++);
      EXPECT_LT(relFrobenius(model, mc), 0.03) << "r " << r << " az " << az;
      EXPECT_EQ(model.row(2).norm(), 0.0);
    }
}

TEST(RadarUncertainty, FlippedDzDphiSignIsCaught) {
  // The authors' slip: dz/dphi with the wrong sign. Off-axis it changes the x-z / y-z
  // correlations enough for the Monte Carlo comparison to fail.
  const RadarNoiseConfig c = testNoise();
  const double r = 10.0, az = 0.7, el = 0.35;
  const Vec3 p = polarToCartesian(r, az, el);
  Mat3 A = polarJacobian(p);
  A(2, 2) = -A(2, 2);
  const Vec3 var(c.sigma_range * c.sigma_range, c.sigma_azimuth * c.sigma_azimuth,
                 c.sigma_elevation * c.sigma_elevation);
  const Mat3 wrong = A * var.asDiagonal() * A.transpose();
  const Mat3 mc = monteCarlo(r, az, el, c, 3, 7);
  EXPECT_GT(relFrobenius(wrong, mc), 0.3);
  EXPECT_LT(relFrobenius(pointCovariance(p, c, 3), mc), 0.03);
}

TEST(RadarUncertainty, SmallAlongBeamLargeAcross) {
  const RadarNoiseConfig c = RadarNoiseConfig::oxfordCts350x();
  const Vec3 p(30.0, 40.0, 0.0);  // r = 50 m
  const Mat3 S = pointCovariance(p, c, 2);
  const Vec3 beam = p.normalized(), across(-beam.y(), beam.x(), 0.0);
  EXPECT_NEAR(beam.dot(S * beam), c.sigma_range * c.sigma_range, 1e-12);
  EXPECT_NEAR(std::sqrt(across.dot(S * across)), 50.0 * c.sigma_azimuth, 1e-9);
}

TEST(RadarUncertainty, AttachAndTransformRotateCovariances) {
  Scan s;
  s.points = {Vec3(10.0, 0.0, 0.0), Vec3(0.0, 20.0, 0.0),
              Vec3(std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0)};
  std::string err;
  ASSERT_TRUE(attachCovariances(s, RadarNoiseConfig::oxfordCts350x(), 2, &err)) << err;
  ASSERT_EQ(s.covariances.size(), 3u);
  EXPECT_FALSE(s.covariances[2].allFinite());
  const Scan t = transformScan(s, se2(5.0, -3.0, M_PI / 2));
  // The first point's beam was x; after a +90 deg yaw it is y: small variance along y.
  EXPECT_NEAR(t.covariances[0](1, 1), s.covariances[0](0, 0), 1e-12);
  EXPECT_NEAR(t.covariances[0](0, 0), s.covariances[0](1, 1), 1e-12);
  EXPECT_FALSE(attachCovariances(s, RadarNoiseConfig::oxfordCts350x(), 4, &err));
  RadarNoiseConfig bad;
  bad.sigma_range = -1.0;
  EXPECT_FALSE(attachCovariances(s, bad, 2, &err));
  EXPECT_NE(err.find("sigma_range"), std::string::npos);
}

TEST(RadarUncertainty, PresetsAreValid) {
  EXPECT_EQ(RadarNoiseConfig::oxfordCts350x().validate(), "");
  EXPECT_EQ(RadarNoiseConfig::tiAwr1843().validate(), "");
  EXPECT_EQ(RadarNoiseConfig::vodZfFrgen21().validate(), "");
  EXPECT_NEAR(RadarNoiseConfig::oxfordCts350x().sigma_range, 0.0144, 1e-12);
}
