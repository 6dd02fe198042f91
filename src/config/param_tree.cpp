#include "coral_introspection/config/param_tree.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace coral_introspection {
namespace config {

// ---- values ------------------------------------------------------------------------------

// Aggregate initialisation in member order: type, b, i, d, s.
Scalar Scalar::ofBool(bool v) { return {Type::kBool, v, 0, 0.0, {}}; }
Scalar Scalar::ofInt(std::int64_t v) { return {Type::kInt, false, v, 0.0, {}}; }
Scalar Scalar::ofDouble(double v) { return {Type::kDouble, false, 0, v, {}}; }
Scalar Scalar::ofString(std::string v) { return {Type::kString, false, 0, 0.0, std::move(v)}; }

std::string Scalar::text() const {
  switch (type) {
    case Type::kBool:
      return b ? "true" : "false";
    case Type::kInt:
      return std::to_string(i);
    case Type::kDouble: {
      std::ostringstream o;
      o << d;
      return o.str();
    }
    case Type::kString:
      break;
  }
  return s;
}

const ParamNode* ParamNode::child(const std::string& name) const {
  for (const auto& [key, node] : children)
    if (key == name) return &node;
  return nullptr;
}

ParamNode* ParamNode::child(const std::string& name) {
  return const_cast<ParamNode*>(static_cast<const ParamNode&>(*this).child(name));
}

std::string ParamNode::describe() const {
  switch (kind) {
    case Kind::kGroup:
      return "a group";
    case Kind::kList:
      return "a list";
    case Kind::kNull:
      return "no value";
    case Kind::kScalar:
      break;
  }
  return "'" + scalar.text() + "'";
}

// ---- building ------------------------------------------------------------------------------

namespace {

// "a/b/c" -> {"a", "b", "c"}
std::vector<std::string> split(const std::string& path) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (true) {
    const std::size_t slash = path.find('/', start);
    parts.push_back(path.substr(start, slash == std::string::npos ? slash : slash - start));
    if (slash == std::string::npos) return parts;
    start = slash + 1;
  }
}

std::string join(const std::string& prefix, const std::string& key) {
  return prefix.empty() ? key : prefix + "/" + key;
}

void mergeInto(const ParamNode& overlay, ParamNode* base) {
  for (const auto& [key, node] : overlay.children) {
    ParamNode* b = base->child(key);
    if (b == nullptr)
      base->children.emplace_back(key, node);
    else if (node.kind == ParamNode::Kind::kGroup && b->kind == ParamNode::Kind::kGroup)
      mergeInto(node, b);
    else
      *b = node;
  }
}

}  // namespace

ParamTree::ParamTree(ParamNode root, std::string source, std::string name_prefix)
    : root_(std::move(root)), source_(std::move(source)), prefix_(std::move(name_prefix)) {}

void ParamTree::set(const std::string& path, ParamNode value) {
  ParamNode* n = &root_;
  for (const std::string& key : split(path)) {
    if (n->kind != ParamNode::Kind::kGroup) *n = ParamNode();
    ParamNode* c = n->child(key);
    if (c == nullptr) {
      n->children.emplace_back(key, ParamNode());
      c = &n->children.back().second;
    }
    n = c;
  }
  *n = std::move(value);
}

void ParamTree::merge(const ParamTree& overlay) {
  mergeInto(overlay.root_, &root_);
  if (!overlay.source_.empty())
    source_ = source_.empty() ? overlay.source_ : source_ + " + " + overlay.source_;
}

bool ParamTree::subtree(const std::string& group, ParamTree* out, std::string* error) const {
  const ParamNode* n = find(group);
  if (n != nullptr && n->kind != ParamNode::Kind::kGroup && n->kind != ParamNode::Kind::kNull) {
    if (error) *error = location(*n) + "group " + prefix_ + group + " must be a map of parameters";
    return false;
  }
  *out = ParamTree(n != nullptr && n->kind == ParamNode::Kind::kGroup ? *n : ParamNode(), source_,
                   prefix_ + group + "/");
  return true;
}

// ---- reading -------------------------------------------------------------------------------

const ParamNode* ParamTree::find(const std::string& path) const {
  const ParamNode* n = &root_;
  for (const std::string& key : split(path)) {
    if (n->kind != ParamNode::Kind::kGroup) return nullptr;
    n = n->child(key);
    if (n == nullptr) return nullptr;
  }
  return n;
}

bool ParamTree::has(const std::string& path) const { return find(path) != nullptr; }

const ParamNode* ParamTree::lookup(const std::string& path, bool* ok) {
  read_.insert(path);
  *ok = true;
  const ParamNode* n = &root_;
  std::string at;
  for (const std::string& key : split(path)) {
    if (n->kind == ParamNode::Kind::kNull) return nullptr;  // a group without keys
    if (n->kind != ParamNode::Kind::kGroup) {
      // "solver: 8" where solver/window_size is read: not a value to ignore.
      *ok = fail(location(*n) + "group " + prefix_ + at + " must be a map of parameters");
      return nullptr;
    }
    n = n->child(key);
    if (n == nullptr) return nullptr;
    at = join(at, key);
  }
  if (n->kind == ParamNode::Kind::kNull) {
    *ok = fail(location(*n) + "parameter " + prefix_ + path +
               " has no value (give one or remove the key)");
    return nullptr;
  }
  return n;
}

std::string ParamTree::location(const ParamNode& n) const {
  return n.where.empty() ? "" : n.where + ": ";
}

bool ParamTree::typeError(const std::string& path, const ParamNode& n, const char* expected) {
  return fail(location(n) + "parameter " + prefix_ + path + " must be " + expected + " (got " +
              n.describe() + ")");
}

bool ParamTree::fail(const std::string& message) {
  error_ = message;
  return false;
}

bool ParamTree::get(const std::string& path, double* out) {
  bool ok = true;
  const ParamNode* n = lookup(path, &ok);
  if (n == nullptr) return ok;
  if (n->kind == ParamNode::Kind::kScalar && n->scalar.type == Scalar::Type::kDouble)
    *out = n->scalar.d;
  else if (n->kind == ParamNode::Kind::kScalar && n->scalar.type == Scalar::Type::kInt)
    *out = static_cast<double>(n->scalar.i);
  else
    return typeError(path, *n, "a number");
  return true;
}

bool ParamTree::get(const std::string& path, int* out) {
  bool ok = true;
  const ParamNode* n = lookup(path, &ok);
  if (n == nullptr) return ok;
  const Scalar& s = n->scalar;
  constexpr double kLimit = 2147483647.0;
  if (n->kind == ParamNode::Kind::kScalar && s.type == Scalar::Type::kInt && s.i >= -kLimit &&
      s.i <= kLimit) {
    *out = static_cast<int>(s.i);
    return true;
  }
  // 12.0 is an integer (XmlRpc and YAML writers may print one so), 12.5 is not.
  if (n->kind == ParamNode::Kind::kScalar && s.type == Scalar::Type::kDouble &&
      s.d == std::round(s.d) && std::abs(s.d) < 1e9) {
    *out = static_cast<int>(s.d);
    return true;
  }
  return typeError(path, *n, "an integer");
}

const Scalar* ParamTree::scalarOf(const std::string& path, Scalar::Type type, const char* expected,
                                  bool* ok) {
  const ParamNode* n = lookup(path, ok);
  if (n == nullptr) return nullptr;
  if (n->kind == ParamNode::Kind::kScalar && n->scalar.type == type) return &n->scalar;
  *ok = typeError(path, *n, expected);
  return nullptr;
}

bool ParamTree::get(const std::string& path, bool* out) {
  bool ok = true;
  if (const Scalar* s = scalarOf(path, Scalar::Type::kBool, "a bool (true/false)", &ok))
    *out = s->b;
  return ok;
}

bool ParamTree::get(const std::string& path, std::string* out) {
  bool ok = true;
  if (const Scalar* s = scalarOf(path, Scalar::Type::kString, "a string", &ok)) *out = s->s;
  return ok;
}

bool ParamTree::getList(const std::string& path, std::size_t n, std::vector<double>* out) {
  bool ok = true;
  const ParamNode* node = lookup(path, &ok);
  if (node == nullptr) return ok;
  const std::string expected =
      n == 0 ? "a list of one number or more" : "a list of " + std::to_string(n) + " numbers";
  const bool numbers = std::all_of(node->list.begin(), node->list.end(), [](const Scalar& s) {
    return s.type == Scalar::Type::kInt || s.type == Scalar::Type::kDouble;
  });
  const bool size_ok = n == 0 ? !node->list.empty() : node->list.size() == n;
  if (node->kind != ParamNode::Kind::kList || !size_ok || !numbers)
    return typeError(path, *node, expected.c_str());
  out->clear();
  for (const Scalar& s : node->list)
    out->push_back(s.type == Scalar::Type::kInt ? static_cast<double>(s.i) : s.d);
  return true;
}

bool ParamTree::getChoice(const std::string& path, const std::vector<std::string>& allowed,
                          int* index) {
  std::string s = allowed[*index];
  if (!get(path, &s)) return false;
  for (std::size_t i = 0; i < allowed.size(); ++i)
    if (s == allowed[i]) {
      *index = static_cast<int>(i);
      return true;
    }
  std::string e =
      location(*find(path)) + "parameter " + prefix_ + path + " = '" + s + "' is not one of:";
  for (const auto& a : allowed) e += " " + a;
  return fail(e);
}

void ParamTree::accept(const std::string& path) { accepted_.insert(path); }

// ---- unknown keys --------------------------------------------------------------------------

bool ParamTree::isAccepted(const std::string& path) const {
  for (const std::string& a : accepted_)
    if (path == a || path.rfind(a + "/", 0) == 0) return true;
  return false;
}

bool ParamTree::isReadGroup(const std::string& path) const {
  const auto it = read_.lower_bound(path + "/");
  return it != read_.end() && it->rfind(path + "/", 0) == 0;
}

void ParamTree::collectUnknown(const ParamNode& group, const std::string& prefix,
                               std::vector<std::string>* out) const {
  for (const auto& [key, node] : group.children) {
    const std::string path = join(prefix, key);
    if (read_.count(path) || isAccepted(path)) continue;
    if (isReadGroup(path)) {
      if (node.kind == ParamNode::Kind::kGroup) collectUnknown(node, path, out);
      continue;  // a read group given as a value was reported by the getter
    }
    // Candidates: every key read, and at the top level also the groups and accepted names
    // (a misspelt group, or a key written without its group).
    std::vector<std::string> valid(read_.begin(), read_.end());
    if (prefix.empty()) {
      for (const std::string& r : read_)
        if (r.find('/') != std::string::npos) valid.push_back(r.substr(0, r.find('/')));
      valid.insert(valid.end(), accepted_.begin(), accepted_.end());
    }
    std::string best = nearestName(path, valid);
    // Within the same group the key alone reads best ("did you mean radius?").
    const std::size_t cut = prefix.size() + 1;
    if (!prefix.empty() && best.rfind(prefix + "/", 0) == 0 &&
        best.find('/', cut) == std::string::npos)
      best = best.substr(cut);
    out->push_back(location(node) + "unknown " +
                   (node.kind == ParamNode::Kind::kGroup ? "group " : "key ") + prefix_ + path +
                   (best.empty() ? "" : " (did you mean " + best + "?)"));
  }
}

std::vector<std::string> ParamTree::unknownKeys() const {
  std::vector<std::string> out;
  collectUnknown(root_, "", &out);
  return out;
}

std::string ParamTree::unknownKeysMessage() const {
  std::string out;
  for (const std::string& m : unknownKeys()) out += (out.empty() ? "" : "; ") + m;
  return out;
}

// ---- suggestions ---------------------------------------------------------------------------

namespace {

std::size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] != b[j - 1] ? 1 : 0)});
      diag = up;
    }
  }
  return row[b.size()];
}

std::string groupOf(const std::string& path) {
  const std::size_t slash = path.find('/');
  return slash == std::string::npos ? "" : path.substr(0, slash);
}

std::string leafOf(const std::string& path) { return path.substr(path.find('/') + 1); }

}  // namespace

std::string nearestName(const std::string& name, const std::vector<std::string>& valid) {
  const std::string leaf = leafOf(name), group = groupOf(name);
  const std::size_t limit = std::max<std::size_t>(2, leaf.size() / 3);
  std::size_t best_score = limit + 1;
  std::string best;
  for (const std::string& c : valid) {
    std::size_t score = editDistance(leaf, leafOf(c)) + (groupOf(c) != group ? 1 : 0);
    // The whole name too, '/' written as '_' (`coral_radius` for coral/radius): by the leaf
    // alone that was nearest to registration/normal_radius.
    std::string flat = c;
    std::replace(flat.begin(), flat.end(), '/', '_');
    score = std::min(score, editDistance(name, flat));
    if (score < best_score && score < leaf.size()) best_score = score, best = c;
  }
  return best;
}

std::string didYouMean(const std::string& name, const std::vector<std::string>& valid) {
  const std::string best = nearestName(name, valid);
  return best.empty() ? "" : " (did you mean " + best + "?)";
}

}  // namespace config
}  // namespace coral_introspection
