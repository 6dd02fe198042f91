// coral_train refuses a number it cannot read whole, before it reads any data: exit 2, the
// option named on stderr, nothing on stdout. Before 2026-12-05 it read "0.5x" as 0.5 and "12.7"
// as 12 (std::stod / std::stoi) and trained on the misread value.
#include <gtest/gtest.h>

#include <string>

#include "support/run_tool.hpp"

TEST(TrainArgs, MalformedNumbersAreRefusedNamingTheOption) {
  const std::string paper = "--oxford /nonexistent_oxford ";
  const std::string preset =
      "--preset " + coral_test::sourceDir() + "/config/lidar_2d.yaml --dataset /nonexistent ";
  coral_test::expectRefused(
      CORAL_TRAIN_EXE,
      {
          {paper + "--radius 0.5x", "--radius must be a number (got '0.5x')"},
          {paper + "--ridge nan", "--ridge must be a number"},
          {paper + "--k 12.7", "--k must be an integer"},
          {paper + "--window -1", "--window must be an integer"},
          {paper + "--magnitudes 0.5,,1", "--magnitudes must be numbers separated by commas"},
          {paper + "--rotations 5deg", "--rotations must be numbers separated by commas"},
          {preset + "--threads 2x", "--threads must be an integer"},
          {preset + "--relative_margin 0.2abc", "--relative_margin must be a number"},
          {preset + "--shard 1x/4", "--shard index must be an integer"},
          {preset + "--shard 1/4.5", "--shard count must be an integer"},
      });
}
