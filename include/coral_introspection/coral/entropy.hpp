// Per-point differential entropy of a local Gaussian (CorAl paper, Eq. 1 and Sec. III-C (1)).
#pragma once

#include "coral_introspection/coral/types.hpp"

namespace coral_introspection {
namespace coral {

// Running first and second moments of points centred on a query point, in Dim (2 or 3)
// dimensions. Centring on the query keeps the sums small (no catastrophic cancellation far
// from the origin) and lets the separate and joint neighbourhoods share work:
// joint = own + other. The 2D form accumulates 3 products instead of 9.
template <int Dim>
struct MomentsN {
  using V = Eigen::Matrix<double, Dim, 1>;
  double n = 0.0;
  V sum = V::Zero();                                                               // sum of (x - p)
  Eigen::Matrix<double, Dim, Dim> sum2 = Eigen::Matrix<double, Dim, Dim>::Zero();  // upper

  // Only the upper triangle of sum2 is accumulated (bit-identical to the full product: the
  // lower entries are the same products); covariance() mirrors it.
  void add(const V& d) {
    n += 1.0;
    sum += d;
    for (int i = 0; i < Dim; ++i)
      for (int j = i; j < Dim; ++j) sum2(i, j) += d(i) * d(j);
  }
  MomentsN& operator+=(const MomentsN& o) {
    n += o.n;
    sum += o.sum;
    sum2 += o.sum2;
    return *this;
  }
  // Unbiased sample covariance 1/(n-1) sum (x - mean)(x - mean)^T, the single estimator
  // used everywhere in the package (the reference code's integer n/(n-1) silently
  // evaluated to 1). Requires n >= 2. Embedded in a 3x3 (zeros) for the 2D form.
  Mat3 covariance() const {
    const V mean = sum / n;
    Mat3 c = Mat3::Zero();
    const Eigen::Matrix<double, Dim, Dim> s2 = sum2.template selfadjointView<Eigen::Upper>();
    c.template topLeftCorner<Dim, Dim>() = (s2 - n * mean * mean.transpose()) / (n - 1.0);
    return c;
  }
};
using Moments = MomentsN<3>;

// Differential entropy of N(mu, Sigma) in nats, restricted to the first `dim` (2 or 3)
// coordinates: h = 1/2 ln((2 pi e)^N det Sigma)  (Eq. 1).
// det is the product of the symmetric matrix's eigenvalues (their logarithms summed when
// it would underflow), never Sigma.determinant().
// epsilon > 0 is option (1) of Sec. III-C: the determinant is floored as det + epsilon, so
// h >= 1/2 ln((2 pi e)^N epsilon) and lines / planes stay finite.
// Returns false (h untouched) when Sigma is not finite, when the points coincide (zero
// covariance, whatever epsilon: no usable covariance), or when Sigma is
// singular / ill-conditioned (smallest eigenvalue <= 1e-12 * largest) and epsilon == 0.
bool differentialEntropy(const Mat3& sigma, int dim, double epsilon, double* h);

// Entropy of the whole point set (all points are one neighbourhood). Used by tests and
// tools; false for fewer than dim + 1 points or a degenerate set.
bool entropyOfPoints(const Points& pts, int dim, double epsilon, double* h);

}  // namespace coral
}  // namespace coral_introspection
