// Demo sequence generator for CoralNodelet: publishes a sequence of scans with their
// odometry pose as TF (fixed frame -> sensor at the scan stamp), injects odometry errors
// into part of it, listens to the nodelet's `alignment` verdicts and prints how many
// injected errors were flagged and how many clean pairs were falsely flagged, then exits.
//
// Sources (~mode):
//   lidar_3d / lidar_2d: a simulated drive through eval::SyntheticScene::structuredYard()
//     (eval::simulateScan, 32 rings or one ring), PointCloud2 on `scan`, frame `lidar`.
//   oxford: real radar. The Oxford Radar RobotCar folder ~oxford_folder is converted with
//     writeOxfordBag (what the oxford_to_bag tool runs), or an existing ~bag is used; its
//     /radar/polar images are replayed on `polar_image` with its ground-truth TF.
//
// Error model ("odometry that jumped"): the published pose is T_fixed_sensor = E_i * T_true,
// E_i a translation perpendicular to the heading. A step at scan k adds +-magnitude to E
// for every scan >= k (signs alternate so the drift stays bounded): only the pair that
// straddles k is inconsistent, later pairs are consistent again. A spike at scan j shifts
// scan j alone: pairs (j-1, j) and (j, j+1) are inconsistent. A pair counts as an
// injected error when the relative pose between its two scans differs from the truth.
//
// Result file (~result_file, optional; scripts/demo.sh sets it): "pid <pid>" right after
// start, then, replaced atomically when the node ends, its summary lines (not printed on
// stdout then) and "exit_code <code>": the script that started roslaunch stops it and
// prints the summary last. Exit code 0 when the sequence was replayed and at least one
// pair judged (misses and false alarms are results, not failures), 1 otherwise, 2 on
// invalid parameters.
//
// Lock step: after scan i the node waits (up to ~result_timeout) for the verdict whose
// stamp_b is scan i's stamp, so results do not depend on CPU load. Stamps advance by the
// sequence's own timing whatever the wall time (holds for screenshots included).
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_msgs/TFMessage.h>
#include <tf2_ros/transform_broadcaster.h>

#include <unistd.h>
#include <algorithm>
#include <condition_variable>
#include <cstdio>
#include <fstream>
#include <map>
#include <mutex>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "coral_introspection/AlignmentQuality.h"
#include "coral_introspection/config/param_tree.hpp"
#include "coral_introspection/config/text_fields.hpp"
#include "coral_introspection/eval/synthetic.hpp"
#include "coral_introspection/ros/conversions.hpp"
#include "coral_introspection/ros/xmlrpc_tree.hpp"
#include "coral_introspection/ros_eval/oxford_bag_writer.hpp"

namespace config = coral_introspection::config;
namespace coral = coral_introspection::coral;
namespace eval = coral_introspection::eval;
namespace ros_adapters = coral_introspection::ros_adapters;
namespace ros_eval = coral_introspection::ros_eval;
using coral_introspection::AlignmentQuality;
using Poses = std::vector<Eigen::Isometry3d, Eigen::aligned_allocator<Eigen::Isometry3d>>;
using Offsets = std::vector<coral::Vec3, Eigen::aligned_allocator<coral::Vec3>>;

namespace {

struct DemoConfig {
  std::string mode = "lidar_3d";           // lidar_3d | lidar_2d | oxford
  int num_scans = 40;                      // scans simulated (lidar modes)
  double rate = 5.0;                       // [Hz] simulated scan rate / max publishing rate
  double step_length = 0.5;                // [m] travelled between simulated scans
  double error_magnitude = 0.5;            // [m] lateral odometry error per step / spike
  std::string error_pattern = "both";      // steps | spikes | both | none
  std::vector<int> step_scans = {10, 20};  // scan index from which a step holds
  std::vector<int> spike_scans = {30};     // single scans shifted
  double result_timeout = 3.0;             // [s] wait for each verdict
  double start_timeout = 60.0;             // [s] wait for the nodelet to connect
  double hold_misaligned = 0.0;            // [s] pause after the first flagged injected pair (rviz)
  double start_delay = 0.0;  // [s] extra wait after the nodelet connected (rviz start)
  int seed = 1;
  std::string fixed_frame = "odom";
  std::string sensor_frame = "lidar";  // lidar modes (oxford: the bag's image frame)
  std::string oxford_folder;           // oxford mode: dataset folder, converted to a bag first
  std::string bag;                     // oxford mode: existing bag (oxford_to_bag output)
  std::string image_topic = "/radar/polar";  // oxford mode: image topic in the bag
  std::string result_file;                   // summary and exit code for scripts/demo.sh

  std::string validate() const {
    std::ostringstream e;
    if (mode != "lidar_3d" && mode != "lidar_2d" && mode != "oxford")
      e << "~mode '" << mode << "' must be lidar_3d, lidar_2d or oxford. ";
    if (mode == "oxford" && oxford_folder.empty() && bag.empty())
      e << "~mode oxford needs ~oxford_folder or ~bag. ";
    if (num_scans < 2 || num_scans > 10000)
      e << "~num_scans " << num_scans << " not in [2, 10000]. ";
    if (!(rate > 0.0 && rate <= 100.0)) e << "~rate " << rate << " Hz not in (0, 100]. ";
    if (!(step_length >= 0.0 && step_length <= 2.0))
      e << "~step_length " << step_length << " m not in [0, 2]. ";
    if (!(error_magnitude >= 0.0 && error_magnitude <= 5.0))
      e << "~error_magnitude " << error_magnitude << " m not in [0, 5]. ";
    if (error_pattern != "steps" && error_pattern != "spikes" && error_pattern != "both" &&
        error_pattern != "none")
      e << "~error_pattern '" << error_pattern << "' must be steps, spikes, both or none. ";
    if (!(result_timeout > 0.0)) e << "~result_timeout must be > 0. ";
    return e.str();
  }
};

// One entry of a scan-index list: a whole number in [0, 999999], blanks around it allowed
// ("10, 20"); "3x", "2.5", "-1" and "" are refused.
bool parseIndex(const std::string& tok, int* out) {
  const std::size_t b = tok.find_first_not_of(' '), e = tok.find_last_not_of(' ');
  long n = 0;
  if (b == std::string::npos || !config::parseInteger(tok.substr(b, e - b + 1), 0, 999999, &n))
    return false;
  *out = static_cast<int>(n);
  return true;
}

// ~step_scans / ~spike_scans: comma-separated scan indices ("10,20"; demo.launch passes them
// as strings so that roslaunch args can carry a list), one integer (`_spike_scans:=25` reaches
// the parameter server as an int) or "" (none). A malformed entry fails the start: skipping it
// would replay a sequence the user did not ask for and report its result.
bool readIndices(config::ParamTree& t, const std::string& key, std::vector<int>* out) {
  const config::ParamNode* n = t.root().child(key);
  const char* expected = "comma-separated whole numbers >= 0";
  if (n && n->kind == config::ParamNode::Kind::kScalar &&
      n->scalar.type == config::Scalar::Type::kInt) {
    int v = 0;
    if (!t.get(key, &v)) return false;
    if (v < 0) return t.fail("~" + key + " " + std::to_string(v) + ": a scan index is >= 0");
    *out = {v};
    return true;
  }
  if (n && !(n->kind == config::ParamNode::Kind::kScalar &&
             n->scalar.type == config::Scalar::Type::kString))
    return t.fail("~" + key + " " + n->describe() + ": not scan indices (" + expected + ")");
  std::string s;
  if (!t.get(key, &s)) return false;
  if (!n) return true;  // absent: the default
  std::vector<int> v;
  // config::splitFields keeps empty entries ("10,,20", "10,20,"), which parseIndex refuses.
  for (const std::string& tok :
       s.empty() ? std::vector<std::string>() : config::splitFields(s, ',')) {
    int i = 0;
    if (!parseIndex(tok, &i))
      return t.fail("~" + key + " '" + s + "': '" + tok + "' is not a scan index (" + expected +
                    ")");
    v.push_back(i);
  }
  *out = v;
  return true;
}

// Every ~parameter through one config::ParamTree: a value of the wrong type, a malformed scan
// index or an unknown (misspelt) name fails the start with exit 2 and the reason, instead of
// a default silently used.
bool loadConfig(const ros::NodeHandle& pnh, DemoConfig* c, std::string* error) {
  XmlRpc::XmlRpcValue v;
  config::ParamTree t;
  if (pnh.getParam(pnh.getNamespace(), v) && !ros_adapters::fromXmlRpc(v, &t, error)) return false;
  // result_file first: a later failure is still reported there (scripts/demo.sh reads it).
  const bool ok =
      t.get("result_file", &c->result_file) && t.get("mode", &c->mode) &&
      t.get("num_scans", &c->num_scans) && t.get("rate", &c->rate) &&
      t.get("step_length", &c->step_length) && t.get("error_magnitude", &c->error_magnitude) &&
      t.get("error_pattern", &c->error_pattern) && readIndices(t, "step_scans", &c->step_scans) &&
      readIndices(t, "spike_scans", &c->spike_scans) &&
      t.get("result_timeout", &c->result_timeout) && t.get("start_timeout", &c->start_timeout) &&
      t.get("hold_misaligned", &c->hold_misaligned) && t.get("start_delay", &c->start_delay) &&
      t.get("seed", &c->seed) && t.get("fixed_frame", &c->fixed_frame) &&
      t.get("sensor_frame", &c->sensor_frame) && t.get("oxford_folder", &c->oxford_folder) &&
      t.get("bag", &c->bag) && t.get("image_topic", &c->image_topic);
  if (!ok) {
    *error = t.error();
    return false;
  }
  *error = t.unknownKeysMessage();
  return error->empty();
}

// ~result_file: written whole to a temporary file, then renamed over it (a reader sees the
// pid line or the complete result, never a partial one). No-op without ~result_file.
void writeResultFile(const std::string& path, const std::string& text) {
  if (path.empty()) return;
  const std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp, std::ios::trunc);
    f << text;
    if (!f) {
      ROS_ERROR("coral_sequence_demo: cannot write %s", tmp.c_str());
      return;
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
    ROS_ERROR("coral_sequence_demo: cannot rename %s to %s", tmp.c_str(), path.c_str());
}

// Ends the node: the failure reason (if any) and the exit code into ~result_file.
int finish(const DemoConfig& cfg, int code, const std::string& summary) {
  writeResultFile(cfg.result_file, summary + "exit_code " + std::to_string(code) + "\n");
  return code;
}

// The scans to replay with their true poses and timing.
struct Sequence {
  Poses T_true;                                  // T_fixed_sensor without error
  std::vector<double> times;                     // [s] since the first scan
  std::vector<sensor_msgs::PointCloud2> clouds;  // lidar modes
  std::vector<sensor_msgs::Image> images;        // oxford mode
  std::string frame;
  std::size_t size() const { return T_true.size(); }
};

// Simulated drive: gently weaving along the yard's long axis, the sensor 1.5 m above the
// floor, heading along the path tangent.
Sequence simulateSequence(const DemoConfig& c) {
  eval::LidarModel model;
  if (c.mode == "lidar_2d") model.rings = 1;
  const eval::SyntheticScene scene = eval::SyntheticScene::structuredYard();
  std::mt19937 rng(static_cast<unsigned>(c.seed));
  Sequence seq;
  seq.frame = c.sensor_frame;
  std_msgs::Header header;
  header.frame_id = c.sensor_frame;  // stamps are set when published
  for (int i = 0; i < c.num_scans; ++i) {
    const double s = i * c.step_length, w = 2.0 * M_PI / 20.0;
    const Eigen::Isometry3d T =
        coral::se2(-10.0 + s, std::sin(w * s), std::atan(w * std::cos(w * s)));
    seq.T_true.push_back(T);
    seq.times.push_back(i / c.rate);
    seq.clouds.push_back(
        ros_adapters::pointsToCloud(eval::simulateScan(scene, T, model, rng), header));
  }
  return seq;
}

// Oxford bag: images of image_topic and the TF (any parent) -> image frame at each stamp.
bool readOxfordBag(const DemoConfig& c, Sequence* seq, std::string* error) {
  std::string path = c.bag;
  if (path.empty()) {
    path = "/tmp/coral_sequence_demo_" + std::to_string(getpid()) + ".bag";
    ros_eval::OxfordBagOptions opt;
    opt.image_topic = c.image_topic;
    ros_eval::OxfordBagSummary summary;
    if (!ros_eval::writeOxfordBag(c.oxford_folder, path, opt, &summary, error)) return false;
    std::printf("[coral_sequence_demo] converted %s -> %s (%zu images, %zu TF)\n",
                c.oxford_folder.c_str(), path.c_str(), summary.images, summary.transforms);
  }
  std::map<std::pair<std::string, uint64_t>, Eigen::Isometry3d> poses;
  try {
    rosbag::Bag bag(path, rosbag::bagmode::Read);
    for (const rosbag::MessageInstance& m : rosbag::View(bag)) {
      if (m.getTopic() == c.image_topic) {
        if (auto img = m.instantiate<sensor_msgs::Image>()) seq->images.push_back(*img);
      } else if (auto tf = m.instantiate<tf2_msgs::TFMessage>()) {
        for (const auto& t : tf->transforms) {
          Eigen::Isometry3d T;
          if (ros_adapters::toEigen(t.transform, &T, error))
            poses[{t.child_frame_id, t.header.stamp.toNSec()}] = T;
        }
      }
    }
  } catch (const std::exception& e) {
    *error = "reading " + path + ": " + e.what();
    return false;
  }
  if (c.bag.empty()) std::remove(path.c_str());
  for (const auto& img : seq->images) {
    const auto it = poses.find({img.header.frame_id, img.header.stamp.toNSec()});
    if (it == poses.end()) {
      *error = "no TF to frame '" + img.header.frame_id + "' at an image stamp";
      return false;
    }
    seq->T_true.push_back(it->second);
    seq->times.push_back((img.header.stamp - seq->images.front().header.stamp).toSec());
  }
  if (seq->images.size() < 2) *error = "fewer than two images on " + c.image_topic;
  seq->frame = seq->images.empty() ? "" : seq->images.front().header.frame_id;
  return seq->images.size() >= 2;
}

// Fixed-frame odometry error E_i (translation) of every scan.
Offsets errorOffsets(const DemoConfig& c, const Poses& T_true) {
  const int n = static_cast<int>(T_true.size());
  Offsets e(n, coral::Vec3::Zero());
  auto lateral = [&](int i) { return coral::Vec3(T_true[i].linear() * coral::Vec3::UnitY()); };
  if (c.error_pattern == "steps" || c.error_pattern == "both") {
    double sign = 1.0;
    for (int k : c.step_scans) {
      if (k < 1 || k >= n) continue;
      const coral::Vec3 jump = sign * c.error_magnitude * lateral(k);
      for (int i = k; i < n; ++i) e[i] += jump;
      sign = -sign;
    }
  }
  if (c.error_pattern == "spikes" || c.error_pattern == "both")
    for (int j : c.spike_scans)
      if (j >= 0 && j < n) e[j] += c.error_magnitude * lateral(j);
  return e;
}

// Verdicts keyed by stamp_b, filled by the subscriber thread.
class ResultBox {
 public:
  void add(const AlignmentQuality& m) {
    std::lock_guard<std::mutex> l(mu_);
    results_[m.stamp_b.toNSec()] = m;
    cv_.notify_all();
  }
  // The verdict for stamp_b, waiting up to timeout seconds; false if none came.
  bool waitFor(const ros::Time& stamp_b, double timeout, AlignmentQuality* out) {
    std::unique_lock<std::mutex> l(mu_);
    cv_.wait_for(l, std::chrono::duration<double>(timeout),
                 [&] { return results_.count(stamp_b.toNSec()) > 0 || !ros::ok(); });
    const auto it = results_.find(stamp_b.toNSec());
    if (it == results_.end()) return false;
    *out = it->second;
    return true;
  }
  std::map<uint64_t, AlignmentQuality> snapshot() {
    std::lock_guard<std::mutex> l(mu_);
    return results_;
  }

 private:
  std::mutex mu_;
  std::condition_variable cv_;
  std::map<uint64_t, AlignmentQuality> results_;
};

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "coral_sequence_demo");
  ros::NodeHandle nh, pnh("~");
  DemoConfig cfg;
  std::string load_error;
  const bool loaded = loadConfig(pnh, &cfg, &load_error);
  writeResultFile(cfg.result_file, "pid " + std::to_string(getpid()) + "\n");
  if (const std::string err = loaded ? cfg.validate() : load_error; !err.empty()) {
    ROS_FATAL("coral_sequence_demo: invalid parameters: %s", err.c_str());
    return finish(cfg, 2, "[coral_sequence_demo] FAILED: invalid parameters: " + err + "\n");
  }
  Sequence seq;
  const bool radar = cfg.mode == "oxford";
  if (radar) {
    std::string error;
    if (!readOxfordBag(cfg, &seq, &error)) {
      ROS_FATAL("coral_sequence_demo: %s", error.c_str());
      return finish(cfg, 1, "[coral_sequence_demo] FAILED: " + error + "\n");
    }
  } else {
    seq = simulateSequence(cfg);
  }
  const Offsets err = errorOffsets(cfg, seq.T_true);
  const int n = static_cast<int>(seq.size());

  ResultBox box;
  ros::Publisher pub = radar ? nh.advertise<sensor_msgs::Image>("polar_image", 2)
                             : nh.advertise<sensor_msgs::PointCloud2>("scan", 2);
  ros::Subscriber sub = nh.subscribe<AlignmentQuality>(
      "alignment", 100,
      [&box](const coral_introspection::AlignmentQualityConstPtr& m) { box.add(*m); });
  tf2_ros::TransformBroadcaster tf;
  ros::AsyncSpinner spinner(1);
  spinner.start();

  // Wait until the nodelet listens to the scans and publishes verdicts.
  const ros::WallTime t0 = ros::WallTime::now();
  while (ros::ok() && (pub.getNumSubscribers() == 0 || sub.getNumPublishers() == 0)) {
    if ((ros::WallTime::now() - t0).toSec() > cfg.start_timeout) {
      ROS_FATAL("coral_sequence_demo: no subscriber on '%s' / publisher of '%s' after %.0f s",
                pub.getTopic().c_str(), sub.getTopic().c_str(), cfg.start_timeout);
      return finish(cfg, 1, "[coral_sequence_demo] FAILED: the nodelet did not connect\n");
    }
    ros::WallDuration(0.1).sleep();
  }
  ros::WallDuration(1.0 + std::max(0.0, cfg.start_delay)).sleep();  // TF listener, rviz

  std::printf("[coral_sequence_demo] %d scans (%s), error pattern '%s', %.2f m lateral, steps at {",
              n, cfg.mode.c_str(), cfg.error_pattern.c_str(), cfg.error_magnitude);
  for (int k : cfg.step_scans) std::printf(" %d", k);
  std::printf(" }, spikes at {");
  for (int j : cfg.spike_scans) std::printf(" %d", j);
  std::printf(" }\n");
  std::fflush(stdout);

  const ros::Time t_start = ros::Time::now();
  std::map<uint64_t, int> index_of_stamp;
  bool held = false;
  ros::WallRate rate(cfg.rate);
  int published = 0;
  for (int i = 0; i < n && ros::ok(); ++i, ++published) {
    const ros::Time stamp = t_start + ros::Duration(seq.times[i]);
    index_of_stamp[stamp.toNSec()] = i;
    geometry_msgs::TransformStamped tf_msg;
    tf_msg.header.stamp = stamp;
    tf_msg.header.frame_id = cfg.fixed_frame;
    tf_msg.child_frame_id = seq.frame;
    tf_msg.transform = ros_adapters::toTransformMsg(Eigen::Translation3d(err[i]) * seq.T_true[i]);
    tf.sendTransform(tf_msg);
    ros::WallDuration(0.02).sleep();  // TF first, so the message filter has it on arrival
    if (radar) {
      sensor_msgs::Image img = seq.images[i];
      img.header.stamp = stamp;
      pub.publish(img);
    } else {
      sensor_msgs::PointCloud2 cloud = seq.clouds[i];
      cloud.header.stamp = stamp;
      pub.publish(cloud);
    }

    AlignmentQuality m;
    if (i > 0 && box.waitFor(stamp, cfg.result_timeout, &m) && !held && cfg.hold_misaligned > 0.0) {
      const auto ia = index_of_stamp.find(m.stamp_a.toNSec());
      const bool injected = ia != index_of_stamp.end() && (err[ia->second] - err[i]).norm() > 1e-6;
      if (injected && m.valid && !m.aligned) {
        std::printf("[coral_sequence_demo] HOLD misaligned pair %d-%d shown for %.0f s\n",
                    ia->second, i, cfg.hold_misaligned);
        std::fflush(stdout);
        held = true;
        ros::WallDuration(cfg.hold_misaligned).sleep();
      }
    }
    rate.sleep();
  }
  ros::WallDuration(0.5).sleep();  // last verdicts in flight

  // Match the verdicts to pairs by stamp_a / stamp_b and score them.
  int inj = 0, inj_flagged = 0, clean = 0, clean_flagged = 0, no_verdict = 0;
  for (const auto& [key, m] : box.snapshot()) {
    const auto ia = index_of_stamp.find(m.stamp_a.toNSec());
    const auto ib = index_of_stamp.find(key);
    if (ia == index_of_stamp.end() || ib == index_of_stamp.end()) continue;
    const bool injected = (err[ib->second] - err[ia->second]).norm() > 1e-6;
    const bool flagged = m.valid && !m.aligned;
    std::printf("  pair %2d-%2d  Q=%7.4f  p=%.3f  overlap=%.2f  %-10s  %s\n", ia->second,
                ib->second, m.quality, m.probability, m.overlap,
                !m.valid ? "NO VERDICT" : (m.aligned ? "aligned" : "MISALIGNED"),
                injected ? (flagged ? "injected error: detected" : "injected error: MISSED")
                         : (flagged ? "clean: FALSE ALARM" : "clean"));
    if (!m.valid) ++no_verdict;
    if (injected) {
      ++inj;
      inj_flagged += flagged;
    } else {
      ++clean;
      clean_flagged += flagged;
    }
  }
  const int code = (published == n && inj + clean > 0) ? 0 : 1;
  char buf[512];
  std::string summary;
  std::snprintf(
      buf, sizeof(buf),
      "[coral_sequence_demo] summary (%d scan pairs judged, %d of them without verdict):\n"
      "  injected errors flagged: %d/%d\n  clean pairs falsely flagged: %d/%d\n",
      inj + clean, no_verdict, inj_flagged, inj, clean_flagged, clean);
  summary += buf;
  if (published < n)
    std::snprintf(buf, sizeof(buf), "interrupted after %d of %d scans", published, n);
  else if (inj + clean == 0)
    std::snprintf(buf, sizeof(buf), "no pair judged (no verdict received)");
  else if (inj_flagged == inj && clean_flagged == 0)
    std::snprintf(buf, sizeof(buf), "every injected error flagged, no false alarm");
  else
    std::snprintf(buf, sizeof(buf), "see the pairs above for misses / false alarms");
  summary +=
      std::string("[coral_sequence_demo] ") + (code == 0 ? "done: " : "FAILED: ") + buf + "\n";
  if (cfg.result_file.empty()) std::fputs(summary.c_str(), stdout);
  std::fflush(stdout);
  spinner.stop();
  ros::shutdown();
  return finish(cfg, code, summary);
}
