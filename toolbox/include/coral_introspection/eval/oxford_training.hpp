// Training scans from an Oxford Radar RobotCar style folder (paper Sec. V-A): RIP features
// for CorAl / MME / NDT and k-strongest points for the CFEAR baselines, both motion
// compensated by the online de-skew policy (radar/deskew.hpp) on the ground-truth poses.
#pragma once

#include <string>
#include <vector>

#include "coral_introspection/eval/oxford_dataset.hpp"
#include "coral_introspection/eval/training_set.hpp"
#include "coral_introspection/radar/rip_features.hpp"

namespace coral_introspection {
namespace eval {

struct OxfordTrainingConfig {
  radar::RipConfig rip;       // CorAl-Radar: k = 12, z_min = 70, w = 2, min range 2.5 m
  bool with_cfear = true;     // also extract the CFEAR input points
  int cfear_k = 12;           // CFEAR k-strongest: k = 12 ...
  double cfear_z_min = 60.0;  // ... z_min = 60 (Sec. V-A b)
  // Sec. V-A: "in all cases, we have compensated for motion distortion", with the velocity
  // the online policy derives from the ground-truth poses (radar::deskewVelocities).
  bool motion_compensation = true;
  int max_scans = 0;             // use only the first max_scans scans; 0 = all
  std::string validate() const;  // empty when valid
};

// k-strongest bins (>= z_min, beyond rip.min_range) of every valid azimuth as Cartesian
// points (Eq. 8) with their azimuth stamps.
radar::RadarFeatures kStrongestPoints(const radar::PolarScan& scan, int k, double z_min,
                                      double min_range, double max_range);

// Loads every scan of `ds` (sensor frames, origin 0) and the accumulated GT poses
// T_first_scan. False with *error on unreadable scans or an invalid config; never throws.
bool loadOxfordTrainingScans(const OxfordDataset& ds, const OxfordTrainingConfig& cfg,
                             const Progress& progress, std::vector<TrainingScan>* scans,
                             coral::Isometries* T_first_scan, std::string* error);

}  // namespace eval
}  // namespace coral_introspection
