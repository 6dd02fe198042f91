// The sliding-window radar-inertial odometry of the second paper (Sec. III, Eq. 2): per
// radar frame a state x_i, IMU preintegration between frames, Doppler residuals of the
// static points and point-to-landmark residuals, both weighted by the polar point
// uncertainty; probability-guided one-to-one association; a marginalisation prior when
// the window slides; zero-velocity and gyro-bias updates on standing frames; failed or
// diverging solves detected and reset. ROS-free: feed IMU samples and radar frames in
// time order, read the reports and the state.
#pragma once

#include <ceres/cost_function.h>
#include <ceres/loss_function.h>
#include <ceres/problem.h>

#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "coral_introspection/rio/config.hpp"
#include "coral_introspection/rio/front_end.hpp"
#include "coral_introspection/rio/imu_check.hpp"
#include "coral_introspection/rio/initializer.hpp"
#include "coral_introspection/rio/marginalization.hpp"
#include "coral_introspection/rio/tracks.hpp"

namespace coral_introspection {
namespace rio {

enum class FrameStatus { kInitializing, kTracking, kReset, kRejected };
const char* toString(FrameStatus s);

// What happened to one radar frame.
struct FrameReport {
  double t = 0.0;
  FrameStatus status = FrameStatus::kInitializing;
  NavState state;  // newest state after the solve (valid unless kInitializing / kRejected)
  bool standing = false, moving_start = false;
  int points = 0, static_points = 0, matched = 0, created = 0, map_matched = 0;
  int landmarks = 0, map_points = 0, point_residuals = 0, doppler_residuals = 0, outliers = 0;
  int iterations = 0;
  double final_cost = 0.0, solve_ms = 0.0;
  double time_offset = 0.0;  // [s] radar-IMU offset t_d after the frame (time_offset.hpp)
  bool has_covariance = false;
  Eigen::Matrix<double, 15, 15> covariance;  // [dp, dtheta (body), dv, dba, dbg] when asked
  std::string message;                       // why a frame was rejected or the window reset
};

// Counters for diagnostics (monotonic since construction).
struct RioCounters {
  long frames = 0, tracked = 0, resets = 0, failed_solves = 0, rejected_frames = 0;
  long imu_out_of_order = 0, time_jumps = 0, imu_gaps = 0, empty_scans = 0, no_doppler = 0;
  long standing_frames = 0;
  long gap_bridged = 0;      // IMU-gap frames placed with the Doppler velocity (subset of imu_gaps)
  long baro_frames = 0;      // frames with a barometer residual (barometer/enabled)
  long bad_baro = 0;         // barometer samples dropped (non-finite, not positive, out of order)
  long offset_at_bound = 0;  // tracked frames with the time offset estimate at its bound
};

class Estimator {
 public:
  // Precondition: cfg.validate() is empty (adapters validate and report first).
  explicit Estimator(const RioConfig& cfg);
  ~Estimator();

  // Feed in time order. Returns the reports of the radar frames processed by this call (a
  // frame waits until the IMU covers its time).
  std::vector<FrameReport> addImu(const ImuSample& s);
  std::vector<FrameReport> addRadar(RadarFrame frame);
  // Barometer samples (pressure in Pa), same clock; used only with barometer/enabled. A frame
  // uses the samples of the interval before it that arrived before the frame is processed.
  void addBaro(const BaroSample& s);

  // When true, each tracked frame's report carries the newest state's covariance.
  void setComputeCovariance(bool on) { compute_covariance_ = on; }
  void reset();  // back to initialisation (everything forgotten)

  bool initialized() const { return !window_.empty(); }
  NavState latest() const;  // newest window state
  std::vector<NavState> windowStates() const;
  Points landmarkPositions() const;  // landmarks and map points, world frame
  const RioCounters& counters() const { return counters_; }
  // Why the input cannot be right (IMU units, imu_check.hpp), "" while it may be. Once set,
  // every radar frame is rejected with this message until reset(): no odometry is better
  // than a confident wrong one.
  const std::string& inputError() const { return input_error_; }
  const RioConfig& config() const { return cfg_; }
  // The radar-IMU time offset t_d [s]: the estimate with time_offset/estimate, else the
  // configured radar_time_offset.
  double timeOffset() const { return td_[0]; }

 private:
  struct WindowFrame;
  struct FactorRef {
    std::shared_ptr<ceres::CostFunction> cost;
    std::shared_ptr<ceres::LossFunction> loss;
    std::vector<double*> blocks;
  };

  std::vector<FrameReport> drain();
  FrameReport process(const RadarFrame& f);
  // The phases of process() (estimator.cpp).
  void initialise(const RadarFrame& f, double t_prev, bool have_imu,
                  const std::vector<ImuSample>& interval, FrameReport* report);
  std::unique_ptr<WindowFrame> predictFrame(const RadarFrame& f,
                                            const std::vector<ImuSample>& interval, NavState* pred);
  void takeFrontEnd(const FrontEndResult& fe, const std::vector<ImuSample>& interval,
                    WindowFrame* w, FrameReport* report);
  void addToWindow(std::unique_ptr<WindowFrame> w, const NavState& pred, FrameReport* report);
  bool solveOrReset(const NavState& pred, FrameReport* report);  // false: reset (reported)
  bool refuseImplausibleImu(const std::vector<ImuSample>& interval, bool standing,
                            FrameReport* report);
  void bridgeImuGap(const RadarFrame& f, double gap, FrameReport* report);
  bool imuInterval(double t0, double t1, std::vector<ImuSample>* out, double* max_gap) const;
  Eigen::Isometry3d radarPose(const NavState& s) const;
  Vec3 radarVelocity(const NavState& s, const Vec3& omega) const;
  void softReset(const NavState& s, double sigma_velocity, const std::string& why,
                 FrameReport* report);
  void installStatePrior(const NavState& s, const Vec15& sigma);

  // Window problem (window_solver.cpp).
  std::vector<FactorRef> unaryFactors(const WindowFrame& f) const;
  FactorRef imuFactor(const WindowFrame& prev, const WindowFrame& f) const;
  void trackFactors(const Track& t, std::vector<FactorRef>* out) const;
  std::vector<FactorRef> pointFactors(int* count) const;
  FactorRef pointFactor(const Observation& o, const WindowFrame& f, const Vec3& landmark) const;
  // Time offset (time_offset.hpp, estimator_time_offset.cpp): r moved by t_d with its rate
  // (r unchanged without time_offset/estimate), the prior of t_d, the bound check.
  FactorRef shifted(FactorRef r, const Eigen::VectorXd& rate) const;
  std::vector<FactorRef> dopplerFactors(const WindowFrame& f) const;
  void installTimeOffsetPrior();
  void addTimeOffset(ceres::Problem* problem, std::vector<FactorRef>* factors);
  void judgeTimeOffset(double dt);
  void judgeArrivalLag(double lag);
  // The radar pose at the measurement time (the frame's time moved by t_d - radar_time_offset
  // with the radar's velocity and rate), where the frame's points were seen: the association
  // predicts the tracks there.
  Eigen::Isometry3d measurementPose(const NavState& s, const Vec3& omega) const;
  // Barometer (barometer.hpp): the frame's mean height and bias state, the bias walk.
  void attachBaro(double t_from, const WindowFrame* prev, WindowFrame* f);
  bool baroWalkFactor(const WindowFrame& prev, const WindowFrame& f, FactorRef* out) const;
  bool solve(FrameReport* report);
  std::string checkHealth(const NavState& predicted) const;
  void rejectOutliers(FrameReport* report);
  void slide();

  RioConfig cfg_;
  StaticInitializer init_;
  ImuRestCheck imu_check_;
  std::string input_error_;
  std::deque<ImuSample> imu_;
  std::deque<RadarFrame> pending_;
  std::deque<std::pair<double, double>> baro_;  // (t, altitude [m]) not yet used by a frame
  std::deque<std::unique_ptr<WindowFrame>> window_;
  std::shared_ptr<ceres::CostFunction> prior_;  // marginalisation prior or initial StatePrior
  std::vector<double*> prior_blocks_;
  Tracks tracks_;
  std::shared_ptr<ceres::LossFunction> loss_;
  double td_[1] = {0.0};                           // t_d, a Ceres block with estimation
  std::shared_ptr<ceres::CostFunction> td_prior_;  // until marginalised into prior_
  double td_at_bound_ = 0.0;                       // [s] of tracked frames at the bound
  std::deque<double> arrival_lag_;                 // newest IMU stamp - frame time, recent
  bool imu_since_frame_ = false;                   // IMU samples since the last radar frame
  RioCounters counters_;
  long next_frame_id_ = 0;
  double last_frame_t_ = -1e300;  // newest radar time seen (processed or initialising)
  bool compute_covariance_ = false;
};

}  // namespace rio
}  // namespace coral_introspection
