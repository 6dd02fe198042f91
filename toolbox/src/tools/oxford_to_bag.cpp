// Converts an Oxford Radar RobotCar folder into a rosbag for replay:
//   rosrun coral_introspection oxford_to_bag <oxford_folder> <output.bag>
//       [--topic /radar/polar] [--fixed-frame odom] [--radar-frame radar] [--tf-topic /tf]
// See README "Radar front end" for the message layout and the TF convention.
#include <ros/time.h>

#include <cstdio>
#include <string>

#include "coral_introspection/eval/tool_args.hpp"
#include "coral_introspection/ros_eval/oxford_bag_writer.hpp"

namespace ros_eval = coral_introspection::ros_eval;
namespace eval = coral_introspection::eval;

namespace {
constexpr const char* kUsage =
    "usage: oxford_to_bag <oxford_folder> <output.bag> [--topic T] [--tf-topic T]\n"
    "          [--fixed-frame F] [--radar-frame F]\n"
    "defaults: --topic /radar/polar --tf-topic /tf --fixed-frame odom --radar-frame radar";
}  // namespace

int main(int argc, char** argv) {
  ros_eval::OxfordBagOptions opt;
  eval::ToolArgs args;
  if (const auto exit = eval::readCommandLine(
          "oxford_to_bag", kUsage, argc, argv,
          {"--topic", "--tf-topic", "--fixed-frame", "--radar-frame"}, {}, &args, 2))
    return *exit;
  if (args.positional.size() != 2)
    return eval::toolError("oxford_to_bag", "<oxford_folder> and <output.bag> are required",
                           kUsage);
  const std::string &folder = args.positional[0], &bag = args.positional[1];
  opt.image_topic = args.get("--topic", opt.image_topic);
  opt.tf_topic = args.get("--tf-topic", opt.tf_topic);
  opt.fixed_frame = args.get("--fixed-frame", opt.fixed_frame);
  opt.radar_frame = args.get("--radar-frame", opt.radar_frame);
  ros::Time::init();
  ros_eval::OxfordBagSummary sum;
  std::string err;
  if (!ros_eval::writeOxfordBag(folder, bag, opt, &sum, &err)) {
    std::fprintf(stderr, "oxford_to_bag: %s\n", err.c_str());
    return 1;
  }
  std::printf("wrote %s: %zu images on %s, %zu transforms %s -> %s on %s, %.3f s\n", bag.c_str(),
              sum.images, opt.image_topic.c_str(), sum.transforms, opt.fixed_frame.c_str(),
              opt.radar_frame.c_str(), opt.tf_topic.c_str(), sum.duration_s);
  return 0;
}
