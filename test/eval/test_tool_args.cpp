// The tools' command lines: options with values (repeatable), flags, unknown names refused.
#include <gtest/gtest.h>

#include "coral_introspection/eval/tool_args.hpp"

using namespace coral_introspection::eval;

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

TEST(ToolArgs, InlineValuesAndPositionalArguments) {
  const char* argv[] = {"tool", "in_dir", "--set=a/b=1", "--loop", "out.bag", "--set", "c=2"};
  ToolArgs a;
  std::string err;
  ASSERT_TRUE(parseToolArgs(7, argv, {"--set"}, {"--loop"}, &a, &err, 2)) << err;
  EXPECT_EQ(a.all("--set"), (std::vector<std::string>{"a/b=1", "c=2"}));
  EXPECT_TRUE(a.all("--absent").empty());
  EXPECT_EQ(a.positional, (std::vector<std::string>{"in_dir", "out.bag"}));
  EXPECT_TRUE(a.flag("--loop"));
  // One positional argument too many, none allowed, a value given to a flag.
  EXPECT_FALSE(parseToolArgs(7, argv, {"--set"}, {"--loop"}, &a, &err, 1));
  EXPECT_NE(err.find("out.bag"), std::string::npos) << err;
  EXPECT_FALSE(parseToolArgs(7, argv, {"--set"}, {"--loop"}, &a, &err));
  EXPECT_NE(err.find("in_dir"), std::string::npos) << err;
  const char* flag_value[] = {"tool", "--loop=1"};
  EXPECT_FALSE(parseToolArgs(2, flag_value, {}, {"--loop"}, &a, &err));
  EXPECT_NE(err.find("takes no value"), std::string::npos) << err;
  // A value may start with '-' (a negative number).
  const char* negative[] = {"tool", "--error", "-0.3"};
  ASSERT_TRUE(parseToolArgs(3, negative, {"--error"}, {}, &a, &err)) << err;
  EXPECT_EQ(a.get("--error"), "-0.3");
}

TEST(ToolArgs, TypedValuesRefuseMalformedNumbers) {
  const char* argv[] = {"tool", "--x", "-2.5e-1", "--n", "7", "--bad", "0.3m", "--big", "1e999"};
  ToolArgs a;
  std::string err;
  ASSERT_TRUE(parseToolArgs(9, argv, {"--x", "--n", "--bad", "--big", "--absent"}, {}, &a, &err));
  double x = 0.0;
  EXPECT_TRUE(numberOption(a, "--x", 1.0, &x, &err));
  EXPECT_EQ(x, -0.25);
  EXPECT_TRUE(numberOption(a, "--absent", 1.5, &x, &err));
  EXPECT_EQ(x, 1.5);
  EXPECT_FALSE(numberOption(a, "--bad", 1.0, &x, &err));
  EXPECT_EQ(err, "--bad must be a number (got '0.3m')");
  EXPECT_FALSE(numberOption(a, "--big", 1.0, &x, &err));
  int n = 0;
  EXPECT_TRUE(intOption(a, "--n", 0, 0, 10, &n, &err));
  EXPECT_EQ(n, 7);
  EXPECT_FALSE(intOption(a, "--n", 0, 0, 5, &n, &err));
  EXPECT_EQ(err, "--n must be an integer in [0, 5] (got '7')");
  EXPECT_FALSE(intOption(a, "--x", 0, -10, 10, &n, &err));  // not an integer
  const char* loose[] = {"tool", "--plus", "+3", "--blank", " 3", "--long", "99999999999999999999"};
  ASSERT_TRUE(parseToolArgs(7, loose, {"--plus", "--blank", "--long"}, {}, &a, &err));
  for (const char* o : {"--plus", "--blank", "--long"}) {  // whole integers only (strtol's slack)
    EXPECT_FALSE(intOption(a, o, 0, -10, 10, &n, &err)) << o;
    EXPECT_FALSE(positiveInt(a, o, 1, &n, &err)) << o;
  }
  EXPECT_TRUE(intOption(a, "--absent", -1, 0, 5, &n, &err));  // the fallback is not checked
  EXPECT_EQ(n, -1);
}

TEST(ToolArgs, NumberListOptionTakesCommaSeparatedNumbersOrRefusesTheBadItem) {
  ToolArgs a;
  const char* argv[] = {"tool",   "--k",  "1.5,2.5,10", "--bad", "1,abc,2", "--hole", "1,,2",
                        "--tail", "1,2,", "--lead",     ",1",    "--empty", ""};
  std::string err;
  ASSERT_TRUE(parseToolArgs(13, argv,
                            {"--k", "--bad", "--hole", "--tail", "--lead", "--empty", "--absent"},
                            {}, &a, &err));
  std::vector<double> k;
  EXPECT_TRUE(numberListOption(a, "--k", {9.0}, &k, &err));
  EXPECT_EQ(k, (std::vector<double>{1.5, 2.5, 10.0}));
  EXPECT_TRUE(numberListOption(a, "--absent", {1.0, 2.0}, &k, &err));
  EXPECT_EQ(k, (std::vector<double>{1.0, 2.0}));
  EXPECT_FALSE(numberListOption(a, "--bad", {}, &k, &err));
  EXPECT_EQ(err, "--bad must be numbers separated by commas (got 'abc')");
  EXPECT_FALSE(numberListOption(a, "--hole", {}, &k, &err));
  EXPECT_EQ(k, (std::vector<double>{1.0, 2.0}));  // unchanged on refusal
  // An empty entry at either end is refused too ("1,2," was once read as [1, 2]).
  EXPECT_FALSE(numberListOption(a, "--tail", {}, &k, &err));
  EXPECT_EQ(err, "--tail must be numbers separated by commas (got '')");
  EXPECT_FALSE(numberListOption(a, "--lead", {}, &k, &err));
  EXPECT_FALSE(numberListOption(a, "--empty", {}, &k, &err));
  EXPECT_EQ(k, (std::vector<double>{1.0, 2.0}));
}

TEST(ToolArgs, ReadCommandLineGivesTheExitStatus) {
  ToolArgs a;
  const char* good[] = {"tool", "--config", "a.yaml"};
  EXPECT_FALSE(readCommandLine("tool", "usage: tool", 3, good, {"--config"}, {}, &a).has_value());
  EXPECT_EQ(a.get("--config"), "a.yaml");
  const char* help[] = {"tool", "--help"};
  EXPECT_EQ(readCommandLine("tool", "usage: tool", 2, help, {"--config"}, {}, &a), 0);
  const char* typo[] = {"tool", "--confg", "a.yaml"};
  EXPECT_EQ(readCommandLine("tool", "usage: tool", 3, typo, {"--config"}, {}, &a), 2);
}

// --rows all|even|odd of coral_loop_eval and coral_error_sweep: the first choice when absent,
// anything else refused with the choices named.
TEST(ToolArgs, ChoiceOptionTakesOneOfTheChoicesOrRefusesWithThem) {
  const std::vector<std::string> rows{"all", "even", "odd"};
  auto choose = [&](int argc, const char* const* argv, std::string* out, std::string* err) {
    ToolArgs a;
    EXPECT_TRUE(parseToolArgs(argc, argv, {"--rows"}, {}, &a, err)) << *err;
    return choiceOption(a, "--rows", rows, out, err);
  };
  std::string err, out;
  const char* none[] = {"tool"};
  ASSERT_TRUE(choose(1, none, &out, &err)) << err;
  EXPECT_EQ(out, "all");
  const char* odd[] = {"tool", "--rows", "odd"};
  ASSERT_TRUE(choose(3, odd, &out, &err)) << err;
  EXPECT_EQ(out, "odd");
  const char* bad[] = {"tool", "--rows=Odd"};
  EXPECT_FALSE(choose(2, bad, &out, &err));
  EXPECT_EQ(err, "--rows must be all, even or odd (got 'Odd')");
}
