// coral_pose_graph, the consumer of the loop verdict on a keyframe sequence without reference
// poses: it refuses what it cannot run (exit 2, the reason naming the option or file, nothing on
// stdout), and on the Livox keyframes with their odometry alone its gated graph accepts no
// false loop edge and stays on the reference, where the same candidates ungated bend it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "coral_introspection/eval/cloud_io.hpp"
#include "coral_introspection/eval/loop_candidates.hpp"
#include "support/run_tool.hpp"

namespace {

namespace fs = std::filesystem;

// A keyframe folder of `n` scans of a small box room (ASCII PCD) and odometry poses 1 m apart.
// Scan `empty` (if >= 0) has no points; `planar`: fields x and y only, the room's walls at z = 0.
std::string boxFolder(const std::string& name, int n, bool with_odometry, int empty = -1,
                      bool planar = false) {
  const std::string dir = coral_test::tempPath(name, "");
  fs::create_directories(dir + "/Scans");
  for (int k = 0; k < n; ++k) {
    char file[64];
    std::snprintf(file, sizeof file, "/Scans/%06d.pcd", k);
    std::vector<std::string> pts;
    for (int i = 0; i < (k == empty ? 0 : 40); ++i)
      for (int j = 0; j < (planar ? 1 : 10); ++j) {
        const double u = -4.0 + 0.2 * i, z = 0.2 * j;
        for (const auto& [x, y] : {std::pair{u, 4.0}, {u, -4.0}, {4.0, u}, {-4.0, u}})
          pts.push_back(std::to_string(x) + " " + std::to_string(y) +
                        (planar ? "" : " " + std::to_string(z)));
      }
    std::ofstream pcd(dir + file);
    pcd << "VERSION .7\n"
        << (planar ? "FIELDS x y\nSIZE 4 4\nTYPE F F\nCOUNT 1 1\n"
                   : "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n")
        << "WIDTH " << pts.size() << "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " << pts.size()
        << "\nDATA ascii\n";
    for (const std::string& p : pts) pcd << p << "\n";
  }
  if (with_odometry) {
    std::ofstream odom(dir + "/odom_poses.txt");
    for (int k = 0; k < n; ++k) odom << "1 0 0 " << k << " 0 1 0 0 0 0 1 0\n";
  }
  return dir;
}

// A new empty folder (a run's --out_dir, a keyframe folder of links).
std::string emptyDir(const std::string& name) {
  const std::string dir = coral_test::tempPath(name, "");
  fs::create_directories(dir);
  return dir;
}

// The candidate rows of a run's candidates.csv (header left out), split into fields.
// The rows of OUT_DIR/FILE (candidates.csv, front_end.csv) below its header, cell by cell.
std::vector<std::vector<std::string>> csvRows(const std::string& out_dir,
                                              const std::string& file = "candidates.csv") {
  std::istringstream csv(coral_test::readWholeFile(out_dir + "/" + file));
  std::vector<std::vector<std::string>> rows;
  std::string line;
  std::getline(csv, line);
  while (std::getline(csv, line)) {
    std::stringstream ss(line);
    rows.emplace_back();
    for (std::string cell; std::getline(ss, cell, ',');) rows.back().push_back(cell);
  }
  return rows;
}

// "ATE against FILE: odometry X m, graph Y m" of a run.
bool ates(const std::string& out, double* odometry, double* graph) {
  const std::size_t at = out.find("ATE against ");
  if (at == std::string::npos) return false;
  const std::size_t colon = out.find(": odometry ", at);
  return colon != std::string::npos &&
         std::sscanf(out.c_str() + colon, ": odometry %lf m, graph %lf m", odometry, graph) == 2;
}

}  // namespace

TEST(PoseGraphArgs, BadOptionsAreRefusedNamingThem) {
  const std::string lidar = coral_test::sourceDir() + "/config/lidar_3d.yaml";
  const std::string radar = coral_test::sourceDir() + "/config/radar_oxford.yaml";
  const std::string planar = coral_test::sourceDir() + "/config/lidar_2d.yaml";
  const std::string box = boxFolder("pose_graph_box", 3, true);
  const std::string no_odom = boxFolder("pose_graph_no_odom", 3, false);
  const std::string out = emptyDir("pose_graph_out");
  const std::string base = "--config " + lidar + " --keyframes " + box + " --out_dir " + out + " ";
  coral_test::expectRefused(
      CORAL_POSE_GRAPH_EXE,
      {
          {"--config " + lidar + " --keyframes " + box,
           "one of --keyframes or --carmen are required"},
          {base + "--carmen " + box + "/log.clf", "one of --keyframes or --carmen are required"},
          {base + "--relations " + box + "/r", "--relations go with --carmen"},
          {base + "--keyframe_distance 2", "go with --carmen"},
          {base + "--proposal sometimes", "--proposal must be odometry or estimate"},
          {base + "--proposal estimate --max_candidates 5", "--max_candidates goes with"},
          {base + "--front_end wheels",
           "--front_end must be odometry, scan_matching or calibrated"},
          {base + "--front_end calibrated", "--front_end calibrated needs --carmen"},
          {"--config " + lidar + " --carmen " + box + "/log.clf --out_dir " + out,
           "a CARMEN log holds 2D laser scans"},
          {"--config " + planar + " --carmen " + box + "/log.clf --out_dir " + out +
               " --reference " + box + "/odom_poses.txt",
           "--reference goes with --keyframes"},
          {"--config " + planar + " --carmen " + box + "/log.clf --out_dir " + out +
               " --keyframe_distance 0",
           "--keyframe_distance and --keyframe_angle must be > 0"},
          {"--config " + planar + " --carmen " + box + "/missing.clf --out_dir " + out,
           box + "/missing.clf"},
          {base + "--gate often", "--gate must be verdict, fitness or none"},
          {base + "--radius 0", "--radius must be > 0"},
          {base + "--radius near", "--radius must be a number"},
          {base + "--max_fitness 0", "--max_fitness must be > 0"},
          {base + "--min_gap 0", "--min_gap"},
          {base + "--max_candidates 0", "--max_candidates"},
          {base + "--lookalikes -1", "--lookalikes"},
          {base + "--registration point_to_line", "--registration: registration must be gicp"},
          {base + "--pcm 1", "--pcm: probability"},
          {base + "--pcm often", "--pcm must be a number"},
          {base + "--radiu 3", "--radiu"},  // a misspelt option is not ignored
          {"--config " + radar + " --keyframes " + box + " --out_dir " + out,
           "keyframes are point clouds"},
          {"--config " + lidar + " --keyframes " + no_odom + " --out_dir " + out,
           no_odom + "/odom_poses.txt"},
          {"--config " + lidar + " --keyframes " + box + " --out_dir " + out + "/missing",
           "cannot write " + out + "/missing/candidates.csv"},
      });
}

// Three keyframes of one room, odometry 1 m apart, min_gap 1, radius 3: the three pairs are
// proposed, registered and judged; the graph is written for every keyframe.
TEST(PoseGraphArgs, ASmallSequenceIsGatedAndWritten) {
  const std::string box = boxFolder("pose_graph_small", 3, true);
  const std::string out = emptyDir("pose_graph_small_out");
  const coral_test::ToolRun r = coral_test::runTool(
      CORAL_POSE_GRAPH_EXE, "--config " + coral_test::sourceDir() + "/config/lidar_3d.yaml" +
                                " --keyframes " + box + " --out_dir " + out + " --min_gap 1");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("3 keyframes; 3 loop candidates (3 within 3.0 m"), std::string::npos)
      << r.out;
  coral_introspection::coral::Isometries poses;
  std::string err;
  ASSERT_TRUE(coral_introspection::eval::readKittiPoses(out + "/trajectory.kitti", &poses, &err))
      << err;
  EXPECT_EQ(poses.size(), 3u);
  EXPECT_EQ(csvRows(out).size(), 3u);
}

// Planar keyframes (PCD fields x, y): read as 2D scans under lidar_2d, where the room's three
// keyframes (the same walls, odometry 1 m apart) register to the same pose and are accepted;
// refused under a 3D preset, naming the file.
TEST(PoseGraphArgs, PlanarKeyframesAreScansOfA2dPreset) {
  const std::string box = boxFolder("pose_graph_planar", 3, true, -1, true);
  const std::string out = emptyDir("pose_graph_planar_out");
  const std::string args = " --keyframes " + box + " --out_dir " + out + " --min_gap 1";
  const coral_test::ToolRun r = coral_test::runTool(
      CORAL_POSE_GRAPH_EXE, "--config " + coral_test::sourceDir() + "/config/lidar_2d.yaml" + args);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("3 loop candidates (3 within 3.0 m of the odometry, 0 look-alike "
                       "registrations), 3 accepted by gate verdict"),
            std::string::npos)
      << r.out;
  coral_test::expectRefused(
      CORAL_POSE_GRAPH_EXE,
      {{"--config " + coral_test::sourceDir() + "/config/lidar_3d.yaml" + args,
        box + "/Scans/000000.pcd: PCD file without fields x, y, z"}});
}

// A keyframe without points (a blinded sensor) is normal input: the pairs with it are
// proposed, not registered, rejected with the reason, and the rest of the graph is written.
TEST(PoseGraphArgs, AnEmptyKeyframeIsRejectedNotACrash) {
  const std::string box = boxFolder("pose_graph_empty", 3, true, 1);
  const std::string out = emptyDir("pose_graph_empty_out");
  for (const char* registration : {"gicp", "ndt", "icp"}) {
    const coral_test::ToolRun r = coral_test::runTool(
        CORAL_POSE_GRAPH_EXE, "--config " + coral_test::sourceDir() + "/config/lidar_3d.yaml" +
                                  " --keyframes " + box + " --out_dir " + out +
                                  " --min_gap 1 --registration " + registration);
    ASSERT_EQ(r.status, 0) << registration << "\n" << r.err;
    const auto rows = csvRows(out);
    for (const std::vector<std::string>& f : rows) {
      ASSERT_EQ(f.size(), 15u);
      if (f[0] != "1" && f[1] != "1") continue;  // a pair without the empty keyframe
      // Not converged, not accepted, no verdict to reject it: the reason instead.
      EXPECT_EQ(f[5] + "," + f[6] + "," + f[7], "0,0,") << f[0] << "-" << f[1];
      EXPECT_NE(f[8].find("no finite point"), std::string::npos) << f[8];
    }
    EXPECT_EQ(rows.size(), 3u) << registration;
  }
}

// The Livox keyframes with their odometry alone (a folder without optimized_poses.txt),
// revisits within 3 m of the odometry plus look-alike places (pairs far apart registered from
// four headings): every loop edge the verdict accepts is within two tolerances of the reference
// (no false edge, the evaluation's label), most revisits are accepted, and the graph's ATE against
// the reference stays within half a tolerance, as the odometry's does (FAST-LIO ends 0.33 m from
// the optimised end: loop closures add little here), while the same candidates ungated (--gate
// none) bend the map.
TEST(PoseGraphLivox, TheVerdictAcceptsNoFalseEdgeWhereUngatedTheMapBends) {
  CORAL_REQUIRE_DATA("hku1_livox_keyframes");
  const std::string dir = emptyDir("pose_graph_livox");
  fs::create_directory_symlink(coral_data + "/Scans", dir + "/Scans");
  fs::create_symlink(coral_data + "/odom_poses.txt", dir + "/odom_poses.txt");
  fs::create_symlink(coral_data + "/times.txt", dir + "/times.txt");
  const bool subset = coral_test::pairStride() > 1;  // sanitizer build: a few candidates
  const std::string common = "--config " + coral_test::sourceDir() + "/config/lidar_3d.yaml" +
                             " --keyframes " + dir + " --reference " + coral_data +
                             "/optimized_poses.txt " +
                             (subset ? "--max_candidates 6 --lookalikes 2" : "--lookalikes 10");
  const std::string out_verdict = emptyDir("pose_graph_livox_verdict");
  const std::string out_none = emptyDir("pose_graph_livox_none");
  const coral_test::ToolRun v =
      coral_test::runTool(CORAL_POSE_GRAPH_EXE, common + " --out_dir " + out_verdict);
  ASSERT_EQ(v.status, 0) << v.err;
  const coral_test::ToolRun n =
      coral_test::runTool(CORAL_POSE_GRAPH_EXE, common + " --out_dir " + out_none + " --gate none");
  ASSERT_EQ(n.status, 0) << n.err;
  std::printf("%s%s", v.out.c_str(), n.out.c_str());

  coral_introspection::coral::Isometries ref, written;
  std::string err;
  ASSERT_TRUE(
      coral_introspection::eval::readKittiPoses(coral_data + "/optimized_poses.txt", &ref, &err));
  ASSERT_TRUE(
      coral_introspection::eval::readKittiPoses(out_verdict + "/trajectory.kitti", &written, &err));
  EXPECT_EQ(written.size(), 314u);
  // Every accepted candidate against the reference's relative pose.
  const auto rows = csvRows(out_verdict);
  int revisits_accepted = 0, false_accepted = 0;
  for (const std::vector<std::string>& f : rows) {
    ASSERT_EQ(f.size(), 15u);
    if (f[6] != "1") continue;
    const int a = std::stoi(f[0]), b = std::stoi(f[1]);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    const double yaw = std::stod(f[13]) * M_PI / 180.0;
    T.translation() << std::stod(f[10]), std::stod(f[11]), std::stod(f[12]);
    T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    double t = 0.0, r_deg = 0.0;
    coral_introspection::eval::relativeError(T, ref[a].inverse() * ref[b], &t, &r_deg);
    // Translation only: the CSV keeps the yaw of the transform, not roll and pitch.
    if (t >= 2 * 0.3) ++false_accepted;
    revisits_accepted += f[2] == "radius" ? 1 : 0;
  }
  EXPECT_GT(rows.size(), 0u);
  EXPECT_EQ(false_accepted, 0) << "accepted loop edges 2 tolerances or more off the reference";
  EXPECT_GE(revisits_accepted, subset ? 1 : 20);
  double odom_v = 0, graph_v = 0, odom_n = 0, graph_n = 0;
  ASSERT_TRUE(ates(v.out, &odom_v, &graph_v)) << v.out;
  ASSERT_TRUE(ates(n.out, &odom_n, &graph_n)) << n.out;
  EXPECT_DOUBLE_EQ(odom_v, odom_n);
  // The gated graph stays within half a tolerance of the reference (it is 0.27 m off itself
  // at the first loop, doc/loop_closure.md: the true edges there pull against it).
  EXPECT_LT(graph_v, 0.5 * 0.3);
  if (!subset) {
    EXPECT_GT(graph_n, 10 * graph_v);  // false edges bend the ungated one
  }
}

// "relation error against FILE (N of M relations): odometry X m / A deg, graph Y m / B deg".
bool relationErrors(const std::string& out, double* odometry, double* graph) {
  const std::size_t at = out.find("relations): odometry ");
  return at != std::string::npos &&
         std::sscanf(out.c_str() + at, "relations): odometry %lf m / %*f deg, graph %lf m",
                     odometry, graph) == 2;
}

// The ACES log read as it is (FLASER scans and wheel odometry, no corrected poses): keyframes
// every metre, loop candidates proposed around the graph's running estimate and closed one by one.
// Measured by the benchmark's relations, the verdict's graph is far better than the odometry
// (0.145 vs 0.549 m, doc/loop_closure.md), while the same proposals gated by ICP fitness
// (LIO-SAM's 0.3) or not at all end worse than the odometry alone.
TEST(PoseGraphCarmen, OnTheAcesLogTheVerdictsGraphBeatsTheOdometryAndTheFitnessGate) {
  CORAL_REQUIRE_DATA("radish_aces");
  const std::string common = "--config " + coral_test::sourceDir() + "/config/lidar_2d.yaml" +
                             " --carmen " + coral_data + "/aces.clf.bz2 --relations " + coral_data +
                             "/aces.relations";
  double odom[3], graph[3];
  const char* gates[3] = {"verdict", "fitness", "none"};
  for (int g = 0; g < 3; ++g) {
    const std::string out = emptyDir(std::string("pose_graph_aces_") + gates[g]);
    const coral_test::ToolRun r = coral_test::runTool(
        CORAL_POSE_GRAPH_EXE, common + " --out_dir " + out + " --gate " + gates[g]);
    ASSERT_EQ(r.status, 0) << r.err;
    std::printf("%s", r.out.c_str());
    ASSERT_TRUE(relationErrors(r.out, &odom[g], &graph[g])) << r.out;
    EXPECT_NE(r.out.find("within 3.0 m of the graph's estimate"), std::string::npos) << r.out;
    coral_introspection::coral::Isometries written;
    std::string err;
    ASSERT_TRUE(
        coral_introspection::eval::readKittiPoses(out + "/trajectory.kitti", &written, &err));
    EXPECT_GT(written.size(), 300u);  // a keyframe per metre of a ~400 m drive
    EXPECT_EQ(csvRows(out).empty(), false);
  }
  EXPECT_DOUBLE_EQ(odom[0], odom[1]);
  EXPECT_LT(graph[0], 0.5 * odom[0]);  // the verdict's loop edges correct the drift
  EXPECT_GT(graph[1], odom[0]);        // the fitness gate's bend the map
  EXPECT_GT(graph[2], odom[0]);        // and so do all of them

  // The scan-matching front end: odometry steps whose registration the stream verdict accepts
  // replace the wheel odometry's (or the pose the verdict's own registration reached, when it
  // rejected the step for that lower minimum of Q: ros_eval::streamVerdictDecision), and the
  // odometry alone comes closer to the relations: 0.236 m against the wheels' 0.549 (0.417
  // without the second try).
  const std::string out = emptyDir("pose_graph_aces_front_end");
  const coral_test::ToolRun r = coral_test::runTool(
      CORAL_POSE_GRAPH_EXE, common + " --out_dir " + out + " --front_end scan_matching");
  ASSERT_EQ(r.status, 0) << r.err;
  std::printf("%s", r.out.c_str());
  int replaced = 0, steps = 0;
  const std::size_t at = r.out.find("front end: ");
  ASSERT_NE(at, std::string::npos) << r.out;
  ASSERT_EQ(std::sscanf(r.out.c_str() + at, "front end: %d of %d", &replaced, &steps), 2);
  EXPECT_GT(replaced, steps / 2);
  EXPECT_LT(replaced, steps);  // some registrations are refused
  // front_end.csv says how each step was measured; some at the verdict's registered pose.
  const auto fe = csvRows(out, "front_end.csv");
  ASSERT_EQ(static_cast<int>(fe.size()), steps);
  int measured = 0, second_tries = 0;
  for (const auto& row : fe) {
    ASSERT_EQ(row.size(), 9u);
    measured += row[4] != "odometry" ? 1 : 0;
    second_tries += row[4] == "verdict_registration" ? 1 : 0;
  }
  EXPECT_EQ(measured, replaced);
  EXPECT_GT(second_tries, 0);
  double matched_odom = 0, matched_graph = 0;
  ASSERT_TRUE(relationErrors(r.out, &matched_odom, &matched_graph)) << r.out;
  EXPECT_LT(matched_odom, 0.5 * odom[0]);
}

// A false loop closure the verdict accepts, and the back end's check behind it. With 20
// look-alike place pairs registered from four headings, the ACES verdict accepts one (keyframes
// 50 and 196, the same corridor from the other direction, 43.8 m off; doc/loop_closure.md). With
// --pcm 0.99 the odometry check keeps it out before it can bend the running estimate (the
// pairwise check alone could not: it is the run's first loop edge), and the graph comes as
// close to the relations as without look-alikes. Every accepted look-alike is marked
// pcm_inconsistent in candidates.csv, and no edge left in the graph is a look-alike.
TEST(PoseGraphCarmen, TheOdometryCheckKeepsAnAcceptedLookAlikeOutOfTheGraph) {
  CORAL_REQUIRE_DATA("radish_aces");
  const std::string common = "--config " + coral_test::sourceDir() + "/config/lidar_2d.yaml" +
                             " --carmen " + coral_data + "/aces.clf.bz2 --relations " + coral_data +
                             "/aces.relations --lookalikes 20";
  double odom = 0, plain = 0, checked = 0;
  const std::string out_plain = emptyDir("pose_graph_aces_lookalikes");
  coral_test::ToolRun r =
      coral_test::runTool(CORAL_POSE_GRAPH_EXE, common + " --out_dir " + out_plain);
  ASSERT_EQ(r.status, 0) << r.err;
  std::printf("%s", r.out.c_str());
  ASSERT_TRUE(relationErrors(r.out, &odom, &plain)) << r.out;
  const std::string out = emptyDir("pose_graph_aces_lookalikes_pcm");
  r = coral_test::runTool(CORAL_POSE_GRAPH_EXE, common + " --pcm 0.99 --out_dir " + out);
  ASSERT_EQ(r.status, 0) << r.err;
  std::printf("%s", r.out.c_str());
  ASSERT_TRUE(relationErrors(r.out, &odom, &checked)) << r.out;
  EXPECT_NE(r.out.find("pcm (chi-square 0.99)"), std::string::npos) << r.out;
  int lookalikes_accepted = 0, in_graph = 0;
  for (const auto& row : csvRows(out)) {
    ASSERT_EQ(row.size(), 15u);
    const bool accepted = row[6] == "1", out_of_graph = row[14] == "1";
    EXPECT_TRUE(accepted || !out_of_graph);  // only accepted edges are checked
    if (accepted && row[2] == "lookalike") {
      ++lookalikes_accepted;
      EXPECT_TRUE(out_of_graph) << "look-alike " << row[0] << " - " << row[1] << " in the graph";
    }
    in_graph += accepted && !out_of_graph ? 1 : 0;
  }
  std::printf("look-alikes accepted by the verdict: %d; loop edges in the checked graph: %d\n",
              lookalikes_accepted, in_graph);
  EXPECT_GE(in_graph, 5);
  EXPECT_LT(checked, 0.5 * odom);  // the checked graph corrects the drift
  EXPECT_LE(checked, plain);       // and is no worse than without the check
}

// The Intel log's lines are not in time order (its FLASER stamps step back 631 times): every one
// of its 2,984 benchmark relations is found and measured (2,345 were while eval::logLineAt
// bisected the log as if it were; doc/loop_closure.md "Intel's log is not in time order").
// Intel's wheel odometry turns too far, by 0.032 rad a 0.55 m step (doc/loop_closure.md
// "Intel's graphs were folded"): its graph's running estimate drifts so far that the verdict
// accepts 13 of the revisits proposed and the graph stays where the odometry is. With
// --front_end calibrated the odometry's yaw is calibrated on the steps its scan matching and the
// stream verdict accept, and then the verdict's graph closes loops. Measured (relation error):
// raw odometry 7.37 m, calibrated 4.47 m; the verdict's graph 2.67 m (48 edges), the fitness
// gate's 5.67 m (421 edges), worse than the calibrated odometry alone.
TEST(PoseGraphCarmen, EveryIntelRelationIsMeasuredAndTheCalibratedOdometryClosesLoops) {
  CORAL_REQUIRE_DATA("radish_intel");
  const std::string common = "--config " + coral_test::sourceDir() + "/config/lidar_2d.yaml" +
                             " --carmen " + coral_data + "/intel.clf.bz2 --relations " +
                             coral_data + "/intel.relations";
  auto run = [&](const std::string& name, const std::string& options, double* odom, double* graph) {
    const std::string out = emptyDir("pose_graph_intel_" + name);
    const coral_test::ToolRun r =
        coral_test::runTool(CORAL_POSE_GRAPH_EXE, common + " --out_dir " + out + options);
    ASSERT_EQ(r.status, 0) << r.err;
    std::printf("%s", r.out.c_str());
    EXPECT_NE(r.out.find("(2984 of 2984 relations)"), std::string::npos) << r.out;
    ASSERT_TRUE(relationErrors(r.out, odom, graph)) << r.out;
    if (options.find("calibrated") == std::string::npos) return;
    int steps = 0, of = 0;
    const std::size_t at = r.out.find("front end: odometry yaw calibrated on ");
    ASSERT_NE(at, std::string::npos) << r.out;
    ASSERT_EQ(std::sscanf(r.out.c_str() + at, "front end: odometry yaw calibrated on %d of %d",
                          &steps, &of),
              2);
    EXPECT_GT(steps, of / 3);
  };
  double raw_odom = 0, raw_graph = 0, odom = 0, verdict = 0, fitness_odom = 0, fitness = 0;
  run("raw", "", &raw_odom, &raw_graph);
  EXPECT_GT(raw_odom, 1.0);                  // Intel's wheel odometry: metres off the relations
  if (coral_test::pairStride() > 1) return;  // sanitizer build: the runs below are slow there
  run("calibrated", " --front_end calibrated", &odom, &verdict);
  EXPECT_LT(odom, 0.75 * raw_odom);      // the calibration alone
  EXPECT_LT(verdict, 0.75 * odom);       // the verdict's loop edges on top
  EXPECT_LT(verdict, 0.75 * raw_graph);  // and against the raw odometry's graph
  run("calibrated_fitness", " --front_end calibrated --gate fitness", &fitness_odom, &fitness);
  EXPECT_DOUBLE_EQ(fitness_odom, odom);
  EXPECT_GT(fitness, odom);  // the fitness gate's edges bend it
  EXPECT_LT(verdict, 0.6 * fitness);
}
