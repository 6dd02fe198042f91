#include "coral_introspection/eval/cloud_io.hpp"

#include <pcl/PCLPointCloud2.h>
#include <pcl/io/pcd_io.h>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

#include "coral_introspection/coral/validation.hpp"

namespace coral_introspection {
namespace core {

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

// Reads field `f` of point i (any PCD numeric type) as double.
double fieldValue(const pcl::PCLPointCloud2& c, const pcl::PCLPointField& f, std::size_t i) {
  const uint8_t* p = c.data.data() + i * c.point_step + f.offset;
  auto as = [p](auto v) {
    std::memcpy(&v, p, sizeof(v));
    return static_cast<double>(v);
  };
  switch (f.datatype) {
    case pcl::PCLPointField::INT8:
      return as(int8_t());
    case pcl::PCLPointField::UINT8:
      return as(uint8_t());
    case pcl::PCLPointField::INT16:
      return as(int16_t());
    case pcl::PCLPointField::UINT16:
      return as(uint16_t());
    case pcl::PCLPointField::INT32:
      return as(int32_t());
    case pcl::PCLPointField::UINT32:
      return as(uint32_t());
    case pcl::PCLPointField::FLOAT32:
      return as(float());
    default:
      return as(double());
  }
}

// PCL's reader handles the three PCD encodings (ascii, binary, binary_compressed) and
// the header; the fields are then read by name whatever their numeric type.
bool loadPcd(const std::string& path, LoadedCloud* cloud, std::string* error) {
  pcl::PCLPointCloud2 c;
  pcl::PCDReader reader;
  if (reader.read(path, c) < 0) return fail(error, path + ": not a readable PCD file");
  const pcl::PCLPointField* f[4] = {nullptr, nullptr, nullptr, nullptr};
  const char* names[4] = {"x", "y", "z", "intensity"};
  for (const pcl::PCLPointField& field : c.fields)
    for (int k = 0; k < 4; ++k)
      if (field.name == names[k]) f[k] = &field;
  if (!f[0] || !f[1] || !f[2]) return fail(error, path + ": PCD file without fields x, y, z");
  const std::size_t n = static_cast<std::size_t>(c.width) * c.height;
  if (c.data.size() < n * c.point_step) return fail(error, path + ": PCD data is truncated");
  cloud->points.resize(n);
  cloud->intensity.assign(f[3] ? n : 0, 0.f);
  for (std::size_t i = 0; i < n; ++i) {
    cloud->points[i] =
        Vec3(fieldValue(c, *f[0], i), fieldValue(c, *f[1], i), fieldValue(c, *f[2], i));
    if (f[3]) cloud->intensity[i] = static_cast<float>(fieldValue(c, *f[3], i));
  }
  return true;
}

bool loadKittiBin(const std::string& path, LoadedCloud* cloud, std::string* error) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) return fail(error, "cannot open " + path);
  const std::streamsize bytes = in.tellg();
  if (bytes % 16 != 0)
    return fail(error, path + ": size " + std::to_string(bytes) +
                           " B is not a multiple of 16 (float32 x, y, z, intensity records)");
  std::vector<float> raw(static_cast<std::size_t>(bytes) / 4);
  in.seekg(0);
  if (!in.read(reinterpret_cast<char*>(raw.data()), bytes))
    return fail(error, path + ": read error");
  const std::size_t n = raw.size() / 4;
  cloud->points.resize(n);
  cloud->intensity.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    cloud->points[i] = Vec3(raw[4 * i], raw[4 * i + 1], raw[4 * i + 2]);
    cloud->intensity[i] = raw[4 * i + 3];
  }
  return true;
}

// All numbers of a text file, in order.
bool readAllNumbers(const std::string& path, std::vector<double>* v, std::string* error) {
  std::ifstream in(path);
  if (!in) return fail(error, "cannot open " + path);
  v->clear();
  std::string line;
  std::vector<double> row;
  for (std::size_t n = 1; std::getline(in, line); ++n) {
    if (!parseNumbers(line, 0, &row))
      return fail(error, path + ":" + std::to_string(n) + ": not a list of numbers");
    v->insert(v->end(), row.begin(), row.end());
  }
  return true;
}

// 12 numbers (3x4 row-major) -> isometry; false when the rotation is not orthonormal.
bool isometryFrom3x4(const double* m, Eigen::Isometry3d* T) {
  Eigen::Matrix3d R;
  Vec3 t;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) R(r, c) = m[4 * r + c];
    t(r) = m[4 * r + 3];
  }
  if (!R.allFinite() || !t.allFinite()) return false;
  if ((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-4) return false;
  if (R.determinant() < 0.0) return false;
  T->setIdentity();
  T->linear() = Eigen::Quaterniond(R).normalized().toRotationMatrix();
  T->translation() = t;
  return true;
}

}  // namespace

bool loadCloud(const std::string& path, LoadedCloud* cloud, std::string* error) {
  cloud->points.clear();
  cloud->intensity.clear();
  const std::string ext = lowerExtension(path);
  try {
    if (ext == "pcd") return loadPcd(path, cloud, error);
    if (ext == "bin") return loadKittiBin(path, cloud, error);
    if (ext == "csv") return readCsvPoints(path, &cloud->points, error);
  } catch (const std::exception& e) {  // PCL may throw on malformed headers
    return fail(error, path + ": " + e.what());
  }
  return fail(error, path + ": unknown point cloud extension (expected .pcd, .bin or .csv)");
}

bool readCsvPoints(const std::string& path, Points* points, std::string* error) {
  std::ifstream in(path);
  if (!in) return fail(error, "cannot open " + path);
  points->clear();
  std::string line;
  std::vector<double> v;
  for (std::size_t n = 1; std::getline(in, line); ++n) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    if (!parseNumbers(line, 0, &v) || v.size() < 3) {
      if (n == 1) continue;  // header
      return fail(error, path + ":" + std::to_string(n) + ": expected at least 3 numbers");
    }
    points->emplace_back(v[0], v[1], v[2]);
  }
  return true;
}

bool readCsvPose(const std::string& path, const std::string& name, Eigen::Isometry3d* pose,
                 std::string* error) {
  std::ifstream in(path);
  if (!in) return fail(error, "cannot open " + path);
  std::string line;
  std::vector<double> v;
  while (std::getline(in, line)) {
    std::string first = line.substr(0, line.find(','));
    first.erase(first.find_last_not_of(" \t") + 1);
    if (first != name) continue;
    if (!parseNumbers(line, 1, &v) || v.size() != 16)
      return fail(error, path + ": pose of " + name + " does not have 16 numbers");
    Eigen::Matrix4d M;
    for (int i = 0; i < 16; ++i) M(i / 4, i % 4) = v[i];
    pose->matrix() = M;
    return true;
  }
  return fail(error, path + ": no pose for " + name);
}

bool readTransformFile(const std::string& path, Eigen::Isometry3d* T, std::string* error) {
  std::vector<double> v;
  if (!readAllNumbers(path, &v, error)) return false;
  if (v.size() != 12 && v.size() != 16)
    return fail(error, path + ": expected a 3x4 or 4x4 matrix (12 or 16 numbers), got " +
                           std::to_string(v.size()));
  if (v.size() == 16 && !(v[12] == 0.0 && v[13] == 0.0 && v[14] == 0.0 && v[15] == 1.0))
    return fail(error, path + ": the last row of a 4x4 transform must be 0 0 0 1");
  if (!isometryFrom3x4(v.data(), T))
    return fail(error, path + ": the rotation part is not a proper rotation (orthonormal, det +1)");
  return true;
}

bool readKittiPoses(const std::string& path, Isometries* poses, std::string* error) {
  std::ifstream in(path);
  if (!in) return fail(error, "cannot open " + path);
  poses->clear();
  std::string line;
  std::vector<double> v;
  for (std::size_t n = 1; std::getline(in, line); ++n) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    Eigen::Isometry3d T;
    if (!parseNumbers(line, 0, &v) || v.size() != 12 || !isometryFrom3x4(v.data(), &T))
      return fail(error, path + ":" + std::to_string(n) + ": expected a 3x4 rotation|translation");
    poses->push_back(T);
  }
  return true;
}

}  // namespace core
}  // namespace coral_introspection
