// coral_loop_eval refuses what it cannot run, before it reads any data: exit 2, the reason on
// stderr naming the option, nothing on stdout (no table a script could take for a result).
// And its --timing: the verdict a back end gets is the one its table counts.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <string>

#include "support/run_tool.hpp"

TEST(LoopEvalArgs, BadOptionsAreRefusedNamingThem) {
  const std::string config = coral_test::sourceDir() + "/config/lidar_3d.yaml";
  const std::string base = "--config " + config + " --keyframes /nonexistent_keyframes ";
  coral_test::expectRefused(
      CORAL_LOOP_EVAL_EXE,
      {
          {base + "--pcm 1", "--pcm: probability must be in (0, 1)"},
          {base + "--pcm 0", "--pcm: probability must be in (0, 1)"},
          {base + "--pcm often", "--pcm must be a number"},
          {base + "--prune 0", "--prune: max_residual must be > 0"},
          {base + "--prune 3 --pcm 2", "--pcm: probability"},
          {base + "--rows middle", "--rows must be all, even or odd"},
          {base + "--lookalikes 0", "--lookalikes"},
          {base + "--lookalikes 60x", "--lookalikes"},
          {base + "--pcn 0.99", "--pcn"},  // a misspelt option is not ignored
          {base + "--calibrate_odometry", "--calibrate_odometry needs --carmen"},
          // The restart check is the preset's (loop_closure/restarts) since 2026-12-03: the old
          // flag is refused, not ignored.
          {base + "--restarts", "--restarts"},
          {"--keyframes /nonexistent_keyframes", "--config and either --keyframes or --carmen"},
      });
}

// --timing runs the preset's loop verdict once more per candidate, as a back end gets it
// (online::judgePair with coral::loopClosureVerdict), and compares it with the table's gate
// "verdict", which coral_loop_eval combines from one evaluation with every term measured (its
// own copy of the loop verdict's steps). On the ACES candidates (odd rows, ~8 s; in the
// sanitizer build, CORAL_VERDICT_PAIR_STRIDE > 1, 4 look-alike pairs instead of 60): the two
// agree on every candidate, and every candidate is timed in one of the kinds.
TEST(LoopEvalTiming, TheVerdictABackEndGetsIsTheTablesOnAces) {
  std::string aces;
  {
    CORAL_REQUIRE_DATA("radish_aces");
    aces = coral_data;
  }
  CORAL_REQUIRE_DATA("radish_intel");  // the corrected ACES poses are kept there
  const coral_test::ToolRun r = coral_test::runTool(
      CORAL_LOOP_EVAL_EXE, "--config " + coral_test::sourceDir() +
                               "/config/lidar_2d.yaml --carmen " + aces +
                               "/aces.clf.bz2 --corrected " + coral_data +
                               "/aces_corrected_poses_on_raw.csv --rows odd --timing" +
                               (coral_test::pairStride() > 1 ? " --lookalikes 4" : ""));
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string tag = "timing: the verdict differs from the table's gate on ";
  const std::size_t at = r.out.find(tag);
  ASSERT_NE(at, std::string::npos) << r.out;
  int differ = -1, total = 0;
  ASSERT_EQ(std::sscanf(r.out.c_str() + at + tag.size(), "%d of %d", &differ, &total), 2);
  EXPECT_EQ(differ, 0) << r.out;
  EXPECT_GE(total, coral_test::pairStride() > 1 ? 100 : 200);
  // The rows per kind: their counts add up to every candidate; times are positive.
  int timed = 0;
  for (const char* kind :
       {"true, accepted", "true, rejected", "false, accepted", "false, rejected"}) {
    const std::size_t row = r.out.find(std::string("\n") + kind);
    if (row == std::string::npos) continue;
    int n = 0;
    double median = 0, p90 = 0, max = 0;
    ASSERT_EQ(std::sscanf(r.out.c_str() + row + 1 + std::strlen(kind), "%d %lf %lf %lf", &n,
                          &median, &p90, &max),
              4)
        << kind;
    EXPECT_GT(median, 0.0) << kind;
    EXPECT_LE(median, p90) << kind;
    EXPECT_LE(p90, max) << kind;
    timed += n;
  }
  EXPECT_EQ(timed, total);
  EXPECT_EQ(r.out.find("false, accepted"), std::string::npos) << "no false candidate accepted";
}
