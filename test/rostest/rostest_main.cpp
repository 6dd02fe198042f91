// main() of every rostest gtest node (see rostest_main.hpp for what each test supplies).
#include "rostest_main.hpp"

#include <gtest/gtest.h>
#include <ros/ros.h>

#include <optional>

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, coral_test::kRostestNode.name);
  // Holds the node up for the whole run: roscpp shuts a node down when the last NodeHandle
  // that started it goes away, e.g. at the end of the first test.
  ros::NodeHandle nh;
  std::optional<ros::AsyncSpinner> spinner;
  if (coral_test::kRostestNode.spinner_threads > 0) {
    spinner.emplace(coral_test::kRostestNode.spinner_threads);
    spinner->start();
  }
  const int result = RUN_ALL_TESTS();
  ros::shutdown();
  return result;
}
