// Benchmark of the radar front end on an Oxford-format folder (ROS-free):
//   coral_benchmark_radar [folder] [--repeats N]
// Prints the median wall time of decoding + RIP extraction per scan and of CorAl per
// consecutive pair with the paper's radar settings (Sec. V-A). For instruction counts run
// it under `valgrind --tool=callgrind` with --repeats 1 (see README "Radar front end").
#include <sys/stat.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "coral_introspection/coral/coral.hpp"
#include "coral_introspection/coral/statistics.hpp"
#include "coral_introspection/eval/oxford_dataset.hpp"
#include "coral_introspection/eval/tool_args.hpp"
#include "coral_introspection/radar/deskew.hpp"
#include "coral_introspection/radar/polar_scan.hpp"
#include "coral_introspection/radar/rip_features.hpp"

using namespace coral_introspection::coral;
using namespace coral_introspection::radar;
using namespace coral_introspection::eval;
using Clock = std::chrono::steady_clock;

namespace {
double ms(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}
std::string defaultFolder() {
  if (const char* env = std::getenv("CORAL_DATA_DIR"))
    return std::string(env) + "/oxford_radar_tiny";
  return "../shared/data/oxford_radar_tiny";
}
constexpr const char* kUsage = "usage: coral_benchmark_radar [oxford_folder] [--repeats N]";
}  // namespace

int main(int argc, char** argv) {
  ToolArgs args;
  if (const auto exit =
          readCommandLine("coral_benchmark_radar", kUsage, argc, argv, {"--repeats"}, {}, &args, 1))
    return *exit;
  std::string err;
  int repeats = 0;
  if (!positiveInt(args, "--repeats", 20, &repeats, &err))
    return toolError("coral_benchmark_radar", err, kUsage);
  const std::string folder = args.positional.empty() ? defaultFolder() : args.positional[0];
  OxfordDataset ds;
  if (!ds.load(folder, &err)) {
    std::fprintf(stderr, "cannot load Oxford folder: %s\n", err.c_str());
    return 1;
  }
  // PNG decompression is not part of the pipeline (ROS delivers raw mono8 images).
  std::vector<cv::Mat> images;
  for (const auto& p : ds.png_paths) images.push_back(cv::imread(p, cv::IMREAD_UNCHANGED));

  const RipConfig rip;  // k = 12, z_min = 70, w = 2, min range 2.5 m
  const CoralConfig coral = CoralConfig::radarPaper();
  const std::size_t n = images.size();
  // De-skew velocities by the online policy (radar/deskew.hpp) on the GT poses.
  std::vector<double> stamps(n);
  Isometries poses;
  for (std::size_t i = 0; i < n; ++i) {
    stamps[i] = ds.stamps_us[i] * 1e-6;  // = the decoded scan's stamp (first row)
    poses.push_back(ds.T_first_scan(i));
  }
  const auto velocities = deskewVelocities(stamps, poses);
  std::vector<RadarFeatures> feats(n);
  std::vector<double> t_extract, t_comp, t_coral;
  std::vector<CoralResult> results(n);
  std::size_t total_features = 0;
  for (int rep = 0; rep < repeats; ++rep) {
    for (std::size_t i = 0; i < n; ++i) {
      PolarScan scan;
      const auto a = Clock::now();
      if (!decodeOxfordImage(images[i], &scan, &err) ||
          !extractRipFeatures(scan, rip, &feats[i], &err)) {
        std::fprintf(stderr, "%s: %s\n", ds.png_paths[i].c_str(), err.c_str());
        return 1;
      }
      const auto b = Clock::now();
      if (velocities[i]) compensateMotion(*velocities[i], scan.stamp, &feats[i]);
      const auto c = Clock::now();
      t_extract.push_back(ms(a, b));
      t_comp.push_back(ms(b, c));
      if (rep == 0) total_features += feats[i].points.size();
    }
    for (std::size_t i = 1; i < n; ++i) {
      Scan prev, curr;
      prev.points = feats[i - 1].points;
      curr.points = feats[i].points;
      curr = transformScan(curr, ds.T_prev_curr[i]);  // GT: both in scan i-1's frame
      const auto a = Clock::now();
      results[i] = computeCoral(prev, curr, coral);
      t_coral.push_back(ms(a, Clock::now()));
    }
  }
  std::printf("folder %s: %zu scans, %zu pairs, %d repeats\n", folder.c_str(), n, n - 1, repeats);
  std::printf("mean RIP features per scan: %.1f\n", static_cast<double>(total_features) / n);
  for (std::size_t i = 1; i < n; ++i)
    std::printf("pair %zu: Q %.4f  H_joint %.4f  H_sep %.4f  overlap %.3f\n", i, results[i].quality,
                results[i].h_joint, results[i].h_sep, results[i].overlap);
  std::printf("median decode + RIP per scan:       %.3f ms\n", median(t_extract));
  std::printf("median motion compensation per scan: %.3f ms\n", median(t_comp));
  std::printf("median CorAl per pair (r = 1 m, 2D): %.3f ms\n", median(t_coral));
  return 0;
}
