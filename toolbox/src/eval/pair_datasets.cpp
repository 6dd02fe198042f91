#include "coral_introspection/eval/pair_datasets.hpp"

#include <fstream>
#include <sstream>

#include "coral_introspection/coral/validation.hpp"
#include "coral_introspection/eval/cloud_io.hpp"

namespace coral_introspection {
namespace eval {

bool parseDatasetSpec(const std::string& text, DatasetSpec* spec, std::string* error) {
  std::string rest = text;
  spec->name.clear();
  const std::size_t eq = rest.find('='), colon = rest.find(':');
  if (eq != std::string::npos && eq < colon) {
    spec->name = rest.substr(0, eq);
    rest = rest.substr(eq + 1);
  }
  const std::size_t c = rest.find(':');
  if (c == std::string::npos || c + 1 >= rest.size())
    return coral::fail(error, "data set '" + text + "' is not [name=]kind:path");
  spec->kind = rest.substr(0, c);
  spec->path = rest.substr(c + 1);
  for (const char* k : {"oxford", "keyframes", "carmen", "cloudlist", "bag"})
    if (spec->kind == k) {
      if (spec->name.empty()) {  // last path component without its extensions
        std::string p = spec->path;
        while (p.size() > 1 && p.back() == '/') p.pop_back();
        spec->name = p.substr(p.find_last_of('/') + 1);
        spec->name = spec->name.substr(0, spec->name.find('.'));
      }
      return true;
    }
  return coral::fail(error, "data set '" + text + "': unknown kind '" + spec->kind +
                                "' (oxford, keyframes, carmen, cloudlist, bag)");
}

namespace {

std::string folderOf(const std::string& path) {
  const std::size_t s = path.find_last_of('/');
  return s == std::string::npos ? "." : path.substr(0, s);
}

bool isNumber(const std::string& s) {
  std::istringstream ss(s);
  double v;
  return static_cast<bool>(ss >> v);
}

// Names in the first column of a cloud list; a first line whose second field is not a
// number is a header.
bool readCloudList(const std::string& path, std::vector<std::string>* names, std::string* error) {
  std::ifstream in(path);
  if (!in) return coral::fail(error, "cannot open " + path);
  std::string line;
  for (std::size_t n = 1; std::getline(in, line); ++n) {
    std::istringstream ls(line);
    std::string name, second;
    if (!std::getline(ls, name, ',') || !std::getline(ls, second, ',')) continue;
    if (n == 1 && !isNumber(second)) continue;
    names->push_back(name.substr(name.find_first_not_of(" \t")));
  }
  return names->size() >= 2 ? true : coral::fail(error, path + ": fewer than two clouds listed");
}

bool loadCloudList(const std::string& path, const Progress& progress, PairDataset* out,
                   std::string* error) {
  std::vector<std::string> names;
  if (!readCloudList(path, &names, error)) return false;
  coral::Isometries poses(names.size());
  for (std::size_t i = 0; i < names.size(); ++i) {
    LoadedCloud c;
    if (!readCsvPose(path, names[i], &poses[i], error) ||
        !loadCloud(folderOf(path) + "/" + names[i], &c, error))
      return false;
    TrainingScan s;
    s.stamp = static_cast<double>(i);
    s.scan.points = std::move(c.points);
    out->scans.push_back(std::move(s));
    if (progress) progress(i + 1, names.size());
  }
  out->pairs = makePairs(poses, 0.0);
  return true;
}

}  // namespace

bool loadPairDataset(const DatasetSpec& spec, const DatasetOptions& o, const Progress& progress,
                     PairDataset* out, std::string* error) {
  *out = PairDataset();
  out->name = spec.name;
  coral::Isometries poses;
  std::string what = "consecutive";
  if (spec.kind == "oxford") {
    OxfordDataset ds;
    if (!ds.load(spec.path, error) ||
        !loadOxfordTrainingScans(ds, o.oxford, progress, &out->scans, &poses, error))
      return false;
  } else if (spec.kind == "keyframes") {
    if (!loadKeyframeSequence(spec.path, o.keyframes, progress, &out->scans, &poses, error))
      return false;
  } else if (spec.kind == "carmen") {
    std::vector<CarmenLaserScan> log;
    std::vector<Relation> relations;
    int unmatched = 0;
    if (!readCarmenLog(spec.path, &log, error) ||
        !readRelations(relationsPath(spec.path), &relations, error) ||
        !relationPairs(log, relations, o.laser, &out->scans, &out->pairs, &unmatched, error))
      return false;
    std::ostringstream s;
    s << out->scans.size() << " scans of " << log.size() << ", " << out->pairs.size()
      << " ground-truth relations"
      << (unmatched ? " (" + std::to_string(unmatched) + " unmatched)" : "");
    out->summary = s.str();
    return true;
  } else if (spec.kind == "cloudlist") {
    if (!loadCloudList(spec.path, progress, out, error)) return false;
    out->summary = std::to_string(out->scans.size()) + " clouds, " +
                   std::to_string(out->pairs.size()) + " consecutive pair(s) (listed poses)";
    return true;
  } else {
    return coral::fail(error,
                       "data set kind '" + spec.kind + "' needs the ROS tooling (coral_train)");
  }
  out->pairs = makePairs(poses, o.spacing);
  if (o.spacing > 0.0) what = "spacing >= " + std::to_string(o.spacing) + " m";
  out->summary = std::to_string(out->scans.size()) + " scans, " +
                 std::to_string(out->pairs.size()) + " pairs (" + what + ")";
  return true;
}

}  // namespace eval
}  // namespace coral_introspection
