// Initialisation from a static start: while the IMU rests (small rate and specific-force
// spread) and the radar's Doppler says it stands still, the mean specific force gives the
// gravity direction (roll and pitch; yaw and position are set to zero, the odometry
// frame) and the mean rate the gyro bias. The magnitude difference between the mean
// specific force and gravity is taken as accelerometer bias along gravity. Without a
// static start within InitConfig::timeout it starts anyway from the latest samples and
// the Doppler velocity (a moving start, reported as such).
#pragma once

#include <string>
#include <vector>

#include "coral_introspection/rio/config.hpp"
#include "coral_introspection/rio/types.hpp"

namespace coral_introspection {
namespace rio {

// Mean and per-axis standard deviation of the samples' rate and specific force.
struct ImuStats {
  int n = 0;
  Vec3 gyro_mean = Vec3::Zero(), acc_mean = Vec3::Zero();
  Vec3 gyro_std = Vec3::Zero(), acc_std = Vec3::Zero();
  double duration = 0.0;
};
ImuStats imuStats(const std::vector<ImuSample>& samples);

// R_world_body with the body's mean specific force along world +z and zero yaw.
Quat gravityAlignedOrientation(const Vec3& acc_mean);

class StaticInitializer {
 public:
  explicit StaticInitializer(const RioConfig& cfg) : cfg_(cfg) {}
  // One radar frame at time t: the IMU samples since the previous frame, whether the
  // Doppler says the radar stands (has_doppler false: unknown) and the Doppler velocity
  // of the radar (radar frame) when known. Returns true once *state is the initial state;
  // *moving_start tells a start without the static interval.
  bool addFrame(double t, const std::vector<ImuSample>& interval, bool has_doppler, bool standing,
                const Vec3* v_radar, NavState* state, bool* moving_start);
  void reset();

 private:
  RioConfig cfg_;
  std::vector<ImuSample> still_;  // samples of the current static interval
  double first_t_ = -1.0;
};

}  // namespace rio
}  // namespace coral_introspection
