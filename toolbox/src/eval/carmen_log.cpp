#include "coral_introspection/eval/carmen_log.hpp"

#include <bzlib.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>

#include "coral_introspection/config/text_fields.hpp"
#include "coral_introspection/coral/types.hpp"
#include "coral_introspection/coral/validation.hpp"

namespace coral_introspection {
namespace eval {

std::string LaserGeometry::validate() const {
  return coral::Problems()
      .require(std::isnan(angle_increment) || angle_increment > 0.0, "angle_increment",
               "> 0 rad (NaN: from the beam count)", angle_increment)
      .require(!std::isinf(start_angle), "start_angle", "finite (NaN: from the beam count)",
               start_angle)
      .require(min_range >= 0.0 && min_range < max_range, "min_range", "in [0, max_range) m",
               min_range)
      .str();
}

namespace {

// Whole file as text; .bz2 files are decompressed (every concatenated stream).
bool readText(const std::string& path, std::string* text, std::string* error) {
  text->clear();
  const bool bz2 = path.size() > 4 && path.compare(path.size() - 4, 4, ".bz2") == 0;
  if (!bz2) {
    std::ifstream f(path, std::ios::binary);
    if (!f) return coral::fail(error, "cannot open " + path);
    std::ostringstream s;
    s << f.rdbuf();
    *text = s.str();
    return true;
  }
  std::unique_ptr<FILE, int (*)(FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!f) return coral::fail(error, "cannot open " + path);
  std::vector<char> unused;
  char buf[1 << 16];
  while (true) {
    int err = BZ_OK;
    BZFILE* bz =
        BZ2_bzReadOpen(&err, f.get(), 0, 0, unused.data(), static_cast<int>(unused.size()));
    if (err != BZ_OK) return coral::fail(error, path + ": not a bzip2 file");
    while (err == BZ_OK) {
      const int n = BZ2_bzRead(&err, bz, buf, sizeof(buf));
      if (err == BZ_OK || err == BZ_STREAM_END) text->append(buf, n);
    }
    if (err != BZ_STREAM_END) {
      BZ2_bzReadClose(&err, bz);
      return coral::fail(error, path + ": corrupt bzip2 data");
    }
    void* rest = nullptr;
    int n_rest = 0;
    BZ2_bzReadGetUnused(&err, bz, &rest, &n_rest);
    unused.assign(static_cast<char*>(rest), static_cast<char*>(rest) + n_rest);
    BZ2_bzReadClose(&err, bz);
    // Another stream follows when bytes are left over or the file is not at its end.
    if (unused.empty()) {
      const int c = std::fgetc(f.get());
      if (c == EOF) return true;
      std::ungetc(c, f.get());
    }
  }
}

// ROBOTLASER1 laser_type start_angle field_of_view angular_resolution maximum_range accuracy
// remission_mode num_readings [ranges] [num_remissions [remissions]] laser_pose_x laser_pose_y
// laser_pose_theta robot_pose_x robot_pose_y robot_pose_theta laser_tv laser_rv
// forward_safety_dist side_safety_dist [turn_axis] ipc_timestamp hostname logger_timestamp.
// CARMEN 0.7 writes num_remissions and turn_axis; older loggers neither: told apart by the first
// field after the ranges (an integer count or a pose) and the number of fields left (13 or 14
// without remissions, 1 + n + 13 or 14 with).
bool parseRobotLaser(const std::string& rest, CarmenLaserScan* s) {
  std::istringstream ls(rest);
  std::vector<std::string> f;
  for (std::string w; ls >> w;) f.push_back(w);
  auto num = [&](std::size_t i, double* v) {
    return i < f.size() && config::parseFiniteNumber(f[i], v);
  };
  double type, start, fov, res, max_range, accuracy, mode, count;
  if (!num(0, &type) || !num(1, &start) || !num(2, &fov) || !num(3, &res) || !num(4, &max_range) ||
      !num(5, &accuracy) || !num(6, &mode) || !num(7, &count) || count < 1.0 ||
      count != std::floor(count) || count > 1e6 || !(res > 0.0) || !(max_range > 0.0))
    return false;
  const std::size_t n = static_cast<std::size_t>(count), first = 8;
  if (f.size() < first + n + 13) return false;
  s->ranges.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    if (!num(first + i, &s->ranges[i])) return false;
  std::size_t at = first + n;  // the fields after the ranges
  const std::size_t left = f.size() - at;
  // num_remissions is written as an integer ("%d"); a pose field never is ("%f"): so a field of
  // digits whose count leaves 13 or 14 fields is the remissions' count.
  const bool digits = f[at].find_first_not_of("0123456789") == std::string::npos;
  const std::size_t remissions = digits ? std::strtoul(f[at].c_str(), nullptr, 10) : 0;
  if (digits && remissions < left && remissions + 1 + 13 <= left && left - 1 - remissions <= 14)
    at += 1 + remissions;
  else if (left != 13 && left != 14)
    return false;
  double pose[3];
  for (int k = 0; k < 3; ++k)
    if (!num(at + k, &pose[k])) return false;
  s->laser_pose = Eigen::Vector3d(pose[0], pose[1], pose[2]);
  s->start_angle = start;
  s->angle_increment = res;
  s->max_range = max_range;
  return num(f.size() - 3, &s->stamp);  // ipc_timestamp, before the hostname
}

}  // namespace

bool readCarmenLog(const std::string& path, std::vector<CarmenLaserScan>* scans,
                   std::string* error) {
  std::string text;
  if (!readText(path, &text, error)) return false;
  scans->clear();
  std::vector<CarmenLaserScan> robot_laser;  // ROBOTLASER1 scans, used when there is no FLASER
  std::size_t raw_laser = 0;                 // RAWLASER lines (no pose: not used)
  std::istringstream in(text);
  std::string line;
  for (std::size_t n = 1; std::getline(in, line); ++n) {
    if (line.rfind("ROBOTLASER1 ", 0) == 0) {
      CarmenLaserScan s;
      if (!parseRobotLaser(line.substr(12), &s))
        return coral::fail(error, path + ":" + std::to_string(n) + ": malformed ROBOTLASER1 line");
      robot_laser.push_back(std::move(s));
      continue;
    }
    raw_laser += line.rfind("RAWLASER", 0) == 0;
    if (line.rfind("FLASER ", 0) != 0) continue;
    // FLASER num_readings [ranges] x y theta odom_x odom_y odom_theta ipc_timestamp host ...
    std::istringstream ls(line.substr(7));
    int count = 0;
    CarmenLaserScan s;
    ls >> count;
    s.ranges.resize(std::max(count, 0));
    for (double& r : s.ranges) ls >> r;
    double odom[3];
    ls >> s.laser_pose.x() >> s.laser_pose.y() >> s.laser_pose.z() >> odom[0] >> odom[1] >>
        odom[2] >> s.stamp;
    if (!ls || count <= 0)
      return coral::fail(error, path + ":" + std::to_string(n) + ": malformed FLASER line");
    scans->push_back(std::move(s));
  }
  // A log may carry each scan twice (FLASER for old readers beside ROBOTLASER1): the FLASER
  // lines then, as before ROBOTLASER1 was read.
  if (scans->empty()) *scans = std::move(robot_laser);
  if (scans->empty())
    return coral::fail(error, path + ": no FLASER or ROBOTLASER1 line (laser scans with a pose)" +
                                  (raw_laser ? "; its " + std::to_string(raw_laser) +
                                                   " RAWLASER lines carry no pose"
                                             : std::string()));
  return true;
}

double LaserGeometry::bearing(std::size_t count, std::size_t i) const {
  // CARMEN's guess (logtools' carmen_laser_guess_fov / _angle_increment) for the spacing; the
  // fan starts at minus half the mode's full field (180 or 100 deg).
  const double deg = M_PI / 180.0;
  const bool narrow = count == 400 || count == 401;
  double inc = angle_increment;
  if (std::isnan(inc)) {
    if (count == 180 || count == 181)
      inc = deg;
    else if (count == 360 || count == 361)
      inc = 0.5 * deg;
    else if (narrow)
      inc = 0.25 * deg;
    else
      inc = count > 1 ? M_PI / static_cast<double>(count - 1) : 0.0;
  }
  const double start = std::isnan(start_angle) ? (narrow ? -50.0 * deg : -M_PI / 2.0) : start_angle;
  return start + static_cast<double>(i) * inc;
}

coral::Points laserPoints(const CarmenLaserScan& scan, const LaserGeometry& g) {
  // A ROBOTLASER1 line states its own geometry and range limit; a FLASER line (NaN) does not.
  LaserGeometry own = g;
  if (std::isfinite(scan.angle_increment)) {
    own.start_angle = scan.start_angle;
    own.angle_increment = scan.angle_increment;
  }
  const double max_range =
      std::isfinite(scan.max_range) ? std::min(g.max_range, scan.max_range) : g.max_range;
  coral::Points p;
  for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
    const double r = scan.ranges[i], a = own.bearing(scan.ranges.size(), i);
    if (r >= g.min_range && r < max_range) p.emplace_back(r * std::cos(a), r * std::sin(a), 0.0);
  }
  return p;
}

bool readRelations(const std::string& path, std::vector<Relation>* relations, std::string* error) {
  std::ifstream in(path);
  if (!in) return coral::fail(error, "cannot open " + path);
  relations->clear();
  std::string line;
  for (std::size_t n = 1; std::getline(in, line); ++n) {
    if (line.find_first_not_of(" \t\r") == std::string::npos || line[0] == '#') continue;
    std::istringstream ls(line);
    Relation r;
    double x, y, z, roll, pitch, yaw;
    if (!(ls >> r.t1 >> r.t2 >> x >> y >> z >> roll >> pitch >> yaw))
      return coral::fail(error,
                         path + ":" + std::to_string(n) + ": expected t1 t2 x y z roll pitch yaw");
    r.T_1_2.translation() = Eigen::Vector3d(x, y, z);
    r.T_1_2.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                        Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                        Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                           .toRotationMatrix();
    relations->push_back(r);
  }
  return true;
}

bool relationPairs(const std::vector<CarmenLaserScan>& log, const std::vector<Relation>& relations,
                   const LaserGeometry& geometry, std::vector<TrainingScan>* scans,
                   std::vector<ScanPair>* pairs, int* unmatched, std::string* error) {
  if (const std::string e = geometry.validate(); !e.empty()) return coral::fail(error, e);
  std::map<double, std::size_t> by_stamp;  // stamp -> log index
  for (std::size_t i = 0; i < log.size(); ++i) by_stamp.emplace(log[i].stamp, i);
  auto find = [&](double t) -> int {
    auto it = by_stamp.lower_bound(t - 1e-4);
    return it != by_stamp.end() && it->first <= t + 1e-4 ? static_cast<int>(it->second) : -1;
  };
  std::map<int, int> scan_of;  // log index -> training scan index
  auto add = [&](int li) {
    auto [it, fresh] = scan_of.emplace(li, static_cast<int>(scans->size()));
    if (fresh) {
      TrainingScan s;
      s.stamp = log[li].stamp;
      s.scan.points = laserPoints(log[li], geometry);
      scans->push_back(std::move(s));
    }
    return it->second;
  };
  scans->clear();
  pairs->clear();
  *unmatched = 0;
  for (const Relation& r : relations) {
    const int i1 = find(r.t1), i2 = find(r.t2);
    if (i1 < 0 || i2 < 0) {
      ++*unmatched;
      continue;
    }
    const bool fwd = r.t1 <= r.t2;  // the earlier scan becomes a
    const int a = add(fwd ? i1 : i2), b = add(fwd ? i2 : i1);
    pairs->push_back({a, b, fwd ? r.T_1_2 : r.T_1_2.inverse()});
  }
  return true;
}

std::string relationsPath(const std::string& log_path) {
  std::string rel = log_path;
  for (const char* ext : {".bz2", ".clf", ".log"})
    if (rel.size() > 4 && rel.compare(rel.size() - 4, 4, ext) == 0) rel.resize(rel.size() - 4);
  return rel + ".relations";
}

int logLineAt(const std::vector<CarmenLaserScan>& log, double stamp) {
  // Mostly in time order, so a binary search finds most stamps; but a log's lines need not be
  // (the Intel log's FLASER stamps step back 631 times, by up to 0.6 s), and there the search
  // lands beside the line: it is then looked for line by line.
  const auto it = std::lower_bound(log.begin(), log.end(), stamp - 1e-4,
                                   [](const CarmenLaserScan& l, double t) { return l.stamp < t; });
  if (it != log.end() && std::abs(it->stamp - stamp) <= 1e-4)
    return static_cast<int>(it - log.begin());
  for (std::size_t i = 0; i < log.size(); ++i)
    if (std::abs(log[i].stamp - stamp) <= 1e-4) return static_cast<int>(i);
  return static_cast<int>(log.size());
}

bool loopRelationPairs(const std::vector<CarmenLaserScan>& log, const std::string& relations_path,
                       const LaserGeometry& geometry, int min_lines,
                       std::vector<TrainingScan>* scans, std::vector<ScanPair>* pairs,
                       std::string* error) {
  std::vector<Relation> relations, loops;
  if (!readRelations(relations_path, &relations, error)) return false;
  for (const Relation& r : relations)
    if (std::abs(logLineAt(log, r.t1) - logLineAt(log, r.t2)) > min_lines) loops.push_back(r);
  int unmatched = 0;
  return relationPairs(log, loops, geometry, scans, pairs, &unmatched, error);
}

namespace {
// Log line `line` as a graph node: its scan (valid readings), its raw odometry pose and the line.
void appendLogScan(const std::vector<CarmenLaserScan>& log, std::size_t line,
                   const LaserGeometry& geometry, std::vector<TrainingScan>* scans,
                   coral::Isometries* T_world_odom, std::vector<int>* raw_index) {
  const CarmenLaserScan& l = log[line];
  TrainingScan t;
  t.stamp = l.stamp;
  t.scan.points = laserPoints(l, geometry);
  scans->push_back(std::move(t));
  T_world_odom->push_back(coral::se2(l.laser_pose.x(), l.laser_pose.y(), l.laser_pose.z()));
  raw_index->push_back(static_cast<int>(line));
}
}  // namespace

bool logKeyframes(const std::vector<CarmenLaserScan>& log, const LaserGeometry& geometry,
                  double min_distance, double min_angle, std::vector<TrainingScan>* scans,
                  coral::Isometries* T_world_odom, std::vector<int>* raw_index,
                  std::string* error) {
  if (const std::string e = geometry.validate(); !e.empty()) return coral::fail(error, e);
  if (!(min_distance > 0.0) || !(min_angle > 0.0))
    return coral::fail(error, "keyframe distance and angle must be > 0");
  scans->clear();
  T_world_odom->clear();
  raw_index->clear();
  for (std::size_t l = 0; l < log.size(); ++l) {
    const Eigen::Vector3d& p = log[l].laser_pose;
    if (!raw_index->empty()) {
      const Eigen::Vector3d& last = log[static_cast<std::size_t>(raw_index->back())].laser_pose;
      const double turned = std::abs(std::remainder(p.z() - last.z(), 2.0 * M_PI));
      if ((p.head<2>() - last.head<2>()).norm() < min_distance && turned < min_angle) continue;
    }
    appendLogScan(log, l, geometry, scans, T_world_odom, raw_index);
  }
  if (scans->size() < 2)
    return coral::fail(error, "fewer than two keyframes (" + std::to_string(log.size()) +
                                  " scans; the odometry hardly moves)");
  return true;
}

bool correctedSequence(const std::vector<CarmenLaserScan>& log, const std::string& corrected_csv,
                       const LaserGeometry& geometry, std::vector<TrainingScan>* scans,
                       coral::Isometries* T_world_ref, coral::Isometries* T_world_odom,
                       std::vector<int>* raw_index, std::string* error) {
  if (const std::string e = geometry.validate(); !e.empty()) return coral::fail(error, e);
  std::ifstream in(corrected_csv);
  if (!in) return coral::fail(error, corrected_csv + ": cannot read");
  scans->clear();
  T_world_ref->clear();
  T_world_odom->clear();
  raw_index->clear();
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (line.empty() || line[0] == '#') continue;
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream s(line);
    long idx = 0, raw = 0;
    double stamp = 0, x = 0, y = 0, theta = 0;
    if (!(s >> idx >> raw >> stamp >> x >> y >> theta))
      return coral::fail(error, corrected_csv + ":" + std::to_string(n) + ": malformed line");
    if (raw < 0 || raw >= static_cast<long>(log.size()))
      return coral::fail(error, corrected_csv + ":" + std::to_string(n) + ": FLASER index " +
                                    std::to_string(raw) + " outside the log (" +
                                    std::to_string(log.size()) + " scans)");
    appendLogScan(log, static_cast<std::size_t>(raw), geometry, scans, T_world_odom, raw_index);
    T_world_ref->push_back(coral::se2(x, y, theta));
  }
  if (scans->empty()) return coral::fail(error, corrected_csv + ": no poses");
  return true;
}

}  // namespace eval
}  // namespace coral_introspection
