#include "coral_introspection/eval/cloud_io.hpp"

#include <pcl/PCLPointCloud2.h>
#include <pcl/io/pcd_io.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <type_traits>
#include <vector>

#include "coral_introspection/coral/validation.hpp"

namespace coral_introspection {
namespace eval {

namespace {

// Numbers separated by commas and/or white space (both layouts occur in libpointmatcher's
// files); the first `skip` fields are ignored. False when a field is not a number.
bool parseNumbers(std::string line, std::size_t skip, std::vector<double>* out) {
  std::replace(line.begin(), line.end(), ',', ' ');
  std::istringstream ss(line);
  std::string field;
  out->clear();
  for (std::size_t col = 0; ss >> field; ++col) {
    if (col < skip) continue;
    std::size_t used = 0;
    try {
      out->push_back(std::stod(field, &used));
    } catch (const std::exception&) {
      return false;
    }
    if (used != field.size()) return false;
  }
  return true;
}

std::string lowerExtension(const std::string& path) {
  const std::size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || path.find('/', dot) != std::string::npos) return "";
  std::string ext = path.substr(dot + 1);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

// The value of type T at p as a double; false when that is not exact (a 64-bit integer
// beyond 2^53 in magnitude). Every other PCD type is exact in a double.
template <class T>
bool readExact(const uint8_t* p, double* out) {
  T v;
  std::memcpy(&v, p, sizeof(v));  // unaligned-safe
  *out = static_cast<double>(v);
  if constexpr (std::is_integral_v<T> && sizeof(T) == 8) {
    constexpr T kExact = T(1) << 53;
    if constexpr (std::is_signed_v<T>)
      return v >= -kExact && v <= kExact;
    else
      return v <= kExact;
  }
  return true;
}

// The types PCD defines: PCL's datatype, the PCD TYPE and SIZE (for messages), the reader.
struct PcdType {
  uint8_t datatype;
  const char* name;
  bool (*read)(const uint8_t*, double*);
};
using F = pcl::PCLPointField;
const PcdType kPcdTypes[] = {{F::INT8, "I 1 (int8)", &readExact<int8_t>},
                             {F::UINT8, "U 1 (uint8)", &readExact<uint8_t>},
                             {F::INT16, "I 2 (int16)", &readExact<int16_t>},
                             {F::UINT16, "U 2 (uint16)", &readExact<uint16_t>},
                             {F::INT32, "I 4 (int32)", &readExact<int32_t>},
                             {F::UINT32, "U 4 (uint32)", &readExact<uint32_t>},
                             {F::INT64, "I 8 (int64)", &readExact<int64_t>},
                             {F::UINT64, "U 8 (uint64)", &readExact<uint64_t>},
                             {F::FLOAT32, "F 4 (float32)", &readExact<float>},
                             {F::FLOAT64, "F 8 (float64)", &readExact<double>}};

// nullptr for a datatype PCD does not define: PCL's reader stores an undefined TYPE / SIZE
// pair (e.g. F 2) as 255, and reads on as if it had no bytes.
const PcdType* pcdType(uint8_t datatype) {
  for (const PcdType& t : kPcdTypes)
    if (t.datatype == datatype) return &t;
  return nullptr;
}

std::string pcdTypeName(uint8_t datatype) {
  const PcdType* t = pcdType(datatype);
  return t ? t->name : "undefined (datatype " + std::to_string(datatype) + ")";
}

// Whether field `f` (a coordinate: x, y or z) can be read; else false with the reason. Coordinates
// must be F 4 or F 8: an integer coordinate is a scaled value (mm, cm, 1/256 m) whose unit the PCD
// header does not state, so it is refused as the nodelet refuses integer PointCloud2 fields
// (reading it as metres is off by that scale; 64-bit integers were once read as the bits of a
// double: every point near 0, merged into one). Intensity, which nothing judges by, may be of
// any defined type (64-bit integers in binary files only). One value per point (COUNT 1)
// is expected of each.
bool checkPcdField(const std::string& path, const pcl::PCLPointField& f, bool coordinate,
                   bool ascii, std::string* error) {
  const std::string what = path + ": field '" + f.name + "' ";
  if (!pcdType(f.datatype))
    return coral::fail(error, what + "has TYPE / SIZE " + pcdTypeName(f.datatype) +
                                  ": PCD defines F 4, F 8 and I / U 1, 2, 4, 8");
  if (coordinate && f.datatype != F::FLOAT32 && f.datatype != F::FLOAT64)
    return coral::fail(error, what + "is TYPE / SIZE " + pcdTypeName(f.datatype) +
                                  ": coordinates are read from F 4 or F 8 only (an integer "
                                  "coordinate is a scaled value of unknown unit; convert it to "
                                  "metres as float32 first)");
  // PCL's ascii reader parses 64-bit integers through a double: 2^53 + 1 arrives as 2^53,
  // and nothing after it can tell.
  if (ascii && (f.datatype == F::INT64 || f.datatype == F::UINT64))
    return coral::fail(error, what + "is TYPE / SIZE " + pcdTypeName(f.datatype) +
                                  " in an ascii PCD: PCL's ascii reader rounds 64-bit integers "
                                  "through a double (beyond 2^53); store the file as binary");
  if (f.count != 1)
    return coral::fail(
        error, what + "has COUNT " + std::to_string(f.count) + " (1 value per point expected)");
  return true;
}

// PCL's reader handles the three PCD encodings (ascii, binary, binary_compressed) and
// the header; the fields are then checked (checkPcdField) and read exactly by name.
bool loadPcd(const std::string& path, LoadedCloud* cloud, std::string* error, bool planar_ok) {
  pcl::PCLPointCloud2 c;
  pcl::PCDReader reader;
  Eigen::Vector4f origin;
  Eigen::Quaternionf orientation;
  int version = 0, encoding = 0;  // encoding 0: DATA ascii
  unsigned int data_start = 0;
  if (reader.readHeader(path, c, origin, orientation, version, encoding, data_start) < 0 ||
      reader.read(path, c) < 0)
    return coral::fail(error, path + ": not a readable PCD file");
  // VIEWPOINT places the sensor in the points' frame. Every scan is read in its own sensor's
  // frame (CorAl's radius, the free-space rays and the transform all start there), so a cloud
  // stored in another frame is refused rather than read as if the sensor stood at its origin.
  const Eigen::Quaternionf identity = Eigen::Quaternionf::Identity();
  if (origin.head<3>().norm() > 1e-6f || orientation.angularDistance(identity) > 1e-6f) {
    char v[160];
    std::snprintf(v, sizeof(v), "%g %g %g %g %g %g %g", origin.x(), origin.y(), origin.z(),
                  orientation.w(), orientation.x(), orientation.y(), orientation.z());
    return coral::fail(error, path + ": VIEWPOINT " + v +
                                  " puts the sensor away from the points' origin; scans are read "
                                  "in their sensor's frame: store the points there (VIEWPOINT 0 0 "
                                  "0 1 0 0 0)");
  }
  const pcl::PCLPointField* f[4] = {nullptr, nullptr, nullptr, nullptr};
  const char* names[4] = {"x", "y", "z", "intensity"};
  for (const pcl::PCLPointField& field : c.fields)
    for (int k = 0; k < 4; ++k)
      if (field.name == names[k]) f[k] = &field;
  if (!f[0] || !f[1] || (!f[2] && !planar_ok))
    return coral::fail(error, path + ": PCD file without fields x, y, z (x, y alone: a 2D scan, " +
                                  (planar_ok ? "read" : "not read here") + ")");
  cloud->planar = f[2] == nullptr;
  for (int k = 0; k < 4; ++k)
    if (f[k] && !checkPcdField(path, *f[k], k < 3, encoding == 0, error)) return false;
  const std::size_t n = static_cast<std::size_t>(c.width) * c.height;
  if (c.data.size() < n * c.point_step) return coral::fail(error, path + ": PCD data is truncated");
  cloud->points.resize(n);
  cloud->intensity.assign(f[3] ? n : 0, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    const uint8_t* point = c.data.data() + i * c.point_step;
    double v[4] = {0.0, 0.0, 0.0, 0.0};
    for (int k = 0; k < 4; ++k)
      if (f[k] && !pcdType(f[k]->datatype)->read(point + f[k]->offset, &v[k]))
        return coral::fail(error, path + ": field '" + f[k]->name + "' of point " +
                                      std::to_string(i) + " (" + pcdTypeName(f[k]->datatype) +
                                      ") is beyond 2^53 in magnitude: not exact as a double");
    cloud->points[i] = coral::Vec3(v[0], v[1], v[2]);
    if (f[3]) cloud->intensity[i] = v[3];
  }
  return true;
}

bool loadKittiBin(const std::string& path, LoadedCloud* cloud, std::string* error) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) return coral::fail(error, "cannot open " + path);
  const std::streamsize bytes = in.tellg();
  if (bytes % 16 != 0)
    return coral::fail(error,
                       path + ": size " + std::to_string(bytes) +
                           " B is not a multiple of 16 (float32 x, y, z, intensity records)");
  std::vector<float> raw(static_cast<std::size_t>(bytes) / 4);
  in.seekg(0);
  if (!in.read(reinterpret_cast<char*>(raw.data()), bytes))
    return coral::fail(error, path + ": read error");
  const std::size_t n = raw.size() / 4;
  cloud->points.resize(n);
  cloud->intensity.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    cloud->points[i] = coral::Vec3(raw[4 * i], raw[4 * i + 1], raw[4 * i + 2]);
    cloud->intensity[i] = raw[4 * i + 3];
  }
  return true;
}

// All numbers of a text file, in order.
bool readAllNumbers(const std::string& path, std::vector<double>* v, std::string* error) {
  std::ifstream in(path);
  if (!in) return coral::fail(error, "cannot open " + path);
  v->clear();
  std::string line;
  std::vector<double> row;
  for (std::size_t n = 1; std::getline(in, line); ++n) {
    if (!parseNumbers(line, 0, &row))
      return coral::fail(error, path + ":" + std::to_string(n) + ": not a list of numbers");
    v->insert(v->end(), row.begin(), row.end());
  }
  return true;
}

// 12 numbers (3x4 row-major) -> isometry; false when the rotation is not orthonormal.
constexpr double kRotationSlack = 2e-3;  // max |R^T R - I| of a rotation as written in a file

bool isometryFrom3x4(const double* m, Eigen::Isometry3d* T) {
  Eigen::Matrix3d R;
  coral::Vec3 t;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) R(r, c) = m[4 * r + c];
    t(r) = m[4 * r + 3];
  }
  if (!R.allFinite() || !t.allFinite()) return false;
  // A rotation written with 3 decimals deviates by up to ~1.7e-3 (0.1 deg at most; 1e-4, the
  // bound until 2026-12-07, refused some written with 4): re-orthonormalised below. A shear
  // or a scale is not a rounded rotation.
  if ((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > kRotationSlack)
    return false;
  if (R.determinant() < 0.0) return false;
  T->setIdentity();
  T->linear() = Eigen::Quaterniond(R).normalized().toRotationMatrix();
  T->translation() = t;
  return true;
}

}  // namespace

bool loadCloud(const std::string& path, LoadedCloud* cloud, std::string* error, bool planar_ok) {
  cloud->points.clear();
  cloud->intensity.clear();
  cloud->planar = false;
  const std::string ext = lowerExtension(path);
  try {
    if (ext == "pcd") return loadPcd(path, cloud, error, planar_ok);
    if (ext == "bin") return loadKittiBin(path, cloud, error);
    if (ext == "csv") return readCsvPoints(path, &cloud->points, error);
  } catch (const std::exception& e) {  // PCL may throw on malformed headers
    return coral::fail(error, path + ": " + e.what());
  }
  return coral::fail(error, path + ": unknown point cloud extension (expected .pcd, .bin or .csv)");
}

bool readCsvPoints(const std::string& path, coral::Points* points, std::string* error) {
  std::ifstream in(path);
  if (!in) return coral::fail(error, "cannot open " + path);
  points->clear();
  std::string line;
  std::vector<double> v;
  for (std::size_t n = 1; std::getline(in, line); ++n) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    if (!parseNumbers(line, 0, &v) || v.size() < 3) {
      if (n == 1) continue;  // header
      return coral::fail(error, path + ":" + std::to_string(n) + ": expected at least 3 numbers");
    }
    points->emplace_back(v[0], v[1], v[2]);
  }
  return true;
}

bool readCsvPose(const std::string& path, const std::string& name, Eigen::Isometry3d* pose,
                 std::string* error) {
  std::ifstream in(path);
  if (!in) return coral::fail(error, "cannot open " + path);
  std::string line;
  std::vector<double> v;
  while (std::getline(in, line)) {
    std::string first = line.substr(0, line.find(','));
    first.erase(first.find_last_not_of(" \t") + 1);
    if (first != name) continue;
    if (!parseNumbers(line, 1, &v) || v.size() != 16)
      return coral::fail(error, path + ": pose of " + name + " does not have 16 numbers");
    Eigen::Matrix4d M;
    for (int i = 0; i < 16; ++i) M(i / 4, i % 4) = v[i];
    pose->matrix() = M;
    return true;
  }
  return coral::fail(error, path + ": no pose for " + name);
}

bool readTransformFile(const std::string& path, Eigen::Isometry3d* T, std::string* error) {
  std::vector<double> v;
  if (!readAllNumbers(path, &v, error)) return false;
  if (v.size() != 12 && v.size() != 16)
    return coral::fail(error, path + ": expected a 3x4 or 4x4 matrix (12 or 16 numbers), got " +
                                  std::to_string(v.size()));
  if (v.size() == 16 && !(v[12] == 0.0 && v[13] == 0.0 && v[14] == 0.0 && v[15] == 1.0))
    return coral::fail(error, path + ": the last row of a 4x4 transform must be 0 0 0 1");
  if (!isometryFrom3x4(v.data(), T))
    return coral::fail(error, path +
                                  ": the rotation part is not a proper rotation (orthonormal to " +
                                  std::to_string(kRotationSlack) + ", det +1)");
  return true;
}

bool readKittiPoses(const std::string& path, coral::Isometries* poses, std::string* error) {
  std::ifstream in(path);
  if (!in) return coral::fail(error, "cannot open " + path);
  poses->clear();
  std::string line;
  std::vector<double> v;
  for (std::size_t n = 1; std::getline(in, line); ++n) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    Eigen::Isometry3d T;
    if (!parseNumbers(line, 0, &v) || v.size() != 12 || !isometryFrom3x4(v.data(), &T))
      return coral::fail(error,
                         path + ":" + std::to_string(n) + ": expected a 3x4 rotation|translation");
    poses->push_back(T);
  }
  return true;
}

}  // namespace eval
}  // namespace coral_introspection
