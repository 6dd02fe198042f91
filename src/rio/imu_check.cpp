#include "coral_introspection/rio/imu_check.hpp"

#include <cmath>
#include <sstream>

#include "coral_introspection/rio/initializer.hpp"

namespace coral_introspection {
namespace rio {

void ImuRestCheck::reset() {
  rest_.clear();
  judged_ = false;
}

std::string ImuRestCheck::addFrame(const std::vector<ImuSample>& interval, bool radar_standing) {
  if (judged_) return "";
  const ImuStats s = imuStats(interval);
  if (!radar_standing || s.n < 2 || !(s.acc_std.maxCoeff() < cfg_.init.max_acc_std)) {
    rest_.clear();
    return "";
  }
  // Consecutive intervals share their end sample; a duplicate does not change the means.
  rest_.insert(rest_.end(), interval.begin(), interval.end());
  const ImuStats r = imuStats(rest_);
  if (r.duration < cfg_.init.static_duration) return "";
  judged_ = true;
  std::ostringstream why;
  why.precision(4);
  const double g = cfg_.imu.gravity, f = r.acc_mean.norm(), w = r.gyro_mean.norm();
  if (std::abs(f - g) > cfg_.health.max_acc_bias)
    why << "IMU units: at rest (" << r.duration << " s, the radar standing) the accelerometer "
        << "measures |f| = " << f << ", not gravity (" << g << " m/s^2 +- health/max_acc_bias "
        << cfg_.health.max_acc_bias << "): not in m/s^2 (in g?)";
  else if (w > cfg_.health.max_gyro_bias)
    why << "IMU units: at rest (" << r.duration << " s, the radar standing) the gyroscope "
        << "measures |omega| = " << w << " (earth rate 7.3e-05 rad/s plus a bias of at most "
        << "health/max_gyro_bias " << cfg_.health.max_gyro_bias << " rad/s): not in rad/s "
        << "(in deg/s?)";
  return why.str();
}

}  // namespace rio
}  // namespace coral_introspection
