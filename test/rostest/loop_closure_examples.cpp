// rostest: the loop-closure examples of doc/examples (C++ and rospy) against coral_node with
// the lidar_3d preset (see loop_closure_examples.test). A true revisit of the hku1 Livox
// keyframes (109 -> 161, transform from the optimised poses) must be added as an edge, the
// same pair with the transform 2.4 m off along x rejected. Both also as a 2D back end: an ACES
// loop relation sent as two sensor_msgs/LaserScan to a lidar_2d node with input_type
// laser_scan.
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "coral_introspection/eval/carmen_loops.hpp"
#include "coral_introspection/eval/loop_candidates.hpp"
#include "coral_introspection/online/introspector.hpp"
#include "rostest_main.hpp"
#include "support/preset.hpp"
#include "support/test_data.hpp"

namespace {

// Line `index` of a KITTI pose file (3x4 row-major T_world_sensor per line).
bool kittiPose(const std::string& path, int index, Eigen::Isometry3d* T) {
  std::ifstream in(path);
  std::string line;
  for (int i = 0; i <= index; ++i)
    if (!std::getline(in, line)) return false;
  std::istringstream ss(line);
  T->setIdentity();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c)
      if (!(ss >> T->matrix()(r, c))) return false;
  return true;
}

void writeTransform(const std::string& path, const Eigen::Isometry3d& T) {
  std::ofstream out(path);
  out.precision(12);
  out << T.matrix() << "\n";
}

void writePlanarPcd(const std::string& path, const coral_introspection::coral::Points& pts) {
  std::ofstream f(path);
  f.precision(9);
  f << "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH " << pts.size()
    << "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " << pts.size() << "\nDATA ascii\n";
  for (const auto& p : pts) f << p.x() << " " << p.y() << " 0\n";
}

// Runs `cmd`, returns its stdout (stderr goes to the test's log) and exit status.
std::string run(const std::string& cmd, int* status) {
  std::string out;
  FILE* p = popen(cmd.c_str(), "r");
  if (p == nullptr) return out;
  char buf[512];
  while (std::fgets(buf, sizeof buf, p) != nullptr) out += buf;
  *status = pclose(p);
  return out;
}

// Directory of this gtest binary: devel/lib/coral_introspection, where the C++ example is.
std::string ownDir() {
  char buf[4096];
  const ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
  if (n <= 0) return ".";
  const std::string exe(buf, n);
  return exe.substr(0, exe.find_last_of('/'));
}

// The rospy example's command line.
std::string rospyExample() {
  // The examples' interpreter: the system one, which has rospy (as in test_config_defaults).
  // The package's generated Python messages sit beside the executables in the devel space
  // (devel/lib/python3/dist-packages); catkin's cached test environment may have an empty
  // PYTHONPATH (a workspace configured before its devel space existed), so name them here.
  return "PYTHONPATH=" + ownDir() + "/../python3/dist-packages:${PYTHONPATH} " +
         "/usr/bin/python3 " + coral_test::sourceDir() + "/doc/examples/loop_closure_gate.py";
}

// Runs example `exe` with `args`: the candidate of t_true must be added, that of t_off rejected
// with a reason. Returns the rejection line.
std::string expectAddedThenRejected(const std::string& exe, const std::string& args,
                                    const std::string& t_true, const std::string& t_off) {
  int status = -1;
  std::string out = run(exe + args + " --transform_file " + t_true, &status);
  EXPECT_EQ(status, 0) << exe;
  EXPECT_EQ(out, "edge added\n") << exe;
  out = run(exe + args + " --transform_file " + t_off, &status);
  EXPECT_EQ(status, 0) << exe;
  EXPECT_EQ(out.rfind("edge rejected: ", 0), 0u) << exe << ": " << out;
  EXPECT_GT(out.size(), std::string("edge rejected: \n").size()) << exe << ": no reason";
  return out;
}

TEST(LoopClosureExamples, TrueRevisitAddedShiftedRejected) {
  CORAL_REQUIRE_DATA("hku1_livox_keyframes");
  Eigen::Isometry3d P109, P161;
  ASSERT_TRUE(kittiPose(coral_data + "/optimized_poses.txt", 109, &P109));
  ASSERT_TRUE(kittiPose(coral_data + "/optimized_poses.txt", 161, &P161));
  const Eigen::Isometry3d T_a_b = P109.inverse() * P161;  // the optimised (true) revisit
  Eigen::Isometry3d T_off = T_a_b;
  T_off.translation().x() += 2.4;
  const std::string t_true = coral_test::tempPath("loop_true", ".txt");
  const std::string t_off = coral_test::tempPath("loop_off", ".txt");
  writeTransform(t_true, T_a_b);
  writeTransform(t_off, T_off);
  ASSERT_TRUE(ros::service::waitForService("/check_alignment", ros::Duration(30.0)));

  const std::string cpp = ownDir() + "/coral_loop_closure_example";
  ASSERT_EQ(access(cpp.c_str(), X_OK), 0) << cpp << " not built (make coral_loop_closure_example)";
  const std::string py = rospyExample();
  const std::string pair =
      " --a " + coral_data + "/Scans/000109.pcd --b " + coral_data + "/Scans/000161.pcd";
  for (const std::string& exe : {cpp, py}) {
    const std::string out = expectAddedThenRejected(exe, pair, t_true, t_off);
    std::printf("%s (2.4 m off): %s", exe.c_str(), out.c_str());
  }
  std::remove(t_true.c_str());
  std::remove(t_off.c_str());
}

// A 2D back end's call: the first ACES benchmark loop relation (file order) that lidar_2d's
// loop verdict accepts in process, its two scans written as planar PCD files; both examples
// with --laser_scan rebuild their LaserScans and must add it, and reject it 0.6 m (two
// tolerances) off by a term of the verdict (judged, not refused).
TEST(LoopClosureExamples, LaserScanRelationAddedShiftedRejected) {
  CORAL_REQUIRE_DATA("radish_aces");
  namespace eval = coral_introspection::eval;
  coral_introspection::ros_adapters::NodeConfig node;
  coral_test::loadPreset("lidar_2d", &node);
  eval::LoopCandidateConfig cfg = eval::evaluationCandidates(2, node.online.verdict.tolerance);
  cfg.max_radius_candidates = 0;  // the relations as they are
  cfg.max_lookalike_pairs = 1;
  eval::CarmenLoopSet set;
  std::string err;
  ASSERT_TRUE(eval::loadCarmenLoopSet(
      coral_data + "/aces.clf.bz2",
      coral_test::dataDir() + "/radish_intel/aces_corrected_poses_on_raw.csv",
      coral_data + "/aces.relations", cfg, 30, 10, &set, &err))
      << err;
  coral_introspection::online::IntrospectorConfig loop = node.online;
  loop.verdict = coral_introspection::coral::loopClosureVerdict(node.online.verdict);
  const eval::LoopCandidate* relation = nullptr;
  for (const eval::LoopCandidate& c : set.revisits)
    if (c.source == "relation" &&
        coral_introspection::online::judgePair(set.rel_scans[c.a].scan, set.rel_scans[c.b].scan,
                                               c.T_a_b, loop, false)
            .verdict.aligned) {
      relation = &c;
      break;
    }
  ASSERT_NE(relation, nullptr) << "no ACES relation accepted in process";
  const std::string a = coral_test::tempPath("loop_scan_a", ".pcd");
  const std::string b = coral_test::tempPath("loop_scan_b", ".pcd");
  const std::string t_true = coral_test::tempPath("loop_scan_true", ".txt");
  const std::string t_off = coral_test::tempPath("loop_scan_off", ".txt");
  writePlanarPcd(a, set.rel_scans[relation->a].scan.points);
  writePlanarPcd(b, set.rel_scans[relation->b].scan.points);
  Eigen::Isometry3d T_off = relation->T_a_b;
  T_off.translation().x() += 0.6;
  writeTransform(t_true, relation->T_a_b);
  writeTransform(t_off, T_off);
  ASSERT_TRUE(ros::service::waitForService("/laser/check_alignment", ros::Duration(30.0)));
  const std::string cpp = ownDir() + "/coral_loop_closure_example";
  ASSERT_EQ(access(cpp.c_str(), X_OK), 0) << cpp << " not built (make coral_loop_closure_example)";
  const std::string args = " --laser_scan --service /laser/check_alignment --a " + a + " --b " + b;
  for (const std::string& exe : {cpp, rospyExample()}) {
    std::string out = expectAddedThenRejected(exe, args, t_true, t_off);
    EXPECT_EQ(out.find("overlap"), std::string::npos) << exe << ": judged, not refused: " << out;
    std::printf("%s, LaserScans (0.6 m off): %s", exe.c_str(), out.c_str());
    // The 3D node refuses LaserScans with the input_type that judges them.
    int status = -1;
    out = run(exe + args + " --transform_file " + t_true + " --service /check_alignment", &status);
    EXPECT_NE(out.find("input_type laser_scan"), std::string::npos) << exe << ": " << out;
  }
}

}  // namespace

// main(): test/rostest/rostest_main.cpp.
const coral_test::RostestNode coral_test::kRostestNode{"loop_closure_examples_test", 0};
