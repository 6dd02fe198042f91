// Runs a command-line tool of the package for a test: its exit status, stdout and stderr.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "support/test_data.hpp"

namespace coral_test {

struct ToolRun {
  int status = -1;  // exit status; -1 when the tool did not exit normally
  std::string out, err;
};

// A whole text file ("" when it cannot be read).
inline std::string readWholeFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// `exe args`, stdout captured through a pipe, stderr through a temp file (removed after).
inline ToolRun runTool(const std::string& exe, const std::string& args) {
  const std::string err_path = tempPath("tool_err", ".txt");
  const std::string cmd = exe + " " + args + " 2>" + err_path;
  ToolRun r;
  FILE* p = popen(cmd.c_str(), "r");
  char buf[4096];
  while (p && fgets(buf, sizeof(buf), p)) r.out += buf;
  const int st = p ? pclose(p) : -1;
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  r.err = readWholeFile(err_path);
  std::remove(err_path.c_str());
  return r;
}

// A command line a tool must refuse: exit 2, `reason` on stderr, nothing on stdout (no output
// a script could take for a result). Each case failing adds a gtest failure naming its args.
struct RefusedCase {
  std::string args, reason;
};
inline void expectRefused(const std::string& exe, const std::vector<RefusedCase>& cases) {
  for (const RefusedCase& c : cases) {
    const ToolRun r = runTool(exe, c.args);
    EXPECT_EQ(r.status, 2) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.reason), std::string::npos) << c.args << "\n" << r.err;
    EXPECT_EQ(r.out, "") << c.args;
  }
}

}  // namespace coral_test
