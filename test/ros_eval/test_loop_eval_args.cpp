// coral_loop_eval refuses what it cannot run, before it reads any data: exit 2, the reason on
// stderr naming the option, nothing on stdout (no table a script could take for a result).
#include <gtest/gtest.h>

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
          // The restart check is the preset's (loop_closure/restarts) since 2026-12-03: the old
          // flag is refused, not ignored.
          {base + "--restarts", "--restarts"},
          {"--keyframes /nonexistent_keyframes", "--config and either --keyframes or --carmen"},
      });
}
