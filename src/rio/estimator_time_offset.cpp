// The radar factors of the window and the radar-IMU time offset t_d (time_offset.hpp): with
// time_offset/estimate each Doppler and point residual is moved to its frame's time by t_d,
// t_d has a prior around radar_time_offset (carried by the marginalisation prior once its
// first frame leaves the window), is bounded by time_offset/max_abs, and an estimate that
// stays at the bound, or radar frames arriving with an IMU lag no t_d within the bound
// explains, refuse the input. Frames keep the time stamp + radar_time_offset.
#include <ceres/ceres.h>

#include <cmath>
#include <iomanip>
#include <sstream>

#include "coral_introspection/coral/statistics.hpp"
#include "coral_introspection/rio/estimator.hpp"
#include "coral_introspection/rio/point_uncertainty.hpp"
#include "coral_introspection/rio/time_offset.hpp"
#include "window_frame.hpp"

namespace coral_introspection {
namespace rio {

Estimator::FactorRef Estimator::shifted(FactorRef r, const Eigen::VectorXd& rate) const {
  if (!cfg_.time_offset.estimate) return r;
  r.cost = std::make_shared<TimeShiftedFactor>(r.cost, rate, cfg_.radar_time_offset);
  r.blocks.push_back(const_cast<double*>(td_));
  return r;
}

std::vector<Estimator::FactorRef> Estimator::dopplerFactors(const WindowFrame& f) const {
  std::vector<FactorRef> out;
  if (!cfg_.solver.use_doppler) return out;
  double* pose = const_cast<double*>(f.x.pose);
  double* sb = const_cast<double*>(f.x.speed_bias);
  // Eq. 9 per static point; the weight (Eq. 10-12) is evaluated at the current estimate of
  // the radar velocity and held during the solve, as is the Doppler's rate for t_d.
  const NavState s = f.state();
  const Vec3 v_radar = radarVelocity(s, f.omega);
  const Vec3 a_radar =
      cfg_.time_offset.estimate
          ? radarAcceleration(s, f.omega, f.alpha, f.acc, cfg_.extrinsics, cfg_.imu.gravity)
          : Vec3::Zero();
  for (const RadarPoint& rp : f.static_points) {
    const double w = 1.0 / std::sqrt(dopplerVariance(rp.p, v_radar, cfg_.uncertainty));
    const Vec3 d = rp.p.normalized();
    out.push_back(shifted(
        {std::make_shared<DopplerFactor>(d, rp.m, f.omega, cfg_.extrinsics, w), loss_, {pose, sb}},
        Eigen::VectorXd::Constant(1, w * d.dot(a_radar))));
  }
  return out;
}

Estimator::FactorRef Estimator::pointFactor(const Observation& o, const WindowFrame& f,
                                            const Vec3& landmark) const {
  FactorRef r{std::make_shared<PointFactor>(o.p, o.W, cfg_.extrinsics),
              loss_,
              {const_cast<double*>(f.x.pose), const_cast<double*>(landmark.data())}};
  if (!cfg_.time_offset.estimate) return r;
  // Eq. 15's measured point moves with the radar: its rate at the frame's current estimate.
  const NavState s = f.state();
  const Vec3 omega_radar = cfg_.extrinsics.R.transpose() * (f.omega - s.bg);
  return shifted(std::move(r), o.W * staticPointRate(o.p, omega_radar, radarVelocity(s, f.omega)));
}

Eigen::Isometry3d Estimator::measurementPose(const NavState& s, const Vec3& omega) const {
  Eigen::Isometry3d T = radarPose(s);
  if (!cfg_.time_offset.estimate) return T;
  const double delta = td_[0] - cfg_.radar_time_offset;
  const Vec3 omega_radar = cfg_.extrinsics.R.transpose() * (omega - s.bg);
  T.translation() += T.linear() * (delta * radarVelocity(s, omega));
  T.linear() = T.linear() * expQ(delta * omega_radar).toRotationMatrix();
  return T;
}

void Estimator::installTimeOffsetPrior() {
  if (cfg_.time_offset.estimate)
    td_prior_ = std::make_shared<TimeOffsetPrior>(cfg_.radar_time_offset, cfg_.time_offset.sigma);
}

void Estimator::addTimeOffset(ceres::Problem* problem, std::vector<FactorRef>* factors) {
  if (!cfg_.time_offset.estimate) return;
  problem->AddParameterBlock(td_, 1);
  problem->SetParameterLowerBound(td_, 0, -cfg_.time_offset.max_abs);
  problem->SetParameterUpperBound(td_, 0, cfg_.time_offset.max_abs);
  if (td_prior_) factors->push_back({td_prior_, nullptr, {td_}});
}

void Estimator::judgeTimeOffset(double dt) {
  const TimeOffsetConfig& c = cfg_.time_offset;
  if (!c.estimate) return;
  // Ceres holds a bounded value exactly at the bound while the bound is active.
  const bool at_bound = std::abs(td_[0]) >= c.max_abs * (1.0 - 1e-6);
  counters_.offset_at_bound += at_bound;
  td_at_bound_ = at_bound ? td_at_bound_ + dt : 0.0;
  if (td_at_bound_ < c.max_time_at_bound) return;
  std::ostringstream s;
  s << std::showpos << std::setprecision(3) << "radar-IMU time offset: the estimate stayed at its "
    << "bound " << td_[0] << " s (time_offset/max_abs) for " << std::noshowpos << td_at_bound_
    << " s of tracked frames: the IMU clock is "
    << (td_[0] > 0.0 ? "ahead of the radar stamps (IMU stamps late?)"
                     : "behind the radar stamps (IMU stamps early?)")
    << " by more than the bound";
  input_error_ = s.str();
}

void Estimator::judgeArrivalLag(double lag) {
  const TimeOffsetConfig& c = cfg_.time_offset;
  if (!c.estimate || !input_error_.empty()) return;
  // The median of the last frames: one frame held up in a queue is not a clock offset.
  constexpr std::size_t kFrames = 20;
  arrival_lag_.push_back(lag);
  if (arrival_lag_.size() > kFrames) arrival_lag_.pop_front();
  if (arrival_lag_.size() < kFrames) return;
  // A measured value (the upper middle one of the even count), as the refusal quotes it.
  const double median = coral::quantile({arrival_lag_.begin(), arrival_lag_.end()}, 0.5);
  if (median >= -c.max_abs && median <= c.max_latency + c.max_abs) return;
  std::ostringstream s;
  s << std::setprecision(3) << "radar-IMU time offset: when a radar frame arrives, the newest "
    << "IMU stamp minus the frame time is " << median << " s (median of " << kFrames
    << " frames), ";
  if (median < 0.0)
    s << "before the IMU covers them: the IMU clock is behind the radar stamps by more than "
      << "time_offset/max_abs " << c.max_abs << " s (IMU stamps early?)";
  else
    s << "more than time_offset/max_latency " << c.max_latency << " s of radar latency plus "
      << "time_offset/max_abs " << c.max_abs << " s: the IMU clock is ahead of the radar "
      << "stamps (IMU stamps late?)";
  input_error_ = s.str();
}

}  // namespace rio
}  // namespace coral_introspection
