// Online introspection of a scan stream, ROS-free: feed it posed scans in arrival order; it
// owns the pairing, the velocity history and the one de-skew policy (radar/deskew.hpp),
// CorAl, the classifier and the Doppler check, and returns a report per scan. Not
// thread-safe: one thread feeds it (the nodelet's worker); judgePair() is a pure function
// of its arguments and may run concurrently (check_alignment).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "coral_introspection/online/introspector_config.hpp"
#include "coral_introspection/online/pairing.hpp"
#include "coral_introspection/radar/deskew.hpp"
#include "coral_introspection/radar/doppler.hpp"
#include "coral_introspection/radar/rip_features.hpp"

namespace coral_introspection {
namespace online {

// One scan as it arrives: points in the sensor frame and the sensor pose at its stamp.
struct ScanInput {
  double stamp = 0.0;  // [s] scan time (radar: the reference time of the row stamps)
  uint64_t id = 0;     // caller's tag, returned in the report (the nodelet: stamp in ns)
  // Points in the sensor frame; radar features also carry per-point stamps (de-skew) and
  // intensity. Lidar: points, and per-point stamps where the scan says when each beam was
  // measured (a LaserScan's time_increment).
  radar::RadarFeatures features;
  bool is_radar = false;  // features.stamps are valid: de-skew with the velocity
  // A lidar scan whose features.stamps are valid: de-skewed as radar features are
  // (motion_compensation/enabled), a slow 2D laser's sweep taking a turn's worth of time.
  bool point_stamps = false;
  // 4D radar: radial velocity per point [m/s] (empty: no Doppler check) and, optionally,
  // the point covariances (sensor frame); empty: from the configured polar noise model.
  std::vector<double> radial_velocity;
  coral::Covariances covariances;
  // T_fixed_sensor at `stamp`; nullopt when the pose is unavailable (TF failure): the scan
  // is counted and reported, the stream state is untouched.
  std::optional<Eigen::Isometry3d> T_fixed_sensor;
  std::string pose_error;  // why the pose is unavailable
};

struct Counters {
  uint64_t scans = 0;          // scans offered (with or without pose)
  uint64_t pose_failures = 0;  // no pose (TF failure)
  uint64_t empty_scans = 0;    // no points
  uint64_t pairs = 0, valid_pairs = 0, misaligned = 0;
  uint64_t too_close = 0, gap_resets = 0, time_resets = 0, duplicate_stamps = 0;
  uint64_t doppler_checks = 0, doppler_inconsistent = 0;
  double coral_seconds = 0.0;  // [s] summed CorAl wall time at the pairs' poses
  // CorAl evaluations: 1 per pair, plus 2 per tolerance axis with the relative check.
  uint64_t coral_evaluations = 0;
};

struct DopplerReport {
  radar::ConsistencyResult result;
  coral::Vec3 velocity_odometry = coral::Vec3::Zero();  // last inter-scan twist, sensor frame
  std::size_t num_points = 0;                           // points with a radial velocity
};

// CorAl + verdict of one pair (the result of judgePair).
struct PairJudgement {
  // verdict.coral: CorAl at the pose; verdict.classifier / .relative: the opinions behind
  // verdict.aligned (meaningful when verdict.valid).
  coral::AlignmentVerdict verdict;
  std::string reason;    // why there is no verdict (empty when verdict.valid)
  coral::Scan ref, cur;  // keep_scans: the pair in the reference sensor frame (ref.origin = 0)
  // The pair as the verdict prepared it (filtered clouds, grids, own-cloud moments): more
  // poses of it cost only the other-cloud searches (online self-calibration).
  std::shared_ptr<const coral::CoralPair> prepared;
};

// CorAl of `cur` moved into `ref`'s sensor frame by T_ref_cur, then the verdict at the
// tolerance (coral::judgeAlignment: classifier, relative check or both).
// Both scans in their own sensor frames (origin 0). Computing in the reference frame (not
// the fixed frame) keeps coordinates small and is exactly what training does.
PairJudgement judgePair(coral::Scan ref, const coral::Scan& cur, const Eigen::Isometry3d& T_ref_cur,
                        const IntrospectorConfig& cfg, bool per_point, bool keep_scans = false);

struct Report {
  double stamp = 0.0;
  uint64_t id = 0;
  bool has_pose = false;
  PairAction action = PairAction::kFirst;  // meaningful with has_pose
  bool judged = false;                     // CorAl ran on (reference, this scan)
  double stamp_ref = 0.0;                  // reference scan of the pair (judged)
  uint64_t id_ref = 0;
  Eigen::Isometry3d T_fixed_ref = Eigen::Isometry3d::Identity();
  PairJudgement pair;     // judged: CorAl, verdict; scans only with ProcessOptions::keep_scans
  std::string reason;     // why there is no verdict for this scan (empty with one)
  bool deskewed = false;  // this radar scan was de-skewed now (else: later, or never)
  radar::RadarFeatures features;  // with keep_features: this scan as de-skewed now
  std::optional<DopplerReport> doppler;
  Counters counters;  // totals after this scan
  bool hasVerdict() const { return judged && pair.verdict.valid; }
};

struct ProcessOptions {
  bool per_point = false;      // CorAl per-point entropies (quality cloud)
  bool keep_scans = false;     // Report::pair.ref / cur filled
  bool keep_features = false;  // Report::features filled
};

class Introspector {
 public:
  // Precondition: cfg.validate() is empty (use setConfig to check).
  explicit Introspector(const IntrospectorConfig& cfg = IntrospectorConfig());
  // Takes effect from the next scan; the stream state is kept. False (config unchanged)
  // with *error when invalid.
  bool setConfig(const IntrospectorConfig& cfg, std::string* error);
  const IntrospectorConfig& config() const { return cfg_; }
  // Forgets the stream: the next scan starts a new sequence. Counters are kept.
  void reset();
  Report process(ScanInput scan, const ProcessOptions& options = ProcessOptions());
  const Counters& counters() const { return counters_; }
  // Online self-calibration (calibration/enabled): process() only sets aside the pairs the
  // fraction selects; this runs the set-aside pair's extra CorAl evaluations and the refit.
  // Call it after the verdict of process() is out (the nodelet: after publishing), so the
  // verdict never waits for calibration. Returns true when a pair was processed. From the
  // next pair on, a refit in use (status().in_use) replaces the configured classifier.
  bool calibrate();
  const SelfCalibration& calibration() const { return calibration_; }

 private:
  struct Held {  // the reference scan
    radar::RadarFeatures features;
    Eigen::Isometry3d T_fixed_sensor = Eigen::Isometry3d::Identity();
    double stamp = 0.0;
    uint64_t id = 0;
    bool needs_deskew = false;  // radar scan whose velocity was not known yet
  };
  void checkDoppler(const ScanInput& scan, Report* report);
  void judge(Held& cur, const ProcessOptions& options, Report* report);

  struct CalibrationJob {  // a selected pair, as judgePair prepared it
    std::shared_ptr<const coral::CoralPair> pair;
    Eigen::Isometry3d T_ref_cur = Eigen::Isometry3d::Identity();
    coral::CoralResult at_pose;
  };
  void updateJudgingConfig();

  IntrospectorConfig cfg_;
  IntrospectorConfig judging_;  // cfg_ with the self-calibrated classifier when in use
  SelfCalibration calibration_;
  std::optional<CalibrationJob> pending_;
  ScanPairing pairing_;
  radar::VelocityHistory velocity_;
  std::optional<Held> reference_;
  Counters counters_;
};

}  // namespace online
}  // namespace coral_introspection
