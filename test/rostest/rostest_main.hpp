// The one main() of the gtest nodes under test/rostest (rostest_main.cpp, a static library
// linked into each of them). A test file says only what differs between them: its node name
// and how many threads serve its subscriptions while the tests run.
#pragma once

namespace coral_test {

struct RostestNode {
  const char* name;     // ros::init's name; rostest's launch file may remap it
  int spinner_threads;  // an AsyncSpinner with this many threads; 0: the tests spin themselves
};

// Defined once by each rostest's .cpp file.
extern const RostestNode kRostestNode;

}  // namespace coral_test
