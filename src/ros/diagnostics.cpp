#include "coral_introspection/ros/diagnostics.hpp"

#include <algorithm>

namespace coral_introspection {
namespace ros_adapters {

void Stats::arrived(const std_msgs::Header& h) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++input_.received;
  pending_.emplace(std::make_pair(h.frame_id, h.stamp), ros::WallTime::now());
}

bool Stats::resolvePending(const std_msgs::Header& h) {
  std::lock_guard<std::mutex> lock(mutex_);
  return pending_.erase(std::make_pair(h.frame_id, h.stamp)) > 0;
}

std::vector<std_msgs::Header> Stats::expirePending(double timeout) {
  std::vector<std_msgs::Header> out;
  std::lock_guard<std::mutex> lock(mutex_);
  const ros::WallTime now = ros::WallTime::now();
  for (auto it = pending_.begin(); it != pending_.end();) {
    if ((now - it->second).toSec() <= timeout) {
      ++it;
      continue;
    }
    std_msgs::Header h;
    h.frame_id = it->first.first;
    h.stamp = it->first.second;
    out.push_back(h);
    it = pending_.erase(it);
  }
  return out;
}

void Stats::count(uint64_t InputCounters::*counter, const std::string& error) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++(input_.*counter);
  last_error_ = error;
}

void Stats::nonFinite(std::size_t n) {
  std::lock_guard<std::mutex> lock(mutex_);
  input_.non_finite_points += n;
}

void Stats::processed(const online::Report& r, const ros::Time& stamp, uint64_t dropped) {
  const double latency = std::max(0.0, (ros::Time::now() - stamp).toSec());
  std::lock_guard<std::mutex> lock(mutex_);
  counters_ = r.counters;
  dropped_ = dropped;
  if (r.has_pose) {
    ++with_pose_;
    latency_sum_ += latency;
  }
  if (!r.has_pose || r.action == online::PairAction::kBackwardsReset ||
      r.action == online::PairAction::kDuplicateReset)
    last_error_ = r.reason;
}

void Stats::diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  std::lock_guard<std::mutex> lock(mutex_);
  const InputCounters &i = input_, &li = last_input_;
  const online::Counters &c = counters_, &l = last_counters_;
  const ros::WallTime now = ros::WallTime::now();
  const double dt = std::max(1e-3, (now - last_report_).toSec());
  const uint64_t scans = with_pose_ - last_with_pose_, pairs = c.pairs - l.pairs;
  const uint64_t problems = (c.pose_failures - l.pose_failures) + (i.bad_inputs - li.bad_inputs) +
                            (i.errors - li.errors) + (c.time_resets - l.time_resets) +
                            (c.duplicate_stamps - l.duplicate_stamps);
  const double frac = c.valid_pairs > 0 ? static_cast<double>(c.misaligned) / c.valid_pairs : 0.0;
  using diagnostic_msgs::DiagnosticStatus;
  if (problems > 0)
    stat.summaryf(DiagnosticStatus::WARN, "%lu input problem(s): %s",
                  static_cast<unsigned long>(problems), last_error_.c_str());
  else if (i.received == 0)
    stat.summary(DiagnosticStatus::OK, "waiting for scans");
  else
    stat.summaryf(DiagnosticStatus::OK, "%.1f %% of pairs misaligned", 100.0 * frac);
  stat.add("rate [scans/s]", scans / dt);
  stat.add("latency [s]", scans > 0 ? (latency_sum_ - last_latency_sum_) / scans : 0.0);
  stat.add("processing time [s]", pairs > 0 ? (c.coral_seconds - l.coral_seconds) / pairs : 0.0);
  stat.add("scans received", i.received);
  stat.add("scans processed", with_pose_);
  stat.add("scans dropped (worker busy)", dropped_);
  stat.add("pairs", c.pairs);
  stat.add("valid pairs", c.valid_pairs);
  stat.add("misaligned pairs", c.misaligned);
  stat.add("fraction misaligned", frac);
  stat.add("tf failures", c.pose_failures);
  stat.add("bad inputs", i.bad_inputs);
  stat.add("non-finite points dropped", i.non_finite_points);
  stat.add("time jumps backwards", c.time_resets);
  stat.add("duplicate stamps", c.duplicate_stamps);
  stat.add("reference too old", c.gap_resets);
  stat.add("callback errors", i.errors);
  if (doppler) {
    stat.add("doppler checks", c.doppler_checks);
    stat.add("doppler inconsistent", c.doppler_inconsistent);
  }
  stat.add("last error", last_error_);
  last_input_ = input_;
  last_counters_ = counters_;
  last_latency_sum_ = latency_sum_;
  last_with_pose_ = with_pose_;
  last_report_ = now;
}

}  // namespace ros_adapters
}  // namespace coral_introspection
