#include "coral_introspection/ros/coral_diagnostics.hpp"

#include <algorithm>
#include <sstream>
#include <tuple>

#include "coral_introspection/AlignmentQuality.h"

namespace coral_introspection {
namespace ros_adapters {

void Stats::arrived(const std_msgs::Header& h, const std::string& publisher) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++input_.received;
  input_.lost_upstream += seq_gaps_.offer(publisher, h.seq);
}

void Stats::inputStopped() {
  std::lock_guard<std::mutex> lock(mutex_);
  seq_gaps_ = online::SequenceGaps();
}

void Stats::waitForTf(const std_msgs::Header& h, const ros::Time& receipt) {
  std::lock_guard<std::mutex> lock(mutex_);
  pending_.emplace(Key(h.frame_id, h.stamp), Pending{ros::WallTime::now(), receipt});
}

std::optional<ros::Time> Stats::resolvePending(const std_msgs::Header& h) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = pending_.find(Key(h.frame_id, h.stamp));
  if (it == pending_.end()) return std::nullopt;
  const ros::Time receipt = it->second.receipt;
  pending_.erase(it);
  return receipt;
}

std::vector<std::pair<std_msgs::Header, ros::Time>> Stats::expirePending(double timeout) {
  std::vector<std::pair<std_msgs::Header, ros::Time>> out;
  std::lock_guard<std::mutex> lock(mutex_);
  const ros::WallTime now = ros::WallTime::now();
  for (auto it = pending_.begin(); it != pending_.end();) {
    if ((now - it->second.arrival).toSec() <= timeout) {
      ++it;
      continue;
    }
    std_msgs::Header h;
    h.frame_id = it->first.first;
    h.stamp = it->first.second;
    out.emplace_back(h, it->second.receipt);
    it = pending_.erase(it);
  }
  return out;
}

void Stats::count(uint64_t InputCounters::*counter, const std::string& error) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++(input_.*counter);
  last_error_ = error;
}

void Stats::inputTopicProblem(const std::string& problem) {
  std::lock_guard<std::mutex> lock(mutex_);
  input_topic_problem_ = problem;
}

void Stats::nonFinite(std::size_t n) {
  std::lock_guard<std::mutex> lock(mutex_);
  input_.non_finite_points += n;
}

void Stats::late() {
  std::lock_guard<std::mutex> lock(mutex_);
  ++input_.late;
}

void Stats::tfCleared() {
  std::lock_guard<std::mutex> lock(mutex_);
  ++input_.tf_clears;
}

void Stats::started(const std_msgs::Header& h) {
  std::lock_guard<std::mutex> lock(mutex_);
  busy_.emplace(ros::WallTime::now(), h.stamp);
}

void Stats::idle() {
  std::lock_guard<std::mutex> lock(mutex_);
  busy_.reset();
}

void Stats::finished(const WorkDone& d) {
  std::lock_guard<std::mutex> lock(mutex_);
  busy_.reset();
  if (d.counters) counters_ = *d.counters;
  Window& w = window_;
  ++w.items;
  if (d.counters) {  // went through the Introspector (not a refusal or drop notice)
    ++w.computed;
    w.seconds += d.seconds;
    w.seconds_max = std::max(w.seconds_max, d.seconds);
  }
  if (time_budget > 0.0 && d.seconds > time_budget) {
    ++over_budget_;
    ++w.over_budget;
  }
  if (d.status == AlignmentQuality::DROPPED) return;  // no latency: never reached the worker
  ++w.with_latency;
  w.latency += d.latency;
  w.latency_max = std::max(w.latency_max, d.latency);
  if (d.status == AlignmentQuality::VERDICT) {
    ++verdicts_;
    ++w.verdicts;
    return;
  }
  last_no_verdict_ = d.reason;
  if (d.status == AlignmentQuality::NO_POSE) last_tf_failure_ = d.reason;
  if (d.problem) last_error_ = d.reason;
}

void Stats::calibrated(const online::CalibrationStatus& status) {
  std::lock_guard<std::mutex> lock(mutex_);
  calibration_ = status;
}

void Stats::diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  std::lock_guard<std::mutex> lock(mutex_);
  const InputCounters &i = input_, &li = last_input_;
  const online::Counters &c = counters_, &l = last_counters_;
  const Window& w = window_;
  const ros::WallTime now = ros::WallTime::now();
  const double dt = std::max(1e-3, (now - last_report_).toSec());
  const double busy = busy_ ? (now - busy_->first).toSec() : 0.0;
  const double frac = c.valid_pairs > 0 ? static_cast<double>(c.misaligned) / c.valid_pairs : 0.0;
  const double mean_seconds = w.computed > 0 ? w.seconds / w.computed : 0.0;

  // Each kind of problem since the last report on its own, overload before TF.
  std::vector<std::string> problems;
  if (!input_topic_problem_.empty()) problems.push_back(input_topic_problem_);
  auto add = [&](uint64_t n, const std::string& what) {
    if (n == 0) return;
    std::ostringstream s;
    s << n << " " << what;
    problems.push_back(s.str());
  };
  if (mailbox) std::tie(dropped_, notices_lost_) = mailbox();
  std::ostringstream overload, budget;
  overload << "scan(s) dropped: worker busy (";
  if (w.computed > 0 || busy == 0.0)
    overload << mean_seconds << " s per scan)";
  else
    overload << "on one scan for " << busy << " s)";
  add(dropped_ - last_dropped_, overload.str());
  if (time_budget > 0.0 && busy > time_budget) {
    std::ostringstream s;
    s << "worker busy for " << busy << " s on the scan at t = " << std::fixed
      << busy_->second.toSec() << " (time_budget " << time_budget << " s)";
    problems.push_back(s.str());
  }
  budget << "scan(s) over time_budget " << time_budget << " s (max " << w.seconds_max << " s)";
  add(w.over_budget, budget.str());
  add(c.pose_failures - l.pose_failures, "TF failure(s): " + last_tf_failure_);
  add(i.late - li.late, "scan(s) with TF after tf_timeout (not judged)");
  add(i.unstamped - li.unstamped, "unstamped scan(s) refused");
  add(i.bad_inputs - li.bad_inputs, "bad input(s)");
  add(i.lost_upstream - li.lost_upstream, "scan(s) lost before the nodelet (header.seq gaps)");
  add((c.time_resets - l.time_resets) + (c.duplicate_stamps - l.duplicate_stamps),
      "pairing restart(s) (time jump / duplicate stamp)");
  add(i.errors - li.errors, "callback error(s)");
  using diagnostic_msgs::DiagnosticStatus;
  if (!problems.empty()) {
    std::ostringstream s;
    for (std::size_t k = 0; k < problems.size(); ++k) s << (k ? "; " : "") << problems[k];
    stat.summary(input_topic_problem_.empty() ? DiagnosticStatus::WARN : DiagnosticStatus::ERROR,
                 s.str());
  } else if (i.received == 0) {
    stat.summary(DiagnosticStatus::OK, "waiting for scans");
  } else {
    stat.summaryf(DiagnosticStatus::OK, "%.1f %% of pairs misaligned", 100.0 * frac);
  }
  stat.add("rate [scans/s]", w.items / dt);
  stat.add("verdict rate [1/s]", w.verdicts / dt);
  stat.add("latency [s]", w.with_latency > 0 ? w.latency / w.with_latency : 0.0);
  stat.add("latency max [s]", w.latency_max);
  stat.add("processing time [s]", mean_seconds);
  stat.add("processing time max [s]", w.seconds_max);
  stat.add("CorAl time per pair [s]",
           c.pairs > l.pairs ? (c.coral_seconds - l.coral_seconds) / (c.pairs - l.pairs) : 0.0);
  stat.add("time budget [s]", time_budget);
  stat.add("worker busy [s]", busy);
  stat.add("scans received", i.received);
  stat.add("scans processed", c.scans);
  stat.add("scans dropped (worker busy)", dropped_);
  stat.add("scans over time budget", over_budget_);
  stat.add("notices lost", notices_lost_);
  stat.add("verdicts", verdicts_);
  stat.add("pairs", c.pairs);
  stat.add("valid pairs", c.valid_pairs);
  // Pairs CorAl could not judge (overlap, degenerate neighbourhoods). CorAl's own
  // degenerate-input counters (CoralResult, "lidar" branch) belong next to this one.
  stat.add("pairs without verdict", c.pairs - c.valid_pairs);
  stat.add("misaligned pairs", c.misaligned);
  stat.add("fraction misaligned", frac);
  stat.add("tf failures", c.pose_failures);
  stat.add("late scans (TF after tf_timeout)", i.late);
  stat.add("unstamped scans refused", i.unstamped);
  stat.add("bad inputs", i.bad_inputs);
  stat.add("scans lost upstream (seq gaps)", i.lost_upstream);
  stat.add("non-finite points dropped", i.non_finite_points);
  stat.add("time jumps backwards", c.time_resets);
  stat.add("tf buffer clears", i.tf_clears);
  stat.add("duplicate stamps", c.duplicate_stamps);
  stat.add("reference too old", c.gap_resets);
  stat.add("callback errors", i.errors);
  if (doppler) {
    stat.add("doppler checks", c.doppler_checks);
    stat.add("doppler inconsistent", c.doppler_inconsistent);
  }
  if (calibration) {
    const online::CalibrationStatus& k = calibration_;
    std::ostringstream beta;
    beta << k.classifier.beta0 << ", " << k.classifier.beta1 << ", " << k.classifier.beta2;
    stat.add("calibration pairs selected", k.pairs_selected);
    stat.add("calibration pairs accepted", k.pairs_accepted);
    stat.add("calibration extra evaluations", k.extra_evaluations);
    stat.add("calibration samples", k.samples);
    stat.add("calibration held-out AUC", k.heldout_auc);
    stat.add("calibration refits", k.refits);
    stat.add("calibration in use", k.in_use ? "true" : "false");
    stat.add("calibration beta0, beta1, beta2", beta.str());
    stat.add("calibration time [s]", k.seconds);
    stat.add("calibration last error", k.last_error);
  }
  stat.add("last error", last_error_);
  stat.add("last tf failure", last_tf_failure_);
  stat.add("last no-verdict reason", last_no_verdict_);
  last_input_ = input_;
  last_counters_ = counters_;
  last_dropped_ = dropped_;
  window_ = Window();
  last_report_ = now;
}

}  // namespace ros_adapters
}  // namespace coral_introspection
