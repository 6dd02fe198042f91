// The one de-skew policy of spinning-radar scans (paper Sec. V-A: "compensated for motion
// distortion"), shared by the online Introspector and every training / evaluation path, so
// the classifier judges features made exactly the way its training features were made.
//
// Policy: within one unbroken sequence of posed scans, scan i is de-skewed with the
// component-wise median of the last <= window inter-scan twists up to scan i (the latest
// twist alone while fewer than `window` are known); the first scan of a sequence uses the
// twist towards the second one. The median ignores a single odometry jump, which would
// otherwise distort the scans next to it (2 m/s of false velocity for a 0.5 m jump at 4 Hz)
// and flag clean pairs.
#pragma once

#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "coral_introspection/radar/motion_compensation.hpp"

namespace coral_introspection {
namespace radar {

struct DeskewConfig {
  bool enabled = true;  // radar: de-skew features with the pose-derived velocity
  int window = 3;       // [intervals] inter-scan twists in the median (odd, 1 = latest only)
  std::string validate() const;  // empty when valid
};

// Constant body velocity that moves the sensor from T_fixed_prev to T_fixed_curr in dt
// seconds: log(T_prev_curr) / dt (twistFromRelativePose), the same twist in both sensor
// frames. false for dt <= 0 (or non-finite).
bool twistBetween(const Eigen::Isometry3d& T_fixed_prev, const Eigen::Isometry3d& T_fixed_curr,
                  double dt, Twist* twist);

// Component-wise median of the twists (upper median for an even count); zero when empty.
Twist medianTwist(const std::deque<Twist>& twists);

// Pose history of one unbroken scan sequence and the velocities the policy derives from it.
class VelocityHistory {
 public:
  explicit VelocityHistory(int window = DeskewConfig().window) : window_(window) {}
  void reset();  // a new sequence starts with the next add()
  // Records the next scan's pose; true when the twist of the interval towards it is known
  // (not the first scan of the sequence and its stamp later than the previous one).
  bool add(double stamp, const Eigen::Isometry3d& T_fixed_sensor);
  bool hasVelocity() const { return !twists_.empty(); }
  // De-skew velocity of the latest scan (the policy above); zero twist before any interval.
  Twist deskewVelocity() const;
  // Twist of the last interval alone (the odometry's latest velocity, e.g. for the Doppler
  // check, which must see a jump rather than filter it).
  const Twist& lastTwist() const { return last_; }

 private:
  int window_;
  std::optional<std::pair<double, Eigen::Isometry3d>> previous_;
  std::deque<Twist> twists_;
  Twist last_;
};

// De-skew velocity of every scan of a recorded sequence by the policy above (training and
// evaluation): a sequence breaks where the stamp does not increase. nullopt for a scan that
// is alone in its sequence. stamps and T_fixed_sensor have the same size.
std::vector<std::optional<Twist>> deskewVelocities(const std::vector<double>& stamps,
                                                   const coral::Isometries& T_fixed_sensor,
                                                   const DeskewConfig& cfg = DeskewConfig());

}  // namespace radar
}  // namespace coral_introspection
