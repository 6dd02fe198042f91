// The README's parameter and diagnostics tables list exactly what the code reads and
// reports: a parameter added, renamed or removed in coral_params.cpp, or a diagnostics key in
// coral_diagnostics.cpp, without the README following makes this fail.
#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "coral_introspection/ros/coral_diagnostics.hpp"
#include "coral_introspection/ros/coral_params.hpp"
#include "support/source_dir.hpp"

using namespace coral_introspection::ros_adapters;

namespace {

std::vector<std::string> readmeLines() {
  std::ifstream in(coral_test::sourceDir() + "/README.md");
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

// The names in the first cell of each row of the table after the line starting with
// `heading`: `a/b`, `c` -> a/b, a/c (a bare name takes the group of the cell's first name).
std::set<std::string> firstCells(const std::string& heading, bool inherit_group) {
  const std::vector<std::string> lines = readmeLines();
  std::set<std::string> names;
  std::size_t k = 0;
  while (k < lines.size() && lines[k].rfind(heading, 0) != 0) ++k;
  while (k < lines.size() && lines[k].rfind("|", 0) != 0) ++k;
  for (k += 2; k < lines.size() && lines[k].rfind("|", 0) == 0; ++k) {  // skip header, ---
    const std::string cell = lines[k].substr(1, lines[k].find('|', 1) - 1);
    std::string group;
    for (std::size_t a = cell.find('`'); a != std::string::npos; a = cell.find('`', a + 1)) {
      const std::size_t b = cell.find('`', a + 1);
      std::string name = cell.substr(a + 1, b - a - 1);
      const std::size_t slash = name.rfind('/');
      if (inherit_group && slash != std::string::npos && group.empty())
        group = name.substr(0, slash + 1);
      else if (inherit_group && slash == std::string::npos && !group.empty())
        name = group + name;
      names.insert(name);
      a = b;
    }
  }
  return names;
}

std::string difference(const std::set<std::string>& a, const std::set<std::string>& b) {
  std::ostringstream s;
  for (const auto& x : a)
    if (!b.count(x)) s << " '" << x << "'";
  return s.str();
}

TEST(ReadmeTables, ParameterTableListsEveryParameterRead) {
  const std::vector<std::string> read = nodeParameterNames();
  const std::set<std::string> code(read.begin(), read.end());
  ASSERT_GT(code.size(), 40u);
  const std::set<std::string> readme = firstCells("**Parameters**", true);
  EXPECT_EQ(difference(code, readme), "") << "read by coral_params.cpp, missing in README";
  EXPECT_EQ(difference(readme, code), "") << "in README, not read by coral_params.cpp";
}

TEST(ReadmeTables, DiagnosticsTableListsEveryKey) {
  ros::Time::init();
  Stats s;
  s.doppler = true;      // the Doppler counters too
  s.calibration = true;  // and the self-calibration's state
  diagnostic_updater::DiagnosticStatusWrapper w;
  s.diagnose(w);
  std::set<std::string> code;
  for (const auto& kv : w.values) code.insert(kv.key);
  ASSERT_GT(code.size(), 30u);
  const std::set<std::string> readme = firstCells("**Diagnostics keys**", false);
  EXPECT_EQ(difference(code, readme), "") << "reported by coral_diagnostics.cpp, missing in README";
  EXPECT_EQ(difference(readme, code), "") << "in README, not reported by coral_diagnostics.cpp";
}

}  // namespace
