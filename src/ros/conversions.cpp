#include "coral_introspection/ros/conversions.hpp"

#include <sensor_msgs/PointField.h>
#include <sensor_msgs/point_cloud2_iterator.h>
#include <tf2_eigen/tf2_eigen.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

namespace coral_introspection {
namespace ros_adapters {

namespace {

using sensor_msgs::PointField;

int typeSize(uint8_t datatype) {
  switch (datatype) {
    case PointField::INT8:
    case PointField::UINT8:
      return 1;
    case PointField::INT16:
    case PointField::UINT16:
      return 2;
    case PointField::INT32:
    case PointField::UINT32:
    case PointField::FLOAT32:
      return 4;
    case PointField::FLOAT64:
      return 8;
    default:
      return 0;
  }
}

template <class T>
double load(const uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));  // unaligned-safe
  return static_cast<double>(v);
}

// Fields are float32 or float64 (findField refuses the rest).
double readValue(const uint8_t* p, uint8_t datatype) {
  return datatype == PointField::FLOAT32 ? load<float>(p) : load<double>(p);
}

struct FieldRef {
  uint32_t offset = 0;
  uint8_t datatype = 0;
};

const char* typeName(uint8_t datatype) {
  static const char* names[] = {"?",     "int8",   "uint8",   "int16",  "uint16",
                                "int32", "uint32", "float32", "float64"};
  return datatype <= PointField::FLOAT64 ? names[datatype] : "?";
}

// Finds a usable field: present, floating point, inside point_step. Integer fields are
// refused rather than read as metres (or m/s): drivers that store integers store scaled
// values (mm, cm, 1/256 m) whose unit the message does not state.
bool findField(const sensor_msgs::PointCloud2& c, const std::string& name, FieldRef* f,
               std::string* error) {
  for (const auto& pf : c.fields) {
    if (pf.name != name) continue;
    const int size = typeSize(pf.datatype);
    if (size == 0) {
      *error = "field '" + name + "' has unknown datatype " + std::to_string(pf.datatype);
      return false;
    }
    if (pf.datatype != PointField::FLOAT32 && pf.datatype != PointField::FLOAT64) {
      *error = "field '" + name + "' is " + typeName(pf.datatype) +
               ": only float32/float64 are read (an integer field is a scaled value of "
               "unknown unit; convert it to metres in float32 before CorAl)";
      return false;
    }
    // In 64 bits: a uint32 offset near 2^32 would wrap past the check and read far outside.
    if (static_cast<uint64_t>(pf.offset) + static_cast<uint64_t>(size) > c.point_step) {
      *error = "field '" + name + "' (offset " + std::to_string(pf.offset) +
               ") lies outside point_step " + std::to_string(c.point_step);
      return false;
    }
    f->offset = pf.offset;
    f->datatype = pf.datatype;
    return true;
  }
  std::ostringstream e;
  e << "cloud has no field '" << name << "' (fields:";
  for (const auto& pf : c.fields) e << " " << pf.name;
  e << ")";
  *error = e.str();
  return false;
}

}  // namespace

bool hasField(const sensor_msgs::PointCloud2& cloud, const std::string& name) {
  for (const auto& f : cloud.fields)
    if (f.name == name) return true;
  return false;
}

// Hand-written rather than pcl::fromROSMsg: measurably faster and more general. On a
// 120k-point XYZI cloud (cloud_conversion_benchmark, doc/benchmarks.md) it takes 9.46 M
// instructions (callgrind) against 11.03 M for pcl::fromROSMsg<PointXYZ> + the copy into
// coral::Points, median 0.42-0.49 ms against 0.52-0.66 ms; and it reads float64 x, y, z, for
// which PCL's field mapping fails ("Failed to find match for field 'x'").
bool cloudToPoints(const sensor_msgs::PointCloud2& c, coral::Points* points, std::string* error,
                   CloudReadStats* stats, const std::string& extra_field,
                   std::vector<double>* extra) {
  std::string dummy;
  if (error == nullptr) error = &dummy;
  points->clear();
  if (extra) extra->clear();
  CloudReadStats st;
  st.total = static_cast<std::size_t>(c.width) * c.height;
  if (stats) *stats = st;
  FieldRef fx, fy, fz, fe;
  if (!findField(c, "x", &fx, error) || !findField(c, "y", &fy, error) ||
      !findField(c, "z", &fz, error))
    return false;
  const bool want_extra = !extra_field.empty() && extra != nullptr;
  if (want_extra && !findField(c, extra_field, &fe, error)) return false;
  if (st.total == 0) return true;
  if (c.is_bigendian) {
    *error = "big-endian point clouds are not supported";
    return false;
  }
  if (c.row_step < static_cast<uint64_t>(c.width) * c.point_step ||
      c.data.size() < static_cast<uint64_t>(c.height) * c.row_step) {
    std::ostringstream e;
    e << "cloud data too short: " << c.data.size() << " bytes for " << c.height << " rows of "
      << c.row_step << " bytes (width " << c.width << ", point_step " << c.point_step << ")";
    *error = e.str();
    return false;
  }
  points->reserve(st.total);
  if (want_extra) extra->reserve(st.total);
  for (uint32_t r = 0; r < c.height; ++r) {
    const uint8_t* row = c.data.data() + static_cast<std::size_t>(r) * c.row_step;
    for (uint32_t i = 0; i < c.width; ++i) {
      const uint8_t* p = row + static_cast<std::size_t>(i) * c.point_step;
      const coral::Vec3 v(readValue(p + fx.offset, fx.datatype),
                          readValue(p + fy.offset, fy.datatype),
                          readValue(p + fz.offset, fz.datatype));
      const double e = want_extra ? readValue(p + fe.offset, fe.datatype) : 0.0;
      if (!v.allFinite() || !std::isfinite(e)) {
        ++st.non_finite;
        continue;
      }
      points->push_back(v);
      if (want_extra) extra->push_back(e);
    }
  }
  if (stats) *stats = st;
  return true;
}

sensor_msgs::PointCloud2 pointsToCloud(const coral::Points& points, const std_msgs::Header& header,
                                       const std::vector<float>* intensity) {
  sensor_msgs::PointCloud2 c;
  c.header = header;
  sensor_msgs::PointCloud2Modifier mod(c);
  const bool with_i = intensity != nullptr && intensity->size() == points.size();
  if (with_i)
    mod.setPointCloud2Fields(4, "x", 1, PointField::FLOAT32, "y", 1, PointField::FLOAT32, "z", 1,
                             PointField::FLOAT32, "intensity", 1, PointField::FLOAT32);
  else
    mod.setPointCloud2FieldsByString(1, "xyz");
  mod.resize(points.size());
  c.height = 1;
  c.width = static_cast<uint32_t>(points.size());
  c.is_dense = true;
  sensor_msgs::PointCloud2Iterator<float> it(c, "x");
  for (std::size_t i = 0; i < points.size(); ++i, ++it) {
    it[0] = static_cast<float>(points[i].x());
    it[1] = static_cast<float>(points[i].y());
    it[2] = static_cast<float>(points[i].z());
  }
  if (with_i) {
    sensor_msgs::PointCloud2Iterator<float> ii(c, "intensity");
    for (std::size_t i = 0; i < points.size(); ++i, ++ii) *ii = (*intensity)[i];
  }
  return c;
}

sensor_msgs::PointCloud2 buildQualityCloud(const coral::Scan& a, const coral::Scan& b,
                                           const coral::CoralResult& result,
                                           const std_msgs::Header& header,
                                           const Eigen::Isometry3d& T_header_scans) {
  sensor_msgs::PointCloud2 c;
  c.header = header;
  sensor_msgs::PointCloud2Modifier mod(c);
  mod.setPointCloud2Fields(7, "x", 1, PointField::FLOAT32, "y", 1, PointField::FLOAT32, "z", 1,
                           PointField::FLOAT32, "q", 1, PointField::FLOAT32, "h_sep", 1,
                           PointField::FLOAT32, "h_joint", 1, PointField::FLOAT32, "scan", 1,
                           PointField::UINT8);
  c.point_step = 28;  // 25 bytes padded: the float fields of every point stay 4-byte aligned
  // Every scored point carries its position (common frame) and scan; with a voxel filter
  // or a query subset these are the voxel centroids / sampled points that were evaluated.
  (void)a;
  (void)b;
  std::size_t count = 0;
  for (const auto& pe : result.per_point) count += pe.valid ? 1 : 0;
  mod.resize(count);
  c.height = 1;
  c.width = static_cast<uint32_t>(count);
  c.is_dense = true;
  if (count == 0) return c;
  sensor_msgs::PointCloud2Iterator<float> it(c, "x");
  sensor_msgs::PointCloud2Iterator<uint8_t> is(c, "scan");
  for (const coral::PointEntropy& pe : result.per_point) {
    if (!pe.valid) continue;
    const coral::Vec3 p = T_header_scans * pe.position.cast<double>();
    it[0] = static_cast<float>(p.x());
    it[1] = static_cast<float>(p.y());
    it[2] = static_cast<float>(p.z());
    it[3] = pe.q();
    it[4] = pe.h_sep;
    it[5] = pe.h_joint;
    *is = pe.scan;
    ++it;
    ++is;
  }
  return c;
}

AlignmentQuality toMessage(const coral::CoralResult& result, const coral::Verdict& verdict,
                           const std_msgs::Header& header, const ros::Time& stamp_a,
                           const ros::Time& stamp_b) {
  AlignmentQuality m;
  m.header = header;
  m.stamp_a = stamp_a;
  m.stamp_b = stamp_b;
  m.status = result.valid ? AlignmentQuality::VERDICT : AlignmentQuality::INVALID_PAIR;
  m.valid = result.valid;
  m.aligned = result.valid && verdict.aligned;
  m.probability = result.valid ? verdict.probability : 0.0;
  m.h_joint = result.h_joint;
  m.h_sep = result.h_sep;
  m.quality = result.quality;
  m.overlap = result.overlap;
  m.num_points_a = static_cast<uint32_t>(result.num_points_a);
  m.num_points_b = static_cast<uint32_t>(result.num_points_b);
  m.num_valid = static_cast<uint32_t>(result.num_valid);
  m.processing_time = result.seconds;
  return m;
}

AlignmentQuality toMessage(const coral::AlignmentVerdict& v, const coral::VerdictConfig& cfg,
                           const std_msgs::Header& header, const ros::Time& stamp_a,
                           const ros::Time& stamp_b) {
  coral::Verdict combined;
  combined.aligned = v.aligned;
  combined.probability = v.probability;
  AlignmentQuality m = toMessage(v.coral, combined, header, stamp_a, stamp_b);
  m.valid = v.valid;  // the relative check may lack valid neighbours where CorAl is valid
  m.status = v.valid ? AlignmentQuality::VERDICT : AlignmentQuality::INVALID_PAIR;
  m.aligned = v.valid && v.aligned;
  m.probability = v.valid ? v.probability : 0.0;
  m.method = coral::verdictMethodName(cfg.method);
  m.rejected_by = v.rejected_by;
  m.tolerance_translation = cfg.tolerance.translation;
  m.tolerance_rotation = cfg.tolerance.rotation_deg;
  m.relative_score = v.relative.valid ? v.relative.score : std::nan("");
  m.free_space_conflict = v.free_space.valid ? v.free_space.conflict : std::nan("");
  m.constraint = v.constraint.valid ? v.constraint.weakest : std::nan("");
  m.correction_hint = v.relative.hint.name;
  m.correction = toTransformMsg(v.relative.hint.name.empty() ? Eigen::Isometry3d::Identity()
                                                             : v.relative.hint.delta);
  if (v.refined) {  // a loop closure's refined or registered pose passes: offered
    m.correction_hint = "refined";
    m.correction = toTransformMsg(v.refinement.delta);
    m.refinement = v.refinement.size;
  }
  for (coral::Axis a : v.relative.flat_axes) m.flat_axes.push_back(coral::axisName(a));
  return m;
}

VelocityConsistency toMessage(const online::DopplerReport& d, const std_msgs::Header& header) {
  const radar::ConsistencyResult& r = d.result;
  VelocityConsistency m;
  m.header = header;
  m.valid = r.valid;
  m.consistent = r.valid && r.consistent;
  m.chi2 = r.chi2;
  m.threshold = r.threshold;
  m.dof = static_cast<uint32_t>(std::max(0, r.dof));
  m.velocity_odometry.x = d.velocity_odometry.x();
  m.velocity_odometry.y = d.velocity_odometry.y();
  m.velocity_odometry.z = d.velocity_odometry.z();
  m.velocity_doppler.x = r.velocity_doppler.x();
  m.velocity_doppler.y = r.velocity_doppler.y();
  m.velocity_doppler.z = r.velocity_doppler.z();
  m.num_points = static_cast<uint32_t>(d.num_points);
  m.num_inliers = static_cast<uint32_t>(r.num_inliers);
  m.inlier_ratio = m.num_points > 0 ? static_cast<double>(m.num_inliers) / m.num_points : 0.0;
  return m;
}

bool toEigen(const geometry_msgs::Transform& t, Eigen::Isometry3d* out, std::string* error) {
  const Eigen::Vector4d q(t.rotation.x, t.rotation.y, t.rotation.z, t.rotation.w);
  const Eigen::Vector3d v(t.translation.x, t.translation.y, t.translation.z);
  if (!q.allFinite() || !v.allFinite()) {
    if (error) *error = "transform has a NaN/Inf entry";
    return false;
  }
  if (std::abs(q.norm() - 1.0) > 1e-3) {
    if (error) {
      std::ostringstream e;
      e << "transform rotation is not a unit quaternion (norm " << q.norm() << ")";
      *error = e.str();
    }
    return false;
  }
  geometry_msgs::TransformStamped ts;
  ts.transform = t;
  Eigen::Isometry3d T = tf2::transformToEigen(ts);
  T.linear() = Eigen::Quaterniond(T.rotation()).normalized().toRotationMatrix();
  *out = T;
  return true;
}

geometry_msgs::Transform toTransformMsg(const Eigen::Isometry3d& T) {
  return tf2::eigenToTransform(T).transform;
}

}  // namespace ros_adapters
}  // namespace coral_introspection
