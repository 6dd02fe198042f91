// Converts an Oxford Radar RobotCar folder into a rosbag for replay:
//   rosrun coral_introspection oxford_to_bag <oxford_folder> <output.bag>
//       [--topic /radar/polar] [--fixed-frame odom] [--radar-frame radar] [--tf-topic /tf]
// See README "Radar front end" for the message layout and the TF convention.
#include <ros/time.h>

#include <cstdio>
#include <cstring>
#include <string>

#include "coral_introspection/ros_eval/oxford_bag_writer.hpp"

namespace ra = coral_introspection::ros_adapters;

int main(int argc, char** argv) {
  ra::OxfordBagOptions opt;
  std::string folder, bag;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "-h" || a == "--help") {
      std::printf(
          "usage: %s <oxford_folder> <output.bag> [--topic T] [--tf-topic T]\n"
          "          [--fixed-frame F] [--radar-frame F]\n"
          "defaults: --topic /radar/polar --tf-topic /tf --fixed-frame odom --radar-frame radar\n",
          argv[0]);
      return 0;
    } else if (a == "--topic" && has_value) {
      opt.image_topic = argv[++i];
    } else if (a == "--tf-topic" && has_value) {
      opt.tf_topic = argv[++i];
    } else if (a == "--fixed-frame" && has_value) {
      opt.fixed_frame = argv[++i];
    } else if (a == "--radar-frame" && has_value) {
      opt.radar_frame = argv[++i];
    } else if (!a.empty() && a[0] != '-' && folder.empty()) {
      folder = a;
    } else if (!a.empty() && a[0] != '-' && bag.empty()) {
      bag = a;
    } else {
      std::fprintf(stderr, "unknown or incomplete argument '%s' (try --help)\n", a.c_str());
      return 2;
    }
  }
  if (folder.empty() || bag.empty()) {
    std::fprintf(stderr, "usage: %s <oxford_folder> <output.bag> [options] (try --help)\n",
                 argv[0]);
    return 2;
  }
  ros::Time::init();
  ra::OxfordBagSummary sum;
  std::string err;
  if (!ra::writeOxfordBag(folder, bag, opt, &sum, &err)) {
    std::fprintf(stderr, "oxford_to_bag: %s\n", err.c_str());
    return 1;
  }
  std::printf("wrote %s: %zu images on %s, %zu transforms %s -> %s on %s, %.3f s\n", bag.c_str(),
              sum.images, opt.image_topic.c_str(), sum.transforms, opt.fixed_frame.c_str(),
              opt.radar_frame.c_str(), opt.tf_topic.c_str(), sum.duration_s);
  return 0;
}
