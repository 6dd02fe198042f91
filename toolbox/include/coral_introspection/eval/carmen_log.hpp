// 2D laser logs in CARMEN format (.clf, or .clf.bz2 read through libbz2) with the SLAM
// benchmark's ground-truth relations (Kuemmerle et al. 2009; ../shared/data/radish_aces):
// FLASER scans and `.relations` lines "t1 t2 x y z roll pitch yaw", the pose of the scan at
// t2 in the frame of the scan at t1 (checked on ACES: p_1 = T_1_2 p_2 brings the median
// nearest-neighbour distance from 0.10 m with the identity to 0.033 m; the inverse gives
// 0.19 m). t is the FLASER field just before the hostname (ipc_timestamp).
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "coral_introspection/eval/training_set.hpp"

namespace coral_introspection {
namespace eval {

struct CarmenLaserScan {
  double stamp = 0.0;            // ipc_timestamp [s]
  std::vector<double> ranges;    // [m], beam i at start_angle + i * angle_increment
  Eigen::Vector3d laser_pose{};  // x, y, theta of the log (raw odometry) [m, m, rad]
  // The geometry a ROBOTLASER1 line states (start_angle, angular_resolution [rad], maximum_range
  // [m]: readings at or past it are no return); NaN for FLASER, whose lines state none.
  double start_angle = NAN, angle_increment = NAN, max_range = NAN;
};

// Beam geometry of the FLASER messages. A FLASER line gives only its number of readings, so by
// default (NaN) the spacing follows from it as CARMEN's readers guess it for a SICK LMS
// (carmen_laser_guess_angle_increment): 180 / 181 beams 1 deg, 360 / 361 0.5 deg, both over 180
// deg from -90 deg; 400 / 401 0.25 deg over 100 deg from -50 deg; any other count 180 deg over
// count - 1 steps. The Radish logs' 180 beams thus lie at -90 + i deg (checked on ACES: 0.5 deg
// offsets or a 180/179 deg spacing fit the relations no better). A fixed spacing read as 1 deg
// would spread a 361-beam scan over 360 deg. Readings >= max_range are "no return".
struct LaserGeometry {
  double start_angle = NAN;      // [rad] beam 0, counter-clockwise from x; NaN: from the count
  double angle_increment = NAN;  // [rad] between beams; NaN: from the count
  double min_range = 0.05;       // [m]
  double max_range = 49.9;       // [m] (ACES saturates at 50.0 m)
  std::string validate() const;  // empty when valid
  // Beam i's bearing [rad] in a scan of `count` readings.
  double bearing(std::size_t count, std::size_t i) const;
};

// Every FLASER line, in file order; in a log without FLASER lines, every ROBOTLASER1 line (CARMEN
// 0.7's laser message: its own beam geometry and range limit, the laser's pose; with or without
// remissions). False with *error on a missing/corrupt file, a malformed FLASER or ROBOTLASER1
// line, or a log with neither (RAWLASER lines carry no pose).
bool readCarmenLog(const std::string& path, std::vector<CarmenLaserScan>* scans,
                   std::string* error);

// Sensor-frame points (z = 0) of the valid readings: in [min_range, max_range) (the lower of
// the geometry's and the line's own), beams where the line's geometry (ROBOTLASER1) or else
// `geometry` puts them.
coral::Points laserPoints(const CarmenLaserScan& scan, const LaserGeometry& geometry);

struct Relation {
  double t1 = 0.0, t2 = 0.0;
  Eigen::Isometry3d T_1_2 = Eigen::Isometry3d::Identity();  // p_1 = T_1_2 p_2
};
bool readRelations(const std::string& path, std::vector<Relation>* relations, std::string* error);
// The log line whose stamp is within 1e-4 s of stamp (relations and corrected poses name scans
// by stamp to 1e-4 s; the first such line); log.size() when none. Log order need not be time
// order.
int logLineAt(const std::vector<CarmenLaserScan>& log, double stamp);

// The relations file of a log: LOG.relations for LOG.clf[.bz2] or LOG.log (the benchmark's
// layout, e.g. aces.clf.bz2 -> aces.relations).
std::string relationsPath(const std::string& log_path);

// One training scan per FLASER scan a relation refers to (matched by stamp to 1e-4 s) and
// one pair per relation, in file order (the earlier scan first). Relations whose stamps
// match no scan are counted in *unmatched and skipped.
bool relationPairs(const std::vector<CarmenLaserScan>& log, const std::vector<Relation>& relations,
                   const LaserGeometry& geometry, std::vector<TrainingScan>* scans,
                   std::vector<ScanPair>* pairs, int* unmatched, std::string* error);

// The loop closures among the benchmark relations of `log`: relations joining scans more
// than `min_lines` FLASER lines apart (1,245 of Intel's 2,984 at 30), as relationPairs makes
// them. False with *error on an unreadable relations file.
bool loopRelationPairs(const std::vector<CarmenLaserScan>& log, const std::string& relations_path,
                       const LaserGeometry& geometry, int min_lines,
                       std::vector<TrainingScan>* scans, std::vector<ScanPair>* pairs,
                       std::string* error);

// Keyframes of a log as a 2D SLAM front end takes them, with no reference: the first scan, then
// every scan whose raw odometry moved at least min_distance [m] or turned at least min_angle
// [rad] from the last keyframe (gmapping's linearUpdate / angularUpdate). Their points, their raw
// odometry poses and their log lines, in log order. False with *error on an invalid geometry, a
// non-positive distance or angle, or a log of fewer than two keyframes.
bool logKeyframes(const std::vector<CarmenLaserScan>& log, const LaserGeometry& geometry,
                  double min_distance, double min_angle, std::vector<TrainingScan>* scans,
                  coral::Isometries* T_world_odom, std::vector<int>* raw_index, std::string* error);

// A SLAM-corrected trajectory on the raw log
// (../shared/data/radish_intel/*_corrected_poses_on_raw.csv: "corrected_idx, raw_flaser_idx,
// raw_ipc_timestamp, x, y, theta", # comments): the scans it covers in log order, their corrected
// poses (reference) and the log's raw odometry poses (laser_pose), all as planar isometries. False
// with *error on an unreadable file or an index outside the log.
bool correctedSequence(const std::vector<CarmenLaserScan>& log, const std::string& corrected_csv,
                       const LaserGeometry& geometry, std::vector<TrainingScan>* scans,
                       coral::Isometries* T_world_ref, coral::Isometries* T_world_odom,
                       std::vector<int>* raw_index, std::string* error);

}  // namespace eval
}  // namespace coral_introspection
