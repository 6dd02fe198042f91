#include "coral_introspection/config/yaml_tree.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <map>

namespace coral_introspection {
namespace config {

namespace {

// A scalar typed as rosparam's YAML 1.1 loader types it (config/yaml_tree.hpp).
Scalar typed(const YAML::Node& n) {
  const std::string& s = n.Scalar();
  if (n.Tag() == "!") return Scalar::ofString(s);  // quoted: always a string
  std::string low = s;
  std::transform(low.begin(), low.end(), low.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  if (low == "true" || low == "yes" || low == "on") return Scalar::ofBool(true);
  if (low == "false" || low == "no" || low == "off") return Scalar::ofBool(false);
  const double inf = std::numeric_limits<double>::infinity();
  if (low == ".inf" || low == "+.inf") return Scalar::ofDouble(inf);
  if (low == "-.inf") return Scalar::ofDouble(-inf);
  if (low == ".nan") return Scalar::ofDouble(std::numeric_limits<double>::quiet_NaN());
  if (s.empty()) return Scalar::ofString(s);
  char* end = nullptr;
  errno = 0;
  const long long i = std::strtoll(s.c_str(), &end, 10);
  if (*end == '\0' && errno == 0) return Scalar::ofInt(i);
  const double d = std::strtod(s.c_str(), &end);
  const bool digit = std::any_of(s.begin(), s.end(), [](char c) { return std::isdigit(c); });
  if (*end == '\0' && digit) return Scalar::ofDouble(d);
  return Scalar::ofString(s);
}

class Builder {
 public:
  explicit Builder(std::string source) : source_(std::move(source)) {}

  // The node of `value`, whose key is at `key_mark`; path names it in messages.
  ParamNode build(const YAML::Node& value, const YAML::Mark& key_mark, const std::string& path) {
    ParamNode n;
    n.where = where(key_mark);
    switch (value.Type()) {
      case YAML::NodeType::Map:
        n.kind = ParamNode::Kind::kGroup;
        group(value, path, &n);
        break;
      case YAML::NodeType::Sequence:
        n.kind = ParamNode::Kind::kList;
        for (const YAML::Node& e : value) {
          if (!e.IsScalar()) {
            problem(located(key_mark) + "parameter " + path +
                    ": a list may hold only values (numbers, strings, bools)");
            break;
          }
          n.list.push_back(typed(e));
        }
        break;
      case YAML::NodeType::Scalar:
        n.kind = ParamNode::Kind::kScalar;
        n.scalar = typed(value);
        break;
      default:
        n.kind = ParamNode::Kind::kNull;
    }
    return n;
  }

  void group(const YAML::Node& map, const std::string& prefix, ParamNode* out) {
    std::map<std::string, int> line_of;  // key -> its first line (1-based)
    for (auto it = map.begin(); it != map.end(); ++it) {
      if (!it->first.IsScalar()) {
        problem(located(it->first.Mark()) + "a key must be a name (in " +
                (prefix.empty() ? "the top level" : prefix) + ")");
        continue;
      }
      const std::string key = it->first.Scalar();
      const std::string path = prefix.empty() ? key : prefix + "/" + key;
      const int line = it->first.Mark().line + 1;
      const auto [first, inserted] = line_of.emplace(key, line);
      if (!inserted) {
        problem((source_.empty() ? "" : source_ + ": ") + "duplicate key " + path + " (lines " +
                std::to_string(first->second) + " and " + std::to_string(line) + ")");
        continue;
      }
      out->children.emplace_back(key, build(it->second, it->first.Mark(), path));
    }
  }

  const std::string& problems() const { return problems_; }

 private:
  // "file:line" of a mark, "" without a file name or a position (a node made in code).
  std::string where(const YAML::Mark& m) const {
    if (source_.empty() || m.is_null()) return "";
    return source_ + ":" + std::to_string(m.line + 1);
  }
  std::string located(const YAML::Mark& m) const {
    const std::string w = where(m);
    return w.empty() ? "" : w + ": ";
  }
  void problem(const std::string& m) { problems_ += (problems_.empty() ? "" : "; ") + m; }

  std::string source_;
  std::string problems_;
};

}  // namespace

bool fromYaml(const YAML::Node& document, ParamTree* out, std::string* error,
              const std::string& source) {
  std::string dummy;
  if (error == nullptr) error = &dummy;
  if (!document.IsDefined() || document.IsNull()) {
    *out = ParamTree(ParamNode(), source);
    return true;
  }
  if (!document.IsMap()) {
    *error = (source.empty() ? "" : source + ": ") +
             "the top level must be a map of groups and parameters";
    return false;
  }
  Builder b(source);
  ParamNode root;
  b.group(document, "", &root);
  if (!b.problems().empty()) {
    *error = b.problems();
    return false;
  }
  *out = ParamTree(std::move(root), source);
  return true;
}

bool parseYaml(const std::string& text, ParamTree* out, std::string* error,
               const std::string& source) {
  YAML::Node doc;
  try {
    doc = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    // e.what() says "yaml-cpp: error at line L, column C: ..."
    if (error) *error = (source.empty() ? "" : source + ": ") + "YAML: " + e.what();
    return false;
  }
  return fromYaml(doc, out, error, source);
}

bool loadYamlFile(const std::string& path, ParamTree* out, std::string* error) {
  YAML::Node doc;
  try {
    doc = YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    if (error) *error = "cannot read " + path;
    return false;
  } catch (const YAML::Exception& e) {
    if (error) *error = path + ": YAML: " + e.what();
    return false;
  }
  return fromYaml(doc, out, error, path);
}

}  // namespace config
}  // namespace coral_introspection
