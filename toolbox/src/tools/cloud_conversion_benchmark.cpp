// Benchmark of the PointCloud2 -> coral::Points reader of the nodelet
// (ros_adapters::cloudToPoints) against PCL's path (pcl::fromROSMsg into
// pcl::PointCloud<pcl::PointXYZ>, then the copy into coral::Points with the same finiteness
// filter), on a synthetic 120k-point XYZI cloud (float32 x, y, z, intensity; 16 B/point,
// 1 % NaN points):
//   rosrun coral_introspection cloud_conversion_benchmark [--points N] [--repeats N]
// Prints the median wall time of each and their ratio. For instruction counts:
//   valgrind --tool=callgrind --callgrind-out-file=cg.out
//       $(catkin_find coral_introspection cloud_conversion_benchmark) --repeats 1   (one line)
//   callgrind_annotate --inclusive=yes cg.out | grep -E "readHandWritten|readWithPcl"
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl_conversions/pcl_conversions.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/point_cloud2_iterator.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "coral_introspection/coral/statistics.hpp"
#include "coral_introspection/eval/tool_args.hpp"
#include "coral_introspection/ros/conversions.hpp"

using namespace coral_introspection;
using Clock = std::chrono::steady_clock;

namespace {

sensor_msgs::PointCloud2 makeCloud(std::size_t n) {
  sensor_msgs::PointCloud2 c;
  c.header.frame_id = "lidar";
  sensor_msgs::PointCloud2Modifier mod(c);
  mod.setPointCloud2Fields(
      4, "x", 1, sensor_msgs::PointField::FLOAT32, "y", 1, sensor_msgs::PointField::FLOAT32, "z", 1,
      sensor_msgs::PointField::FLOAT32, "intensity", 1, sensor_msgs::PointField::FLOAT32);
  mod.resize(n);
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(-50.f, 50.f);
  sensor_msgs::PointCloud2Iterator<float> x(c, "x"), y(c, "y"), z(c, "z"), i(c, "intensity");
  for (std::size_t k = 0; k < n; ++k, ++x, ++y, ++z, ++i) {
    const bool nan = k % 100 == 0;  // 1 % invalid returns, as drivers publish them
    *x = nan ? std::numeric_limits<float>::quiet_NaN() : u(rng);
    *y = u(rng);
    *z = 0.1f * u(rng);
    *i = 100.f;
  }
  return c;
}

// noinline: separate entries in callgrind's per-function counts.
__attribute__((noinline)) std::size_t readHandWritten(const sensor_msgs::PointCloud2& c,
                                                      coral::Points* pts) {
  std::string err;
  if (!ros_adapters::cloudToPoints(c, pts, &err)) std::fprintf(stderr, "%s\n", err.c_str());
  return pts->size();
}

__attribute__((noinline)) std::size_t readWithPcl(const sensor_msgs::PointCloud2& c,
                                                  coral::Points* pts) {
  pcl::PointCloud<pcl::PointXYZ> pc;
  pcl::fromROSMsg(c, pc);
  pts->clear();
  pts->reserve(pc.size());
  for (const auto& p : pc.points)
    if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))
      pts->emplace_back(p.x, p.y, p.z);
  return pts->size();
}

constexpr const char* kUsage = "usage: cloud_conversion_benchmark [--points N] [--repeats N]";

}  // namespace

int main(int argc, char** argv) {
  eval::ToolArgs args;
  if (const auto exit = eval::readCommandLine("cloud_conversion_benchmark", kUsage, argc, argv,
                                              {"--points", "--repeats"}, {}, &args))
    return *exit;
  std::string err;
  int points = 0, repeats = 0;
  if (!eval::positiveInt(args, "--points", 120000, &points, &err) ||
      !eval::positiveInt(args, "--repeats", 200, &repeats, &err))
    return eval::toolError("cloud_conversion_benchmark", err, kUsage);
  const std::size_t n = static_cast<std::size_t>(points);
  const sensor_msgs::PointCloud2 cloud = makeCloud(n);
  coral::Points a, b;
  std::vector<double> t_hand, t_pcl;
  for (int r = 0; r < repeats; ++r) {  // interleaved, so load changes hit both alike
    // Fresh output per call, as the nodelet reads every message into a new scan.
    a = coral::Points();
    b = coral::Points();
    auto t0 = Clock::now();
    readHandWritten(cloud, &a);
    auto t1 = Clock::now();
    readWithPcl(cloud, &b);
    auto t2 = Clock::now();
    t_hand.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    t_pcl.push_back(std::chrono::duration<double, std::milli>(t2 - t1).count());
  }
  if (a.size() != b.size() || !std::equal(a.begin(), a.end(), b.begin())) {
    std::fprintf(stderr, "the two readers disagree (%zu vs %zu points)\n", a.size(), b.size());
    return 1;
  }
  const std::size_t finite = a.size();
  // Generality: x, y, z as float64 (some drivers and 4D radars publish them so).
  sensor_msgs::PointCloud2 c64;
  sensor_msgs::PointCloud2Modifier mod(c64);
  mod.setPointCloud2Fields(3, "x", 1, sensor_msgs::PointField::FLOAT64, "y", 1,
                           sensor_msgs::PointField::FLOAT64, "z", 1,
                           sensor_msgs::PointField::FLOAT64);
  mod.resize(1);
  sensor_msgs::PointCloud2Iterator<double> x64(c64, "x"), y64(c64, "y"), z64(c64, "z");
  *x64 = 1.0, *y64 = 2.0, *z64 = 3.0;
  readHandWritten(c64, &a);
  readWithPcl(c64, &b);
  const coral::Vec3 want(1.0, 2.0, 3.0);
  const bool hand64 = a.size() == 1 && a[0] == want, pcl64 = b.size() == 1 && b[0] == want;

  // The upper middle value of the even repeat counts, as this benchmark always reported.
  const double mh = coral::quantile(t_hand, 0.5), mp = coral::quantile(t_pcl, 0.5);
  std::printf("%zu-point XYZI cloud (%zu finite), %d repeats, median wall time:\n", n, finite,
              repeats);
  std::printf("  cloudToPoints (hand-written)        %8.3f ms\n", mh);
  std::printf("  pcl::fromROSMsg + copy to Points    %8.3f ms\n", mp);
  std::printf("  ratio pcl / hand-written            %8.2f\n", mp / mh);
  std::printf("float64 x, y, z read correctly: hand-written %s, pcl %s\n", hand64 ? "yes" : "no",
              pcl64 ? "yes" : "no");
  return 0;
}
