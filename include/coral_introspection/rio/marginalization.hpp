// Marginalisation of the oldest window state into a Gaussian prior (Schur complement of
// the linearised factors that touch it), instead of holding that state constant as the
// authors' code does. Parameter blocks are identified by their address; a block of 7
// doubles is a pose (PoseManifold, tangent 6), any other block is Euclidean.
#pragma once

#include <ceres/cost_function.h>
#include <ceres/loss_function.h>

#include <Eigen/Core>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace coral_introspection {
namespace rio {

// Tangent size of a block of `size` doubles (7 -> 6, else size).
inline int tangentSize(int size) { return size == 7 ? 6 : size; }

// The prior left by a marginalisation: r(x) = r0 + J (x [-] x0) over the kept blocks,
// [-] being the manifold difference. A plain (not owned) cost function for Ceres.
class MarginalizationPrior : public ceres::CostFunction {
 public:
  MarginalizationPrior(std::vector<double*> blocks, std::vector<int> sizes,
                       std::vector<Eigen::VectorXd> x0, Eigen::VectorXd r0, Eigen::MatrixXd J);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;
  const std::vector<double*>& blocks() const { return blocks_; }

 private:
  std::vector<double*> blocks_;
  std::vector<int> sizes_, offsets_;  // ambient sizes, tangent offsets into J's columns
  std::vector<Eigen::VectorXd> x0_;
  Eigen::VectorXd r0_;
  Eigen::MatrixXd J_;
};

class Marginalizer {
 public:
  // Adds one factor evaluated at the blocks' current values. loss may be null.
  void add(std::shared_ptr<const ceres::CostFunction> cost,
           std::shared_ptr<const ceres::LossFunction> loss, std::vector<double*> blocks);
  // Schur-complements the blocks in `drop` out of the added factors. Returns the prior on
  // every other block, or nullptr with *error when nothing is kept or it fails.
  std::unique_ptr<MarginalizationPrior> marginalize(const std::set<double*>& drop,
                                                    std::string* error) const;

 private:
  struct Factor {
    std::shared_ptr<const ceres::CostFunction> cost;
    std::shared_ptr<const ceres::LossFunction> loss;
    std::vector<double*> blocks;
  };
  std::vector<Factor> factors_;
};

}  // namespace rio
}  // namespace coral_introspection
