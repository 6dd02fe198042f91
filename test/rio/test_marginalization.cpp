// Marginalisation: on a linear problem, solving the reduced problem (prior + remaining
// factors) gives exactly the full problem's solution for the remaining variables.
#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <random>

#include "coral_introspection/rio/marginalization.hpp"
#include "coral_introspection/rio/pose_manifold.hpp"
#include "rio/rio_test_utils.hpp"

using namespace coral_introspection::rio;

namespace {
// r = W (A x_a + B x_b - c) over two 2-D blocks (B empty for a unary factor).
class Linear : public ceres::CostFunction {
 public:
  Linear(Eigen::Matrix2d A, Eigen::Matrix2d B, Eigen::Vector2d c, bool binary)
      : A_(A), B_(B), c_(c), binary_(binary) {
    set_num_residuals(2);
    mutable_parameter_block_sizes()->push_back(2);
    if (binary) mutable_parameter_block_sizes()->push_back(2);
  }
  bool Evaluate(double const* const* x, double* r, double** J) const override {
    Eigen::Vector2d e = A_ * Eigen::Map<const Eigen::Vector2d>(x[0]) - c_;
    if (binary_) e += B_ * Eigen::Map<const Eigen::Vector2d>(x[1]);
    Eigen::Map<Eigen::Vector2d> res(r);
    res = e;
    using Mat22 = Eigen::Matrix<double, 2, 2, Eigen::RowMajor>;
    if (J && J[0]) Eigen::Map<Mat22>{J[0]} = A_;
    if (J && binary_ && J[1]) Eigen::Map<Mat22>{J[1]} = B_;
    return true;
  }

 private:
  Eigen::Matrix2d A_, B_;
  Eigen::Vector2d c_;
  bool binary_;
};

struct Problem {
  std::vector<std::shared_ptr<Linear>> factors;
  std::vector<std::vector<int>> vars;
};

Problem makeProblem() {
  // A chain x0 - x1 - x2 - x3 with a loop x0 - x2 and absolute factors on x0 and x3.
  std::mt19937 rng(3);
  std::normal_distribution<double> g;
  auto M = [&] {
    Eigen::Matrix2d m;
    m << 1 + 0.3 * g(rng), 0.3 * g(rng), 0.3 * g(rng), 1 + 0.3 * g(rng);
    return m;
  };
  auto V = [&] { return Eigen::Vector2d(g(rng), g(rng)); };
  Problem p;
  p.factors.push_back(std::make_shared<Linear>(M(), Eigen::Matrix2d::Zero(), V(), false));
  p.vars.push_back({0});
  for (auto [a, b] : std::vector<std::pair<int, int>>{{0, 1}, {1, 2}, {2, 3}, {0, 2}}) {
    p.factors.push_back(std::make_shared<Linear>(M(), -M(), V(), true));
    p.vars.push_back({a, b});
  }
  p.factors.push_back(std::make_shared<Linear>(M(), Eigen::Matrix2d::Zero(), V(), false));
  p.vars.push_back({3});
  return p;
}

void solve(ceres::Problem* problem) {
  ceres::Solver::Options o;
  o.linear_solver_type = ceres::DENSE_QR;
  o.function_tolerance = o.gradient_tolerance = o.parameter_tolerance = 1e-15;
  ceres::Solver::Summary s;
  ceres::Solve(o, problem, &s);
}
}  // namespace

TEST(Marginalization, LinearProblemKeepsTheSolution) {
  const Problem p = makeProblem();
  ceres::Problem::Options po;
  po.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  // Full problem.
  std::vector<Eigen::Vector2d> full(4, Eigen::Vector2d::Zero());
  {
    ceres::Problem problem(po);
    for (std::size_t f = 0; f < p.factors.size(); ++f) {
      std::vector<double*> blocks;
      for (int v : p.vars[f]) blocks.push_back(full[v].data());
      problem.AddResidualBlock(p.factors[f].get(), nullptr, blocks);
    }
    solve(&problem);
  }
  // Marginalise x0 at an arbitrary linearisation point (linear: the point does not matter).
  std::vector<Eigen::Vector2d> red = {Eigen::Vector2d(0.3, -1.0), Eigen::Vector2d(2.0, 1.0),
                                      Eigen::Vector2d(-1.0, 0.5), Eigen::Vector2d(0.0, 0.0)};
  Marginalizer marg;
  for (std::size_t f = 0; f < p.factors.size(); ++f) {
    const auto& vs = p.vars[f];
    if (std::find(vs.begin(), vs.end(), 0) == vs.end()) continue;
    std::vector<double*> blocks;
    for (int v : vs) blocks.push_back(red[v].data());
    marg.add(p.factors[f], nullptr, blocks);
  }
  std::string err;
  auto prior = marg.marginalize({red[0].data()}, &err);
  ASSERT_TRUE(prior) << err;
  EXPECT_EQ(prior->blocks().size(), 2u);  // x1 and x2
  ceres::Problem problem(po);
  problem.AddResidualBlock(prior.get(), nullptr, prior->blocks());
  for (std::size_t f = 0; f < p.factors.size(); ++f) {
    const auto& vs = p.vars[f];
    if (std::find(vs.begin(), vs.end(), 0) != vs.end()) continue;
    std::vector<double*> blocks;
    for (int v : vs) blocks.push_back(red[v].data());
    problem.AddResidualBlock(p.factors[f].get(), nullptr, blocks);
  }
  solve(&problem);
  for (int v = 1; v < 4; ++v) EXPECT_LT((red[v] - full[v]).norm(), 1e-9) << "x" << v;
}

TEST(Marginalization, PriorJacobianAndPoseBlocks) {
  // A pose block kept by the prior: the prior's Jacobian matches central differences at
  // its linearisation point and its residual there equals r0.
  double pose[7] = {1, 2, 3, 0, 0, 0, 1};
  Eigen::Map<Quat> q(pose + 3);
  q = expQ(Vec3(0.1, 0.2, 0.3));
  Eigen::VectorXd x0a = Eigen::Map<Eigen::VectorXd>(pose, 7);
  Eigen::MatrixXd J = Eigen::MatrixXd::Random(6, 6);
  Eigen::VectorXd r0 = Eigen::VectorXd::Random(6);
  MarginalizationPrior prior({pose}, {7}, {x0a}, r0, J);
  double const* params[] = {pose};
  Eigen::VectorXd r(6);
  prior.Evaluate(params, r.data(), nullptr);
  EXPECT_LT((r - r0).norm(), 1e-12);
  EXPECT_LT(rio_test::jacobianError(prior, {pose}), 1e-6);
}
