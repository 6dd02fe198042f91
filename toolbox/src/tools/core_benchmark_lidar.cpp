// Benchmark and quality check of lidar CorAl on the shared data (ROS-free):
//   coral_benchmark_lidar [--data DIR] [--repeats N] [CorAl flags] [--timing] [--quality]
//                         [--degenerate] [--seed_study N] [--write_pair DIR]
// --timing: median ms per pair (transform of b + computeCoral) on two 64-beam pairs built
//   from the View-of-Delft HDL-64 frames (see makeTimingPair). With --repeats 1 it is one
//   run for `valgrind --tool=callgrind`.
// --quality: Q at the registered pose against Q with induced offsets of b (in b's sensor
//   frame), and the classifier's verdicts, on the libpointmatcher pair and on consecutive
//   Livox keyframes (hku1_livox_keyframes, optimized_poses.txt).
// --degenerate: identical-point clusters (5k-40k per scan: time and verdict), and a Livox
//   pair with a 0.7 m lateral error plus 0 / 1500 / 3000 no-returns at each sensor origin,
//   or one point at 1e30 (issue 13).
// --seed_study N: the subset estimator on the timing pair over N seeds (spread of Q against
//   the reported standard error). --write_pair DIR: a.bin, b.bin, T_a_b.txt of the timing
//   pair, for coral_check.
// CorAl flags (defaults: CoralConfig): --radius --dynamic --r_min --r_max --alpha_deg
//   --epsilon --min_neighbours --voxel_leaf --max_queries --threads --seed; classifier:
//   --beta0 --beta1 --beta2 --threshold. Built with -DCORAL_BASELINE it also compiles
//   against the code before the lidar work (commit 5c79551), without the new flags; that
//   commit predates coral/statistics and eval/tool_args, so add their two .hpp/.cpp pairs
//   (standard library only) to that build.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "coral_introspection/coral/classifier.hpp"
#include "coral_introspection/coral/coral.hpp"
#include "coral_introspection/coral/statistics.hpp"
#include "coral_introspection/eval/cloud_io.hpp"
#include "coral_introspection/eval/perturbation.hpp"
#include "coral_introspection/eval/tool_args.hpp"

using namespace coral_introspection::coral;
using namespace coral_introspection::eval;
using Clock = std::chrono::steady_clock;

namespace {

struct Options {
  std::string data = "../shared/data";
  int repeats = 5;
  bool timing = false, quality = false, degenerate = false;
  int seed_study = 0;
  std::string write_pair;
  CoralConfig coral;
  ClassifierConfig clf;
};

constexpr const char* kUsage =
    "usage: coral_benchmark_lidar [--data DIR] [--repeats N] [CorAl flags] [--timing] [--quality]\n"
    "                             [--degenerate] [--seed_study N] [--write_pair DIR]\n"
    "CorAl flags: --radius M --dynamic --r_min M --r_max M --alpha_deg DEG --epsilon E\n"
    "             --min_neighbours N"
#ifndef CORAL_BASELINE
    " --voxel_leaf M --max_queries N --threads N --seed N"
#endif
    "\nclassifier: --beta0 B --beta1 B --beta2 B --threshold T";

const std::vector<std::string> kFlags = {"--timing", "--quality", "--degenerate", "--dynamic"};

std::vector<std::string> valueOptions() {
  std::vector<std::string> options = {"--data",      "--write_pair",    "--repeats", "--seed_study",
                                      "--radius",    "--r_min",         "--r_max",   "--alpha_deg",
                                      "--epsilon",   "--beta0",         "--beta1",   "--beta2",
                                      "--threshold", "--min_neighbours"};
#ifndef CORAL_BASELINE
  options.insert(options.end(), {"--voxel_leaf", "--max_queries", "--threads", "--seed"});
#endif
  return options;
}

// False with *error on a malformed number or settings the configs refuse.
bool parse(const ToolArgs& args, Options* o, std::string* error) {
  if (const char* env = std::getenv("CORAL_DATA_DIR")) o->data = env;
  CoralConfig& c = o->coral;
  c.per_point = false;
  o->data = args.get("--data", o->data);
  o->write_pair = args.get("--write_pair");
  o->timing = args.flag("--timing");
  o->quality = args.flag("--quality");
  o->degenerate = args.flag("--degenerate");
  if (args.flag("--dynamic")) c.dynamic_radius = true;
  // Values only have to be numbers here; their ranges are the configs' (validate() below).
  auto number = [&](const char* name, double* v) { return numberOption(args, name, *v, v, error); };
  auto integer = [&](const char* name, int* v) {
    return intOption(args, name, *v, std::numeric_limits<int>::min(),
                     std::numeric_limits<int>::max(), v, error);
  };
  if (!(integer("--repeats", &o->repeats) && integer("--seed_study", &o->seed_study) &&
        number("--radius", &c.radius) && number("--r_min", &c.r_min) &&
        number("--r_max", &c.r_max) && number("--alpha_deg", &c.alpha_deg) &&
        number("--epsilon", &c.epsilon) && integer("--min_neighbours", &c.min_neighbours) &&
#ifndef CORAL_BASELINE
        number("--voxel_leaf", &c.voxel_leaf) && integer("--max_queries", &c.max_queries) &&
        integer("--threads", &c.threads) && integer("--seed", &c.query_seed) &&
#endif
        number("--beta0", &o->clf.beta0) && number("--beta1", &o->clf.beta1) &&
        number("--beta2", &o->clf.beta2) && number("--threshold", &o->clf.threshold)))
    return false;
  if (!o->timing && !o->quality && !o->degenerate && o->seed_study == 0 && o->write_pair.empty())
    o->timing = o->quality = true;
  if (o->repeats < 1) o->repeats = 1;
  const std::string e = c.validate() + o->clf.validate();
  if (!e.empty()) *error = "bad settings: " + e;
  return e.empty();
}

void printSettings(const CoralConfig& c, const ClassifierConfig& k) {
  std::printf("CorAl: dim %d, r %.2f m%s, epsilon %g, min neighbours %d/%d", c.dimension, c.radius,
              c.dynamic_radius ? " (dynamic)" : "", c.epsilon, c.min_neighbours,
              c.min_neighbours_other);
#ifndef CORAL_BASELINE
  std::printf(", voxel leaf %.2f m, max queries %d, seed %d, threads %d", c.voxel_leaf,
              c.max_queries, c.query_seed, c.threads);
#endif
  std::printf("; classifier %.2f %.2f %.2f t %.2f\n", k.beta0, k.beta1, k.beta2, k.threshold);
}

// A 64-beam timing pair from one real HDL-64 frame (View-of-Delft frames are not
// consecutive): a = the frame; b = the same frame re-sampled (each point kept with
// probability 0.9), jittered (sigma 1 cm per axis) and expressed in a sensor frame moved
// by T_a_b = (1.0 m, 0.2 m, 0 m, yaw 2 deg). Seeded, so every run builds the same pair.
struct TimingPair {
  Scan a, b_sensor;
  Eigen::Isometry3d T_a_b = Eigen::Isometry3d::Identity();
  std::string name;
};

TimingPair makeTimingPair(const Points& frame) {
  TimingPair p;
  p.name = "VoD 01047 + resampled/jittered/moved copy";
  p.T_a_b = Eigen::Translation3d(1.0, 0.2, 0.0) *
            Eigen::AngleAxisd(2.0 * M_PI / 180.0, Eigen::Vector3d::UnitZ());
  const Eigen::Isometry3d T_b_a = p.T_a_b.inverse();
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> keep(0.0, 1.0);
  std::normal_distribution<double> jitter(0.0, 0.01);
  p.a.points = frame;
  for (const Vec3& x : frame) {
    if (keep(rng) >= 0.9) continue;
    p.b_sensor.points.push_back(T_b_a * (x + Vec3(jitter(rng), jitter(rng), jitter(rng))));
  }
  return p;
}

bool writeBin(const std::string& path, const Points& pts) {
  std::ofstream f(path, std::ios::binary);
  for (const Vec3& p : pts) {
    const float r[4] = {float(p.x()), float(p.y()), float(p.z()), 0.f};
    f.write(reinterpret_cast<const char*>(r), sizeof(r));
  }
  return bool(f);
}

// Median ms of transform + CorAl over the repeats; prints the pair's result.
void timePair(const std::string& name, const Scan& a, const Scan& b_sensor,
              const Eigen::Isometry3d& T_a_b, const Options& o) {
  std::vector<double> ms;
  CoralResult r;
  for (int k = 0; k < o.repeats; ++k) {
    const auto t0 = Clock::now();
    r = computeCoral(a, transformScan(b_sensor, T_a_b), o.coral);
    ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
  }
  const Verdict v = classify(o.clf, r.h_joint, r.h_sep);
  std::printf("%-45s %7zu %7zu  %9.2f ms  Q %.4f", name.c_str(), r.num_points_a, r.num_points_b,
              median(ms), r.quality);
#ifndef CORAL_BASELINE
  std::printf(" +- %.4f (used %zu/%zu, scored %zu)", r.quality_stderr, r.num_used_a, r.num_used_b,
              r.num_queries);
#endif
  std::printf("  valid %d aligned %d p %.3f\n", r.valid, r.valid && v.aligned, v.probability);
}

bool loadFrame(const std::string& path, Points* pts) {
  LoadedCloud c;
  std::string err;
  if (!loadCloud(path, &c, &err)) {
    std::fprintf(stderr, "%s\n", err.c_str());
    return false;
  }
  *pts = c.points;
  return true;
}

// Quality statistics of one dataset: per offset group, how often Q(offset) > Q(pose) and
// how often the verdict is right (aligned at the pose, misaligned with the offset).
struct GroupStats {
  std::string group;
  int n = 0, ordered = 0, rejected = 0;
  double sum_q = 0.0;
};
struct QualityStats {
  int pairs = 0, valid = 0, accepted = 0;
  double sum_q0 = 0.0, sum_se = 0.0;
  std::vector<double> ms;
  std::vector<GroupStats> groups;
};

void qualityPair(const Scan& a, const Scan& b_sensor, const Eigen::Isometry3d& T_a_b,
                 const std::vector<Perturbation>& offsets, const Options& o, QualityStats* s) {
  const auto t0 = Clock::now();
  const CoralResult r0 = computeCoral(a, transformScan(b_sensor, T_a_b), o.coral);
  s->ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
  ++s->pairs;
  if (!r0.valid) return;
  ++s->valid;
  s->sum_q0 += r0.quality;
#ifndef CORAL_BASELINE
  s->sum_se += r0.quality_stderr;
#endif
  s->accepted += classify(o.clf, r0.h_joint, r0.h_sep).aligned ? 1 : 0;
  for (const Perturbation& p : offsets) {
    auto it = std::find_if(s->groups.begin(), s->groups.end(),
                           [&](const GroupStats& g) { return g.group == p.group; });
    if (it == s->groups.end()) {
      s->groups.push_back({p.group});
      it = s->groups.end() - 1;
    }
    const CoralResult r = computeCoral(a, transformScan(b_sensor, perturb(T_a_b, p)), o.coral);
    ++it->n;
    it->ordered += r.quality > r0.quality ? 1 : 0;
    it->rejected += !(r.valid && classify(o.clf, r.h_joint, r.h_sep).aligned) ? 1 : 0;
    it->sum_q += r.quality;
  }
}

void printQuality(const char* name, const QualityStats& s) {
  std::printf("%s: %d pairs, %d valid at the pose, aligned verdict %d/%d, mean Q %.4f", name,
              s.pairs, s.valid, s.accepted, s.valid, s.valid ? s.sum_q0 / s.valid : 0.0);
#ifndef CORAL_BASELINE
  std::printf(" (mean stderr %.4f)", s.valid ? s.sum_se / s.valid : 0.0);
#endif
  std::printf(", median %.2f ms per CorAl\n", median(s.ms));
  for (const GroupStats& g : s.groups)
    std::printf(
        "  offset %-16s Q above the pose's %4d/%-4d  misaligned verdict %4d/%-4d  mean Q %.4f\n",
        g.group.c_str(), g.ordered, g.n, g.rejected, g.n, g.n ? g.sum_q / g.n : 0.0);
}

std::vector<Perturbation> qualityOffsets() {
  PerturbationConfig pc;
  pc.translations = {0.1, 0.3, 0.5};
  pc.rotations = {0.05};
  return makePerturbations(pc);
}

bool runQuality(const Options& o) {
  const std::vector<Perturbation> offsets = qualityOffsets();
  std::string err;
  {  // libpointmatcher pair, both clouds in the common frame of carCloudList.csv
    const std::string dir = o.data + "/libpointmatcher_car_cloud";
    Scan a, b;
    Eigen::Isometry3d T_w_a, T_w_b;
    if (!readCsvPoints(dir + "/car_cloud400.csv", &a.points, &err) ||
        !readCsvPoints(dir + "/car_cloud401.csv", &b.points, &err) ||
        !readCsvPose(dir + "/carCloudList.csv", "car_cloud400.csv", &T_w_a, &err) ||
        !readCsvPose(dir + "/carCloudList.csv", "car_cloud401.csv", &T_w_b, &err)) {
      std::fprintf(stderr, "%s\n", err.c_str());
      return false;
    }
    QualityStats s;
    qualityPair(a, b, T_w_a.inverse() * T_w_b, offsets, o, &s);
    printQuality("libpointmatcher car pair", s);
  }
  {  // Livox keyframes k, k+1 with the registered poses (b in a's frame)
    const std::string dir = o.data + "/hku1_livox_keyframes";
    Isometries poses;
    if (!readKittiPoses(dir + "/optimized_poses.txt", &poses, &err)) {
      std::fprintf(stderr, "%s\n", err.c_str());
      return false;
    }
    QualityStats s;
    Scan prev;
    for (std::size_t k = 0; k < poses.size(); ++k) {
      char name[32];
      std::snprintf(name, sizeof(name), "/Scans/%06zu.pcd", k);
      Scan cur;
      if (!loadFrame(dir + name, &cur.points)) return false;
      if (k > 0) qualityPair(prev, cur, poses[k - 1].inverse() * poses[k], offsets, o, &s);
      prev = cur;
    }
    printQuality("Livox HKU_1 keyframes k, k+1", s);
  }
  return true;
}

void printDegenerate(const char* name, const CoralResult& r, double ms, const Options& o) {
  const Verdict v = classify(o.clf, r.h_joint, r.h_sep);
  std::printf("%-52s %9.1f ms  valid %d aligned %d p %.3f Q %.4f", name, ms, r.valid,
              r.valid && v.aligned, r.valid ? v.probability : 0.0, r.quality);
#ifndef CORAL_BASELINE
  std::printf("  merged %zu degenerate %zu out of range %zu%s%s", r.num_merged, r.num_degenerate,
              r.num_out_of_range, r.reason.empty() ? "" : "  reason: ", r.reason.c_str());
#endif
  std::printf("\n");
}

bool runDegenerate(const Options& o) {
  for (int n : {5000, 10000, 20000, 40000}) {
    Scan a, b;
    a.points.assign(n, Vec3(3.0, 1.0, 0.5));
    b.points.assign(n, Vec3(3.0, 1.0, 0.5));
    const auto t0 = Clock::now();
    const CoralResult r = computeCoral(a, b, o.coral);
    const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    const std::string name = std::to_string(n) + " identical points per scan";
    printDegenerate(name.c_str(), r, ms, o);
  }
  const std::string dir = o.data + "/hku1_livox_keyframes";
  Isometries poses;
  std::string err;
  Scan a, b;
  if (!readKittiPoses(dir + "/optimized_poses.txt", &poses, &err) ||
      !loadFrame(dir + "/Scans/000100.pcd", &a.points) ||
      !loadFrame(dir + "/Scans/000101.pcd", &b.points)) {
    std::fprintf(stderr, "%s\n", err.c_str());
    return false;
  }
  const Eigen::Isometry3d T_a_b = poses[100].inverse() * poses[101];
  const Eigen::Isometry3d left = T_a_b * se2(0.0, 0.7, 0.0);
  for (int extra : {-1, 0, 1500, 3000, -2}) {
    Scan ea = a, eb = b;
    for (int i = 0; i < extra; ++i) {
      ea.points.push_back(Vec3::Zero());
      eb.points.push_back(Vec3::Zero());
    }
    if (extra == -2) eb.points.push_back(Vec3(1e30, 0.0, 0.0));
    const auto t0 = Clock::now();
    const CoralResult r = computeCoral(ea, transformScan(eb, extra == -1 ? T_a_b : left), o.coral);
    const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    const std::string name =
        extra == -1   ? std::string("Livox 100/101 at the pose")
        : extra == -2 ? std::string("Livox 100/101, 0.7 m left, + 1 point at 1e30")
                      : "Livox 100/101, 0.7 m left, + " + std::to_string(extra) + " at origin";
    printDegenerate(name.c_str(), r, ms, o);
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  ToolArgs args;
  if (const auto exit = readCommandLine("coral_benchmark_lidar", kUsage, argc, argv, valueOptions(),
                                        kFlags, &args))
    return *exit;
  Options o;
  std::string err;
  if (!parse(args, &o, &err)) return toolError("coral_benchmark_lidar", err, kUsage);
  printSettings(o.coral, o.clf);
  const std::string vod = o.data + "/view_of_delft_example/lidar/training/velodyne/";
  if (o.timing || o.seed_study > 0 || !o.write_pair.empty()) {
    Points f549, f1047, f1201;
    if (!loadFrame(vod + "00549.bin", &f549) || !loadFrame(vod + "01047.bin", &f1047) ||
        !loadFrame(vod + "01201.bin", &f1201))
      return 1;
    const TimingPair tp = makeTimingPair(f1047);
    if (!o.write_pair.empty()) {
      std::ofstream t(o.write_pair + "/T_a_b.txt");
      t.precision(12);
      t << tp.T_a_b.matrix() << "\n";
      if (!t || !writeBin(o.write_pair + "/a.bin", tp.a.points) ||
          !writeBin(o.write_pair + "/b.bin", tp.b_sensor.points)) {
        std::fprintf(stderr, "cannot write the pair into %s\n", o.write_pair.c_str());
        return 1;
      }
      std::printf("wrote %s/{a.bin,b.bin,T_a_b.txt}\n", o.write_pair.c_str());
    }
    if (o.timing) {
      std::printf(
          "%d repeats; pair, points a, points b, median time per pair (transform b + CorAl)\n",
          o.repeats);
      timePair(tp.name, tp.a, tp.b_sensor, tp.T_a_b, o);
      Scan a, b;
      a.points = f549;
      b.points = f1201;
      timePair("VoD 00549 vs 01201 (different places)", a, b, Eigen::Isometry3d::Identity(), o);
    }
#ifndef CORAL_BASELINE
    if (o.seed_study > 0) {
      std::vector<double> qs;
      double se = 0.0;
      Options s = o;
      s.coral.max_queries = 0;
      const double q_full =
          computeCoral(tp.a, transformScan(tp.b_sensor, tp.T_a_b), s.coral).quality;
      for (int seed = 1; seed <= o.seed_study; ++seed) {
        s.coral = o.coral;
        s.coral.query_seed = seed;
        const CoralResult r = computeCoral(tp.a, transformScan(tp.b_sensor, tp.T_a_b), s.coral);
        qs.push_back(r.quality);
        se += r.quality_stderr;
      }
      double mean = 0.0, ss = 0.0;
      for (double q : qs) mean += q;
      mean /= qs.size();
      for (double q : qs) ss += (q - mean) * (q - mean);
      std::printf(
          "seed study (%d seeds): Q every point %.4f; subset Q mean %.4f, std over seeds "
          "%.4f, mean reported stderr %.4f, min %.4f max %.4f\n",
          o.seed_study, q_full, mean, qs.size() > 1 ? std::sqrt(ss / (qs.size() - 1)) : 0.0,
          se / qs.size(), *std::min_element(qs.begin(), qs.end()),
          *std::max_element(qs.begin(), qs.end()));
    }
#endif
  }
  if (o.quality && !runQuality(o)) return 1;
  if (o.degenerate && !runDegenerate(o)) return 1;
  return 0;
}
