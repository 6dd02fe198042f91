// One ROS-free parameter tree for every configuration of the package: CoralNodelet and
// RioNodelet (built from the parameter server's XmlRpc tree by the ROS adapter), the preset
// files of coral_check / coral_train / ... and the rio YAML files (built from YAML by
// config/yaml_tree.hpp). A tree is parsed once and then read by the loader of one config
// struct through typed getters; everything the loader never asked for is an error naming
// the nearest valid name, never a silently ignored setting (a misspelt `coarl:` once left
// every CorAl setting at its default and turned a 0.5 m error into "aligned").
//
// Paths are "key" or "group/key" (groups may nest). Messages name the source of a value as
// "file:line: " when the tree was read from a YAML file.
#pragma once

#include <cstdint>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace coral_introspection {
namespace config {

// A bool, integer, floating-point number or string: what a YAML plain or quoted scalar or
// an XmlRpc scalar holds.
struct Scalar {
  enum class Type { kBool, kInt, kDouble, kString };
  Type type = Type::kString;
  bool b = false;
  std::int64_t i = 0;
  double d = 0.0;
  std::string s;

  static Scalar ofBool(bool v);
  static Scalar ofInt(std::int64_t v);
  static Scalar ofDouble(double v);
  static Scalar ofString(std::string v);
  std::string text() const;  // the value as written, for messages
};

// One node: a group of named nodes (in the order given), a scalar, a list of scalars, or
// nothing (a YAML key without a value: an empty group where a group is read, an error where
// a value is read).
struct ParamNode {
  enum class Kind { kGroup, kScalar, kList, kNull };
  Kind kind = Kind::kGroup;
  Scalar scalar;
  std::vector<Scalar> list;
  std::vector<std::pair<std::string, ParamNode>> children;
  std::string where;  // "file:line" of the key, "" when unknown (parameter server, code)

  const ParamNode* child(const std::string& name) const;
  ParamNode* child(const std::string& name);
  std::string describe() const;  // "'big'", "a group", "a list", "no value": for messages
};

class ParamTree {
 public:
  ParamTree() = default;  // empty: every setting keeps its default
  // source: the file(s) the tree was read from ("" when none); name_prefix: what messages
  // put before every path (a subtree's "group/").
  explicit ParamTree(ParamNode root, std::string source = "", std::string name_prefix = "");

  const ParamNode& root() const { return root_; }
  bool empty() const { return root_.children.empty(); }
  // "file: " (or "preset.yaml + classifier.yaml: " after a merge) for a loader's own
  // messages about the whole tree (a failed validate()), "" when not from a file. Messages
  // of the tree itself already carry "file:line: ".
  std::string origin() const { return source_.empty() ? "" : source_ + ": "; }

  // Puts `value` at path, creating the groups on the way (a scalar in the way is replaced).
  void set(const std::string& path, ParamNode value);
  // Every value of `overlay` replaces the one at its path here; groups merge key by key (a
  // classifier file loaded over a preset replaces only its classifier/ values, as roslaunch's
  // <rosparam command="load"> does). Values equal in both files are fine: no duplicate there.
  void merge(const ParamTree& overlay);
  // The group at `group` as a tree of its own whose messages name its keys "group/key";
  // absent or without a value: an empty tree. False with *error when it is not a group.
  bool subtree(const std::string& group, ParamTree* out, std::string* error) const;

  // ---- reading (the loader of a config struct) ---------------------------------------------
  // Each getter records `path` as a valid name (also when it is absent) and leaves *out
  // unchanged when it is absent. False, with error() naming the path, its source and the
  // value, when it has the wrong type: a double takes an integer, an int takes an integral
  // number, a bool only true/false (yes/no/on/off in YAML), a string only a string.
  bool get(const std::string& path, double* out);
  bool get(const std::string& path, int* out);
  bool get(const std::string& path, bool* out);
  bool get(const std::string& path, std::string* out);
  // A list of exactly n numbers; n = 0: a list of one number or more.
  bool getList(const std::string& path, std::size_t n, std::vector<double>* out);
  // A string restricted to `allowed`; *index: position in allowed (its entry the default).
  bool getChoice(const std::string& path, const std::vector<std::string>& allowed, int* index);
  // True when a value (or a group) is at path. Not a read.
  bool has(const std::string& path) const;
  // Names a key or a whole group read by someone else (the rio adapters' `ros` group, the
  // keys dynamic_reconfigure keeps in a nodelet's namespace): never unknown.
  void accept(const std::string& path);
  // Stores message in error() and returns false (a loader's own checks).
  bool fail(const std::string& message);
  const std::string& error() const { return error_; }
  // Every path a getter asked for, sorted.
  std::vector<std::string> readPaths() const { return {read_.begin(), read_.end()}; }

  // After reading: every group or key that no getter asked for and nobody accepted, in
  // document order, each with the nearest valid name, e.g.
  //   "unknown group coarl (did you mean coral?)"
  //   "unknown key coral/radus (did you mean radius?)"
  //   "unknown key window_size (did you mean solver/window_size?)"
  // prefixed "file:line: " when known.
  std::vector<std::string> unknownKeys() const;
  // The same "; "-joined, "" when there are none.
  std::string unknownKeysMessage() const;

 private:
  const ParamNode* find(const std::string& path) const;
  // The node at path for a getter (records the read); nullptr when absent or on an error
  // (error_ set: a value where a group is needed).
  const ParamNode* lookup(const std::string& path, bool* ok);
  bool typeError(const std::string& path, const ParamNode& n, const char* expected);
  // The scalar at path when it has `type`; nullptr when absent or (*ok false) of another type.
  const Scalar* scalarOf(const std::string& path, Scalar::Type type, const char* expected,
                         bool* ok);
  bool isAccepted(const std::string& path) const;
  bool isReadGroup(const std::string& path) const;
  void collectUnknown(const ParamNode& group, const std::string& prefix,
                      std::vector<std::string>* out) const;
  std::string location(const ParamNode& n) const;

  ParamNode root_;
  std::string source_;
  std::string prefix_;  // "ros/" for a subtree: messages name the full path
  std::set<std::string> read_, accepted_;
  std::string error_;
};

// " (did you mean X?)" for the entry of `valid` nearest to `name`, "" when none is close.
// Names are "key" or "group/key": the edit distance of the part after the first '/' must be
// at most max(2, its length / 3), and a candidate in another group costs one more, so a key
// put into the wrong group (or written without its group) finds its group. Shared by every
// loader and by rio_offline's topic check.
std::string didYouMean(const std::string& name, const std::vector<std::string>& valid);
// The nearest entry itself, "" when none is close (same rule).
std::string nearestName(const std::string& name, const std::vector<std::string>& valid);

}  // namespace config
}  // namespace coral_introspection
