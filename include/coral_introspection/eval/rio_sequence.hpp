// A plain-text radar-inertial sequence (IMU samples, radar frames, optional ground truth)
// so the odometry runs, and is evaluated, without ROS: simulated sequences are written
// in it and real recordings can be converted to it.
//   imu <t> <ax> <ay> <az> <gx> <gy> <gz>
//   radar <t> <n>           followed by n lines: <x> <y> <z> <radial_velocity> <intensity>
//   gt <t> <px> <py> <pz> <qx> <qy> <qz> <qw>      (body pose in the world, optional)
// Lines are in time order; '#' starts a comment.
#pragma once

#include <string>
#include <vector>

#include "coral_introspection/rio/types.hpp"

namespace coral_introspection {
namespace core {

struct StampedPose {
  double t = 0.0;
  rio::Vec3 p = rio::Vec3::Zero();
  rio::Quat q = rio::Quat::Identity();
};

struct RioSequence {
  std::vector<rio::ImuSample> imu;
  std::vector<rio::RadarFrame> radar;
  std::vector<StampedPose> ground_truth;
};

bool writeRioSequence(const std::string& path, const RioSequence& seq, std::string* error);
bool readRioSequence(const std::string& path, RioSequence* seq, std::string* error);

// Replays the sequence through `on_imu` / `on_radar` in time order (radar after the IMU
// samples of the same time).
template <class OnImu, class OnRadar>
void replay(const RioSequence& seq, OnImu&& on_imu, OnRadar&& on_radar) {
  std::size_t i = 0, r = 0;
  while (i < seq.imu.size() || r < seq.radar.size()) {
    if (r >= seq.radar.size() || (i < seq.imu.size() && seq.imu[i].t <= seq.radar[r].t))
      on_imu(seq.imu[i++]);
    else
      on_radar(seq.radar[r++]);
  }
}

}  // namespace core
}  // namespace coral_introspection
