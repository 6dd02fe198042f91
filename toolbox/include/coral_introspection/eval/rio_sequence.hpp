// A plain-text radar-inertial sequence (IMU samples, radar frames, optional ground truth)
// so the odometry runs, and is evaluated, without ROS: simulated sequences are written
// in it and real recordings can be converted to it.
//   imu <t> <ax> <ay> <az> <gx> <gy> <gz>
//   radar <t> <n>           followed by n lines: <x> <y> <z> <radial_velocity> <intensity>
//   gt <t> <px> <py> <pz> <qx> <qy> <qz> <qw>      (body pose in the world, optional)
//   baro <t> <pressure [Pa]>                        (barometer, optional)
// Lines are in time order; '#' starts a comment.
#pragma once

#include <string>
#include <vector>

#include "coral_introspection/rio/barometer.hpp"
#include "coral_introspection/rio/types.hpp"

namespace coral_introspection {
namespace eval {

struct StampedPose {
  double t = 0.0;
  rio::Vec3 p = rio::Vec3::Zero();
  rio::Quat q = rio::Quat::Identity();
};

struct RioSequence {
  std::vector<rio::ImuSample> imu;
  std::vector<rio::RadarFrame> radar;
  std::vector<StampedPose> ground_truth;
  std::vector<rio::BaroSample> baro;
};

bool writeRioSequence(const std::string& path, const RioSequence& seq, std::string* error);
bool readRioSequence(const std::string& path, RioSequence* seq, std::string* error);

// Replays the sequence through `on_imu` / `on_radar` / `on_baro` in time order (at equal
// times: IMU, barometer, then radar).
template <class OnImu, class OnRadar, class OnBaro>
void replay(const RioSequence& seq, OnImu&& on_imu, OnRadar&& on_radar, OnBaro&& on_baro) {
  std::size_t i = 0, r = 0, b = 0;
  auto t = [](std::size_t k, const auto& v) { return k < v.size() ? v[k].t : 1e300; };
  while (i < seq.imu.size() || r < seq.radar.size() || b < seq.baro.size()) {
    const double ti = t(i, seq.imu), tr = t(r, seq.radar), tb = t(b, seq.baro);
    if (ti <= tr && ti <= tb)
      on_imu(seq.imu[i++]);
    else if (tb <= tr)
      on_baro(seq.baro[b++]);
    else
      on_radar(seq.radar[r++]);
  }
}

// The same without a barometer (its samples are skipped).
template <class OnImu, class OnRadar>
void replay(const RioSequence& seq, OnImu&& on_imu, OnRadar&& on_radar) {
  replay(seq, on_imu, on_radar, [](const rio::BaroSample&) {});
}

}  // namespace eval
}  // namespace coral_introspection
