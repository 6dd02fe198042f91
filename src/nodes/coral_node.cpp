// Standalone node running the same CoralNodelet class (nodelet::Loader in-process), for
// users who do not want a nodelet manager. Remappings and private parameters apply as
// for the nodelet.
#include <nodelet/loader.h>
#include <ros/ros.h>

int main(int argc, char** argv) {
  ros::init(argc, argv, "coral");
  nodelet::Loader loader;
  nodelet::M_string remappings(ros::names::getRemappings());
  nodelet::V_string my_argv(argv + 1, argv + argc);
  if (!loader.load(ros::this_node::getName(), "coral_introspection/CoralNodelet", remappings,
                   my_argv)) {
    ROS_FATAL("could not load coral_introspection/CoralNodelet (see the error above)");
    return 1;
  }
  ros::spin();
  return 0;
}
