#include "coral_introspection/eval/rio_run.hpp"

#include <algorithm>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "coral_introspection/coral/statistics.hpp"

namespace coral_introspection {
namespace eval {

void RioRun::add(const std::vector<rio::FrameReport>& reports) {
  for (const rio::FrameReport& r : reports) {
    reports_.push_back(r);
    if (r.status == rio::FrameStatus::kInitializing) {
      waiting_.push_back(r.t);
      continue;
    }
    if (r.status == rio::FrameStatus::kRejected) continue;
    for (double t : waiting_) trajectory_.push_back({t, r.state.p, r.state.q});
    waiting_.clear();
    trajectory_.push_back({r.t, r.state.p, r.state.q});
  }
}

std::string RioRun::summary(double wall_seconds, double duration) const {
  int tracked = 0, resets = 0, rejected = 0, init = 0;
  std::vector<double> solve;
  for (const rio::FrameReport& r : reports_) {
    tracked += r.status == rio::FrameStatus::kTracking;
    resets += r.status == rio::FrameStatus::kReset;
    rejected += r.status == rio::FrameStatus::kRejected;
    init += r.status == rio::FrameStatus::kInitializing;
    if (r.status == rio::FrameStatus::kTracking) solve.push_back(r.solve_ms);
  }
  std::ostringstream s;
  s << "frames processed: " << reports_.size() << " (tracked " << tracked << ", initialising "
    << init << ", resets " << resets << ", rejected " << rejected << ")\n";
  if (!solve.empty()) {
    double mean = 0;
    for (double x : solve) mean += x;
    s << "solver time per frame: median " << coral::quantile(solve, 0.5) << " ms, mean "
      << mean / solve.size() << " ms\n";
  }
  if (wall_seconds > 0 && !reports_.empty()) {
    s << "time per frame (everything): " << 1e3 * wall_seconds / reports_.size() << " ms";
    if (duration > 0) s << "; " << duration / wall_seconds << "x real time";
    s << "\n";
  }
  return s.str();
}

std::string timeOffsetSummary(const rio::Estimator& est) {
  const rio::RioConfig& c = est.config();
  std::ostringstream s;
  s << "radar-IMU time offset: ";
  if (!c.time_offset.estimate) {
    s << est.timeOffset() << " s (configured, not estimated)\n";
    return s.str();
  }
  s << "estimated " << est.timeOffset() << " s (prior " << c.radar_time_offset << " +- "
    << c.time_offset.sigma << " s, bound +-" << c.time_offset.max_abs << " s; at the bound on "
    << est.counters().offset_at_bound << " frames)\n";
  return s.str();
}

bool RioRun::writeReports(const std::string& path, std::string* error) const {
  std::ofstream out(path);
  if (!out) {
    if (error) *error = "cannot write " + path;
    return false;
  }
  out << "t,status,px,py,pz,qx,qy,qz,qw,vx,vy,vz,bax,bay,baz,bgx,bgy,bgz,standing,points,"
         "static_points,matched,created,map_matched,landmarks,map_points,point_residuals,"
         "doppler_residuals,outliers,iterations,final_cost,solve_ms,time_offset,message\n";
  for (const rio::FrameReport& r : reports_) {
    const rio::NavState& s = r.state;
    out << std::fixed << std::setprecision(6) << r.t << ',' << rio::toString(r.status);
    for (double v : {s.p.x(), s.p.y(), s.p.z(), s.q.x(), s.q.y(), s.q.z(), s.q.w(), s.v.x(),
                     s.v.y(), s.v.z(), s.ba.x(), s.ba.y(), s.ba.z(), s.bg.x(), s.bg.y(), s.bg.z()})
      out << ',' << v;
    out << ',' << r.standing << ',' << r.points << ',' << r.static_points << ',' << r.matched << ','
        << r.created << ',' << r.map_matched << ',' << r.landmarks << ',' << r.map_points << ','
        << r.point_residuals << ',' << r.doppler_residuals << ',' << r.outliers << ','
        << r.iterations << ',' << r.final_cost << ',' << r.solve_ms << ',' << r.time_offset << ",\""
        << r.message << "\"\n";
  }
  return static_cast<bool>(out);
}

}  // namespace eval
}  // namespace coral_introspection
