#include "coral_introspection/rio/initializer.hpp"

#include "coral_introspection/coral/types.hpp"

namespace coral_introspection {
namespace rio {

ImuStats imuStats(const std::vector<ImuSample>& samples) {
  ImuStats s;
  s.n = static_cast<int>(samples.size());
  if (s.n == 0) return s;
  for (const ImuSample& x : samples) s.gyro_mean += x.gyro, s.acc_mean += x.acc;
  s.gyro_mean /= s.n;
  s.acc_mean /= s.n;
  Vec3 vg = Vec3::Zero(), va = Vec3::Zero();
  for (const ImuSample& x : samples) {
    vg += (x.gyro - s.gyro_mean).cwiseAbs2();
    va += (x.acc - s.acc_mean).cwiseAbs2();
  }
  s.gyro_std = (vg / s.n).cwiseSqrt();
  s.acc_std = (va / s.n).cwiseSqrt();
  s.duration = samples.back().t - samples.front().t;
  return s;
}

Quat gravityAlignedOrientation(const Vec3& acc_mean) {
  // The specific force at rest points up: R acc_mean / |acc_mean| = e_z. The rotation
  // taking a to e_z about a x e_z, then the yaw of that rotation removed.
  const Vec3 a = acc_mean.normalized();
  Quat q = Quat::FromTwoVectors(a, Vec3::UnitZ());
  const Mat3 R = q.toRotationMatrix();
  const double yaw = coral::yawOf(R);
  return (Eigen::AngleAxisd(-yaw, Vec3::UnitZ()) * q).normalized();
}

void StaticInitializer::reset() {
  still_.clear();
  first_t_ = -1.0;
}

bool StaticInitializer::addFrame(double t, const std::vector<ImuSample>& interval, bool has_doppler,
                                 bool standing, const Vec3* v_radar, NavState* state,
                                 bool* moving_start) {
  if (first_t_ < 0.0) first_t_ = t;
  const ImuStats s = imuStats(interval);
  const bool imu_still = s.n >= 2 && s.gyro_std.maxCoeff() < cfg_.init.max_gyro_std &&
                         s.acc_std.maxCoeff() < cfg_.init.max_acc_std;
  const bool still = imu_still && (!has_doppler || standing);
  if (still)
    still_.insert(still_.end(), interval.begin(), interval.end());
  else
    still_.clear();
  *moving_start = false;
  const ImuStats rest = imuStats(still_);
  NavState x;
  x.t = t;
  if (still && rest.duration >= cfg_.init.static_duration) {
    x.q = gravityAlignedOrientation(rest.acc_mean);
    x.bg = rest.gyro_mean;
    x.ba = rest.acc_mean - cfg_.imu.gravity * rest.acc_mean.normalized();
    *state = x;
    return true;
  }
  if (t - first_t_ < cfg_.init.timeout || s.n < 2) return false;
  // Moving start: gravity from the latest interval's mean (rough), Doppler velocity.
  x.q = gravityAlignedOrientation(s.acc_mean);
  if (v_radar) {
    const Vec3 v_body = cfg_.extrinsics.R * *v_radar - s.gyro_mean.cross(cfg_.extrinsics.t);
    x.v = x.q * v_body;
  }
  *state = x;
  *moving_start = true;
  return true;
}

}  // namespace rio
}  // namespace coral_introspection
