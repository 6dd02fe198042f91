#include "coral_introspection/rio/estimator.hpp"

#include <algorithm>

#include "coral_introspection/rio/prior_factors.hpp"
#include "coral_introspection/rio/time_offset.hpp"
#include "window_frame.hpp"

namespace coral_introspection {
namespace rio {

namespace {

// IMU interval judged before the very first radar frame (no previous frame): one radar
// period at the usual 10 Hz.
constexpr double kFirstIntervalS = 0.1;  // [s]

// Prior of the state a window restarts from (softReset). The pose stays where it is, so that
// the odometry frame continues: position and yaw (unobservable for the window) held tight,
// roll and pitch looser, since gravity re-observes them.
constexpr double kResetSigmaPosition = 1e-3;   // [m]
constexpr double kResetSigmaRollPitch = 0.02;  // [rad], about 1.1 deg
constexpr double kResetSigmaYaw = 1e-3;        // [rad]

// Velocity sigmas of a (re)started window, by where its velocity comes from. [m/s]
// - the IMU prediction of a window whose solve failed or diverged: not checked by any radar
//   residual, so walking-speed uncertainty;
constexpr double kSigmaVelocityAfterFailedSolve = 0.5;
// - an IMU gap bridged with this frame's Doppler velocity: a measured velocity, within the
//   fit's noise and the attitude held over the gap;
constexpr double kSigmaVelocityBridgedDoppler = 0.2;
// - an IMU gap bridged with the previous velocity held (no Doppler fit): the robot may have
//   accelerated during the gap;
constexpr double kSigmaVelocityBridgedConstant = 1.0;
// - a moving start (no static interval): the Doppler velocity with a rough gravity direction
//   (initializer.hpp), far looser than the standstill's InitConfig::sigma_velocity.
constexpr double kSigmaVelocityMovingStart = 0.5;

// [s] of gyro samples before a frame whose slope is its angular acceleration (the Doppler's
// rate for the time offset, time_offset.hpp): about 10 samples of a 200 Hz IMU, short enough
// for the hand-held motion's changes of rate (peaks of 2.7 rad/s within a few tenths of a s).
constexpr double kAngularAccelerationSpan = 0.05;

}  // namespace

const char* toString(FrameStatus s) {
  switch (s) {
    case FrameStatus::kInitializing:
      return "initializing";
    case FrameStatus::kTracking:
      return "tracking";
    case FrameStatus::kReset:
      return "reset";
    case FrameStatus::kRejected:
      return "rejected";
  }
  return "?";
}

Estimator::Estimator(const RioConfig& cfg) : cfg_(cfg), init_(cfg), imu_check_(cfg) {
  td_[0] = cfg_.radar_time_offset;
  if (cfg_.solver.loss == "huber")
    loss_ = std::make_shared<ceres::HuberLoss>(cfg_.solver.loss_scale);
  else if (cfg_.solver.loss == "cauchy")
    loss_ = std::make_shared<ceres::CauchyLoss>(cfg_.solver.loss_scale);
}

Estimator::~Estimator() = default;

void Estimator::reset() {
  init_.reset();
  imu_check_.reset();
  input_error_.clear();
  imu_.clear();
  pending_.clear();
  baro_.clear();
  window_.clear();
  prior_.reset();
  prior_blocks_.clear();
  tracks_.clear();
  last_frame_t_ = -1e300;
  td_[0] = cfg_.radar_time_offset;
  td_prior_.reset();
  td_at_bound_ = 0.0;
  arrival_lag_.clear();
  imu_since_frame_ = false;
}

NavState Estimator::latest() const {
  return window_.empty() ? NavState() : window_.back()->state();
}

std::vector<NavState> Estimator::windowStates() const {
  std::vector<NavState> out;
  for (const auto& f : window_) out.push_back(f->state());
  return out;
}

Points Estimator::landmarkPositions() const {
  Points out;
  for (const auto& [id, t] : tracks_.all())
    if (t.landmark || t.fixed) out.push_back(t.position);
  return out;
}

Eigen::Isometry3d Estimator::radarPose(const NavState& s) const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = s.q.toRotationMatrix() * cfg_.extrinsics.R;
  T.translation() = s.p + s.q * cfg_.extrinsics.t;
  return T;
}

Vec3 Estimator::radarVelocity(const NavState& s, const Vec3& omega) const {
  // Eq. 9's K: R_E^T (R^T v + (omega - b_g)^ t_E).
  return cfg_.extrinsics.R.transpose() *
         (s.q.conjugate() * s.v + (omega - s.bg).cross(cfg_.extrinsics.t));
}

std::vector<FrameReport> Estimator::addImu(const ImuSample& s) {
  if (!imu_.empty() && s.t <= imu_.back().t) {
    if (imu_.back().t - s.t > 1.0) {  // a new sequence (bag restarted): start over
      ++counters_.time_jumps;
      reset();
    } else {
      ++counters_.imu_out_of_order;
      return {};
    }
  }
  if (!s.acc.allFinite() || !s.gyro.allFinite()) {
    ++counters_.imu_out_of_order;
    return {};
  }
  imu_.push_back(s);
  imu_since_frame_ = true;
  return drain();
}

std::vector<FrameReport> Estimator::addRadar(RadarFrame frame) {
  frame.t += cfg_.radar_time_offset;
  std::vector<FrameReport> out;
  if (frame.t <= last_frame_t_) {
    FrameReport r;
    r.t = frame.t;
    r.status = FrameStatus::kRejected;
    ++counters_.rejected_frames;
    if (last_frame_t_ - frame.t > 1.0) {
      ++counters_.time_jumps;
      r.message = "radar time jumped back by more than 1 s: restarting";
      reset();
    } else {
      r.message = "radar frame not newer than the previous one: dropped";
    }
    out.push_back(r);
    if (frame.t <= last_frame_t_) return out;
  }
  last_frame_t_ = frame.t;
  // Only with IMU samples since the previous frame: in an IMU gap the newest stamp stands
  // still while the radar goes on, which is not a clock offset.
  if (imu_since_frame_) judgeArrivalLag(imu_.back().t - frame.t);
  imu_since_frame_ = false;
  pending_.push_back(std::move(frame));
  while (pending_.size() > 50) {  // no IMU for a long time: forget the oldest frames
    FrameReport r;
    r.t = pending_.front().t;
    r.status = FrameStatus::kRejected;
    r.message = "no IMU data covering the radar frame";
    ++counters_.rejected_frames;
    out.push_back(r);
    pending_.pop_front();
  }
  for (FrameReport& r : drain()) out.push_back(std::move(r));
  return out;
}

std::vector<FrameReport> Estimator::drain() {
  std::vector<FrameReport> out;
  while (!pending_.empty() && !imu_.empty() && imu_.back().t >= pending_.front().t) {
    out.push_back(process(pending_.front()));
    pending_.pop_front();
  }
  // Keep the IMU samples the next interval needs (from the newest frame on).
  const double keep_from =
      window_.empty() ? imu_.empty() ? 0.0 : imu_.back().t - 2.0 : window_.back()->t;
  while (imu_.size() > 2 && imu_[1].t <= keep_from) imu_.pop_front();
  return out;
}

bool Estimator::imuInterval(double t0, double t1, std::vector<ImuSample>* out,
                            double* max_gap) const {
  out->clear();
  *max_gap = 0.0;
  if (imu_.empty() || imu_.front().t > t0 || imu_.back().t < t1) return false;
  auto lerp = [](const ImuSample& a, const ImuSample& b, double t) {
    const double u = b.t > a.t ? (t - a.t) / (b.t - a.t) : 0.0;
    return ImuSample{t, a.acc + u * (b.acc - a.acc), a.gyro + u * (b.gyro - a.gyro)};
  };
  // Interpolated samples at both ends, the measured ones strictly inside.
  for (std::size_t k = 1; k < imu_.size(); ++k) {
    const ImuSample &a = imu_[k - 1], &b = imu_[k];
    if (b.t < t0 || a.t > t1) continue;
    *max_gap = std::max(*max_gap, b.t - a.t);
    if (out->empty()) out->push_back(lerp(a, b, t0));
    if (b.t < t1) out->push_back(b);
    if (b.t >= t1) {
      out->push_back(lerp(a, b, t1));
      break;
    }
  }
  return out->size() >= 2;
}

// One radar frame, in phases: input checks, the IMU interval since the previous frame, then
// either initialisation (empty window), an IMU-gap bridge, or tracking: IMU prediction, radar
// front end, association, window solve (reset when it fails), outliers and the slide.
FrameReport Estimator::process(const RadarFrame& f) {
  ++counters_.frames;
  FrameReport report;
  report.t = f.t;
  report.time_offset = td_[0];
  if (!input_error_.empty()) {
    ++counters_.rejected_frames;
    report.status = FrameStatus::kRejected;
    report.message = input_error_;
    return report;
  }
  if (f.points.empty()) ++counters_.empty_scans;
  if (!f.points.empty() && f.radial_velocity.size() != f.points.size()) ++counters_.no_doppler;

  std::vector<ImuSample> interval;
  double gap = 0.0;
  const double t_prev = window_.empty() ? f.t - kFirstIntervalS : window_.back()->t;
  const bool have_imu = imuInterval(std::max(t_prev, imu_.front().t), f.t, &interval, &gap);

  if (window_.empty()) {
    initialise(f, t_prev, have_imu, interval, &report);
    return report;
  }
  if (!have_imu || gap > cfg_.health.max_imu_gap) {
    bridgeImuGap(f, have_imu ? gap : f.t - window_.back()->t, &report);
    return report;
  }

  NavState pred;
  std::unique_ptr<WindowFrame> w = predictFrame(f, interval, &pred);
  const Vec3 v_pred = radarVelocity(pred, w->omega);
  const FrontEndResult fe = processRadarFrame(f, cfg_, &v_pred);
  if (refuseImplausibleImu(interval, fe.standing, &report)) return report;
  takeFrontEnd(fe, interval, w.get(), &report);
  addToWindow(std::move(w), pred, &report);
  if (!solveOrReset(pred, &report)) return report;
  judgeTimeOffset(window_.back()->t - window_[window_.size() - 2]->t);
  report.time_offset = td_[0];
  rejectOutliers(&report);
  report.state = window_.back()->state();
  report.status = FrameStatus::kTracking;
  report.landmarks = tracks_.numLandmarks();
  report.map_points = tracks_.numMapPoints();
  ++counters_.tracked;
  slide();
  return report;
}

void Estimator::initialise(const RadarFrame& f, double t_prev, bool have_imu,
                           const std::vector<ImuSample>& interval, FrameReport* report) {
  // From a static start (StaticInitializer); the first frame is the window's only one.
  const FrontEndResult fe = processRadarFrame(f, cfg_, nullptr);
  if (have_imu && refuseImplausibleImu(interval, fe.standing, report)) return;
  NavState x;
  bool moving = false;
  const Vec3* v = fe.doppler_fit ? &fe.v_radar : nullptr;
  if (!have_imu || !init_.addFrame(f.t, interval, fe.has_doppler, fe.standing, v, &x, &moving)) {
    report->status = FrameStatus::kInitializing;
    const ImuStats st = imuStats(interval);
    report->message = "waiting for a static start (IMU rate std " +
                      std::to_string(st.gyro_std.maxCoeff()) + " rad/s, specific force std " +
                      std::to_string(st.acc_std.maxCoeff()) + " m/s^2, Doppler " +
                      (!fe.has_doppler   ? std::string("none")
                       : !fe.doppler_fit ? std::string("no consensus")
                                         : std::to_string(fe.v_radar.norm()) + " m/s") +
                      ")";
    return;
  }
  x.t = f.t;
  auto w = std::make_unique<WindowFrame>();
  w->id = next_frame_id_++;
  w->t = f.t;
  toBlocks(x, &w->x);
  w->omega = interval.back().gyro;
  w->acc = interval.back().acc;
  w->alpha = angularAcceleration(interval, kAngularAccelerationSpan);
  w->standing = fe.standing;
  attachBaro(t_prev, nullptr, w.get());
  window_.push_back(std::move(w));
  const InitConfig& ic = cfg_.init;
  Vec15 sigma;
  sigma << Vec3::Constant(ic.sigma_position), ic.sigma_roll_pitch, ic.sigma_roll_pitch,
      ic.sigma_yaw, Vec3::Constant(moving ? kSigmaVelocityMovingStart : ic.sigma_velocity),
      Vec3::Constant(ic.sigma_acc_bias), Vec3::Constant(ic.sigma_gyro_bias);
  installStatePrior(x, sigma);
  report->status = FrameStatus::kTracking;
  report->state = x;
  report->moving_start = moving;
  report->message =
      moving ? "started without a static interval" : "initialised from a static start";
}

std::unique_ptr<Estimator::WindowFrame> Estimator::predictFrame(
    const RadarFrame& f, const std::vector<ImuSample>& interval, NavState* pred) {
  // The new frame's state: the previous one propagated by the IMU preintegration.
  const WindowFrame& prev = *window_.back();
  const NavState prev_state = prev.state();
  auto w = std::make_unique<WindowFrame>();
  w->id = next_frame_id_++;
  w->t = f.t;
  w->pre =
      std::make_unique<Preintegration>(interval.front(), prev_state.ba, prev_state.bg, cfg_.imu);
  for (std::size_t k = 1; k < interval.size(); ++k) w->pre->push(interval[k]);
  *pred = w->pre->predict(prev_state);
  pred->t = f.t;
  toBlocks(*pred, &w->x);
  attachBaro(prev.t, &prev, w.get());
  w->omega = interval.back().gyro;
  w->acc = interval.back().acc;
  w->alpha = angularAcceleration(interval, kAngularAccelerationSpan);
  return w;
}

void Estimator::takeFrontEnd(const FrontEndResult& fe, const std::vector<ImuSample>& interval,
                             WindowFrame* w, FrameReport* report) {
  // The front end's static points (Doppler residuals) and standing detection; a standing
  // frame whose gyro was still also measures the gyro bias. Called before w joins the window:
  // window_.back() is still the previous frame.
  const NavState prev_state = window_.back()->state();
  for (int k : fe.static_points) w->static_points.push_back(fe.points[k]);
  w->standing = cfg_.zero_velocity.enabled && fe.standing;
  const ImuStats st = imuStats(interval);
  w->gyro_still = w->standing && st.n >= cfg_.zero_velocity.min_gyro_samples &&
                  st.gyro_std.maxCoeff() < cfg_.zero_velocity.max_gyro_std &&
                  (st.gyro_mean - prev_state.bg).norm() < cfg_.zero_velocity.max_gyro_rate;
  w->gyro_mean = st.gyro_mean;
  w->gyro_sigma = cfg_.imu.gyro_noise / std::sqrt(std::max(st.duration, 1e-3));
  counters_.standing_frames += w->standing;
  report->points = static_cast<int>(fe.points.size());
  report->static_points = static_cast<int>(w->static_points.size());
  report->standing = w->standing;
}

void Estimator::addToWindow(std::unique_ptr<WindowFrame> w, const NavState& pred,
                            FrameReport* report) {
  window_.push_back(std::move(w));
  const WindowFrame& f = *window_.back();
  if (!cfg_.solver.use_points || f.static_points.empty()) return;
  // Probability-guided association of the static points (Sec. III-D).
  Points pts;
  coral::Covariances covs;
  std::vector<Mat3> W;
  for (const RadarPoint& rp : f.static_points) {
    pts.push_back(rp.p);
    covs.push_back(rp.cov);
    W.push_back(whitening3(rp.cov, cfg_.uncertainty.min_variance));
  }
  auto pose_of = [this](long id) {
    for (const auto& fr : window_)
      if (fr->id == id) return radarPose(fr->state());
    return Eigen::Isometry3d::Identity();  // not reached: tracks only hold window frames
  };
  const Tracks::Stats s = tracks_.associate(f.id, pts, covs, W, measurementPose(pred, f.omega),
                                            pose_of, cfg_.association);
  report->matched = s.matched;
  report->created = s.created;
  report->map_matched = s.map_matched;
  tracks_.promote(cfg_.association.min_observations, pose_of);
}

bool Estimator::solveOrReset(const NavState& pred, FrameReport* report) {
  // A failed or diverged solve puts every window state back as it was and restarts the
  // window at the IMU prediction.
  std::vector<NavState> before;
  std::vector<double> bias_before;
  for (const auto& fr : window_) {
    before.push_back(fr->state());
    bias_before.push_back(fr->baro_bias[0]);
  }
  const double td_before = td_[0];
  const bool solved = solve(report);
  const std::string problem = solved ? checkHealth(pred) : "the solver failed";
  if (problem.empty()) return true;
  ++counters_.failed_solves;
  for (std::size_t k = 0; k < window_.size(); ++k) {
    toBlocks(before[k], &window_[k]->x);
    window_[k]->baro_bias[0] = bias_before[k];
  }
  td_[0] = td_before;
  report->status = FrameStatus::kReset;
  softReset(pred, kSigmaVelocityAfterFailedSolve, problem, report);
  return false;
}

bool Estimator::refuseImplausibleImu(const std::vector<ImuSample>& interval, bool standing,
                                     FrameReport* report) {
  input_error_ = imu_check_.addFrame(interval, standing);
  if (input_error_.empty()) return false;
  ++counters_.rejected_frames;
  report->status = FrameStatus::kRejected;
  report->message = input_error_;
  return true;
}

void Estimator::bridgeImuGap(const RadarFrame& f, double gap, FrameReport* report) {
  // No IMU over the interval: no preintegration, so the window restarts at this frame
  // (softReset). Its position is not the previous one (a moving radar would leave frozen
  // poses behind): the trapezoid of the previous velocity and the Doppler velocity of this
  // frame, or the previous velocity alone without a Doppler fit. Attitude and biases are
  // held (no gyro); the radar-to-body lever-arm term needs the rate and is left out.
  ++counters_.imu_gaps;
  const NavState prev = window_.back()->state();
  const double dt = f.t - prev.t;
  const FrontEndResult fe = processRadarFrame(f, cfg_, nullptr);
  NavState x = prev;
  x.t = f.t;
  double sigma_v = kSigmaVelocityBridgedConstant;
  std::string how = "constant velocity (no Doppler fit)";
  if (fe.doppler_fit) {
    x.v = prev.q * (cfg_.extrinsics.R * fe.v_radar);
    sigma_v = kSigmaVelocityBridgedDoppler;
    how = "the Doppler velocity";
    ++counters_.gap_bridged;
  }
  x.p = prev.p + 0.5 * (prev.v + x.v) * dt;
  report->status = FrameStatus::kReset;
  softReset(x, sigma_v,
            "IMU gap of " + std::to_string(gap) + " s before the radar frame: bridged with " + how,
            report);
}

void Estimator::installStatePrior(const NavState& s, const Vec15& sigma) {
  prior_ = std::make_shared<StatePrior>(s, Mat15(sigma.cwiseInverse().asDiagonal()));
  prior_blocks_ = {window_.back()->x.pose, window_.back()->x.speed_bias};
  // t_d keeps its estimate; its prior restarts with the window's.
  installTimeOffsetPrior();
}

void Estimator::softReset(const NavState& s, double sigma_velocity, const std::string& why,
                          FrameReport* report) {
  // Keep the newest frame (at state s) as the only window frame, forget tracks and prior,
  // and anchor it with a prior: pose where it is (continuity of the odometry frame; roll
  // and pitch looser, gravity re-observes them), velocity and biases as given.
  std::unique_ptr<WindowFrame> last = std::move(window_.back());
  window_.clear();
  tracks_.clear();
  last->t = s.t;
  last->pre.reset();
  toBlocks(s, &last->x);
  last->static_points.clear();
  last->standing = last->gyro_still = false;
  last->has_baro = last->has_baro_bias = false;  // the bias restarts at the next reading
  window_.push_back(std::move(last));
  ++counters_.resets;
  Vec15 sigma;
  sigma << Vec3::Constant(kResetSigmaPosition), kResetSigmaRollPitch, kResetSigmaRollPitch,
      kResetSigmaYaw, Vec3::Constant(sigma_velocity), Vec3::Constant(cfg_.init.sigma_acc_bias),
      Vec3::Constant(cfg_.init.sigma_gyro_bias);
  installStatePrior(s, sigma);
  report->state = s;
  report->message = why;
}

}  // namespace rio
}  // namespace coral_introspection
