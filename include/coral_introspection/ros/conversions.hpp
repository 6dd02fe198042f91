// ROS <-> core conversions: PointCloud2, tf2 / geometry_msgs transforms, CorAl report ->
// AlignmentQuality, quality and feature clouds. Nothing here throws: failures return
// false with a message, so nodelet callbacks can count them and carry on.
#pragma once

#include <geometry_msgs/Transform.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/Header.h>

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "coral_introspection/AlignmentQuality.h"
#include "coral_introspection/VelocityConsistency.h"
#include "coral_introspection/coral/classifier.hpp"
#include "coral_introspection/coral/coral.hpp"
#include "coral_introspection/coral/types.hpp"
#include "coral_introspection/coral/verdict.hpp"
#include "coral_introspection/online/introspector.hpp"

namespace coral_introspection {
namespace ros_adapters {

struct CloudReadStats {
  std::size_t total = 0;       // points in the message (width * height)
  std::size_t non_finite = 0;  // dropped because x, y, z (or the extra field) is NaN/Inf
};

// True when the cloud has a field of that name.
bool hasField(const sensor_msgs::PointCloud2& cloud, const std::string& name);

// Reads x, y, z of every point. Each of x, y, z may be float32 or float64 at any offset,
// so XYZ, XYZI, Ouster/Velodyne layouts and 4D radar clouds all read directly; integer
// fields are refused (a scaled value of unknown unit, e.g. millimetres, is not metres). Points with
// a non-finite coordinate are dropped and counted. When extra_field is non-empty its value is read
// for every kept point into *extra (e.g. the Doppler radial velocity); a point whose extra value is
// non-finite is dropped too. Returns false with *error on a malformed message (missing or integer
// x/y/z or extra field, data shorter than width * height * point_step, a field outside point_step,
// big endian data); an empty cloud is valid (zero points).
bool cloudToPoints(const sensor_msgs::PointCloud2& cloud, coral::Points* points, std::string* error,
                   CloudReadStats* stats = nullptr, const std::string& extra_field = std::string(),
                   std::vector<double>* extra = nullptr);

// x, y, z (+ intensity when given, same size) float32 cloud, one row.
sensor_msgs::PointCloud2 pointsToCloud(const coral::Points& points, const std_msgs::Header& header,
                                       const std::vector<float>* intensity = nullptr);

// Per-point quality cloud of a CorAl pair: fields x, y, z, q, h_sep, h_joint (float32) and
// scan (uint8, 0 = a, 1 = b), from the positions the per-point entries carry (the scored
// points in the scans' common frame, which T_header_scans maps into the header's frame:
// voxel centroids / the query subset when those are on; a and b are no longer read). Only
// points with a valid per-point entropy (overlap, not rejected) are written, so colouring by
// q shows where the two scans disagree.
sensor_msgs::PointCloud2 buildQualityCloud(
    const coral::Scan& a, const coral::Scan& b, const coral::CoralResult& result,
    const std_msgs::Header& header,
    const Eigen::Isometry3d& T_header_scans = Eigen::Isometry3d::Identity());

// Verdict message of a pair (status VERDICT, or INVALID_PAIR when !result.valid; reason and
// latency left to the caller). verdict is used only when result.valid (else aligned = false,
// probability = 0).
AlignmentQuality toMessage(const coral::CoralResult& result, const coral::Verdict& verdict,
                           const std_msgs::Header& header, const ros::Time& stamp_a,
                           const ros::Time& stamp_b);

// Verdict message of a pair judged by coral::judgeAlignment (online::judgePair): CorAl at
// the pose, the combined verdict of cfg.method, the tolerance it judged, and the relative
// check's correction hint and flat axes.
AlignmentQuality toMessage(const coral::AlignmentVerdict& verdict, const coral::VerdictConfig& cfg,
                           const std_msgs::Header& header, const ros::Time& stamp_a,
                           const ros::Time& stamp_b);

// Doppler check of one scan (header: the scan's stamp and sensor frame).
VelocityConsistency toMessage(const online::DopplerReport& doppler, const std_msgs::Header& header);

// geometry_msgs::Transform <-> Eigen. A non-unit or non-finite quaternion is rejected
// (false) rather than silently normalised into a different rotation.
bool toEigen(const geometry_msgs::Transform& t, Eigen::Isometry3d* out, std::string* error);
geometry_msgs::Transform toTransformMsg(const Eigen::Isometry3d& T);

}  // namespace ros_adapters
}  // namespace coral_introspection
