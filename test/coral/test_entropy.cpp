// Differential entropy (Eq. 1) against analytic Gaussians and degenerate inputs.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "coral_introspection/coral/entropy.hpp"

using namespace coral_introspection::coral;

namespace {
double analyticEntropy(const Mat3& S, int dim) {
  const double det = dim == 2 ? S.topLeftCorner<2, 2>().determinant() : S.determinant();
  return 0.5 * std::log(std::pow(2.0 * M_PI * M_E, dim) * det);
}

Points sampleGaussian(const Mat3& S, int n, int dim, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  const Mat3 L = S.llt().matrixL();
  Points pts;
  for (int i = 0; i < n; ++i) {
    Vec3 p = L * Vec3(g(rng), g(rng), g(rng)) + Vec3(100.0, -50.0, 20.0);  // far from 0
    if (dim == 2) p.z() = 0.0;
    pts.push_back(p);
  }
  return pts;
}
}  // namespace

TEST(Entropy, KnownGaussian3DWithinTwoPercent) {
  Mat3 S;
  S << 2.0, 0.3, 0.1, 0.3, 1.0, -0.2, 0.1, -0.2, 0.5;
  for (unsigned seed : {1u, 2u, 3u}) {
    double h = 0.0;
    ASSERT_TRUE(entropyOfPoints(sampleGaussian(S, 2000, 3, seed), 3, 0.0, &h));
    const double expected = analyticEntropy(S, 3);
    EXPECT_NEAR(h, expected, 0.02 * std::abs(expected)) << "seed " << seed;
  }
}

TEST(Entropy, KnownGaussian2DWithinTwoPercent) {
  Mat3 S = Mat3::Identity();
  S.topLeftCorner<2, 2>() << 3.0, 0.8, 0.8, 1.5;
  double h = 0.0;
  ASSERT_TRUE(entropyOfPoints(sampleGaussian(S, 2000, 2, 7), 2, 0.0, &h));
  const double expected = analyticEntropy(S, 2);
  EXPECT_NEAR(h, expected, 0.02 * std::abs(expected));
}

TEST(Entropy, MatchesClosedFormForDiagonalCovariance) {
  Mat3 S = Vec3(0.01, 0.04, 0.09).asDiagonal();
  double h = 0.0;
  ASSERT_TRUE(differentialEntropy(S, 3, 0.0, &h));
  EXPECT_NEAR(h, analyticEntropy(S, 3), 1e-12);
  // A tiny but well-conditioned covariance: log(det) of the product would underflow in
  // float, the eigenvalue sum of logs does not.
  Mat3 tiny = Vec3(1e-60, 2e-60, 3e-60).asDiagonal();
  ASSERT_TRUE(differentialEntropy(tiny, 3, 0.0, &h));
  EXPECT_NEAR(h, 0.5 * (3 * std::log(2 * M_PI * M_E) + std::log(6e-180)), 1e-9);
}

TEST(Entropy, DegenerateNeighbourhoodsAreExcludedOrFloored) {
  Points line, plane;
  for (int i = 0; i < 20; ++i) line.push_back(Vec3(i * 0.1, 2 * i * 0.1, 3 * i * 0.1));
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) plane.push_back(Vec3(i * 0.1, j * 0.1, 1.0));
  double h = 123.0;
  EXPECT_FALSE(entropyOfPoints(line, 3, 0.0, &h));
  EXPECT_FALSE(entropyOfPoints(plane, 3, 0.0, &h));
  EXPECT_FALSE(entropyOfPoints(line, 2, 0.0, &h));  // collinear in 2D too
  EXPECT_EQ(h, 123.0);
  // Epsilon floor (Sec. III-C option 1): finite and exactly the floor value.
  const double eps = 1e-8;
  ASSERT_TRUE(entropyOfPoints(plane, 3, eps, &h));
  EXPECT_NEAR(h, 0.5 * (3 * std::log(2 * M_PI * M_E) + std::log(eps)), 1e-9);
  // Floor never lowers a well-conditioned entropy.
  Mat3 S = Mat3::Identity();
  double h0 = 0.0, h1 = 0.0;
  ASSERT_TRUE(differentialEntropy(S, 3, 0.0, &h0));
  ASSERT_TRUE(differentialEntropy(S, 3, eps, &h1));
  EXPECT_GE(h1, h0);
  EXPECT_NEAR(h1, h0, 1e-7);
}

TEST(Entropy, TooFewOrNonFinitePointsGiveNoResult) {
  double h = 0.0;
  EXPECT_FALSE(entropyOfPoints({}, 3, 0.0, &h));
  EXPECT_FALSE(entropyOfPoints({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}, 3, 0.0, &h));
  Points with_nan = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1),
                     Vec3(std::numeric_limits<double>::quiet_NaN(), 0, 0)};
  EXPECT_FALSE(entropyOfPoints(with_nan, 3, 0.0, &h));
  Mat3 inf = Mat3::Identity();
  inf(1, 1) = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(differentialEntropy(inf, 3, 1e-8, &h));
}
