// The parameter tree every config loader reads (config/param_tree.hpp): YAML typing, typed
// getters, and the messages for the mistakes a user makes in a preset (a misspelt group or
// key, a group given twice, a value of the wrong type), with and without a file name.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "coral_introspection/config/yaml_tree.hpp"
#include "support/test_data.hpp"

namespace config = coral_introspection::config;

namespace {

config::ParamTree parse(const std::string& yaml, const std::string& source = "") {
  config::ParamTree t;
  std::string err;
  EXPECT_TRUE(config::parseYaml(yaml, &t, &err, source)) << err;
  return t;
}

std::string parseError(const std::string& yaml, const std::string& source = "") {
  config::ParamTree t;
  std::string err;
  EXPECT_FALSE(config::parseYaml(yaml, &t, &err, source));
  return err;
}

// What a loader of coral/radius, coral/min_neighbours and rip/k leaves unknown in `t`.
std::string unknownAfterReading(config::ParamTree t) {
  double radius = 0.3;
  int n = 0;
  EXPECT_TRUE(t.get("coral/radius", &radius) && t.get("coral/min_neighbours", &n) &&
              t.get("rip/k", &n))
      << t.error();
  return t.unknownKeysMessage();
}

}  // namespace

TEST(ParamTree, MisspeltGroupNamesTheNearestGroup) {
  EXPECT_EQ(unknownAfterReading(parse("coarl:\n  radius: 1.0\n")),
            "unknown group coarl (did you mean coral?)");
  EXPECT_EQ(unknownAfterReading(parse("rip: {k: 3}\ncoarl:\n  radius: 1.0\n", "p.yaml")),
            "p.yaml:2: unknown group coarl (did you mean coral?)");
  EXPECT_EQ(unknownAfterReading(parse("lidar: {rate: 10}\n")), "unknown group lidar");
}

TEST(ParamTree, MisspeltKeyNamesTheNearestKey) {
  EXPECT_EQ(unknownAfterReading(parse("coral:\n  radus: 1.0\n")),
            "unknown key coral/radus (did you mean radius?)");
  EXPECT_EQ(unknownAfterReading(parse("coral:\n  radius: 1.0\n  radus: 1.0\n", "p.yaml")),
            "p.yaml:3: unknown key coral/radus (did you mean radius?)");
  // A key in the wrong group, or without its group, finds its group; every problem at once.
  EXPECT_EQ(unknownAfterReading(parse("rip: {radius: 1}\nmin_neighbours: 3\n")),
            "unknown key rip/radius (did you mean coral/radius?); unknown key min_neighbours "
            "(did you mean coral/min_neighbours?)");
}

TEST(ParamTree, DuplicateKeysAreErrors) {
  const std::string twice = "coral:\n  radius: 1.0\nrip:\n  k: 3\ncoral:\n  radius: 0.5\n";
  EXPECT_EQ(parseError(twice), "duplicate key coral (lines 1 and 5)");
  EXPECT_EQ(parseError(twice, "p.yaml"), "p.yaml: duplicate key coral (lines 1 and 5)");
  EXPECT_EQ(parseError("coral:\n  radius: 1.0\n  radius: 2.0\n"),
            "duplicate key coral/radius (lines 2 and 3)");
}

TEST(ParamTree, WrongTypeNamesPathSourceAndValue) {
  config::ParamTree t = parse("coral:\n  radius: big\n  k: 2.5\n  on: 1\n", "p.yaml");
  double d = 0.0;
  int i = 0;
  bool b = false;
  std::string s;
  EXPECT_FALSE(t.get("coral/radius", &d));
  EXPECT_EQ(t.error(), "p.yaml:2: parameter coral/radius must be a number (got 'big')");
  EXPECT_FALSE(t.get("coral/k", &i));
  EXPECT_EQ(t.error(), "p.yaml:3: parameter coral/k must be an integer (got '2.5')");
  EXPECT_FALSE(t.get("coral/on", &b));
  EXPECT_EQ(t.error(), "p.yaml:4: parameter coral/on must be a bool (true/false) (got '1')");
  EXPECT_FALSE(t.get("coral", &s));
  EXPECT_EQ(t.error(), "p.yaml:1: parameter coral must be a string (got a group)");
  EXPECT_FALSE(parse("coral: 3\n").get("coral/radius", &d));
  config::ParamTree n = parse("coral:\n  radius:\n");
  EXPECT_FALSE(n.get("coral/radius", &d));
  EXPECT_EQ(n.error(), "parameter coral/radius has no value (give one or remove the key)");
  config::ParamTree c = parse("coral: {aggregation: max}");
  int index = 0;
  EXPECT_FALSE(c.getChoice("coral/aggregation", {"mean", "median"}, &index));
  EXPECT_EQ(c.error(), "parameter coral/aggregation = 'max' is not one of: mean median");
}

TEST(ParamTree, ScalarsAreTypedLikeRosparam) {
  config::ParamTree t = parse(
      "a: 3\nb: 1.0e-4\nc: true\nd: no\ne: mean\nf: '12'\ng: -2.5\nh: [1, 2.5]\ni: 400.0\n"
      "j: .inf\n");
  double d = 0.0;
  int i = 0;
  bool b = true;
  std::string s;
  std::vector<double> v;
  ASSERT_TRUE(t.get("a", &i) && t.get("b", &d)) << t.error();
  EXPECT_EQ(i, 3);
  EXPECT_DOUBLE_EQ(d, 1e-4);
  ASSERT_TRUE(t.get("a", &d) && t.get("c", &b) && t.get("e", &s)) << t.error();
  EXPECT_EQ(d, 3.0);  // an integer is a number
  EXPECT_TRUE(b);
  EXPECT_EQ(s, "mean");
  ASSERT_TRUE(t.get("d", &b) && t.get("f", &s) && t.get("i", &i) && t.get("j", &d)) << t.error();
  EXPECT_FALSE(b);
  EXPECT_EQ(s, "12");  // quoted stays a string
  EXPECT_EQ(i, 400);   // an integral number is an integer
  EXPECT_TRUE(std::isinf(d));
  EXPECT_FALSE(t.get("f", &i));
  ASSERT_TRUE(t.getList("h", 2, &v)) << t.error();
  EXPECT_EQ(v, (std::vector<double>{1.0, 2.5}));
  EXPECT_FALSE(t.getList("h", 3, &v));
  EXPECT_EQ(t.error(), "parameter h must be a list of 3 numbers (got a list)");
  v.clear();
  ASSERT_TRUE(t.getList("h", 0, &v)) << t.error();  // any length
  EXPECT_EQ(v, (std::vector<double>{1.0, 2.5}));
  EXPECT_FALSE(t.getList("a", 0, &v));
  EXPECT_EQ(t.error().find("parameter a must be a list of one number or more"), 0u) << t.error();
  // Absent: unchanged, no error.
  d = 7.0;
  EXPECT_TRUE(t.get("nothing/here", &d));
  EXPECT_EQ(d, 7.0);
}

TEST(ParamTree, MergeAcceptAndSubtree) {
  config::ParamTree base = parse("coral:\n  radius: 1.0\nclassifier:\n  beta0: 4\n", "p.yaml");
  base.merge(parse("classifier:\n  beta0: 12.5\n  threshold: 0.6\n", "c.yaml"));
  double radius = 0.0, beta0 = 0.0;
  ASSERT_TRUE(base.get("coral/radius", &radius) && base.get("classifier/beta0", &beta0));
  EXPECT_EQ(radius, 1.0);
  EXPECT_EQ(beta0, 12.5);
  EXPECT_EQ(base.origin(), "p.yaml + c.yaml: ");
  EXPECT_EQ(base.unknownKeysMessage(), "c.yaml:3: unknown key classifier/threshold");
  base.accept("classifier/threshold");
  EXPECT_EQ(base.unknownKeysMessage(), "");

  config::ParamTree file = parse("ros: {imu_topc: /imu}\n"), ros;
  std::string err;
  ASSERT_TRUE(file.subtree("ros", &ros, &err)) << err;
  std::string topic;
  ASSERT_TRUE(ros.get("imu_topic", &topic));
  EXPECT_EQ(ros.unknownKeysMessage(), "unknown key ros/imu_topc (did you mean imu_topic?)");
  EXPECT_FALSE(parse("ros: [a, b]\n").subtree("ros", &ros, &err));
  EXPECT_EQ(err, "group ros must be a map of parameters");
  EXPECT_TRUE(parse("ros:\n").subtree("ros", &ros, &err));  // no value: an empty group
  EXPECT_TRUE(ros.empty());
}

TEST(ParamTree, FilesAndSyntaxErrors) {
  const std::string path = coral_test::tempPath("param_tree", ".yaml");
  std::ofstream(path) << "coral:\n  radius: 0.5\n";
  config::ParamTree t;
  std::string err;
  ASSERT_TRUE(config::loadYamlFile(path, &t, &err)) << err;
  EXPECT_EQ(t.origin(), path + ": ");
  EXPECT_EQ(t.root().child("coral")->child("radius")->where, path + ":2");
  std::ofstream(path) << "coral: [1, 2\n";
  EXPECT_FALSE(config::loadYamlFile(path, &t, &err));
  EXPECT_NE(err.find(path + ": YAML: "), std::string::npos) << err;
  EXPECT_NE(err.find("line"), std::string::npos) << err;
  std::remove(path.c_str());
  EXPECT_FALSE(config::loadYamlFile(path, &t, &err));
  EXPECT_EQ(err, "cannot read " + path);
  EXPECT_EQ(parseError("- 1\n- 2\n"), "the top level must be a map of groups and parameters");
  EXPECT_TRUE(parse("").empty());
}

TEST(ParamTree, DidYouMeanOnlyForCloseNames) {
  const std::vector<std::string> valid = {"imu_topic", "radar_topic", "trigger_topic"};
  EXPECT_EQ(config::didYouMean("radar_topc", valid), " (did you mean radar_topic?)");
  // '/' written as '_': the whole name, not only its leaf.
  const std::vector<std::string> paths = {"coral/radius", "registration/normal_radius"};
  EXPECT_EQ(config::didYouMean("coral_radius", paths), " (did you mean coral/radius?)");
  EXPECT_EQ(config::didYouMean("lidar", valid), "");
  EXPECT_EQ(config::didYouMean("x", {"y"}), "");  // one letter off a one-letter key is no hint
}
