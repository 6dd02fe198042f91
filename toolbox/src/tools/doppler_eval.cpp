// Doppler introspection figures (core/doppler.hpp) on the TI mmWave demo bag or on
// simulated scans:
//  - fit quality on moving scans: median |residual| and inlier ratio of the robust fit;
//  - consistency test: acceptance with a reference velocity (bag: the Doppler fits of the
//    neighbouring scans, interpolated to the scan time; synthetic: the true velocity) and
//    rejection with 0.3 m/s injected into that reference;
//  - synthetic: the false-alarm rate of the nodelet's check (online::Introspector) with and
//    without point covariances (target: 1 - confidence = 1 %).
// Usage: doppler_eval [--bag FILE] [--synthetic] [--velocity-field NAME] [--min-speed M/S]
//        [--sigma-ref M/S] [--error M/S]
#include <ros/time.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/point_cloud2_iterator.h>
#include <std_msgs/Header.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "coral_introspection/coral/statistics.hpp"
#include "coral_introspection/eval/doppler_simulation.hpp"
#include "coral_introspection/eval/tool_args.hpp"
#include "coral_introspection/online/introspector.hpp"
#include "coral_introspection/radar/doppler.hpp"
#include "coral_introspection/radar/radar_uncertainty.hpp"

using namespace coral_introspection::coral;
using namespace coral_introspection::radar;
using namespace coral_introspection::eval;

namespace {

struct Frame {
  double stamp = 0.0;
  Points points;
  std::vector<double> vr;
  Covariances cov;
  EgoVelocityResult fit;
};

constexpr const char* kUsage =
    "usage: doppler_eval [--bag FILE] [--synthetic] [--velocity-field NAME] [--min-speed M/S]\n"
    "                    [--sigma-ref M/S] [--error M/S]";

Vec3 randomUnit(std::mt19937& rng) {
  std::normal_distribution<double> g;
  return Vec3(g(rng), g(rng), g(rng)).normalized();
}

bool readBag(const std::string& path, const std::string& field, std::vector<Frame>* frames) {
  rosbag::Bag bag;
  try {
    bag.open(path, rosbag::bagmode::Read);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cannot open %s: %s\n", path.c_str(), e.what());
    return false;
  }
  // The scan headers carry a zero stamp; the trigger with the same seq has the real one.
  std::map<uint32_t, double> trigger;
  for (const rosbag::MessageInstance& m :
       rosbag::View(bag, rosbag::TopicQuery("/sensor_platform/radar_right/trigger")))
    if (auto h = m.instantiate<std_msgs::Header>()) trigger[h->seq] = h->stamp.toSec();
  for (const rosbag::MessageInstance& m :
       rosbag::View(bag, rosbag::TopicQuery("/ti_mmwave/radar_scan_pcl"))) {
    auto pc = m.instantiate<sensor_msgs::PointCloud2>();
    if (!pc || pc->width * pc->height == 0) continue;
    Frame f;
    const auto it = trigger.find(pc->header.seq);
    f.stamp = it != trigger.end() ? it->second : m.getTime().toSec();
    sensor_msgs::PointCloud2ConstIterator<float> x(*pc, "x"), y(*pc, "y"), z(*pc, "z"),
        v(*pc, field);
    for (; x != x.end(); ++x, ++y, ++z, ++v) {
      f.points.emplace_back(*x, *y, *z);
      f.vr.push_back(*v);
    }
    frames->push_back(std::move(f));
  }
  std::sort(frames->begin(), frames->end(),
            [](const Frame& a, const Frame& b) { return a.stamp < b.stamp; });
  return true;
}

// False-alarm rate of the online Doppler check (the nodelet's code path: online::Introspector
// with poses that move at the true velocity) on n simulated scan pairs with random sensor
// velocities; point covariances from the simulator's own polar noise, or none.
double onlineFalseAlarms(const DopplerSimConfig& sim, bool random_velocity, bool covariances, int n,
                         double* checked) {
  coral_introspection::online::IntrospectorConfig c;
  c.doppler.enabled = true;
  c.doppler.point_covariances = covariances;
  c.doppler.noise = sim.position_noise;
  coral_introspection::online::Introspector intro(c);
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int tested = 0, flagged = 0;
  for (int i = 0; i < n; ++i) {
    const Vec3 v = random_velocity ? Vec3(1.75 + 1.25 * u(rng), 0.5 * u(rng), 0.2 * u(rng))
                                   : Vec3(3.0, 0.0, 0.0);
    for (int k = 0; k < 2; ++k) {  // a new sequence (gap > max_time_gap) for each pair
      const DopplerSimScan s = simulateDopplerScan(v, sim, rng);
      coral_introspection::online::ScanInput in;
      in.stamp = 10.0 * i + 0.1 * k;
      in.features.points = s.points;
      in.radial_velocity = s.radial_velocity;
      in.T_fixed_sensor = Eigen::Isometry3d(Eigen::Translation3d(v * 0.1 * k));
      const auto r = intro.process(in);
      if (!r.doppler || !r.doppler->result.valid) continue;
      ++tested;
      flagged += !r.doppler->result.consistent;
    }
  }
  *checked = tested;
  return tested > 0 ? static_cast<double>(flagged) / tested : 0.0;
}

}  // namespace

int main(int argc, char** argv) {
  std::string bag_path = "../shared/data/ti_mmwave_demo/ti_mmwave_rospkg_demo.bag";
  std::string field = "velocity";
  bool synthetic = false;
  double min_speed = 0.2, error = 0.3;
  DopplerConfig cfg;
  cfg.sigma_reference_velocity = 0.01;  // velocity change between neighbouring scans (~0.1 s)
  ToolArgs args;
  if (const auto exit =
          readCommandLine("doppler_eval", kUsage, argc, argv,
                          {"--bag", "--velocity-field", "--min-speed", "--sigma-ref", "--error"},
                          {"--synthetic"}, &args))
    return *exit;
  std::string err;
  if (!numberOption(args, "--min-speed", min_speed, &min_speed, &err) ||
      !numberOption(args, "--sigma-ref", cfg.sigma_reference_velocity,
                    &cfg.sigma_reference_velocity, &err) ||
      !numberOption(args, "--error", error, &error, &err))
    return toolError("doppler_eval", err, kUsage);
  synthetic = args.flag("--synthetic");
  bag_path = args.get("--bag", bag_path);
  field = args.get("--velocity-field", field);
  ros::Time::init();
  const RadarNoiseConfig noise =
      synthetic ? DopplerSimConfig{}.position_noise : RadarNoiseConfig::tiAwr1843();
  std::vector<Frame> frames;
  std::vector<Vec3> truth;
  std::mt19937 rng(7);
  if (synthetic) {
    const DopplerSimConfig sim;  // 60 points, 30% movers, 0.05 m/s Doppler noise
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int i = 0; i < 400; ++i) {
      truth.emplace_back(1.75 + 1.25 * u(rng), 0.5 * u(rng), 0.2 * u(rng));
      const DopplerSimScan s = simulateDopplerScan(truth.back(), sim, rng);
      Frame f;
      f.stamp = 0.1 * i;
      f.points = s.points;
      f.vr = s.radial_velocity;
      frames.push_back(f);
    }
    cfg.sigma_reference_velocity = 0.0;  // the reference is the exact velocity
  } else if (!readBag(bag_path, field, &frames)) {
    return 1;
  }

  std::vector<double> residuals, ratios;
  std::size_t valid = 0;
  for (Frame& f : frames) {
    Scan s;
    s.points = f.points;
    attachCovariances(s, noise, 3, nullptr);
    f.cov = s.covariances;
    f.fit = estimateEgoVelocity(f.points, f.vr, cfg, &f.cov);
    if (!f.fit.valid) continue;
    ++valid;
    if (f.fit.velocity.norm() < min_speed) continue;
    residuals.push_back(f.fit.median_residual);
    ratios.push_back(f.fit.inlier_ratio);
  }
  std::printf("%s: %zu scans, %zu with a valid Doppler fit, %zu moving (|v| >= %.2f m/s)\n",
              synthetic ? "synthetic" : bag_path.c_str(), frames.size(), valid, residuals.size(),
              min_speed);
  std::printf("moving scans: median |residual| %.3f m/s, median inlier ratio %.3f\n",
              quantile(residuals, 0.5), quantile(ratios, 0.5));  // upper middle, as always

  int tested = 0, accepted = 0, rejected = 0;
  for (std::size_t i = 1; i + 1 < frames.size(); ++i) {
    const Frame &prev = frames[i - 1], &cur = frames[i], &next = frames[i + 1];
    Vec3 ref;
    Mat3 ref_cov = Mat3::Zero();
    if (synthetic) {
      ref = truth[i];
    } else {  // neighbours' Doppler fits interpolated to this scan's time, with their
              // covariance; sigma_reference covers the change of velocity between scans
      if (!prev.fit.valid || !next.fit.valid || !(next.stamp > prev.stamp)) continue;
      if (prev.fit.planar || next.fit.planar) continue;
      const double w = (cur.stamp - prev.stamp) / (next.stamp - prev.stamp);
      ref = (1.0 - w) * prev.fit.velocity + w * next.fit.velocity;
      ref_cov = (1.0 - w) * (1.0 - w) * prev.fit.covariance + w * w * next.fit.covariance;
    }
    if (ref.norm() < min_speed) continue;
    const ConsistencyResult ok =
        checkVelocityConsistency(cur.points, cur.vr, ref, cfg, &cur.cov, &ref_cov);
    const ConsistencyResult bad = checkVelocityConsistency(
        cur.points, cur.vr, ref + error * randomUnit(rng), cfg, &cur.cov, &ref_cov);
    if (!ok.valid || !bad.valid) continue;
    ++tested;
    accepted += ok.consistent;
    rejected += !bad.consistent;
  }
  std::printf(
      "consistency (confidence %.2f, sigma_doppler %.2f m/s, sigma_reference %.2f m/s): "
      "%d moving scans, accepted %.1f%% with the reference velocity, rejected %.1f%% "
      "with %.2f m/s injected error\n",
      cfg.confidence, cfg.sigma_doppler, cfg.sigma_reference_velocity, tested,
      tested ? 100.0 * accepted / tested : 0.0, tested ? 100.0 * rejected / tested : 0.0, error);
  if (synthetic) {
    // The tool's scans (60 points, 30 % movers, random velocity), then the nodelet_doppler
    // rostest's (300 points, 20 % movers, 3 m/s forward).
    DopplerSimConfig rostest;
    rostest.num_points = 300;
    rostest.outlier_fraction = 0.2;
    for (const bool dense : {false, true}) {
      const DopplerSimConfig sim = dense ? rostest : DopplerSimConfig();
      double n_cov = 0, n_plain = 0;
      const double with_cov = onlineFalseAlarms(sim, !dense, true, 4000, &n_cov);
      const double without = onlineFalseAlarms(sim, !dense, false, 4000, &n_plain);
      std::printf(
          "online check (Introspector, poses at the true velocity, confidence %.2f), %d points, "
          "%.0f %% movers, %s: false alarms %.2f%% with point covariances (%.0f checks), %.2f%% "
          "without (%.0f checks)\n",
          coral_introspection::online::IntrospectorConfig().doppler.check.confidence,
          sim.num_points, 100.0 * sim.outlier_fraction,
          dense ? "v = 3 m/s forward" : "random velocity", 100.0 * with_cov, n_cov, 100.0 * without,
          n_plain);
    }
  }
  return 0;
}
