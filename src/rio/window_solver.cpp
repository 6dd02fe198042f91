// The window problem of Eq. 2: building it from the window frames, the landmark tracks
// and the prior; solving it; checking the solution; sliding the window.
#include <ceres/ceres.h>

#include <chrono>
#include <cmath>
#include <map>
#include <set>

#include "coral_introspection/rio/barometer.hpp"
#include "coral_introspection/rio/estimator.hpp"
#include "coral_introspection/rio/imu_factor.hpp"
#include "coral_introspection/rio/point_uncertainty.hpp"
#include "coral_introspection/rio/pose_manifold.hpp"
#include "coral_introspection/rio/prior_factors.hpp"
#include "window_frame.hpp"

namespace coral_introspection {
namespace rio {

namespace {
PoseManifold* poseManifold() {
  static PoseManifold m;  // stateless; shared by every problem (not owned by Ceres)
  return &m;
}
}  // namespace

std::vector<Estimator::FactorRef> Estimator::unaryFactors(const WindowFrame& f) const {
  std::vector<FactorRef> out = dopplerFactors(f);
  double* pose = const_cast<double*>(f.x.pose);
  double* sb = const_cast<double*>(f.x.speed_bias);
  if (f.standing)
    out.push_back(
        {std::make_shared<ZeroVelocityFactor>(cfg_.zero_velocity.sigma_velocity), nullptr, {sb}});
  if (f.gyro_still)
    out.push_back({std::make_shared<GyroBiasFactor>(f.gyro_mean, f.gyro_sigma), nullptr, {sb}});
  if (f.has_baro)
    out.push_back({std::make_shared<BaroFactor>(f.baro_height, f.baro_dt, f.baro_sigma),
                   nullptr,
                   {pose, sb, const_cast<double*>(f.baro_bias)}});
  return out;
}

Estimator::FactorRef Estimator::imuFactor(const WindowFrame& prev, const WindowFrame& f) const {
  return {std::make_shared<ImuFactor>(f.pre.get()),
          nullptr,
          {const_cast<double*>(prev.x.pose), const_cast<double*>(prev.x.speed_bias),
           const_cast<double*>(f.x.pose), const_cast<double*>(f.x.speed_bias)}};
}

void Estimator::trackFactors(const Track& t, std::vector<FactorRef>* out) const {
  for (const Observation& o : t.obs)
    for (const auto& f : window_)
      if (f->id == o.frame) out->push_back(pointFactor(o, *f, t.position));
}

std::vector<Estimator::FactorRef> Estimator::pointFactors(int* count) const {
  std::vector<FactorRef> out;
  if (!cfg_.solver.use_points) return out;
  for (const auto& [id, t] : tracks_.all())
    if (t.landmark || t.fixed) trackFactors(t, &out);
  *count = static_cast<int>(out.size());
  return out;
}

bool Estimator::solve(FrameReport* report) {
  for (std::size_t k = 1; k < window_.size(); ++k) {  // keep the bias linearisation valid
    Preintegration& pre = *window_[k]->pre;
    const NavState s = window_[k - 1]->state();
    if ((s.ba - pre.linearizedBa()).norm() > 0.1 || (s.bg - pre.linearizedBg()).norm() > 0.01)
      pre.repropagate(s.ba, s.bg);
  }
  ceres::Problem::Options po;
  po.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  std::vector<FactorRef> factors;
  for (std::size_t k = 0; k < window_.size(); ++k) {
    WindowFrame& f = *window_[k];
    problem.AddParameterBlock(f.x.pose, 7, poseManifold());
    problem.AddParameterBlock(f.x.speed_bias, 9);
    if (f.has_baro_bias) problem.AddParameterBlock(f.baro_bias, 1);
    FactorRef walk;
    if (k > 0) factors.push_back(imuFactor(*window_[k - 1], f));
    if (k > 0 && baroWalkFactor(*window_[k - 1], f, &walk)) factors.push_back(std::move(walk));
    if (cfg_.solver.use_doppler)  // one Doppler residual per static point
      report->doppler_residuals += static_cast<int>(f.static_points.size());
    for (FactorRef& r : unaryFactors(f)) factors.push_back(std::move(r));
  }
  for (FactorRef& r : pointFactors(&report->point_residuals)) factors.push_back(std::move(r));
  if (prior_) factors.push_back({prior_, nullptr, prior_blocks_});
  addTimeOffset(&problem, &factors);
  for (const FactorRef& r : factors) problem.AddResidualBlock(r.cost.get(), r.loss.get(), r.blocks);
  if (!prior_) {  // the authors' scheme: the oldest state is held constant
    problem.SetParameterBlockConstant(window_.front()->x.pose);
    problem.SetParameterBlockConstant(window_.front()->x.speed_bias);
  }
  for (auto& [id, t] : tracks_.all())
    if (t.fixed && problem.HasParameterBlock(t.position.data()))
      problem.SetParameterBlockConstant(t.position.data());

  ceres::Solver::Options opt;
  opt.linear_solver_type = ceres::DENSE_SCHUR;
  opt.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  opt.max_num_iterations = cfg_.solver.max_iterations;
  opt.max_solver_time_in_seconds = cfg_.solver.max_solver_time;
  opt.num_threads = 1;
  opt.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  const auto t0 = std::chrono::steady_clock::now();
  ceres::Solve(opt, &problem, &summary);
  report->solve_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  report->iterations = static_cast<int>(summary.iterations.size());
  report->final_cost = summary.final_cost;
  if (!summary.IsSolutionUsable()) return false;

  if (compute_covariance_) {
    ceres::Covariance::Options co;
    co.algorithm_type = ceres::SPARSE_QR;
    co.num_threads = 1;
    ceres::Covariance cov(co);
    double* pose = window_.back()->x.pose;
    double* sb = window_.back()->x.speed_bias;
    std::vector<std::pair<const double*, const double*>> blocks = {
        {pose, pose}, {pose, sb}, {sb, sb}};
    if (cov.Compute(blocks, &problem)) {
      Eigen::Matrix<double, 6, 6, Eigen::RowMajor> pp;
      Eigen::Matrix<double, 6, 9, Eigen::RowMajor> ps;
      Eigen::Matrix<double, 9, 9, Eigen::RowMajor> ss;
      cov.GetCovarianceBlockInTangentSpace(pose, pose, pp.data());
      cov.GetCovarianceBlockInTangentSpace(pose, sb, ps.data());
      cov.GetCovarianceBlockInTangentSpace(sb, sb, ss.data());
      report->covariance << pp, ps, ps.transpose(), ss;
      report->has_covariance = true;
    }
  }
  return true;
}

std::string Estimator::checkHealth(const NavState& predicted) const {
  for (const auto& f : window_) {
    const NavState s = f->state();
    if (!s.p.allFinite() || !s.q.coeffs().allFinite() || !s.v.allFinite() || !s.ba.allFinite() ||
        !s.bg.allFinite() || !std::isfinite(f->baro_bias[0]) || !std::isfinite(td_[0]))
      return "non-finite state after the solve";
  }
  const NavState s = window_.back()->state();
  const HealthConfig& h = cfg_.health;
  auto fmt = [](const char* what, double value, double limit) {
    return std::string("diverged: ") + what + " " + std::to_string(value) + " > " +
           std::to_string(limit);
  };
  if (s.v.norm() > h.max_speed) return fmt("speed [m/s]", s.v.norm(), h.max_speed);
  if (s.ba.norm() > h.max_acc_bias) return fmt("|b_a| [m/s^2]", s.ba.norm(), h.max_acc_bias);
  if (s.bg.norm() > h.max_gyro_bias) return fmt("|b_g| [rad/s]", s.bg.norm(), h.max_gyro_bias);
  const double jump = (s.p - predicted.p).norm();
  if (jump > h.max_correction)
    return fmt("correction of the IMU prediction [m]", jump, h.max_correction);
  return "";
}

void Estimator::rejectOutliers(FrameReport* report) {
  std::map<long, const WindowFrame*> frame_of;
  for (const auto& f : window_) frame_of[f->id] = f.get();
  std::vector<std::pair<long, long>> drop;  // (track, frame)
  for (const auto& [id, t] : tracks_.all()) {
    if (!t.landmark && !t.fixed) continue;
    for (const Observation& o : t.obs) {
      auto it = frame_of.find(o.frame);
      if (it == frame_of.end()) continue;
      const FactorRef f = pointFactor(o, *it->second, t.position);
      Vec3 r;
      f.cost->Evaluate(f.blocks.data(), r.data(), nullptr);
      if (r.squaredNorm() > cfg_.association.outlier_chi2) drop.emplace_back(id, o.frame);
    }
  }
  for (auto [track, frame] : drop)
    tracks_.dropObservation(track, frame, cfg_.association.min_observations);
  report->outliers = static_cast<int>(drop.size());
}

void Estimator::slide() {
  if (static_cast<int>(window_.size()) <= cfg_.solver.window_size) return;
  WindowFrame& oldest = *window_.front();
  WindowFrame& next = *window_[1];
  std::vector<long> marginalized_tracks;
  if (cfg_.solver.marginalize) {
    // Marginalise the oldest state over the factors that touch it (the prior, the IMU
    // factor to the next frame, its Doppler / zero-velocity / gyro factors) together with
    // the landmarks it observes and all their observations (as VINS-Mono does with the
    // features of its oldest frame): their information stays in the prior, which then
    // spans the window frames that saw those landmarks.
    Marginalizer marg;
    std::set<double*> drop = {oldest.x.pose, oldest.x.speed_bias};
    if (prior_) marg.add(prior_, nullptr, prior_blocks_);
    const FactorRef imu = imuFactor(oldest, next);
    marg.add(imu.cost, imu.loss, imu.blocks);
    FactorRef walk;  // the barometer bias goes with its state (kept in the prior via the walk)
    if (baroWalkFactor(oldest, next, &walk)) marg.add(walk.cost, walk.loss, walk.blocks);
    if (oldest.has_baro_bias) drop.insert(oldest.baro_bias);
    // The prior of t_d goes into the marginalisation prior, which carries t_d from then on.
    if (td_prior_) marg.add(td_prior_, nullptr, {td_});
    for (const FactorRef& r : unaryFactors(oldest)) marg.add(r.cost, r.loss, r.blocks);
    for (auto& [id, t] : tracks_.all()) {
      if (!t.landmark || t.fixed || t.obs.empty() || t.obs.front().frame != oldest.id) continue;
      std::vector<FactorRef> fs;
      trackFactors(t, &fs);
      for (const FactorRef& r : fs) marg.add(r.cost, r.loss, r.blocks);
      drop.insert(t.position.data());
      marginalized_tracks.push_back(id);
    }
    std::string err;
    std::shared_ptr<MarginalizationPrior> p = marg.marginalize(drop, &err);
    td_prior_.reset();
    if (p) {
      prior_blocks_ = p->blocks();
      prior_ = std::move(p);
    } else {  // should not happen; fall back to a loose prior on the next state
      Vec15 sigma;
      sigma << Vec3::Constant(0.01), Vec3::Constant(0.01), Vec3::Constant(0.1),
          Vec3::Constant(cfg_.init.sigma_acc_bias), Vec3::Constant(cfg_.init.sigma_gyro_bias);
      prior_ = std::make_shared<StatePrior>(next.state(), Mat15(sigma.cwiseInverse().asDiagonal()));
      prior_blocks_ = {next.x.pose, next.x.speed_bias};
      installTimeOffsetPrior();
    }
  } else {
    prior_.reset();  // the authors' scheme: next solves hold the new oldest state constant
    prior_blocks_.clear();
  }
  tracks_.retire(marginalized_tracks, cfg_.association);
  tracks_.dropFrame(oldest.id, cfg_.association);
  window_.pop_front();
}

}  // namespace rio
}  // namespace coral_introspection
