// The tools' command lines: options with values (repeatable), flags, unknown names refused.
#include <gtest/gtest.h>

#include "coral_introspection/eval/tool_args.hpp"

using namespace coral_introspection::core;

TEST(ToolArgs, OptionsFlagsAndRepeats) {
  const char* argv[] = {"tool", "--config", "a.yaml", "--data", "x", "--loop", "--data", "y"};
  ToolArgs a;
  std::string err;
  ASSERT_TRUE(parseToolArgs(8, argv, {"--config", "--data", "--out"}, {"--loop"}, &a, &err)) << err;
  EXPECT_EQ(a.get("--config"), "a.yaml");
  EXPECT_EQ(a.values.at("--data"), (std::vector<std::string>{"x", "y"}));
  EXPECT_EQ(a.flags.count("--loop"), 1u);
  EXPECT_FALSE(a.has("--out"));
  EXPECT_EQ(a.get("--out", "default"), "default");
  EXPECT_FALSE(a.help);
}

TEST(ToolArgs, UnknownMissingAndBadNumbersAreRefused) {
  ToolArgs a;
  std::string err;
  const char* typo[] = {"tool", "--confg", "a.yaml"};
  EXPECT_FALSE(parseToolArgs(3, typo, {"--config"}, {}, &a, &err));
  EXPECT_NE(err.find("--confg"), std::string::npos);
  const char* missing[] = {"tool", "--config"};
  EXPECT_FALSE(parseToolArgs(2, missing, {"--config"}, {}, &a, &err));
  EXPECT_NE(err.find("missing value"), std::string::npos);
  const char* stride[] = {"tool", "--stride", "0"};
  ASSERT_TRUE(parseToolArgs(3, stride, {"--stride"}, {}, &a, &err));
  int n = 0;
  EXPECT_FALSE(positiveInt(a, "--stride", 1, &n, &err));
  EXPECT_NE(err.find("--stride"), std::string::npos);
  const char* help[] = {"tool", "-h"};
  ASSERT_TRUE(parseToolArgs(2, help, {}, {}, &a, &err));
  EXPECT_TRUE(a.help);
  EXPECT_TRUE(positiveInt(a, "--stride", 4, &n, &err));
  EXPECT_EQ(n, 4);
}
