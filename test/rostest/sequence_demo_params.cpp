// rostest: coral_sequence_demo refuses ~parameters it cannot read whole (exit 2, the reason on
// its output and in ~result_file) instead of skipping or defaulting them. Until 2026-12-05 it
// read a scan index "3x" as 3, skipped "x" with a warning and kept the default of a value of
// the wrong type or a misspelt name. Each case starts the node under its own name, so its
// private parameters (`_name:=value`) do not meet another case's.
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <string>

#include "rostest_main.hpp"
#include "support/run_tool.hpp"

namespace {

struct Outcome {
  coral_test::ToolRun run;
  std::string result_file;  // ~result_file's content
};

Outcome startDemo(const std::string& params) {
  static int n = 0;
  const std::string file = coral_test::tempPath("demo_result", ".txt");
  Outcome o;
  o.run =
      coral_test::runTool(CORAL_SEQUENCE_DEMO_EXE,
                          "__name:=demo_case_" + std::to_string(++n) + " _result_file:=" + file +
                              " _start_timeout:=1 _num_scans:=3 " + params);
  o.result_file = coral_test::readWholeFile(file);
  std::remove(file.c_str());
  return o;
}

TEST(SequenceDemoParams, MalformedValuesFailTheStartWithTheReason) {
  const struct {
    std::string params, reason;
  } cases[] = {
      {"_step_scans:=3x", "'3x' is not a scan index"},
      {"_spike_scans:=\"4,,5\"", "'' is not a scan index"},
      {"_spike_scans:=\"4,5,\"", "~spike_scans '4,5,': '' is not a scan index"},
      {"_step_scans:=2.5", "~step_scans '2.5': not scan indices"},
      {"_spike_scans:=-1", "a scan index is >= 0"},
      {"_num_scans:=many", "num_scans"},
      {"_rate:=fast", "rate"},
      {"_error_magnitud:=0.3", "did you mean error_magnitude?"},
      {"_mode:=lidar_4d", "~mode 'lidar_4d' must be"},
  };
  for (const auto& c : cases) {
    const Outcome o = startDemo(c.params);
    EXPECT_EQ(o.run.status, 2) << c.params << "\n" << o.run.out << o.run.err;
    EXPECT_NE((o.run.out + o.run.err).find(c.reason), std::string::npos) << c.params << "\n"
                                                                         << o.run.out << o.run.err;
    EXPECT_NE(o.result_file.find(c.reason), std::string::npos) << c.params << "\n" << o.result_file;
    EXPECT_NE(o.result_file.find("exit_code 2"), std::string::npos) << o.result_file;
  }
}

TEST(SequenceDemoParams, ValidValuesPassToTheSequence) {
  // A list as demo.launch passes it, one index as `rosrun ... _spike_scans:=2` does (an int on
  // the parameter server), and none. With no nodelet listening the node ends with exit 1
  // ("did not connect"): past the parameters.
  for (const std::string params : {"_step_scans:=\" 1, 2\" _spike_scans:=2",
                                   "_step_scans:=\"\" _spike_scans:=\"\" _error_pattern:=none"}) {
    const Outcome o = startDemo(params);
    EXPECT_EQ(o.run.status, 1) << params << "\n" << o.run.out << o.run.err;
    EXPECT_NE(o.result_file.find("did not connect"), std::string::npos) << params << "\n"
                                                                        << o.result_file;
  }
}

}  // namespace

const coral_test::RostestNode coral_test::kRostestNode{"sequence_demo_params_test", 0};
