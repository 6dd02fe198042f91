#include "coral_introspection/eval/tool_args.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "coral_introspection/config/text_fields.hpp"

namespace coral_introspection {
namespace eval {

std::string ToolArgs::get(const std::string& option, const std::string& fallback) const {
  const auto it = values.find(option);
  return it == values.end() || it->second.empty() ? fallback : it->second.back();
}

std::vector<std::string> ToolArgs::all(const std::string& option) const {
  const auto it = values.find(option);
  return it == values.end() ? std::vector<std::string>() : it->second;
}

bool parseToolArgs(int argc, const char* const* argv, const std::vector<std::string>& options,
                   const std::vector<std::string>& flags, ToolArgs* out, std::string* error,
                   std::size_t max_positional) {
  *out = ToolArgs();
  auto known = [](const std::vector<std::string>& names, const std::string& n) {
    return std::find(names.begin(), names.end(), n) != names.end();
  };
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i];
    // "--name=value" is "--name value" (a value may hold '=' itself: split at the first).
    const std::size_t eq = arg.rfind("--", 0) == 0 ? arg.find('=') : std::string::npos;
    const bool inline_value = eq != std::string::npos;
    const std::string value = inline_value ? arg.substr(eq + 1) : "";
    if (inline_value) arg.resize(eq);
    if (!inline_value && (arg == "-h" || arg == "--help")) {
      out->help = true;
    } else if (known(flags, arg)) {
      if (inline_value) {
        *error = arg + " takes no value";
        return false;
      }
      out->flags.insert(arg);
    } else if (known(options, arg)) {
      if (inline_value) {
        out->values[arg].push_back(value);
      } else if (i + 1 < argc) {
        out->values[arg].push_back(argv[++i]);
      } else {
        *error = "missing value after " + arg;
        return false;
      }
    } else if (!arg.empty() && arg[0] != '-' && out->positional.size() < max_positional) {
      out->positional.push_back(arg);
    } else {
      *error = "unknown argument " + std::string(argv[i]);
      return false;
    }
  }
  return true;
}

int toolError(const char* tool, const std::string& message, const char* usage) {
  std::fprintf(stderr, "%s: %s\n%s\n", tool, message.c_str(), usage);
  return 2;
}

std::optional<int> readCommandLine(const char* tool, const char* usage, int argc,
                                   const char* const* argv, const std::vector<std::string>& options,
                                   const std::vector<std::string>& flags, ToolArgs* out,
                                   std::size_t max_positional) {
  std::string error;
  if (!parseToolArgs(argc, argv, options, flags, out, &error, max_positional))
    return toolError(tool, error, usage);
  if (out->help) {
    std::printf("%s\n", usage);
    return 0;
  }
  return std::nullopt;
}

bool numberOption(const ToolArgs& args, const std::string& option, double fallback, double* out,
                  std::string* error) {
  if (!args.has(option)) {
    *out = fallback;
    return true;
  }
  const std::string v = args.get(option);
  if (!config::parseFiniteNumber(v, out)) {
    *error = option + " must be a number (got '" + v + "')";
    return false;
  }
  return true;
}

bool numberListOption(const ToolArgs& args, const std::string& option,
                      const std::vector<double>& fallback, std::vector<double>* out,
                      std::string* error) {
  if (!args.has(option)) {
    *out = fallback;
    return true;
  }
  std::vector<double> list;
  for (const std::string& item : config::splitFields(args.get(option), ',')) {
    double x;
    if (!config::parseFiniteNumber(item, &x)) {
      *error = option + " must be numbers separated by commas (got '" + item + "')";
      return false;
    }
    list.push_back(x);
  }
  *out = list;
  return true;
}

namespace {
// v as a whole integer in [min, max] (config::parseInteger: no blanks, no '+'); false otherwise.
bool intIn(const std::string& v, int min, int max, int* out) {
  long n = 0;
  if (!config::parseInteger(v, min, max, &n)) return false;
  *out = static_cast<int>(n);
  return true;
}
}  // namespace

bool intOption(const ToolArgs& args, const std::string& option, int fallback, int min, int max,
               int* out, std::string* error) {
  if (!args.has(option)) {
    *out = fallback;
    return true;
  }
  const std::string v = args.get(option);
  if (intIn(v, min, max, out)) return true;
  *error = option + " must be an integer in [" + std::to_string(min) + ", " + std::to_string(max) +
           "] (got '" + v + "')";
  return false;
}

bool positiveInt(const ToolArgs& args, const std::string& option, int fallback, int* out,
                 std::string* error) {
  if (!args.has(option)) {
    *out = fallback;
    return true;
  }
  const std::string v = args.get(option);
  if (intIn(v, 1, 1000000000, out)) return true;
  *error = option + " must be a positive integer (got '" + v + "')";
  return false;
}

bool choiceOption(const ToolArgs& args, const std::string& option,
                  const std::vector<std::string>& choices, std::string* out, std::string* error) {
  *out = args.get(option, choices.empty() ? "" : choices.front());
  std::string list;
  for (std::size_t i = 0; i < choices.size(); ++i) {
    if (choices[i] == *out) return true;
    list += (i == 0 ? "" : i + 1 == choices.size() ? " or " : ", ") + choices[i];
  }
  *error = option + " must be " + list + " (got '" + *out + "')";
  return false;
}

}  // namespace eval
}  // namespace coral_introspection
