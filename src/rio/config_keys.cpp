#include "coral_introspection/rio/config_keys.hpp"

#include <algorithm>
#include <set>

namespace coral_introspection {
namespace rio {

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

std::string keyText(const YAML::Node& key) { return key.as<std::string>("<non-scalar key>"); }

}  // namespace

std::string didYouMean(const std::string& name, const std::vector<std::string>& valid) {
  const std::string leaf = leafOf(name), group = groupOf(name);
  const std::size_t limit = std::max<std::size_t>(2, leaf.size() / 3);
  std::size_t best_score = limit + 1;
  std::string best;
  for (const std::string& c : valid) {
    const std::size_t score = editDistance(leaf, leafOf(c)) + (groupOf(c) != group ? 1 : 0);
    if (score < best_score && score < leaf.size()) best_score = score, best = c;
  }
  return best.empty() ? "" : " (did you mean " + best + "?)";
}

std::string unknownKeys(const YAML::Node& root, const std::vector<std::string>& valid,
                        const std::vector<std::string>& other_groups, const std::string& prefix) {
  if (!root.IsDefined() || !root.IsMap()) return "";  // (a const [] of a missing key: invalid)
  std::set<std::string> groups, top, paths(valid.begin(), valid.end());
  for (const std::string& v : valid) {
    if (groupOf(v).empty())
      top.insert(v);
    else
      groups.insert(groupOf(v));
  }
  // A misspelt top-level name is compared with the groups, the top-level keys and every
  // key (a key written without its group).
  std::vector<std::string> top_candidates(groups.begin(), groups.end());
  top_candidates.insert(top_candidates.end(), top.begin(), top.end());
  top_candidates.insert(top_candidates.end(), other_groups.begin(), other_groups.end());
  top_candidates.insert(top_candidates.end(), valid.begin(), valid.end());
  std::string out;
  auto add = [&out](const std::string& m) { out += (out.empty() ? "" : "; ") + m; };
  for (auto it = root.begin(); it != root.end(); ++it) {
    const std::string key = keyText(it->first);
    if (std::find(other_groups.begin(), other_groups.end(), key) != other_groups.end() ||
        top.count(key))
      continue;
    if (!groups.count(key)) {
      add(std::string("unknown ") + (it->second.IsMap() ? "group " : "parameter ") + prefix + key +
          didYouMean(key, top_candidates));
      continue;
    }
    if (it->second.IsNull()) continue;  // an empty group: every setting keeps its default
    if (!it->second.IsMap()) {
      add("group " + prefix + key + " must be a map of parameters");
      continue;
    }
    for (auto jt = it->second.begin(); jt != it->second.end(); ++jt) {
      const std::string path = key + "/" + keyText(jt->first);
      if (!paths.count(path)) add("unknown parameter " + prefix + path + didYouMean(path, valid));
    }
  }
  return out;
}

}  // namespace rio
}  // namespace coral_introspection
