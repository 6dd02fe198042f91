#include "coral_introspection/eval/sample_csv.hpp"

#include <algorithm>
#include <fstream>
#include <map>
#include <set>

#include "coral_introspection/config/text_fields.hpp"
#include "coral_introspection/coral/validation.hpp"

namespace coral_introspection {
namespace eval {

namespace {

bool number(const std::string& s, double* v) {
  try {
    std::size_t used = 0;
    *v = std::stod(s, &used);  // also "nan", "-nan", "inf"
    return used == s.size();
  } catch (const std::exception&) {
    return false;
  }
}

}  // namespace

bool readSamplesCsv(const std::string& path, SampleSet* set, std::string* error) {
  std::ifstream in(path);
  if (!in) return coral::fail(error, "cannot open " + path);
  std::string line;
  if (!std::getline(in, line)) return coral::fail(error, path + ": empty file");
  const std::vector<std::string> head = config::splitFields(line, ',');
  const std::vector<std::string> fixed = {"pair", "stamp_a", "stamp_b", "offset", "dx",
                                          "dy",   "dyaw",    "group",   "label"};
  if (head.size() < fixed.size() || !std::equal(fixed.begin(), fixed.end(), head.begin()))
    return coral::fail(error,
                       path + ": not a samples file (header starts with " + head.front() + ")");
  std::size_t first_feature = fixed.size();
  const bool with_dataset = head.size() > fixed.size() && head[fixed.size()] == "dataset";
  if (with_dataset) ++first_feature;
  *set = SampleSet();
  std::vector<int> method_of;  // column -> method index
  for (std::size_t c = first_feature; c < head.size(); ++c) {
    const std::size_t slash = head[c].find('/');
    if (slash == std::string::npos) return coral::fail(error, path + ": column '" + head[c] + "'");
    const std::string m = head[c].substr(0, slash);
    if (set->methods.empty() || set->methods.back().name != m) set->methods.push_back({m, {}});
    set->methods.back().feature_names.push_back(head[c].substr(slash + 1));
    method_of.push_back(static_cast<int>(set->methods.size()) - 1);
  }
  for (std::size_t n = 2; std::getline(in, line); ++n) {
    if (line.empty()) continue;
    const std::vector<std::string> f = config::splitFields(line, ',');
    const std::string where = path + ":" + std::to_string(n);
    if (f.size() != head.size()) return coral::fail(error, where + ": wrong number of columns");
    Sample s;
    double v[6];
    for (int i : {0, 1, 2, 4, 5, 6})
      if (!number(f[i], &v[i < 3 ? i : i - 1])) return coral::fail(error, where + ": bad number");
    double label = 0.0;
    if (!number(f[8], &label)) return coral::fail(error, where + ": bad label");
    s.pair = static_cast<int>(v[0]);
    s.stamp_a = v[1];
    s.stamp_b = v[2];
    s.offset = f[3];
    s.dx = v[3];
    s.dy = v[4];
    s.dyaw = v[5];
    s.group = f[7];
    s.label = static_cast<int>(label);
    if (with_dataset) s.dataset = f[9];
    s.features.resize(set->methods.size());
    for (std::size_t c = first_feature; c < f.size(); ++c) {
      double x = 0.0;
      if (!number(f[c], &x)) return coral::fail(error, where + ": bad feature '" + f[c] + "'");
      s.features[method_of[c - first_feature]].push_back(x);
    }
    if (!s.group.empty() &&
        std::find(set->groups.begin(), set->groups.end(), s.group) == set->groups.end())
      set->groups.push_back(s.group);
    set->samples.push_back(std::move(s));
  }
  return true;
}

bool mergeSampleSets(SampleSet* into, const SampleSet& part, std::string* error) {
  if (into->methods.empty() && into->samples.empty()) {
    into->methods = part.methods;
  } else {
    bool same = into->methods.size() == part.methods.size();
    for (std::size_t m = 0; same && m < part.methods.size(); ++m)
      same = into->methods[m].name == part.methods[m].name &&
             into->methods[m].feature_names == part.methods[m].feature_names;
    if (!same)
      return coral::fail(error, "sample sets with different methods/features cannot be merged");
  }
  std::set<std::pair<std::string, int>> have;
  for (const Sample& s : into->samples) have.insert({s.dataset, s.pair});
  for (const Sample& s : part.samples)
    if (have.count({s.dataset, s.pair}))
      return coral::fail(error, "pair " + std::to_string(s.pair) + " of data set '" + s.dataset +
                                    "' occurs in two sample files");
  for (const std::string& g : part.groups)
    if (std::find(into->groups.begin(), into->groups.end(), g) == into->groups.end())
      into->groups.push_back(g);
  std::map<std::string, int> rank;  // data set -> order of first appearance
  into->samples.insert(into->samples.end(), part.samples.begin(), part.samples.end());
  for (const Sample& s : into->samples) rank.emplace(s.dataset, static_cast<int>(rank.size()));
  std::stable_sort(into->samples.begin(), into->samples.end(),
                   [&](const Sample& a, const Sample& b) {
                     const int ra = rank.at(a.dataset), rb = rank.at(b.dataset);
                     return ra != rb ? ra < rb : a.pair < b.pair;
                   });
  return true;
}

}  // namespace eval
}  // namespace coral_introspection
