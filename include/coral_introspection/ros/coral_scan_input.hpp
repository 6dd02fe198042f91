// Turns an input message (PointCloud2, LaserScan, or a polar radar image through the RIP front
// end) into the Introspector's input: points in the sensor frame, stamp and id from the header.
// The pose is looked up by the caller. Never throws: errors come back as false + message.
#pragma once

#include <sensor_msgs/Image.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>

#include <string>

#include "coral_introspection/online/introspector.hpp"
#include "coral_introspection/ros/conversions.hpp"
#include "coral_introspection/ros/coral_params.hpp"

namespace coral_introspection {
namespace ros_adapters {

struct SensorScan {
  online::ScanInput scan;              // no pose yet (T_fixed_sensor unset)
  std::size_t dropped_non_finite = 0;  // cloud points with NaN/Inf
};

// "point clouds (input_type pointcloud)", "polar radar images (input_type polar_image)" or
// "laser scans (input_type laser_scan)": what a nodelet of this type judges, for the messages
// refusing another kind.
std::string inputKindName(InputType type);

// PointCloud2 -> points (sensor frame). With doppler/enabled and the cloud holding
// doppler/velocity_field, the field is read into scan.radial_velocity. A cloud without a
// finite point is an error (dropped_non_finite still counts its NaN/Inf points).
bool toSensorScan(const sensor_msgs::PointCloud2& cloud, const NodeConfig& cfg, SensorScan* out,
                  std::string* error);

// LaserScan -> planar points (sensor frame, z = 0), beam i at angle_min + i angle_increment
// (either sign). Readings outside [range_min, range_max) are not returns (REP 117: +-Inf is no
// return or too close; a reading at range_max is how many drivers write "no return", and kept
// as a point it would be a wall that is not there: doc/loop_closure.md "No-return readings");
// NaN readings are counted in dropped_non_finite. Refused: non-finite or zero angle_increment,
// angles spanning more than a turn, range limits not 0 <= range_min < range_max (finite), and a
// scan without a return. A finite, non-zero time_increment stamps each point with its beam's
// time (header stamp + i time_increment; scan.point_stamps) for the de-skew.
bool toSensorScan(const sensor_msgs::LaserScan& scan, const NodeConfig& cfg, SensorScan* out,
                  std::string* error);

// mono8 polar image -> RIP features (sensor frame, not motion-compensated, is_radar). Row
// stamps are shifted so that the scan reference time equals the header stamp (the time TF
// is looked up at), whatever the image's embedded clock (Oxford layout) says. An image
// without a RIP feature is an error.
bool toSensorScan(const sensor_msgs::Image& image, const NodeConfig& cfg, SensorScan* out,
                  std::string* error);

// The Introspector's input for a scan whose pose could not be looked up (TF failure).
online::ScanInput noPoseInput(const std_msgs::Header& header, const std::string& fixed_frame,
                              const std::string& error);

}  // namespace ros_adapters
}  // namespace coral_introspection
