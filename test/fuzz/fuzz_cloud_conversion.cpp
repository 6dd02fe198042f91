// libFuzzer harness: a sensor_msgs/PointCloud2 with fuzzed layout -> cloudToPoints.
// Width, height, point_step, row_step, endianness and up to 6 fields (name from a small
// set, any offset, datatype and count) come from the input, the data bytes from its rest.
// Only the message headers of roscpp are used: no master, no node. Whatever is accepted
// must be finite points (and extra values), no more than the message holds.
#include <sensor_msgs/PointCloud2.h>

#include <cmath>

#include "coral_introspection/ros/conversions.hpp"
#include "fuzz_input.hpp"

using coral_fuzz::FuzzInput;
namespace ra = coral_introspection::ros_adapters;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  FuzzInput in(data, size);
  sensor_msgs::PointCloud2 c;
  const uint8_t shape = in.byte();
  // Mostly small plausible shapes; sometimes raw 32-bit values (overflow probes).
  c.height = shape & 1 ? in.take<uint32_t>() : in.range(0, 3);
  c.width = shape & 2 ? in.take<uint32_t>() : in.range(0, 40);
  c.point_step = shape & 4 ? in.take<uint32_t>() : in.range(0, 40);
  c.row_step = shape & 8 ? in.take<uint32_t>() : c.width * c.point_step + in.range(0, 3) - 1;
  c.is_bigendian = (shape & 0x30) == 0x30;
  c.is_dense = shape & 0x40;
  static const char* const kNames[] = {"x", "y", "z", "velocity", "intensity", ""};
  const int num_fields = in.range(0, 6);
  for (int i = 0; i < num_fields; ++i) {
    sensor_msgs::PointField f;
    const uint8_t kind = in.byte();
    f.name = kNames[kind % 6];
    f.offset = kind & 0x80 ? in.take<uint32_t>() : in.range(0, 40);
    f.datatype = in.range(0, 9);  // 1..8 are the valid PointField types
    f.count = in.range(0, 2);
    c.fields.push_back(f);
  }
  c.data.assign(in.rest(), in.rest() + in.remaining());

  const bool with_extra = shape & 0x80;
  coral_introspection::coral::Points pts;
  std::vector<double> extra;
  ra::CloudReadStats stats;
  std::string err;
  const bool ok = ra::cloudToPoints(c, &pts, &err, &stats, with_extra ? "velocity" : "",
                                    with_extra ? &extra : nullptr);
  CORAL_FUZZ_CHECK(ok || !err.empty());
  if (!ok) return 0;
  const uint64_t total = static_cast<uint64_t>(c.width) * c.height;
  CORAL_FUZZ_CHECK(stats.total == total);
  CORAL_FUZZ_CHECK(pts.size() + stats.non_finite == total);
  for (const auto& p : pts) CORAL_FUZZ_CHECK(p.allFinite());
  if (with_extra) {
    CORAL_FUZZ_CHECK(extra.size() == pts.size());
    for (double e : extra) CORAL_FUZZ_CHECK(std::isfinite(e));
  }
  return 0;
}
