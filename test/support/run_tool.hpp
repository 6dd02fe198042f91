// Runs a command-line tool of the package for a test: its exit status, stdout and stderr.
#pragma once

#include <sys/wait.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "support/test_data.hpp"

namespace coral_test {

struct ToolRun {
  int status = -1;  // exit status; -1 when the tool did not exit normally
  std::string out, err;
};

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
  std::ifstream e(err_path);
  std::stringstream ss;
  ss << e.rdbuf();
  r.err = ss.str();
  std::remove(err_path.c_str());
  return r;
}

}  // namespace coral_test
