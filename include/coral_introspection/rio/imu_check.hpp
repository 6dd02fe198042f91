// Whether the IMU's units can be right, judged from the data at rest. A gyro in deg/s or an
// accelerometer in g does not fail any solve outright: the odometry runs, every health check
// resets it, and a confident, wrong trajectory comes out (TI bag with the gyro in deg/s:
// 221 failed solves, a 2.4 km path). At rest the answer is known: the specific force is
// gravity plus the accelerometer bias, the rate is the gyro bias plus the earth rate
// (7.3e-5 rad/s). Rest = the radar's Doppler says the radar stands still and the specific
// force is steady (std below init/max_acc_std), for init/static_duration without a break.
// The bounds are the health limits of the biases (health/max_acc_bias,
// health/max_gyro_bias): a bias beyond them would reset the odometry anyway. A recording
// without rest is not judged.
#pragma once

#include <string>
#include <vector>

#include "coral_introspection/rio/config.hpp"
#include "coral_introspection/rio/types.hpp"

namespace coral_introspection {
namespace rio {

class ImuRestCheck {
 public:
  explicit ImuRestCheck(const RioConfig& cfg) : cfg_(cfg) {}
  // One radar frame: the IMU samples since the previous frame and whether the Doppler says
  // the radar stands still. Returns why the units cannot be right once a rest interval was
  // long enough to judge, "" otherwise (plausible or not judged yet).
  std::string addFrame(const std::vector<ImuSample>& interval, bool radar_standing);
  bool judged() const { return judged_; }
  void reset();

 private:
  RioConfig cfg_;
  std::vector<ImuSample> rest_;
  bool judged_ = false;
};

}  // namespace rio
}  // namespace coral_introspection
