// Every parameter CoralNodelet reads (nodeParameterNames), set to 0, -1, +-1e12, NaN or inf
// over each preset, either fails the load with a message, or gives a config with which the
// nodelet's work runs without throwing: the scans converted (polar images through the radar
// front end), a stream of them through the Introspector (pairing, de-skew, Doppler check,
// verdict, self-calibration) and the loop-closure verdict of the service. A throw in a nodelet
// callback takes down every nodelet of the manager. free_space/bin_deg 0 once passed the load
// unvalidated and threw std::length_error in the free-space check (2026-12-06).
// Point-cloud presets: every parameter, on the synthetic yard pair. The Doppler and
// self-calibration groups are only validated and used when enabled: radar_ti_mmwave (Doppler
// on) and lidar_3d with calibration/enabled sweep those groups. The polar-image presets
// (radar_oxford, radar_mulran) sweep the groups of the radar path on two real Oxford scans.
#include <gtest/gtest.h>
#include <sensor_msgs/image_encodings.h>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "coral_introspection/config/yaml_tree.hpp"
#include "coral_introspection/coral/verdict.hpp"
#include "coral_introspection/online/introspector.hpp"
#include "coral_introspection/ros/coral_params.hpp"
#include "coral_introspection/ros/coral_scan_input.hpp"
#include "support/source_dir.hpp"
#include "support/test_data.hpp"
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
  int exercised = 0;  // of the judged: the scans were made and went through the nodelet's work
};

// The scans of one run under a loaded config: (points or image) -> ScanInput; false with the
// reason when the config's front end refuses them (an error the nodelet reports, no throw).
using MakeScans =
    std::function<bool(const ros_adapters::NodeConfig&, std::vector<online::ScanInput>*)>;

// What the nodelet does with the scans: the stream through the Introspector, the calibration
// step after each verdict, and the loop-closure verdict of the first and last scan.
void exercise(const ros_adapters::NodeConfig& c, const std::vector<online::ScanInput>& scans) {
  online::Introspector intro(c.online);
  for (const online::ScanInput& s : scans) {
    intro.process(s);
    intro.calibrate();
  }
  online::IntrospectorConfig loop = c.online;
  loop.verdict = coral::loopClosureVerdict(c.online.verdict);
  coral::Scan a, b;
  a.points = scans.front().features.points;
  b.points = scans.back().features.points;
  online::judgePair(a, b, scans.front().T_fixed_sensor->inverse() * *scans.back().T_fixed_sensor,
                    loop, false);
}

// `preset` (with `base` YAML over it) with each parameter whose name starts with one of
// `groups` (all when empty) at each extreme value; run on the scans when it loads.
Tally sweep(const std::string& preset, const std::string& base,
            const std::vector<std::string>& groups, const MakeScans& make_scans) {
  Tally t;
  // The sanitizer build (CORAL_VERDICT_PAIR_STRIDE > 1, ~22x slower: 348 s for the lidar
  // sweeps alone): 0 and NaN only.
  const std::vector<std::string> values =
      coral_test::pairStride() > 1
          ? std::vector<std::string>{"0", ".nan"}
          : std::vector<std::string>{"0", "-1", "1.0e12", "-1.0e12", ".nan", ".inf"};
  for (const std::string& name : ros_adapters::nodeParameterNames()) {
    if (!groups.empty() && std::none_of(groups.begin(), groups.end(), [&](const std::string& g) {
          return name.rfind(g, 0) == 0;
        }))
      continue;
    for (const std::string& value : values) {
      SCOPED_TRACE(preset + ": " + name + " = " + value);
      config::ParamTree tree, overlay, base_tree;
      std::string err;
      if (!config::loadYamlFile(coral_test::sourceDir() + "/config/" + preset, &tree, &err) ||
          !config::parseYaml(base, &base_tree, &err) ||
          !config::parseYaml(yamlOf(name, value), &overlay, &err)) {
        ADD_FAILURE() << err;
        return t;
      }
      tree.merge(base_tree);
      tree.merge(overlay);
      ros_adapters::NodeConfig c;
      if (!ros_adapters::loadNodeConfig(tree, &c, &err)) {
        EXPECT_FALSE(err.empty());  // refused, with the reason
        ++t.refused;
        continue;
      }
      ++t.judged;
      EXPECT_NO_THROW({
        std::vector<online::ScanInput> scans;
        if (make_scans(c, &scans)) {
          exercise(c, scans);
          ++t.exercised;
        }
      });
    }
  }
  std::printf("%s%s: %d refused, %d judged (%d with scans)\n", preset.c_str(),
              base.empty() ? "" : " (+ base)", t.refused, t.judged, t.exercised);
  return t;
}

// The yard pair as a stream of three scans 0.1 s apart (a, b, then a again: a loop back),
// with radial velocities of the static scene for the Doppler check (sensor moving along x).
MakeScans yardScans(int rings) {
  const test::YardPair pair = test::yardPair(rings);
  return [pair](const ros_adapters::NodeConfig&, std::vector<online::ScanInput>* scans) {
    const coral::Points* clouds[] = {&pair.a.points, &pair.b.points, &pair.a.points};
    const Eigen::Isometry3d poses[] = {Eigen::Isometry3d::Identity(), pair.T_a_b,
                                       pair.T_a_b * pair.T_a_b};
    for (int i = 0; i < 3; ++i) {
      online::ScanInput s;
      s.stamp = 10.0 + 0.1 * i;
      s.id = i;
      s.features.points = *clouds[i];
      for (const coral::Vec3& p : s.features.points)
        s.radial_velocity.push_back(-6.0 * p.x() / std::max(p.norm(), 1e-3));
      s.T_fixed_sensor = poses[i];
      scans->push_back(s);
    }
    return true;
  };
}

// Two real Oxford scans as the nodelet receives them (mono8 sensor_msgs::Image), the Oxford
// layout or, `plain`, without its 11 metadata columns (MulRan's layout), through
// toSensorScan with the config under test.
MakeScans oxfordScans(const std::string& dir, bool plain) {
  std::vector<std::string> pngs;
  for (const auto& e : std::filesystem::directory_iterator(dir + "/radar"))
    if (e.path().extension() == ".png") pngs.push_back(e.path().string());
  std::sort(pngs.begin(), pngs.end());
  std::vector<sensor_msgs::Image> images;
  for (std::size_t i = 0; i < 2 && i < pngs.size(); ++i) {
    cv::Mat m = cv::imread(pngs[i], cv::IMREAD_GRAYSCALE);
    if (plain && !m.empty()) m = m.colRange(11, m.cols).clone();
    sensor_msgs::Image im;
    im.header.stamp = ros::Time(100.0 + 0.25 * i);
    im.header.frame_id = "radar";
    im.encoding = sensor_msgs::image_encodings::MONO8;
    im.height = m.rows;
    im.width = m.cols;
    im.step = m.cols;
    im.data.assign(m.data, m.data + m.total());
    images.push_back(im);
  }
  return [images](const ros_adapters::NodeConfig& c, std::vector<online::ScanInput>* scans) {
    for (std::size_t i = 0; i < images.size(); ++i) {
      ros_adapters::SensorScan s;
      std::string err;
      if (!ros_adapters::toSensorScan(images[i], c, &s, &err)) return false;
      s.scan.T_fixed_sensor = coral::se2(1.5 * i, 0.0, 0.0);
      scans->push_back(s.scan);
    }
    return scans->size() == 2;
  };
}

// Both outcomes occur (a sweep that loaded nothing, or refused nothing, tested nothing; a
// third of the bounds with the sanitizer build's two values of six). Most loaded configs make
// their scans (a front end that refused every one tested nothing).
void expectBoth(const Tally& t, int min_refused, int min_judged) {
  const int share = coral_test::pairStride() > 1 ? 3 : 1;
  EXPECT_GE(t.refused, min_refused / share);
  EXPECT_GE(t.judged, std::max(1, min_judged / share));
  EXPECT_GE(t.exercised * 10, t.judged * 8);
}

TEST(ParamExtremes, EveryNumberAtItsExtremesIsRefusedOrJudgedWithoutThrowing) {
  expectBoth(sweep("lidar_2d.yaml", "", {}, yardScans(1)), 300, 50);
  expectBoth(sweep("lidar_3d.yaml", "", {}, yardScans(16)), 300, 50);
}

TEST(ParamExtremes, DopplerAndSelfCalibrationGroupsWhenEnabled) {
  expectBoth(sweep("radar_ti_mmwave.yaml", "", {"doppler/"}, yardScans(16)), 30, 10);
  expectBoth(sweep("lidar_3d.yaml", "calibration:\n  enabled: true\n  fraction_of_pairs: 1.0\n",
                   {"calibration/"}, yardScans(16)),
             20, 3);
}

TEST(ParamExtremes, RadarPathGroupsOnRealPolarImages) {
  CORAL_REQUIRE_DATA("oxford_radar_tiny");
  const std::vector<std::string> groups = {"radar/", "rip/", "motion_compensation/", "coral/"};
  expectBoth(sweep("radar_oxford.yaml", "", groups, oxfordScans(coral_data, false)), 60, 20);
  expectBoth(sweep("radar_mulran.yaml", "", groups, oxfordScans(coral_data, true)), 60, 20);
}

}  // namespace
}  // namespace coral_introspection
