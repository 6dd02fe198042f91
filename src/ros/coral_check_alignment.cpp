#include "coral_introspection/ros/coral_check_alignment.hpp"

#include "coral_introspection/online/introspector.hpp"
#include "coral_introspection/ros/conversions.hpp"
#include "coral_introspection/ros/coral_scan_input.hpp"

#include <vector>

namespace coral_introspection {
namespace ros_adapters {

namespace {

// A message of the request counts as given when anything beyond its header is set (a
// layout, a size or data): an unfilled field of the request is a default-constructed one.
bool given(const sensor_msgs::PointCloud2& c) {
  return !c.fields.empty() || c.width > 0 || c.height > 0 || !c.data.empty();
}
bool given(const sensor_msgs::Image& i) {
  return !i.encoding.empty() || i.width > 0 || i.height > 0 || !i.data.empty();
}
bool given(const sensor_msgs::LaserScan& s) {
  return !s.ranges.empty() || !s.intensities.empty() || s.angle_increment != 0.0f ||
         s.angle_min != 0.0f || s.angle_max != 0.0f || s.range_max != 0.0f;
}

// The three kinds of scan pair a request can hold, in the order of the request's fields.
enum class Kind { kClouds, kImages, kLaserScans };
struct KindInfo {
  Kind kind;
  const char* a;  // field names
  const char* b;
  const char* plural;  // "point clouds"
  const char* input;   // the input_type of the nodelet that judges them
};
constexpr KindInfo kKinds[] = {
    {Kind::kClouds, "cloud_a", "cloud_b", "point clouds", "pointcloud"},
    {Kind::kImages, "image_a", "image_b", "polar images", "polar_image"},
    {Kind::kLaserScans, "scan_a", "scan_b", "laser scans", "laser_scan"},
};

// The request's two messages of kind k, handed to f(a, b): the one place that maps a kind to
// its fields (f is generic: the messages differ in type, its result must not).
template <typename F>
auto withPair(const CheckAlignment::Request& req, Kind k, F&& f) {
  switch (k) {
    case Kind::kClouds:
      return f(req.cloud_a, req.cloud_b);
    case Kind::kImages:
      return f(req.image_a, req.image_b);
    case Kind::kLaserScans:
      break;
  }
  return f(req.scan_a, req.scan_b);
}

const KindInfo& infoOf(Kind k) {
  for (const auto& i : kKinds)
    if (i.kind == k) return i;
  return kKinds[0];  // unreachable: every kind has its row
}

std::pair<bool, bool> givenPair(const CheckAlignment::Request& req, Kind k) {
  return withPair(req, k, [](const auto& a, const auto& b) {
    return std::pair<bool, bool>{given(a), given(b)};
  });
}

// What a nodelet of this input type judges: its own kind, and a laser-scan nodelet also planar
// point clouds (a client holding clouds, or requests written before the scan fields).
bool judges(InputType type, Kind k) {
  switch (type) {
    case InputType::kPointCloud:
      return k == Kind::kClouds;
    case InputType::kPolarImage:
      return k == Kind::kImages;
    case InputType::kLaserScan:
      break;
  }
  return k == Kind::kLaserScans || k == Kind::kClouds;
}

// "scan_a and scan_b (or cloud_a and cloud_b)": the fields a nodelet of this type wants.
std::string wantedFields(InputType type) {
  std::string out;
  for (const auto& k : kKinds)
    if (judges(type, k.kind) && k.kind != Kind::kClouds) out = std::string(k.a) + " and " + k.b;
  if (judges(type, Kind::kClouds))
    out = out.empty() ? "cloud_a and cloud_b" : out + " (or cloud_a and cloud_b)";
  return out;
}

// The kind the request holds (requestKindError empty), or clouds for a request with none.
Kind heldKind(const CheckAlignment::Request& req) {
  for (const auto& k : kKinds) {
    const auto [a, b] = givenPair(req, k.kind);
    if (a || b) return k.kind;
  }
  return Kind::kClouds;
}

}  // namespace

std::string requestKindError(const CheckAlignment::Request& req, InputType type) {
  std::string held;                     // the given fields, e.g. "cloud_a, image_b"
  std::vector<const char*> held_kinds;  // their kinds, e.g. "point clouds"
  const KindInfo* only = nullptr;       // the kind held, when it is one
  for (const auto& k : kKinds) {
    const auto [a, b] = givenPair(req, k.kind);
    for (const auto& [set, name] : {std::pair<bool, const char*>{a, k.a}, {b, k.b}})
      if (set) held += std::string(held.empty() ? "" : ", ") + name;
    if (!a && !b) continue;
    held_kinds.push_back(k.plural);
    only = &k;
  }
  const std::string wanted = wantedFields(type);
  const std::string self = "this nodelet is configured for " + inputKindName(type);
  if (held_kinds.empty())
    return "the request holds no scan (cloud_a, cloud_b, image_a, image_b, scan_a and scan_b "
           "are all empty); " +
           self + ": fill " + wanted;
  // Two kinds in one request: which pair was meant cannot be told (the other fields of a
  // cloud request are not leftovers to be ignored).
  if (held_kinds.size() > 1) {
    std::string mixed = held_kinds[0];  // "point clouds, polar images and laser scans"
    for (std::size_t i = 1; i < held_kinds.size(); ++i)
      mixed += std::string(i + 1 < held_kinds.size() ? ", " : " and ") + held_kinds[i];
    return "the request mixes " + mixed + " (" + held + "); " + self + ": fill " + wanted + " only";
  }
  if (!judges(type, only->kind))
    return self + "; the request holds " + only->plural + " (" + held +
           "): send them to a nodelet with input_type " + only->input;
  const auto [a, b] = givenPair(req, only->kind);
  if (!(a && b))
    return std::string(a ? only->b : only->a) + " is empty: the request needs two " + only->plural +
           " (" + only->a + " and " + only->b + ")";
  return "";
}

bool answerCheckAlignment(const CheckAlignment::Request& req, const NodeConfig& cfg,
                          CheckAlignment::Response* res) {
  const Kind kind = heldKind(req);
  const auto [ha, stamp_b] = withPair(req, kind, [](const auto& a, const auto& b) {
    return std::pair<std_msgs::Header, ros::Time>{a.header, b.header.stamp};
  });
  SensorScan sa, sb;
  std::string error = requestKindError(req, cfg.input_type);
  auto convert = [&](const auto& msg, const char* name, SensorScan* s) {
    if (toSensorScan(msg, cfg, s, &error)) return true;
    error = std::string(name) + ": " + error;
    return false;
  };
  auto convertBoth = [&] {
    const KindInfo& info = infoOf(kind);
    return withPair(req, kind, [&](const auto& a, const auto& b) {
      return convert(a, info.a, &sa) && convert(b, info.b, &sb);
    });
  };
  Eigen::Isometry3d T_a_b;
  const bool ok = error.empty() && convertBoth() && toEigen(req.transform_a_b, &T_a_b, &error);
  if (!ok) {
    res->result = toMessage(coral::AlignmentVerdict(), cfg.online.verdict, ha, ha.stamp, stamp_b);
    res->error = "request refused: " + error;
    res->result.status = AlignmentQuality::REFUSED;
    res->result.reason = res->error;
    return false;
  }
  coral::Scan a, b;
  a.points = std::move(sa.scan.features.points);
  b.points = std::move(sb.scan.features.points);
  // A loop-closure candidate: the gated verdict with the loop gate (coral/verdict.hpp).
  online::IntrospectorConfig judge = cfg.online;
  if (req.loop_closure) judge.verdict = coral::loopClosureVerdict(cfg.online.verdict);
  const online::PairJudgement j = online::judgePair(std::move(a), b, T_a_b, judge, false);
  res->result = toMessage(j.verdict, judge.verdict, ha, ha.stamp, stamp_b);
  res->result.loop_closure = req.loop_closure;
  res->result.reason = j.reason;
  res->error = j.reason;
  return true;
}

}  // namespace ros_adapters
}  // namespace coral_introspection
