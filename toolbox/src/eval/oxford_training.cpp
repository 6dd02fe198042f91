#include "coral_introspection/eval/oxford_training.hpp"

#include "coral_introspection/coral/validation.hpp"

#include <algorithm>
#include <cmath>

#include "coral_introspection/radar/deskew.hpp"
#include "coral_introspection/radar/polar_scan.hpp"

namespace coral_introspection {
namespace eval {

std::string OxfordTrainingConfig::validate() const {
  return coral::Problems()
      .nested("rip", rip.validate())
      .require(cfear_k >= 1, "cfear_k", ">= 1", cfear_k)
      .require(cfear_z_min >= 0.0 && cfear_z_min <= 255.0, "cfear_z_min", "in [0, 255]",
               cfear_z_min)
      .require(max_scans == 0 || max_scans >= 2, "max_scans", "0 or >= 2", max_scans)
      .str();
}

radar::RadarFeatures kStrongestPoints(const radar::PolarScan& scan, int k, double z_min,
                                      double min_range, double max_range) {
  radar::RadarFeatures out;
  const double res = scan.range_resolution;
  const int first = std::max(0, static_cast<int>(std::ceil(min_range / res)));
  const int end = std::min(scan.power.cols, static_cast<int>(std::floor(max_range / res)) + 1);
  std::vector<int> bins;
  for (int row = 0; row < scan.power.rows; ++row) {
    if (row < static_cast<int>(scan.valid.size()) && !scan.valid[row]) continue;
    radar::kStrongest(scan.power.ptr<uint8_t>(row), first, end, k, z_min, &bins);
    const double a = scan.azimuths[row];
    for (int b : bins) {
      out.points.emplace_back(b * res * std::cos(a), b * res * std::sin(a), 0.0);  // Eq. 8
      out.intensity.push_back(scan.power.at<uint8_t>(row, b));
      out.stamps.push_back(scan.stamps[row]);
    }
  }
  return out;
}

bool loadOxfordTrainingScans(const OxfordDataset& ds, const OxfordTrainingConfig& cfg,
                             const Progress& progress, std::vector<TrainingScan>* scans,
                             coral::Isometries* T_first_scan, std::string* error) {
  if (const std::string e = cfg.validate(); !e.empty()) {
    if (error) *error = e;
    return false;
  }
  std::size_t n = ds.png_paths.size();
  if (cfg.max_scans > 0) n = std::min<std::size_t>(n, cfg.max_scans);
  scans->assign(n, TrainingScan());
  T_first_scan->clear();
  std::vector<radar::RadarFeatures> rip(n), ks(n);
  std::vector<double> stamps(n);
  for (std::size_t i = 0; i < n; ++i) {
    radar::PolarScan polar;
    std::string err;
    if (!radar::loadOxfordScan(ds.png_paths[i], &polar, &err) ||
        !radar::extractRipFeatures(polar, cfg.rip, &rip[i], &err)) {
      if (error) *error = ds.png_paths[i] + ": " + err;
      return false;
    }
    if (cfg.with_cfear)
      ks[i] = kStrongestPoints(polar, cfg.cfear_k, cfg.cfear_z_min, cfg.rip.min_range,
                               cfg.rip.max_range);
    stamps[i] = polar.stamp;
    T_first_scan->push_back(ds.T_first_scan(i));
    if (progress) progress(i + 1, n);
  }
  // The online de-skew policy (radar/deskew.hpp) on the ground-truth poses: the features
  // are made exactly as the Introspector makes them from the same poses.
  const auto velocities = radar::deskewVelocities(stamps, *T_first_scan);
  for (std::size_t i = 0; i < n; ++i) {
    if (cfg.motion_compensation && velocities[i]) {
      radar::compensateMotion(*velocities[i], stamps[i], &rip[i]);
      radar::compensateMotion(*velocities[i], stamps[i], &ks[i]);
    }
    TrainingScan& s = (*scans)[i];
    s.stamp = stamps[i];
    s.scan.points = std::move(rip[i].points);
    s.scan.origin = coral::Vec3::Zero();
    s.cfear_points = std::move(ks[i].points);
  }
  return true;
}

}  // namespace eval
}  // namespace coral_introspection
