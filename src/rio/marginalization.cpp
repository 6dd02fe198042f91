#include "coral_introspection/rio/marginalization.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <map>

#include "coral_introspection/rio/pose_manifold.hpp"

namespace coral_introspection {
namespace rio {

namespace {
// x [-] x0 in the tangent space of a block of `size` doubles.
Eigen::VectorXd boxMinus(const double* x, const Eigen::VectorXd& x0, int size) {
  Eigen::VectorXd d(tangentSize(size));
  if (size == 7)
    PoseManifold().Minus(x, x0.data(), d.data());
  else
    d = Eigen::Map<const Eigen::VectorXd>(x, size) - x0;
  return d;
}
}  // namespace

MarginalizationPrior::MarginalizationPrior(std::vector<double*> blocks, std::vector<int> sizes,
                                           std::vector<Eigen::VectorXd> x0, Eigen::VectorXd r0,
                                           Eigen::MatrixXd J)
    : blocks_(std::move(blocks)),
      sizes_(std::move(sizes)),
      x0_(std::move(x0)),
      r0_(std::move(r0)),
      J_(std::move(J)) {
  int off = 0;
  for (int s : sizes_) {
    offsets_.push_back(off);
    off += tangentSize(s);
    mutable_parameter_block_sizes()->push_back(s);
  }
  set_num_residuals(static_cast<int>(r0_.size()));
}

bool MarginalizationPrior::Evaluate(double const* const* parameters, double* residuals,
                                    double** jacobians) const {
  const int n = static_cast<int>(r0_.size());
  Eigen::VectorXd dx(J_.cols());
  for (std::size_t k = 0; k < blocks_.size(); ++k)
    dx.segment(offsets_[k], tangentSize(sizes_[k])) = boxMinus(parameters[k], x0_[k], sizes_[k]);
  Eigen::Map<Eigen::VectorXd> res(residuals, n);
  res = r0_ + J_ * dx;
  if (jacobians == nullptr) return true;
  for (std::size_t k = 0; k < blocks_.size(); ++k) {
    if (jacobians[k] == nullptr) continue;
    Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> Jk(
        jacobians[k], n, sizes_[k]);
    Jk.setZero();
    // The tangent Jacobian goes into the first columns (PoseManifold's convention). For
    // a pose this neglects d(Log)/d(dtheta) != I away from x0, as VINS-Mono does.
    Jk.leftCols(tangentSize(sizes_[k])) = J_.middleCols(offsets_[k], tangentSize(sizes_[k]));
  }
  return true;
}

void Marginalizer::add(std::shared_ptr<const ceres::CostFunction> cost,
                       std::shared_ptr<const ceres::LossFunction> loss,
                       std::vector<double*> blocks) {
  factors_.push_back({std::move(cost), std::move(loss), std::move(blocks)});
}

std::unique_ptr<MarginalizationPrior> Marginalizer::marginalize(const std::set<double*>& drop,
                                                                std::string* error) const {
  // Tangent layout: dropped blocks first (m), then kept blocks (n).
  // Blocks in order of first appearance (deterministic, unlike address order).
  std::map<double*, int> size_of;
  std::vector<double*> order;
  for (const Factor& f : factors_)
    for (std::size_t k = 0; k < f.blocks.size(); ++k)
      if (size_of.emplace(f.blocks[k], f.cost->parameter_block_sizes()[k]).second)
        order.push_back(f.blocks[k]);
  std::map<double*, int> offset;
  std::vector<double*> kept;
  int m = 0;
  for (double* ptr : order)
    if (drop.count(ptr)) offset[ptr] = m, m += tangentSize(size_of[ptr]);
  int n = 0;
  for (double* ptr : order)
    if (!drop.count(ptr)) offset[ptr] = m + n, n += tangentSize(size_of[ptr]), kept.push_back(ptr);
  if (n == 0) {
    if (error) *error = "marginalisation keeps no block";
    return nullptr;
  }

  // H = sum J^T J, b = sum J^T r (robust losses applied as Ceres' first-order corrector).
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(m + n, m + n);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(m + n);
  for (const Factor& f : factors_) {
    const int nr = f.cost->num_residuals();
    const std::size_t nb = f.blocks.size();
    Eigen::VectorXd r(nr);
    std::vector<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> J(nb);
    std::vector<double*> jac_ptrs(nb);
    for (std::size_t k = 0; k < nb; ++k) {
      J[k].resize(nr, f.cost->parameter_block_sizes()[k]);
      jac_ptrs[k] = J[k].data();
    }
    if (!f.cost->Evaluate(f.blocks.data(), r.data(), jac_ptrs.data())) {
      if (error) *error = "a factor failed to evaluate during marginalisation";
      return nullptr;
    }
    double scale = 1.0;
    if (f.loss) {
      double rho[3];
      f.loss->Evaluate(r.squaredNorm(), rho);
      scale = std::sqrt(std::max(rho[1], 0.0));
    }
    r *= scale;
    for (std::size_t a = 0; a < nb; ++a) {
      const int oa = offset[f.blocks[a]], ta = tangentSize(J[a].cols());
      const Eigen::MatrixXd Ja = scale * J[a].leftCols(ta);
      b.segment(oa, ta) += Ja.transpose() * r;
      for (std::size_t c = 0; c < nb; ++c) {
        const int oc = offset[f.blocks[c]], tc = tangentSize(J[c].cols());
        H.block(oa, oc, ta, tc) += Ja.transpose() * (scale * J[c].leftCols(tc));
      }
    }
  }

  // Schur complement onto the kept blocks by block Gaussian elimination, one dropped block
  // at a time (the result does not depend on the order); each step touches only the rows
  // coupled to that block, so many landmarks observed by few frames stay cheap.
  // Pseudo-inverses with an eigenvalue threshold keep unobserved directions harmless.
  const double eps = 1e-8;
  std::vector<char> alive(m + n, 1);
  for (double* ptr : order) {
    if (!drop.count(ptr)) continue;
    const int o = offset[ptr], sz = tangentSize(size_of[ptr]);
    std::vector<int> nz;
    for (int i = 0; i < m + n; ++i)
      if (alive[i] && (i < o || i >= o + sz) && H.block(i, o, 1, sz).cwiseAbs().maxCoeff() > 0.0)
        nz.push_back(i);
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(
        0.5 * (H.block(o, o, sz, sz) + H.block(o, o, sz, sz).transpose()));
    const Eigen::VectorXd inv =
        (es.eigenvalues().array() > eps).select(es.eigenvalues().array().inverse(), 0.0);
    const Eigen::MatrixXd Hdd_inv =
        es.eigenvectors() * inv.asDiagonal() * es.eigenvectors().transpose();
    Eigen::MatrixXd C(nz.size(), sz);
    for (std::size_t k = 0; k < nz.size(); ++k) C.row(k) = H.block(nz[k], o, 1, sz);
    const Eigen::MatrixXd CHi = C * Hdd_inv;
    const Eigen::MatrixXd update = CHi * C.transpose();
    const Eigen::VectorXd bu = CHi * b.segment(o, sz);
    for (std::size_t a = 0; a < nz.size(); ++a) {
      b(nz[a]) -= bu(a);
      for (std::size_t c = 0; c < nz.size(); ++c) H(nz[a], nz[c]) -= update(a, c);
    }
    for (int i = o; i < o + sz; ++i) alive[i] = 0;
  }
  const Eigen::MatrixXd A = H.bottomRightCorner(n, n);
  const Eigen::VectorXd bb = b.tail(n);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(0.5 * (A + A.transpose()));
  const Eigen::VectorXd S = (es.eigenvalues().array() > eps).select(es.eigenvalues().array(), 0.0);
  const Eigen::VectorXd S_sqrt = S.cwiseSqrt();
  const Eigen::VectorXd S_inv_sqrt =
      (S.array() > eps).select(S_sqrt.array().inverse(), 0.0).matrix();
  // J^T J = A and J^T r0 = bb: the prior reproduces the marginal's gradient and Hessian.
  Eigen::MatrixXd J = S_sqrt.asDiagonal() * es.eigenvectors().transpose();
  Eigen::VectorXd r0 = S_inv_sqrt.asDiagonal() * es.eigenvectors().transpose() * bb;
  if (!J.allFinite() || !r0.allFinite()) {
    if (error) *error = "marginalisation produced a non-finite prior";
    return nullptr;
  }

  std::vector<int> sizes;
  std::vector<Eigen::VectorXd> x0;
  for (double* p : kept) {
    sizes.push_back(size_of[p]);
    x0.push_back(Eigen::Map<const Eigen::VectorXd>(p, size_of[p]));
  }
  return std::make_unique<MarginalizationPrior>(kept, sizes, x0, r0, J);
}

}  // namespace rio
}  // namespace coral_introspection
