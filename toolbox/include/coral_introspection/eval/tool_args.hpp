// Command lines of the evaluation tools: "--name value" (or "--name=value") options, some
// repeatable, "--name" flags and, where a tool takes them, plain positional arguments; each
// checked against what the tool declares, so a misspelt option is an error with the usage,
// never silently ignored. Typed getters refuse malformed numbers the same way.
#pragma once

#include <cstddef>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace coral_introspection {
namespace eval {

struct ToolArgs {
  std::map<std::string, std::vector<std::string>> values;  // option -> its values, in order
  std::set<std::string> flags;                             // flags given
  std::vector<std::string> positional;                     // non-option arguments, in order
  bool help = false;                                       // -h or --help
  // The last value of `option`, or `fallback` when it was not given.
  std::string get(const std::string& option, const std::string& fallback = "") const;
  // Every value of a repeatable option, in order (empty when it was not given).
  std::vector<std::string> all(const std::string& option) const;
  bool has(const std::string& option) const { return values.count(option) > 0; }
  bool flag(const std::string& name) const { return flags.count(name) > 0; }
};

// `options`: names taking a value ("--config"); `flags`: names without one. An option given
// twice keeps both values (ToolArgs::values). Arguments not starting with '-' are positional,
// at most `max_positional` of them. False with *error on an unknown name, a missing value, a
// value given to a flag or one positional argument too many.
bool parseToolArgs(int argc, const char* const* argv, const std::vector<std::string>& options,
                   const std::vector<std::string>& flags, ToolArgs* out, std::string* error,
                   std::size_t max_positional = 0);

// "<tool>: <message>" and the usage on stderr; returns 2, the tools' exit status for bad
// arguments or input.
int toolError(const char* tool, const std::string& message, const char* usage);

// parseToolArgs for a tool's main(): the status main() returns now (0 after printing `usage`
// on stdout for -h / --help, 2 after toolError for a bad command line), or nothing when the
// tool goes on with *out:  if (const auto exit = readCommandLine(...)) return *exit;
std::optional<int> readCommandLine(const char* tool, const char* usage, int argc,
                                   const char* const* argv, const std::vector<std::string>& options,
                                   const std::vector<std::string>& flags, ToolArgs* out,
                                   std::size_t max_positional = 0);

// Typed options: *out = fallback when the option is not given, else its (last) value; false
// with *error naming the option when the whole value is not such a number.
// A finite number (strtod syntax, e.g. "0.5", "-2", "1e-4").
bool numberOption(const ToolArgs& args, const std::string& option, double fallback, double* out,
                  std::string* error);
// Comma-separated finite numbers, each as numberOption's (e.g. "1.5,2.5,3").
bool numberListOption(const ToolArgs& args, const std::string& option,
                      const std::vector<double>& fallback, std::vector<double>* out,
                      std::string* error);
// An integer in [min, max].
bool intOption(const ToolArgs& args, const std::string& option, int fallback, int min, int max,
               int* out, std::string* error);
// An integer in [1, 10^9] (e.g. "--stride").
bool positiveInt(const ToolArgs& args, const std::string& option, int fallback, int* out,
                 std::string* error);
// One of `choices` (the first when the option is not given), e.g. "--rows" all|even|odd.
bool choiceOption(const ToolArgs& args, const std::string& option,
                  const std::vector<std::string>& choices, std::string* out, std::string* error);

}  // namespace eval
}  // namespace coral_introspection
