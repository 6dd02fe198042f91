// coral_check: offline CorAl verdict for one pair of scans, with a nodelet preset.
//   rosrun coral_introspection coral_check --config PRESET.yaml [--classifier FILE.yaml]
//       [--loop_closure] --a FILE --b FILE --transform_file T.txt [--repeat N]
// --loop_closure: the pair is a loop-closure candidate (the check_alignment request's
// loop_closure): the gated verdict with the preset's loop_closure/ gate (coral/verdict.hpp).
// FILE: .pcd (ascii/binary, fields x y z [intensity]), .bin (KITTI float32 x y z i), .csv
// (x,y,z columns) for a point-cloud preset; .png (polar radar image, the preset's
// radar/polar_format) for a polar_image preset. T.txt: 4x4 or 3x4 row-major T_a_b mapping
// points of b into a's frame. The preset is read with the nodelet's own parameter loader
// (no ROS master needed), so it means exactly what it means online; an unknown group or
// key, a duplicate key or a wrong type exits with status 2 and the message the nodelet logs.
// Prints one JSON object on one line; `seconds` is the median over the repeats of the time
// from the loaded clouds (images) to the verdict, preprocessing included. Exit status 0 when
// it judged (valid or not), 2 with a message on stderr for bad arguments or input.
#include <malloc.h>

#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "coral_introspection/coral/classifier.hpp"
#include "coral_introspection/coral/coral.hpp"
#include "coral_introspection/coral/statistics.hpp"
#include "coral_introspection/eval/cloud_io.hpp"
#include "coral_introspection/eval/tool_args.hpp"
#include "coral_introspection/online/introspector.hpp"
#include "coral_introspection/radar/deskew.hpp"
#include "coral_introspection/radar/polar_scan.hpp"
#include "coral_introspection/ros/coral_params.hpp"
#include "coral_introspection/ros/coral_scan_input.hpp"
#include "coral_introspection/ros_eval/preset_file.hpp"

using namespace coral_introspection;
using ros_adapters::NodeConfig;

namespace {

constexpr const char* kUsage =
    "usage: coral_check --config PRESET.yaml [--classifier FILE.yaml] [--loop_closure] --a FILE "
    "--b FILE --transform_file T.txt [--repeat N]";

int fail(const std::string& msg) {
  std::fprintf(stderr, "coral_check: %s\n", msg.c_str());
  return 2;
}

std::string extension(const std::string& path) {
  const std::size_t dot = path.find_last_of('.');
  std::string e = dot == std::string::npos ? "" : path.substr(dot + 1);
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return e;
}

// One input as loaded from disk: a point cloud, or a polar image with its time stamp.
struct Input {
  coral::Points points;
  coral::Scan scan;  // the cloud as a scan in its own frame (origin 0)
  cv::Mat image;
  double stamp = 0.0;  // [s] scan time of a radar image (Oxford layout), 0 otherwise
};

bool loadInput(const std::string& path, const NodeConfig& cfg, Input* in, std::string* error) {
  const bool radar = cfg.input_type == ros_adapters::InputType::kPolarImage;
  const std::string ext = extension(path);
  if (radar != (ext == "png")) {
    *error = path + ": the preset's input_type is " +
             (radar ? "polar_image (expects a .png)" : "pointcloud (expects .pcd, .bin or .csv)");
    return false;
  }
  if (!radar) {
    eval::LoadedCloud c;
    // Planar PCDs are read here: the preset's dimension tells a 2D scan from a flat 3D cloud.
    if (!eval::loadCloud(path, &c, error, true)) return false;
    if (c.planar && cfg.online.coral.dimension != 2) {
      *error = path + ": a planar PCD (fields x, y, no z) under a 3D preset (coral/dimension " +
               std::to_string(cfg.online.coral.dimension) + "): write z, or use a 2D preset";
      return false;
    }
    in->points = c.points;
    in->scan.points = std::move(c.points);
    return true;
  }
  in->image = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (in->image.empty() || in->image.type() != CV_8UC1) {
    *error = path + ": not a readable 8-bit grey PNG";
    return false;
  }
  if (cfg.polar_format == ros_adapters::PolarFormat::kOxford) {
    radar::PolarScan scan;  // for the embedded scan time only
    if (!radar::decodeOxfordImage(in->image, &scan, error)) {
      *error = path + ": " + *error;
      return false;
    }
    in->stamp = scan.stamp;
  }
  return true;
}

// Sensor-frame points of one input: the cloud as is, or the RIP features of the image
// through the nodelet's own image path.
bool sensorPoints(const Input& in, const NodeConfig& cfg, radar::RadarFeatures* out,
                  std::string* error) {
  if (in.image.empty()) {
    out->points = in.points;
    return true;
  }
  sensor_msgs::Image msg;
  msg.header.stamp.fromSec(in.stamp);
  msg.encoding = "mono8";
  msg.height = static_cast<uint32_t>(in.image.rows);
  msg.width = static_cast<uint32_t>(in.image.cols);
  msg.step = msg.width;
  msg.data.resize(static_cast<std::size_t>(msg.step) * msg.height);
  for (int r = 0; r < in.image.rows; ++r)
    std::copy(in.image.ptr<uint8_t>(r), in.image.ptr<uint8_t>(r) + in.image.cols,
              msg.data.begin() + static_cast<std::ptrdiff_t>(r) * msg.step);
  ros_adapters::SensorScan scan;
  if (!ros_adapters::toSensorScan(msg, cfg, &scan, error)) return false;
  *out = std::move(scan.scan.features);
  return true;
}

// Reason strings are plain sentences; quotes and backslashes escaped for JSON.
std::string jsonEscape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += (static_cast<unsigned char>(c) < 0x20) ? ' ' : c;
  }
  return out;
}

// Everything after loading: features (radar, de-skewed by the one policy: a two-scan
// sequence uses the pair's own twist for both), then the Introspector's judgePair.
bool judge(const Input& ia, const Input& ib, const Eigen::Isometry3d& T_a_b, const NodeConfig& cfg,
           online::PairJudgement* out, std::string* error) {
  if (ia.image.empty()) {  // clouds: CorAl on the loaded scans
    *out = online::judgePair(ia.scan, ib.scan, T_a_b, cfg.online, false);
    return true;
  }
  radar::RadarFeatures fa, fb;
  if (!sensorPoints(ia, cfg, &fa, error) || !sensorPoints(ib, cfg, &fb, error)) return false;
  const auto twists = radar::deskewVelocities(
      {ia.stamp, ib.stamp}, {Eigen::Isometry3d::Identity(), T_a_b}, cfg.online.deskew);
  if (cfg.online.deskew.enabled && twists[0] && twists[1]) {
    radar::compensateMotion(*twists[0], ia.stamp, &fa);
    radar::compensateMotion(*twists[1], ib.stamp, &fb);
  }
  coral::Scan a, b;
  a.points = std::move(fa.points);
  b.points = std::move(fb.points);
  *out = online::judgePair(std::move(a), b, T_a_b, cfg.online, false);
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  // Some library linked here fixes glibc's mmap threshold (its dynamic adjustment is off:
  // every pair's multi-megabyte buffers were fresh pages, 3000 page faults and ~40 ms of
  // kernel time per pair on a 64-beam pair). Large blocks come from the reused heap.
  mallopt(M_MMAP_THRESHOLD, 256 << 20);
  mallopt(M_TRIM_THRESHOLD, 512 << 20);
  eval::ToolArgs args;
  if (const auto exit = eval::readCommandLine(
          "coral_check", kUsage, argc, argv,
          {"--config", "--classifier", "--a", "--b", "--transform_file", "--repeat"},
          {"--loop_closure"}, &args))
    return *exit;
  std::string usage_error;
  int repeat = 1;
  if (!eval::intOption(args, "--repeat", 1, 1, 100000, &repeat, &usage_error))
    return eval::toolError("coral_check", usage_error, kUsage);
  const std::string config = args.get("--config"), classifier = args.get("--classifier"),
                    path_a = args.get("--a"), path_b = args.get("--b"),
                    transform = args.get("--transform_file");
  const bool loop_closure = args.flag("--loop_closure");
  if (config.empty() || path_a.empty() || path_b.empty() || transform.empty())
    return eval::toolError("coral_check", "--config, --a, --b and --transform_file are required",
                           kUsage);

  std::string err;
  // The classifier file over the preset, key by key, as coral.launch loads both. A misspelt
  // group or key, a duplicate key or a wrong type is an error naming file and line.
  std::vector<std::string> presets = {config};
  if (!classifier.empty()) presets.push_back(classifier);
  NodeConfig cfg;
  if (!ros_eval::loadPresetFiles(presets, &cfg, &err)) return fail(err);

  if (loop_closure) cfg.online.verdict = coral::loopClosureVerdict(cfg.online.verdict);
  Eigen::Isometry3d T_a_b;
  if (!eval::readTransformFile(transform, &T_a_b, &err)) return fail(err);
  Input a, b;
  if (!loadInput(path_a, cfg, &a, &err) || !loadInput(path_b, cfg, &b, &err)) return fail(err);

  online::PairJudgement out;
  std::vector<double> seconds;
  for (int k = 0; k < repeat; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    if (!judge(a, b, T_a_b, cfg, &out, &err)) return fail(err);
    seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  const double median = coral::median(std::move(seconds));
  const coral::CoralResult& r = out.verdict.coral;
  char fs[32] = "null";  // JSON has no NaN: null when the free space was not measured
  if (out.verdict.free_space.valid)
    std::snprintf(fs, sizeof fs, "%.6f", out.verdict.free_space.conflict);
  const std::string free_space = fs;
  char cs[32] = "null";  // likewise the constraint term
  if (out.verdict.constraint.valid)
    std::snprintf(cs, sizeof cs, "%.6f", out.verdict.constraint.weakest);
  // A loop closure rejected at its pose whose refined pose passes (loop_closure/max_refinement,
  // or the better alignment loop_closure/restarts found), or accepted at the pose registered
  // from the given one (loop_closure/max_registered_offset): that pose, 3x4 row-major as
  // --transform_file reads it; null otherwise.
  std::string refined = "null";
  if (out.verdict.refined) {
    const Eigen::Isometry3d T = T_a_b * out.verdict.refinement.delta;
    refined = "[";
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 4; ++k) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%s%.9g", i + k > 0 ? ", " : "", T.matrix()(i, k));
        refined += buf;
      }
    refined += "]";
  }
  std::printf(
      "{\"valid\": %s, \"aligned\": %s, \"probability\": %.6f, \"quality\": %.6f, "
      "\"h_joint\": %.6f, \"h_sep\": %.6f, \"overlap\": %.6f, \"num_points_a\": %zu, "
      "\"num_points_b\": %zu, \"seconds\": %.6f, \"quality_stderr\": %.6f, \"num_valid\": %zu, "
      "\"num_queries\": %zu, \"num_non_finite\": %zu, \"num_out_of_range\": %zu, "
      "\"num_beyond_max_range\": %zu, \"num_beam_thinned\": %zu, \"num_thinned\": %zu, "
      "\"num_merged\": %zu, "
      "\"num_degenerate\": %zu, \"reason\": \"%s\", "
      "\"method\": \"%s\", \"loop_closure\": %s, \"rejected_by\": \"%s\", "
      "\"free_space_conflict\": %s, \"constraint\": %s, \"refinement\": %.6f, "
      "\"refined_transform\": %s}\n",
      r.valid ? "true" : "false", out.verdict.valid && out.verdict.aligned ? "true" : "false",
      out.verdict.valid ? out.verdict.probability : 0.0, r.quality, r.h_joint, r.h_sep, r.overlap,
      r.num_points_a, r.num_points_b, median, r.quality_stderr, r.num_valid, r.num_queries,
      r.num_non_finite, r.num_out_of_range, r.num_beyond_max_range, r.num_beam_thinned,
      r.num_thinned, r.num_merged, r.num_degenerate, jsonEscape(out.reason).c_str(),
      coral::verdictMethodName(cfg.online.verdict.method), loop_closure ? "true" : "false",
      jsonEscape(out.verdict.rejected_by).c_str(), free_space.c_str(), cs,
      out.verdict.refined ? out.verdict.refinement.size : 0.0, refined.c_str());
  return 0;
}
