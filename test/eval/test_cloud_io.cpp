// Point cloud / transform / pose-list readers (eval/cloud_io) on files written here with
// known content, and on the shared real data when present.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <vector>

#include "coral_introspection/eval/cloud_io.hpp"
#include "support/test_data.hpp"

using namespace coral_introspection::coral;
using namespace coral_introspection::eval;
using coral_test::tempPath;

namespace {

void writeText(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

struct PcdField {
  std::string name;
  char type;  // PCD TYPE: F, I or U
  int size;   // PCD SIZE [bytes]
};

// One value of TYPE / SIZE as stored in a binary PCD (little endian), parsed from its text.
void appendBinary(const PcdField& f, const std::string& text, std::string* out) {
  char bytes[8];
  if (f.type == 'F' && f.size == 4) {
    const float v = std::stof(text);
    std::memcpy(bytes, &v, 4);
  } else if (f.type == 'F') {
    const double v = std::stod(text);
    std::memcpy(bytes, &v, 8);
  } else {  // the low `size` bytes of the two's complement value (x86, ARM: little endian)
    const uint64_t v = f.type == 'U' ? std::stoull(text) : static_cast<uint64_t>(std::stoll(text));
    std::memcpy(bytes, &v, 8);
  }
  out->append(bytes, static_cast<std::size_t>(f.size));
}

// Writes a PCD file with these fields (COUNT 1 each) and rows of values given as text, in
// the ascii or the binary encoding.
void writePcd(const std::string& path, const std::vector<PcdField>& fields,
              const std::vector<std::vector<std::string>>& rows, bool binary) {
  std::string names, sizes, types, counts;
  for (const PcdField& f : fields) {
    names += " " + f.name;
    sizes += " " + std::to_string(f.size);
    types += std::string(" ") + f.type;
    counts += " 1";
  }
  const std::string n = std::to_string(rows.size());
  std::string text = "VERSION 0.7\nFIELDS" + names + "\nSIZE" + sizes + "\nTYPE" + types +
                     "\nCOUNT" + counts + "\nWIDTH " + n +
                     "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + n + "\nDATA " +
                     (binary ? "binary" : "ascii") + "\n";
  for (const auto& row : rows)
    for (std::size_t k = 0; k < fields.size(); ++k)
      if (binary)
        appendBinary(fields[k], row[k], &text);
      else
        text += row[k] + (k + 1 < fields.size() ? " " : "\n");
  std::ofstream(path, std::ios::binary) << text;
}

// Every type PCD defines (TYPE, SIZE).
const std::vector<std::pair<char, int>> kPcdTypes = {{'I', 1}, {'U', 1}, {'I', 2}, {'U', 2},
                                                     {'I', 4}, {'U', 4}, {'I', 8}, {'U', 8},
                                                     {'F', 4}, {'F', 8}};

}  // namespace

TEST(CloudIo, AsciiPcdWithMixedTypesAndIntensity) {
  const std::string p = tempPath("ascii", ".pcd");
  writeText(p,
            "VERSION 0.7\nFIELDS x y z intensity\nSIZE 4 8 4 2\nTYPE F F F U\nCOUNT 1 1 1 1\n"
            "WIDTH 3\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA ascii\n"
            "1.5 -2 3 7\n0 0 0 0\n-4.25 1e3 0.5 65535\n");
  LoadedCloud c;
  std::string err;
  ASSERT_TRUE(loadCloud(p, &c, &err)) << err;
  ASSERT_EQ(c.points.size(), 3u);
  ASSERT_EQ(c.intensity.size(), 3u);
  EXPECT_EQ(c.points[0], Vec3(1.5, -2.0, 3.0));
  EXPECT_EQ(c.points[2], Vec3(-4.25, 1000.0, 0.5));
  EXPECT_FLOAT_EQ(c.intensity[0], 7.f);
  EXPECT_FLOAT_EQ(c.intensity[2], 65535.f);
  std::remove(p.c_str());
}

TEST(CloudIo, PcdWithoutIntensityAndWithoutXyz) {
  const std::string p = tempPath("xyz", ".PCD");
  writeText(p,
            "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 1\n"
            "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA ascii\n1 2 3\n4 5 6\n");
  LoadedCloud c;
  std::string err;
  ASSERT_TRUE(loadCloud(p, &c, &err)) << err;
  EXPECT_EQ(c.points.size(), 2u);
  EXPECT_TRUE(c.intensity.empty());
  writeText(p,
            "VERSION 0.7\nFIELDS a b\nSIZE 4 4\nTYPE F F\nCOUNT 1 1\nWIDTH 1\nHEIGHT 1\n"
            "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 1\nDATA ascii\n1 2\n");
  EXPECT_FALSE(loadCloud(p, &c, &err));
  EXPECT_NE(err.find("x, y, z"), std::string::npos) << err;
  std::remove(p.c_str());
}

// A planar scan written without its zeros (FIELDS x y): refused by default (keyframes, cloud
// lists and benchmarks read 3D clouds), read with z = 0 and marked planar when the caller allows
// it (coral_check, which refuses it under a 3D preset); a file with z is not planar, nor is one
// read after it.
TEST(CloudIo, PcdWithXAndYOnlyIsAPlanarScan) {
  const std::string p = tempPath("xy", ".pcd");
  writeText(p,
            "VERSION 0.7\nFIELDS x y intensity\nSIZE 4 8 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 2\n"
            "HEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA ascii\n1.5 -2 7\n3 4 8\n");
  LoadedCloud c;
  std::string err;
  EXPECT_FALSE(loadCloud(p, &c, &err));
  EXPECT_NE(err.find("without fields x, y, z (x, y alone: a 2D scan, not read here)"),
            std::string::npos)
      << err;
  ASSERT_TRUE(loadCloud(p, &c, &err, true)) << err;
  EXPECT_TRUE(c.planar);
  ASSERT_EQ(c.points.size(), 2u);
  EXPECT_EQ(c.points[0], Vec3(1.5, -2.0, 0.0));
  EXPECT_EQ(c.points[1], Vec3(3.0, 4.0, 0.0));
  EXPECT_FLOAT_EQ(c.intensity[1], 8.f);
  writeText(p,
            "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 1\nHEIGHT 1\n"
            "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 1\nDATA ascii\n1 2 0\n");
  ASSERT_TRUE(loadCloud(p, &c, &err)) << err;
  EXPECT_FALSE(c.planar);
  std::remove(p.c_str());
}

// x of every PCD type, in both encodings: F 4 and F 8 are read exactly (0.1 stays the double
// 0.1 in F 8, not the float's 0.100000001), every integer type is refused with the field
// and its type named: 64-bit integers were once read as the bits of a double (every point
// ~1e-323 m, all merged into one, then "too few points" instead of the reason).
TEST(CloudIo, PcdCoordinatesOfEveryTypeAreReadExactlyOrRefused) {
  const std::string p = tempPath("coord", ".pcd");
  for (const bool binary : {false, true})
    for (const auto& [type, size] : kPcdTypes) {
      SCOPED_TRACE(std::string(binary ? "binary " : "ascii ") + type + " " + std::to_string(size));
      const std::string x = type == 'F' ? "0.1" : "3";
      writePcd(p, {{"x", type, size}, {"y", 'F', 4}, {"z", 'F', 8}},
               {{x, "-2.5", "7"}, {"-" + x, "1", "0.25"}}, binary);
      LoadedCloud c;
      std::string err;
      if (type != 'F') {
        EXPECT_FALSE(loadCloud(p, &c, &err));
        const std::string named = std::string("field 'x' is TYPE / SIZE ") + type + " " +
                                  std::to_string(size) + " (" + (type == 'U' ? "uint" : "int") +
                                  std::to_string(8 * size) + ")";
        EXPECT_NE(err.find(named), std::string::npos) << err;
        EXPECT_NE(err.find("coordinates are read from F 4 or F 8 only"), std::string::npos) << err;
        continue;
      }
      ASSERT_TRUE(loadCloud(p, &c, &err)) << err;
      ASSERT_EQ(c.points.size(), 2u);
      const double expected = size == 4 ? static_cast<double>(0.1f) : 0.1;
      EXPECT_EQ(c.points[0], Vec3(expected, -2.5, 7.0));
      EXPECT_EQ(c.points[1], Vec3(-expected, 1.0, 0.25));
    }
  std::remove(p.c_str());
}

// intensity (read by nothing that judges) of every PCD type, at the ends of its range: read
// exactly into a double (uint32 4294967295 would be 4294967296 as a float). A 64-bit value
// (binary files) is exact up to 2^53 in magnitude; beyond it the file is refused, not
// rounded. In an ascii file PCL itself rounds 64-bit integers (2^53 + 1 arrives as 2^53):
// refused whatever the values.
TEST(CloudIo, PcdIntensityOfEveryTypeIsReadExactly) {
  const std::string p = tempPath("intensity", ".pcd");
  const std::map<std::string, std::pair<std::string, double>> extremes = {
      {"I1", {"-128", -128.0}},
      {"U1", {"255", 255.0}},
      {"I2", {"-32768", -32768.0}},
      {"U2", {"65535", 65535.0}},
      {"I4", {"-2147483648", -2147483648.0}},
      {"U4", {"4294967295", 4294967295.0}},
      {"I8", {"-9007199254740992", -9007199254740992.0}},
      {"U8", {"9007199254740992", 9007199254740992.0}},
      {"F4", {"0.1", static_cast<double>(0.1f)}},
      {"F8", {"0.1", 0.1}}};
  for (const bool binary : {false, true})
    for (const auto& [type, size] : kPcdTypes) {
      const std::string key = type + std::to_string(size);
      SCOPED_TRACE(std::string(binary ? "binary " : "ascii ") + key);
      const auto& [text, value] = extremes.at(key);
      writePcd(p, {{"x", 'F', 4}, {"y", 'F', 4}, {"z", 'F', 4}, {"intensity", type, size}},
               {{"1", "2", "3", text}, {"4", "5", "6", "0"}}, binary);
      LoadedCloud c;
      std::string err;
      if (!binary && size == 8 && type != 'F') {  // PCL parses these through a double
        EXPECT_FALSE(loadCloud(p, &c, &err));
        EXPECT_NE(err.find("field 'intensity' is TYPE / SIZE " + std::string(1, type) + " 8 (" +
                           (type == 'U' ? "u" : "") + "int64) in an ascii PCD"),
                  std::string::npos)
            << err;
        continue;
      }
      ASSERT_TRUE(loadCloud(p, &c, &err)) << err;
      ASSERT_EQ(c.intensity.size(), 2u);
      EXPECT_EQ(c.intensity[0], value);
      EXPECT_EQ(c.intensity[1], 0.0);
      EXPECT_EQ(c.points[1], Vec3(4, 5, 6));
    }
  for (const auto& [type, text] : {std::pair<char, std::string>{'I', "9007199254740993"},
                                   {'I', "-9007199254740993"},
                                   {'U', "18446744073709551615"}}) {
    SCOPED_TRACE(text);
    writePcd(p, {{"x", 'F', 4}, {"y", 'F', 4}, {"z", 'F', 4}, {"intensity", type, 8}},
             {{"1", "2", "3", "0"}, {"4", "5", "6", text}}, true);
    LoadedCloud c;
    std::string err;
    EXPECT_FALSE(loadCloud(p, &c, &err));
    EXPECT_NE(err.find("field 'intensity' of point 1"), std::string::npos) << err;
    EXPECT_NE(err.find("beyond 2^53"), std::string::npos) << err;
  }
  std::remove(p.c_str());
}

// A TYPE / SIZE pair PCD does not define (half floats, 3-byte integers) and a COUNT other
// than 1 (the next field would be read as part of this one, or nothing at all) are refused.
TEST(CloudIo, PcdUndefinedTypeSizeAndCountAreRefused) {
  const std::string p = tempPath("undefined", ".pcd");
  const std::string tail = "WIDTH 1\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 1\nDATA ascii\n";
  LoadedCloud c;
  std::string err;
  for (const char* sizes_types : {"SIZE 2 4 4\nTYPE F F F\n", "SIZE 4 3 4\nTYPE F I F\n"}) {
    writeText(p, std::string("VERSION 0.7\nFIELDS x y z\n") + sizes_types + "COUNT 1 1 1\n" + tail +
                     "1 2 3\n");
    EXPECT_FALSE(loadCloud(p, &c, &err)) << sizes_types;
    EXPECT_NE(err.find("PCD defines F 4, F 8 and I / U 1, 2, 4, 8"), std::string::npos) << err;
  }
  writeText(
      p, "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 2 1 1\n" + tail + "1 9 2 3\n");
  EXPECT_FALSE(loadCloud(p, &c, &err));
  EXPECT_NE(err.find("field 'x' has COUNT 2"), std::string::npos) << err;
  std::remove(p.c_str());
}

// A VIEWPOINT other than the identity says the points are not in their sensor's frame: refused
// with the viewpoint named, not read as if the sensor stood at the origin. The identity, written
// with -0 or a negated quaternion, is read.
TEST(CloudIo, PcdWithTheSensorAwayFromItsOriginIsRefused) {
  const std::string p = tempPath("viewpoint", ".pcd");
  const std::string head =
      "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
      "WIDTH 1\nHEIGHT 1\n";
  LoadedCloud c;
  std::string err;
  for (const char* viewpoint : {"VIEWPOINT 2 0 0 1 0 0 0", "VIEWPOINT 0 0 1.5 1 0 0 0",
                                "VIEWPOINT 0 0 0 0.7071068 0 0 0.7071068"}) {
    writeText(p, head + viewpoint + "\nPOINTS 1\nDATA ascii\n1 2 3\n");
    EXPECT_FALSE(loadCloud(p, &c, &err)) << viewpoint;
    EXPECT_NE(err.find("VIEWPOINT"), std::string::npos) << err;
    EXPECT_NE(err.find("sensor's frame"), std::string::npos) << err;
  }
  for (const char* viewpoint : {"VIEWPOINT -0 0 0 1 0 0 0", "VIEWPOINT 0 0 0 -1 0 0 0"}) {
    writeText(p, head + viewpoint + "\nPOINTS 1\nDATA ascii\n1 2 3\n");
    ASSERT_TRUE(loadCloud(p, &c, &err)) << viewpoint << ": " << err;
    EXPECT_EQ(c.points[0], Vec3(1, 2, 3));
  }
  std::remove(p.c_str());
}

TEST(CloudIo, KittiBinRecordsAndTruncatedFile) {
  const std::string p = tempPath("kitti", ".bin");
  const float rec[8] = {1.f, 2.f, 3.f, 0.25f, -7.f, 8.5f, -9.f, 1.f};
  std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(rec), sizeof(rec));
  LoadedCloud c;
  std::string err;
  ASSERT_TRUE(loadCloud(p, &c, &err)) << err;
  ASSERT_EQ(c.points.size(), 2u);
  EXPECT_EQ(c.points[1], Vec3(-7.0, 8.5, -9.0));
  EXPECT_FLOAT_EQ(c.intensity[0], 0.25f);
  std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(rec), 20);
  EXPECT_FALSE(loadCloud(p, &c, &err));
  EXPECT_NE(err.find("multiple of 16"), std::string::npos) << err;
  std::remove(p.c_str());
}

TEST(CloudIo, UnknownExtensionAndMissingFile) {
  LoadedCloud c;
  std::string err;
  EXPECT_FALSE(loadCloud("/nonexistent/scan.ply", &c, &err));
  EXPECT_NE(err.find("extension"), std::string::npos) << err;
  EXPECT_FALSE(loadCloud("/nonexistent/scan.pcd", &c, &err));
  EXPECT_FALSE(loadCloud("/nonexistent/scan.bin", &c, &err));
}

TEST(CloudIo, TransformFile3x4And4x4) {
  const std::string p = tempPath("T", ".txt");
  // 90 deg about z, translation (1, 2, 3).
  writeText(p, "0 -1 0 1\n1 0 0 2\n0 0 1 3\n");
  Eigen::Isometry3d T;
  std::string err;
  ASSERT_TRUE(readTransformFile(p, &T, &err)) << err;
  EXPECT_TRUE((T * Vec3(1, 0, 0)).isApprox(Vec3(1, 3, 3)));
  writeText(p, "0,-1,0,1\n1,0,0,2\n0,0,1,3\n0,0,0,1\n");
  ASSERT_TRUE(readTransformFile(p, &T, &err)) << err;
  EXPECT_TRUE((T * Vec3(0, 1, 0)).isApprox(Vec3(0, 2, 3)));
  writeText(p, "0 -1 0 1\n1 0 0 2\n0 0 1 3\n0 0 1 1\n");  // bad last row
  EXPECT_FALSE(readTransformFile(p, &T, &err));
  writeText(p, "2 0 0 0\n0 1 0 0\n0 0 1 0\n");  // scale, not a rotation
  EXPECT_FALSE(readTransformFile(p, &T, &err));
  EXPECT_NE(err.find("rotation"), std::string::npos) << err;
  writeText(p, "1 0 0\n0 1 0\n");  // 6 numbers
  EXPECT_FALSE(readTransformFile(p, &T, &err));
  std::remove(p.c_str());
}

TEST(CloudIo, SharedLivoxKeyframesAndPoses) {
  CORAL_REQUIRE_DATA("hku1_livox_keyframes");
  LoadedCloud c;
  std::string err;
  ASSERT_TRUE(loadCloud(coral_data + "/Scans/000000.pcd", &c, &err)) << err;
  EXPECT_EQ(c.points.size(), 3430u);  // the file header says WIDTH 3430
  EXPECT_EQ(c.intensity.size(), 3430u);
  for (const Vec3& p : c.points) ASSERT_LT(p.norm(), 500.0);
  Isometries poses;
  ASSERT_TRUE(readKittiPoses(coral_data + "/optimized_poses.txt", &poses, &err)) << err;
  EXPECT_EQ(poses.size(), 314u);  // one per keyframe
}

TEST(CloudIo, SharedViewOfDelftLidarBin) {
  CORAL_REQUIRE_DATA("view_of_delft_example/lidar/training/velodyne");
  LoadedCloud c;
  std::string err;
  ASSERT_TRUE(loadCloud(coral_data + "/00549.bin", &c, &err)) << err;
  EXPECT_EQ(c.points.size(), 2684352u / 16u);
}
