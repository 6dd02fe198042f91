#include "coral_introspection/ros_eval/oxford_bag_writer.hpp"

#include <geometry_msgs/TransformStamped.h>
#include <rosbag/bag.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/image_encodings.h>
#include <tf2_msgs/TFMessage.h>

#include <cstring>
#include <exception>
#include <opencv2/imgcodecs.hpp>

#include "coral_introspection/eval/oxford_dataset.hpp"
#include "coral_introspection/radar/polar_scan.hpp"
#include "coral_introspection/ros/conversions.hpp"

namespace coral_introspection {
namespace ros_eval {

namespace {
ros::Time fromMicroseconds(int64_t us) {
  return ros::Time(static_cast<uint32_t>(us / 1000000),
                   static_cast<uint32_t>((us % 1000000) * 1000));
}
}  // namespace

bool writeOxfordBag(const std::string& folder, const std::string& bag_path,
                    const OxfordBagOptions& options, OxfordBagSummary* summary,
                    std::string* error) {
  std::string err;
  eval::OxfordDataset ds;
  if (!ds.load(folder, &err)) {
    if (error) *error = err;
    return false;
  }
  if (options.image_topic.empty() || options.tf_topic.empty() || options.fixed_frame.empty() ||
      options.radar_frame.empty() || options.fixed_frame == options.radar_frame ||
      !(options.tf_lead_s >= 0.0 && options.tf_lead_s < 1.0)) {
    if (error)
      *error =
          "invalid options: topics and frames must be non-empty, frames distinct, "
          "tf_lead_s in [0, 1) s";
    return false;
  }
  OxfordBagSummary sum;
  try {
    rosbag::Bag bag(bag_path, rosbag::bagmode::Write);
    for (std::size_t i = 0; i < ds.png_paths.size(); ++i) {
      const cv::Mat img = cv::imread(ds.png_paths[i], cv::IMREAD_UNCHANGED);
      radar::PolarScan check;  // refuse corrupt scans rather than writing them
      if (img.empty() || !radar::decodeOxfordImage(img, &check, &err)) {
        if (error) *error = ds.png_paths[i] + ": " + (img.empty() ? "unreadable PNG" : err);
        bag.close();
        return false;
      }
      const ros::Time stamp = fromMicroseconds(ds.stamps_us[i]);

      geometry_msgs::TransformStamped tf;
      tf.header.stamp = stamp;
      tf.header.frame_id = options.fixed_frame;
      tf.child_frame_id = options.radar_frame;
      tf.transform =
          ros_adapters::toTransformMsg(ds.T_first_scan(i));  // T_odom_radar, odom = scan 0
      tf2_msgs::TFMessage tf_msg;
      tf_msg.transforms.push_back(tf);
      const ros::Time tf_time = stamp - ros::Duration(options.tf_lead_s) > ros::Time(0, 1)
                                    ? stamp - ros::Duration(options.tf_lead_s)
                                    : stamp;
      bag.write(options.tf_topic, tf_time, tf_msg);
      ++sum.transforms;

      sensor_msgs::Image msg;
      msg.header.stamp = stamp;
      msg.header.frame_id = options.radar_frame;
      msg.height = static_cast<uint32_t>(img.rows);
      msg.width = static_cast<uint32_t>(img.cols);
      msg.encoding = sensor_msgs::image_encodings::MONO8;
      msg.is_bigendian = 0;
      msg.step = msg.width;
      msg.data.resize(static_cast<std::size_t>(msg.step) * msg.height);
      for (int r = 0; r < img.rows; ++r)
        std::memcpy(&msg.data[static_cast<std::size_t>(r) * msg.step], img.ptr<uint8_t>(r),
                    msg.step);
      bag.write(options.image_topic, stamp, msg);
      ++sum.images;
    }
    bag.close();
  } catch (const std::exception& e) {
    if (error) *error = "writing bag '" + bag_path + "': " + e.what();
    return false;
  }
  sum.duration_s = (ds.stamps_us.back() - ds.stamps_us.front()) * 1e-6;
  if (summary) *summary = sum;
  return true;
}

}  // namespace ros_eval
}  // namespace coral_introspection
