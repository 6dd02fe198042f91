#include "coral_introspection/radar/deskew.hpp"

#include <algorithm>
#include <cmath>

#include "coral_introspection/coral/statistics.hpp"
#include "coral_introspection/coral/validation.hpp"

namespace coral_introspection {
namespace radar {

std::string DeskewConfig::validate() const {
  return coral::Problems()
      .require(window >= 1 && window <= 9 && window % 2 == 1, "window", "odd, in [1, 9]", window)
      .str();
}

bool twistBetween(const Eigen::Isometry3d& T_fixed_prev, const Eigen::Isometry3d& T_fixed_curr,
                  double dt, Twist* twist) {
  if (!(dt > 0.0) || !std::isfinite(dt)) return false;
  *twist = twistFromRelativePose(T_fixed_prev.inverse() * T_fixed_curr, dt);  // SE(3) log
  return true;
}

Twist medianTwist(const std::deque<Twist>& twists) {
  Twist out;
  if (twists.empty()) return out;
  std::vector<double> v(twists.size());
  for (int k = 0; k < 6; ++k) {
    for (std::size_t i = 0; i < twists.size(); ++i)
      v[i] = k < 3 ? twists[i].linear[k] : twists[i].angular[k - 3];
    // Per component, a measured value (the upper middle one for an even count).
    (k < 3 ? out.linear[k] : out.angular[k - 3]) = coral::quantile(v, 0.5);
  }
  return out;
}

void VelocityHistory::reset() {
  previous_.reset();
  twists_.clear();
  last_ = Twist();
}

bool VelocityHistory::add(double stamp, const Eigen::Isometry3d& T_fixed_sensor) {
  Twist t;
  const bool ok =
      previous_ && twistBetween(previous_->second, T_fixed_sensor, stamp - previous_->first, &t);
  previous_.emplace(stamp, T_fixed_sensor);
  if (!ok) return false;
  last_ = t;
  twists_.push_back(t);
  while (static_cast<int>(twists_.size()) > window_) twists_.pop_front();
  return true;
}

Twist VelocityHistory::deskewVelocity() const {
  return static_cast<int>(twists_.size()) < window_ ? last_ : medianTwist(twists_);
}

std::vector<std::optional<Twist>> deskewVelocities(const std::vector<double>& stamps,
                                                   const coral::Isometries& T_fixed_sensor,
                                                   const DeskewConfig& cfg) {
  const std::size_t n = std::min(stamps.size(), T_fixed_sensor.size());
  std::vector<std::optional<Twist>> out(n);
  VelocityHistory history(cfg.window);
  std::size_t first = 0;  // first scan of the current sequence
  for (std::size_t i = 0; i < n; ++i) {
    if (i > 0 && !(stamps[i] > stamps[i - 1])) {  // time did not advance: new sequence
      history.reset();
      first = i;
    }
    if (!history.add(stamps[i], T_fixed_sensor[i])) continue;
    out[i] = history.deskewVelocity();
    if (!out[first]) out[first] = out[i];  // first scan: the twist towards the second
  }
  return out;
}

}  // namespace radar
}  // namespace coral_introspection
