// ROS adapter conversions (no ROS master): PointCloud2 layouts, bad clouds, quality cloud,
// transforms, report -> message.
#include <gtest/gtest.h>
#include <sensor_msgs/point_cloud2_iterator.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "coral_introspection/ros/conversions.hpp"

using namespace coral_introspection;
using sensor_msgs::PointField;

namespace {

// Cloud with fields given as (name, datatype) packed in order, 2 rows x 2 columns, values
// written by value(point, field index).
template <class F>
sensor_msgs::PointCloud2 makeCloud(const std::vector<std::pair<std::string, uint8_t>>& fields,
                                   F value, uint32_t width = 2, uint32_t height = 2) {
  sensor_msgs::PointCloud2 c;
  uint32_t off = 0;
  for (const auto& f : fields) {
    PointField pf;
    pf.name = f.first;
    pf.datatype = f.second;
    pf.count = 1;
    pf.offset = off;
    off += f.second == PointField::FLOAT64 ? 8 : (f.second == PointField::UINT8 ? 1 : 4);
    c.fields.push_back(pf);
  }
  c.point_step = off + 3;  // padding, as real drivers have
  c.width = width;
  c.height = height;
  c.row_step = c.point_step * width + 5;  // row padding too
  c.data.assign(c.row_step * height, 0);
  for (uint32_t r = 0; r < height; ++r)
    for (uint32_t i = 0; i < width; ++i) {
      uint8_t* p = c.data.data() + r * c.row_step + i * c.point_step;
      for (std::size_t k = 0; k < fields.size(); ++k) {
        const double v = value(r * width + i, k);
        if (fields[k].second == PointField::FLOAT64)
          std::memcpy(p + c.fields[k].offset, &v, 8);
        else if (fields[k].second == PointField::FLOAT32) {
          const float f = static_cast<float>(v);
          std::memcpy(p + c.fields[k].offset, &f, 4);
        } else if (fields[k].second == PointField::UINT8) {
          p[c.fields[k].offset] = static_cast<uint8_t>(v);
        }
      }
    }
  return c;
}

}  // namespace

TEST(CloudToPoints, ReadsFloat32WithPaddingAndOtherFields) {
  // Field order z, intensity, x, y: offsets, not order, must matter.
  const auto c = makeCloud({{"z", PointField::FLOAT32},
                            {"intensity", PointField::FLOAT32},
                            {"x", PointField::FLOAT32},
                            {"y", PointField::FLOAT32}},
                           [](uint32_t i, std::size_t k) { return k == 1 ? 99.0 : 10.0 * i + k; });
  coral::Points pts;
  std::string err;
  ros_adapters::CloudReadStats st;
  ASSERT_TRUE(ros_adapters::cloudToPoints(c, &pts, &err, &st)) << err;
  ASSERT_EQ(pts.size(), 4u);
  EXPECT_EQ(st.total, 4u);
  EXPECT_EQ(st.non_finite, 0u);
  EXPECT_DOUBLE_EQ(pts[3].x(), 32.0);
  EXPECT_DOUBLE_EQ(pts[3].y(), 33.0);
  EXPECT_DOUBLE_EQ(pts[3].z(), 30.0);
}

TEST(CloudToPoints, ReadsFloat64AndExtraField) {
  const auto c =
      makeCloud({{"x", PointField::FLOAT64},
                 {"y", PointField::FLOAT64},
                 {"z", PointField::FLOAT64},
                 {"velocity", PointField::FLOAT32}},
                [](uint32_t i, std::size_t k) { return k == 3 ? -0.5 * i : 1.0 + i + 0.25 * k; });
  coral::Points pts;
  std::vector<double> vel;
  std::string err;
  ASSERT_TRUE(ros_adapters::cloudToPoints(c, &pts, &err, nullptr, "velocity", &vel)) << err;
  ASSERT_EQ(pts.size(), 4u);
  ASSERT_EQ(vel.size(), 4u);
  EXPECT_DOUBLE_EQ(pts[2].x(), 3.0);
  EXPECT_DOUBLE_EQ(pts[2].z(), 3.5);
  EXPECT_DOUBLE_EQ(vel[2], -1.0);
  EXPECT_TRUE(ros_adapters::hasField(c, "velocity"));
  EXPECT_FALSE(ros_adapters::hasField(c, "rcs"));
  EXPECT_FALSE(ros_adapters::cloudToPoints(c, &pts, &err, nullptr, "rcs", &vel));
  EXPECT_NE(err.find("rcs"), std::string::npos) << err;
}

TEST(CloudToPoints, DropsAndCountsNonFinite) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const auto c = makeCloud(
      {{"x", PointField::FLOAT32}, {"y", PointField::FLOAT32}, {"z", PointField::FLOAT32}},
      [&](uint32_t i, std::size_t k) {
        if (i == 1 && k == 2) return nan;
        if (i == 2 && k == 0) return -inf;
        return 1.0 * i;
      });
  coral::Points pts;
  std::string err;
  ros_adapters::CloudReadStats st;
  ASSERT_TRUE(ros_adapters::cloudToPoints(c, &pts, &err, &st));
  ASSERT_EQ(pts.size(), 2u);
  EXPECT_EQ(st.non_finite, 2u);
  EXPECT_DOUBLE_EQ(pts[0].x(), 0.0);
  EXPECT_DOUBLE_EQ(pts[1].x(), 3.0);
}

// Integer coordinates are refused, not read as metres: int16 millimetres would otherwise
// become a cloud 1000x too large without a word.
TEST(CloudToPoints, IntegerFieldsAreRefusedWithTheType) {
  auto c = makeCloud(
      {{"x", PointField::FLOAT32}, {"y", PointField::FLOAT32}, {"z", PointField::FLOAT32}},
      [](uint32_t i, std::size_t) { return 1.0 * i; });
  coral::Points pts;
  std::string err;
  ASSERT_TRUE(ros_adapters::cloudToPoints(c, &pts, &err)) << err;
  c.fields[1].datatype = PointField::INT16;
  EXPECT_FALSE(ros_adapters::cloudToPoints(c, &pts, &err));
  EXPECT_NE(err.find("field 'y' is int16"), std::string::npos) << err;
  c.fields[1].datatype = PointField::FLOAT32;
  auto v = makeCloud({{"x", PointField::FLOAT32},
                      {"y", PointField::FLOAT32},
                      {"z", PointField::FLOAT32},
                      {"velocity", PointField::UINT8}},
                     [](uint32_t, std::size_t) { return 1.0; });
  std::vector<double> vel;
  EXPECT_FALSE(ros_adapters::cloudToPoints(v, &pts, &err, nullptr, "velocity", &vel));
  EXPECT_NE(err.find("field 'velocity' is uint8"), std::string::npos) << err;
  EXPECT_TRUE(ros_adapters::cloudToPoints(v, &pts, &err)) << "an unused integer field is fine";
}

// Every PointField datatype as y (and as the extra field): float32 and float64 are read
// exactly (float64 0.1 + 1e-12 is not rounded through a float), the six integer types are
// refused naming field and type, a datatype sensor_msgs does not define (0, 9, 255) is
// refused as unknown. The field's bytes hold a value that would be read wrongly otherwise.
TEST(CloudToPoints, EveryDatatypeIsReadExactlyOrRefused) {
  const char* const names[] = {"", "int8", "uint8", "int16", "uint16", "int32", "uint32"};
  const double fine = 0.1 + 1e-12;
  for (int t = 0; t <= 255; ++t) {
    const auto datatype = static_cast<uint8_t>(t);
    SCOPED_TRACE("datatype " + std::to_string(t));
    for (const bool extra : {false, true}) {
      auto c = makeCloud({{"x", PointField::FLOAT32},
                          {"y", PointField::FLOAT64},
                          {"z", PointField::FLOAT32},
                          {"v", PointField::FLOAT64}},
                         [&](uint32_t i, std::size_t k) { return k % 2 ? fine * (i + 1) : 1.0; });
      c.fields[extra ? 3 : 1].datatype = datatype;
      if (datatype == PointField::FLOAT32)  // the first 4 bytes as a float32 of its own
        for (uint32_t i = 0; i < 4; ++i) {
          const float f = static_cast<float>(fine * (i + 1));
          const uint32_t row = i / 2, col = i % 2;
          std::memcpy(c.data.data() + row * c.row_step + col * c.point_step +
                          c.fields[extra ? 3 : 1].offset,
                      &f, 4);
        }
      coral::Points pts;
      std::vector<double> v;
      std::string err;
      const bool ok = ros_adapters::cloudToPoints(c, &pts, &err, nullptr, "v", &v);
      if (datatype == PointField::FLOAT32 || datatype == PointField::FLOAT64) {
        ASSERT_TRUE(ok) << err;
        ASSERT_EQ(pts.size(), 4u);
        const double want =
            datatype == PointField::FLOAT64 ? fine * 4 : static_cast<float>(fine * 4);
        EXPECT_EQ(extra ? v[3] : pts[3].y(), want);
        continue;
      }
      EXPECT_FALSE(ok);
      EXPECT_TRUE(pts.empty());
      const std::string field = extra ? "field 'v'" : "field 'y'";
      const std::string why = datatype >= PointField::INT8 && datatype <= PointField::UINT32
                                  ? field + " is " + names[datatype] + ": only float32/float64"
                                  : field + " has unknown datatype " + std::to_string(t);
      EXPECT_NE(err.find(why), std::string::npos) << err;
    }
  }
}

TEST(CloudToPoints, MissingXyzIsAClearError) {
  const auto c = makeCloud(
      {{"x", PointField::FLOAT32}, {"y", PointField::FLOAT32}, {"intensity", PointField::FLOAT32}},
      [](uint32_t, std::size_t) { return 1.0; });
  coral::Points pts;
  std::string err;
  EXPECT_FALSE(ros_adapters::cloudToPoints(c, &pts, &err));
  EXPECT_NE(err.find("no field 'z'"), std::string::npos) << err;
  EXPECT_NE(err.find("intensity"), std::string::npos) << err;  // lists what is there
}

TEST(CloudToPoints, TruncatedDataAndFieldOutsidePointAreErrors) {
  auto c = makeCloud(
      {{"x", PointField::FLOAT32}, {"y", PointField::FLOAT32}, {"z", PointField::FLOAT32}},
      [](uint32_t, std::size_t) { return 1.0; });
  coral::Points pts;
  std::string err;
  auto short_cloud = c;
  short_cloud.data.resize(c.data.size() - 1);
  EXPECT_FALSE(ros_adapters::cloudToPoints(short_cloud, &pts, &err));
  EXPECT_NE(err.find("too short"), std::string::npos) << err;
  auto bad_offset = c;
  bad_offset.fields[2].offset = c.point_step - 2;
  EXPECT_FALSE(ros_adapters::cloudToPoints(bad_offset, &pts, &err));
  EXPECT_NE(err.find("outside point_step"), std::string::npos) << err;
  // An offset whose sum with the field size wraps in 32 bits (found by fuzz_cloud_conversion).
  bad_offset.fields[2].offset = 0xFFFFFFFFu;
  EXPECT_FALSE(ros_adapters::cloudToPoints(bad_offset, &pts, &err));
  EXPECT_NE(err.find("outside point_step"), std::string::npos) << err;
}

TEST(CloudToPoints, EmptyCloudIsValidAndEmpty) {
  sensor_msgs::PointCloud2 c;
  sensor_msgs::PointCloud2Modifier(c).setPointCloud2FieldsByString(1, "xyz");
  coral::Points pts(3, coral::Vec3::Ones());
  std::string err;
  ASSERT_TRUE(ros_adapters::cloudToPoints(c, &pts, &err)) << err;
  EXPECT_TRUE(pts.empty());
}

TEST(PointsToCloud, RoundTripsWithIntensity) {
  coral::Points pts{coral::Vec3(1, 2, 3), coral::Vec3(-4, 5.5, 0)};
  std::vector<float> inten{7.f, 8.f};
  std_msgs::Header h;
  h.frame_id = "radar";
  const auto c = ros_adapters::pointsToCloud(pts, h, &inten);
  EXPECT_EQ(c.header.frame_id, "radar");
  coral::Points back;
  std::vector<double> ib;
  std::string err;
  ASSERT_TRUE(ros_adapters::cloudToPoints(c, &back, &err, nullptr, "intensity", &ib));
  ASSERT_EQ(back.size(), 2u);
  EXPECT_DOUBLE_EQ(back[1].y(), 5.5);
  EXPECT_DOUBLE_EQ(ib[1], 8.0);
}

TEST(QualityCloud, HoldsValidPointsWithEntropiesAndScanIndex) {
  coral::Scan a, b;
  a.points = {coral::Vec3(0, 0, 0), coral::Vec3(1, 0, 0)};
  b.points = {coral::Vec3(2, 0, 0)};
  coral::CoralResult r;
  r.per_point.resize(3);
  for (int k = 0; k < 3; ++k) {  // computeCoral fills position and scan of every entry
    r.per_point[k].position = (k < 2 ? a.points[k] : b.points[0]).cast<float>();
    r.per_point[k].scan = k < 2 ? 0 : 1;
  }
  r.per_point[0].valid = true;
  r.per_point[0].h_sep = -2.f;
  r.per_point[0].h_joint = -1.5f;
  r.per_point[1].valid = false;  // not in the cloud
  r.per_point[2].valid = true;
  r.per_point[2].h_sep = -1.f;
  r.per_point[2].h_joint = 0.5f;
  std_msgs::Header h;
  h.frame_id = "odom";
  const auto c = ros_adapters::buildQualityCloud(a, b, r, h);
  ASSERT_EQ(c.width * c.height, 2u);
  // Padded so every float of every point is 4-byte aligned (UBSan: misaligned float access).
  EXPECT_EQ(c.point_step % 4, 0u);
  EXPECT_EQ(c.data.size(), 2u * c.point_step);
  EXPECT_EQ(c.row_step, 2u * c.point_step);
  for (const char* f : {"x", "y", "z", "q", "h_sep", "h_joint", "scan"})
    EXPECT_TRUE(ros_adapters::hasField(c, f)) << f;
  sensor_msgs::PointCloud2ConstIterator<float> x(c, "x"), q(c, "q"), hs(c, "h_sep");
  sensor_msgs::PointCloud2ConstIterator<uint8_t> s(c, "scan");
  EXPECT_FLOAT_EQ(*x, 0.f);
  EXPECT_FLOAT_EQ(*q, 0.5f);
  EXPECT_FLOAT_EQ(*hs, -2.f);
  EXPECT_EQ(*s, 0);
  ++x, ++q, ++s;
  EXPECT_FLOAT_EQ(*x, 2.f);
  EXPECT_FLOAT_EQ(*q, 1.5f);
  EXPECT_EQ(*s, 1);
}

TEST(ToMessage, InvalidResultIsNeverAligned) {
  coral::CoralResult r;
  r.valid = false;
  r.h_joint = 1.0;
  r.h_sep = 0.5;
  r.quality = 0.5;
  r.overlap = 0.01;
  r.num_points_a = 10;
  coral::Verdict v;
  v.aligned = true;
  v.probability = 0.9;
  std_msgs::Header h;
  const auto m = ros_adapters::toMessage(r, v, h, ros::Time(1.0), ros::Time(2.0));
  EXPECT_FALSE(m.valid);
  EXPECT_FALSE(m.aligned);
  EXPECT_EQ(m.probability, 0.0);
  EXPECT_EQ(m.num_points_a, 10u);
  EXPECT_DOUBLE_EQ(m.quality, 0.5);
  EXPECT_EQ(m.stamp_b, ros::Time(2.0));
  r.valid = true;
  const auto m2 = ros_adapters::toMessage(r, v, h, ros::Time(1.0), ros::Time(2.0));
  EXPECT_TRUE(m2.aligned);
  EXPECT_DOUBLE_EQ(m2.probability, 0.9);
}

// The verdict's terms reach the message: method, tolerance, the relative check's hint as a
// name and a transform, flat axes; a verdict without valid neighbours is not "valid" even
// though CorAl at the pose was.
TEST(ToMessage, CarriesToleranceHintAndFlatAxes) {
  coral::VerdictConfig cfg;
  cfg.method = coral::VerdictMethod::kRelative;
  cfg.tolerance.translation = 0.5;
  cfg.tolerance.rotation_deg = 1.0;
  const std::vector<coral::ToleranceOffset> offsets = coral::toleranceOffsets(cfg.tolerance, 2);
  coral::AlignmentVerdict v;
  v.coral.valid = true;
  v.coral.quality = 0.4;
  // Q at the pose 0.4; x- (index 1) is much lower: misaligned, hint x-; yaw hardly changes.
  v.relative =
      coral::decideRelative(0.4, offsets, {0.9, 0.1, 0.8, 0.8, 0.4001, 0.4002}, cfg.relative);
  coral::combineVerdict(cfg.method, v.classifier, v.relative, cfg.relative, &v);
  ASSERT_TRUE(v.valid);
  std_msgs::Header h;
  const auto m = ros_adapters::toMessage(v, cfg, h, ros::Time(1.0), ros::Time(2.0));
  EXPECT_TRUE(m.valid);
  EXPECT_FALSE(m.aligned);
  EXPECT_EQ(m.method, "relative");
  EXPECT_DOUBLE_EQ(m.tolerance_translation, 0.5);
  EXPECT_DOUBLE_EQ(m.tolerance_rotation, 1.0);
  EXPECT_EQ(m.correction_hint, "x-");
  EXPECT_NEAR(m.correction.translation.x, -0.5, 1e-12);
  EXPECT_NEAR(m.correction.rotation.w, 1.0, 1e-12);
  ASSERT_EQ(m.flat_axes.size(), 1u);
  EXPECT_EQ(m.flat_axes[0], "yaw");
  EXPECT_GT(m.relative_score, cfg.relative.margin);
  EXPECT_TRUE(std::isnan(m.free_space_conflict));  // not measured

  // A gated verdict rejected by the free-space term carries the conflict and names the term.
  coral::VerdictConfig gated = cfg;
  gated.method = coral::VerdictMethod::kGated;
  gated.gate.max_free_space = 0.1;
  coral::AlignmentVerdict fs = v;
  fs.relative = coral::decideRelative(0.4, offsets, {0.9, 0.8, 0.8, 0.8, 0.7, 0.7}, cfg.relative);
  fs.free_space.valid = true;
  fs.free_space.conflict = 0.25;
  auto gatedMessage = [&] {  // the gated verdict of fs's terms, as a message
    coral::combineVerdict(gated.method, fs.classifier, fs.relative, gated.relative, &fs, gated.gate,
                          coral::gateTerms(fs));
    return ros_adapters::toMessage(fs, gated, h, ros::Time(1.0), ros::Time(2.0));
  };
  const auto mf = gatedMessage();
  EXPECT_TRUE(mf.valid);
  EXPECT_FALSE(mf.aligned);
  EXPECT_DOUBLE_EQ(mf.free_space_conflict, 0.25);
  EXPECT_NE(mf.rejected_by.find("free-space conflict 0.25 > 0.1"), std::string::npos)
      << mf.rejected_by;
  EXPECT_TRUE(std::isnan(mf.constraint));  // not measured

  // Free space passing, the constraint term below its bound: rejected by it, value carried.
  gated.gate.min_constraint = 0.3;
  fs.free_space.conflict = 0.05;
  fs.constraint.valid = true;
  fs.constraint.weakest = 0.02;
  const auto mc = gatedMessage();
  EXPECT_FALSE(mc.aligned);
  EXPECT_DOUBLE_EQ(mc.constraint, 0.02);
  EXPECT_NE(mc.rejected_by.find("constraint 0.02 < 0.3"), std::string::npos) << mc.rejected_by;

  coral::AlignmentVerdict none;  // CorAl valid, no valid neighbour: no verdict
  none.coral.valid = true;
  coral::combineVerdict(cfg.method, none.classifier, none.relative, cfg.relative, &none);
  const auto n = ros_adapters::toMessage(none, cfg, h, ros::Time(1.0), ros::Time(2.0));
  EXPECT_FALSE(n.valid);
  EXPECT_FALSE(n.aligned);
  EXPECT_TRUE(std::isnan(n.relative_score));
  EXPECT_EQ(n.correction_hint, "");
  EXPECT_NEAR(n.correction.rotation.w, 1.0, 1e-12);  // identity: no step suggested
}

TEST(Transforms, RoundTripAndRejectBadQuaternion) {
  const Eigen::Isometry3d T = coral::se2(1.0, -2.0, 0.7) * Eigen::Translation3d(0, 0, 0.3);
  const geometry_msgs::Transform m = ros_adapters::toTransformMsg(T);
  Eigen::Isometry3d back;
  std::string err;
  ASSERT_TRUE(ros_adapters::toEigen(m, &back, &err)) << err;
  EXPECT_TRUE(back.isApprox(T, 1e-12));
  EXPECT_NEAR((back * coral::Vec3(1, 0, 0) - T * coral::Vec3(1, 0, 0)).norm(), 0.0, 1e-12);
  geometry_msgs::Transform zero;  // all-zero quaternion: a common uninitialised request
  EXPECT_FALSE(ros_adapters::toEigen(zero, &back, &err));
  EXPECT_NE(err.find("unit quaternion"), std::string::npos) << err;
  geometry_msgs::Transform nan = m;
  nan.translation.x = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(ros_adapters::toEigen(nan, &back, &err));
}
