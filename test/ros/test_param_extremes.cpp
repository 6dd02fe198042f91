// Every parameter CoralNodelet reads (nodeParameterNames), set to 0, -1, +-1e12, NaN or inf
// over each point-cloud preset, either fails the load with a message, or gives a config whose
// stream and loop-closure verdicts on a synthetic pair return without throwing. A throw in a
// nodelet callback takes down every nodelet of the manager. free_space/bin_deg 0 once passed
// the load unvalidated and threw std::length_error in the free-space check (2026-12-06).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "coral_introspection/config/yaml_tree.hpp"
#include "coral_introspection/coral/verdict.hpp"
#include "coral_introspection/online/introspector.hpp"
#include "coral_introspection/ros/coral_params.hpp"
#include "support/source_dir.hpp"
#include "support/yard_pair.hpp"

namespace coral_introspection {
namespace {

// `path` (group/key or key) = value as a YAML document.
std::string yamlOf(const std::string& path, const std::string& value) {
  const std::size_t slash = path.find('/');
  if (slash == std::string::npos) return path + ": " + value + "\n";
  return path.substr(0, slash) + ":\n  " + path.substr(slash + 1) + ": " + value + "\n";
}

struct Tally {
  int refused = 0, judged = 0;
};

// The preset with each parameter at each extreme value; judged on `pair` when it loads.
Tally sweep(const std::string& preset, const test::YardPair& pair) {
  Tally t;
  const std::vector<std::string> values = {"0", "-1", "1.0e12", "-1.0e12", ".nan", ".inf"};
  for (const std::string& name : ros_adapters::nodeParameterNames())
    for (const std::string& value : values) {
      SCOPED_TRACE(preset + ": " + name + " = " + value);
      config::ParamTree tree, overlay;
      std::string err;
      if (!config::loadYamlFile(coral_test::sourceDir() + "/config/" + preset, &tree, &err) ||
          !config::parseYaml(yamlOf(name, value), &overlay, &err)) {
        ADD_FAILURE() << err;
        return t;
      }
      tree.merge(overlay);
      ros_adapters::NodeConfig c;
      if (!ros_adapters::loadNodeConfig(tree, &c, &err)) {
        EXPECT_FALSE(err.empty());  // refused, with the reason
        ++t.refused;
        continue;
      }
      ++t.judged;
      for (bool loop : {false, true}) {
        online::IntrospectorConfig o = c.online;
        if (loop) o.verdict = coral::loopClosureVerdict(o.verdict);
        EXPECT_NO_THROW(online::judgePair(pair.a, pair.b, pair.T_a_b, o, false)) << "loop " << loop;
      }
    }
  return t;
}

TEST(ParamExtremes, EveryNumberAtItsExtremesIsRefusedOrJudgedWithoutThrowing) {
  const Tally planar = sweep("lidar_2d.yaml", test::yardPair(1));
  const Tally rings = sweep("lidar_3d.yaml", test::yardPair(16));
  // Both outcomes occur (a sweep that loaded nothing, or refused nothing, tested nothing).
  for (const Tally& t : {planar, rings}) {
    EXPECT_GT(t.refused, 300);
    EXPECT_GT(t.judged, 50);
  }
  std::printf("lidar_2d: %d refused, %d judged; lidar_3d: %d refused, %d judged\n", planar.refused,
              planar.judged, rings.refused, rings.judged);
}

}  // namespace
}  // namespace coral_introspection
