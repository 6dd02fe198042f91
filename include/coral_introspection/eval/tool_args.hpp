// Command lines of the evaluation tools: "--name value" options (some repeatable) and
// "--name" flags, each checked against what the tool declares, so a misspelt option is an
// error with the usage, never silently ignored.
#pragma once

#include <map>
#include <set>
#include <string>
#include <vector>

namespace coral_introspection {
namespace core {

struct ToolArgs {
  std::map<std::string, std::vector<std::string>> values;  // option -> its values, in order
  std::set<std::string> flags;                             // flags given
  bool help = false;                                       // -h or --help
  // The last value of `option`, or `fallback` when it was not given.
  std::string get(const std::string& option, const std::string& fallback = "") const;
  bool has(const std::string& option) const { return values.count(option) > 0; }
};

// `options`: names taking a value ("--config"); `flags`: names without one. An option given
// twice keeps both values (ToolArgs::values). False with *error on an unknown name or a
// missing value.
bool parseToolArgs(int argc, const char* const* argv, const std::vector<std::string>& options,
                   const std::vector<std::string>& flags, ToolArgs* out, std::string* error);

// "<tool>: <message>" and the usage on stderr; returns 2, the tools' exit status for bad
// arguments or input.
int toolError(const char* tool, const std::string& message, const char* usage);

// A positive integer option (e.g. "--stride"); false with *error naming it otherwise.
bool positiveInt(const ToolArgs& args, const std::string& option, int fallback, int* out,
                 std::string* error);

}  // namespace core
}  // namespace coral_introspection
