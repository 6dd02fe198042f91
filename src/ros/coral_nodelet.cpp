// CoralNodelet: the ROS adapter of online::Introspector. The input side (ScanSource)
// converts messages and looks up TF, then hands each posed scan to one worker thread
// through a newest-wins mailbox; the worker runs the Introspector (pairing, de-skew, CorAl,
// classifier, Doppler) and publishes one AlignmentQuality per input scan: the verdict, or
// why there is none (refused, no TF, dropped while the worker was busy, not paired). No lock
// is held while CorAl runs, and the service and the diagnostics timer run on the nodelet's
// multi-threaded queue, so diagnostics, dynamic_reconfigure and check_alignment stay
// responsive while a pair is computed (doc/online_behaviour.md).
#include <diagnostic_updater/diagnostic_updater.h>
#include <dynamic_reconfigure/server.h>
#include <nodelet/nodelet.h>

#include <atomic>
#include <boost/thread/recursive_mutex.hpp>
#include <optional>
#include <pluginlib/class_list_macros.hpp>
#include <thread>

#include "coral_introspection/CheckAlignment.h"
#include "coral_introspection/CoralConfig.h"
#include "coral_introspection/online/mailbox.hpp"
#include "coral_introspection/ros/coral_check_alignment.hpp"
#include "coral_introspection/ros/coral_diagnostics.hpp"
#include "coral_introspection/ros/coral_outputs.hpp"
#include "coral_introspection/ros/coral_scan_source.hpp"
#include "coral_introspection/ros/guarded.hpp"
#include "coral_introspection/ros/heap_release.hpp"

namespace coral_introspection {

using ReconfigureConfig = coral_introspection::CoralConfig;  // generated from cfg/Coral.cfg
using ros_adapters::NodeConfig;
using ros_adapters::ScanEvent;

class CoralNodelet : public nodelet::Nodelet {
 public:
  ~CoralNodelet() override {
    timer_.stop();
    source_.reset();  // no more scans
    mailbox_.close();
    if (worker_.joinable()) worker_.join();
  }

 private:
  // A scan replaced in the mailbox leaves this notice in its place (published in order).
  static ScanEvent dropNotice(const ScanEvent& scan) {
    ScanEvent e;
    e.kind = ScanEvent::Kind::kDropped;
    e.header = scan.header;
    e.receipt = scan.receipt;
    e.reason = "dropped: the worker was still busy with an earlier scan (newest scan wins)";
    return e;
  }

  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    // Whole private namespace at once: every key is checked, an unknown group or key (a
    // typo) fails the load with the message coral_check prints for the same preset.
    XmlRpc::XmlRpcValue tree;
    pnh.getParam(pnh.getNamespace(), tree);
    std::string error;
    if (!ros_adapters::loadNodeConfig(tree, &config_, &error, namespaceKeys())) {
      NODELET_FATAL("invalid parameters in %s: %s", pnh.getNamespace().c_str(), error.c_str());
      throw std::runtime_error("CoralNodelet: invalid parameters: " + error);  // load fails
    }
    if (config_.testing_pair_delay > 0.0)
      NODELET_WARN("testing/pair_delay = %.3g s: every pair is slowed down (tests only)",
                   config_.testing_pair_delay);
    introspector_ = online::Introspector(config_.online);
    stats_.doppler = config_.online.doppler.enabled;
    stats_.calibration = config_.online.calibration.enabled;
    if (config_.online.calibration.enabled &&
        config_.online.verdict.method == coral::VerdictMethod::kRelative)
      NODELET_INFO(
          "calibration/enabled with classifier/method relative: the refitted classifier "
          "is written (calibration/output_file) but does not judge");
    stats_.time_budget = config_.time_budget;
    stats_.mailbox = [this] { return std::make_pair(mailbox_.dropped(), mailbox_.noticesLost()); };
    worker_ = std::thread(&CoralNodelet::work, this);
    source_ = std::make_unique<ros_adapters::ScanSource>(nh, config_, &stats_, [this](ScanEvent e) {
      // A posed scan replaces a scan still waiting for the worker (which becomes a
      // "dropped" notice); notices (refused, no TF) never replace anything.
      const bool droppable = e.kind == ScanEvent::Kind::kScan;
      mailbox_.put(std::move(e), droppable);
    });

    // Service and diagnostics on the multi-threaded queue: they answer even while the
    // nodelet's own queue is busy with input.
    ros::NodeHandle& mt = getMTNodeHandle();
    updater_ = std::make_shared<diagnostic_updater::Updater>(nh, pnh, getName());
    updater_->setHardwareID("coral_introspection");
    updater_->add("CorAl alignment", &stats_, &ros_adapters::Stats::diagnose);
    timer_ = mt.createWallTimer(ros::WallDuration(1.0), &CoralNodelet::timerCb, this);
    reconfigure_ =
        std::make_shared<dynamic_reconfigure::Server<ReconfigureConfig>>(reconfigure_mutex_, pnh);
    reconfigure_->updateConfig(  // start from the YAML values, not the .cfg defaults
        ros_adapters::toReconfigure<ReconfigureConfig>(config_));
    reconfigure_->setCallback(boost::bind(&CoralNodelet::reconfigureCb, this,
                                          boost::placeholders::_1, boost::placeholders::_2));
    service_ = mt.advertiseService("check_alignment", &CoralNodelet::checkAlignment, this);
    {
      // Held across advertise: connectCb (run from another thread as soon as a subscriber
      // appears) must see the assigned publishers (pointcloud_to_laserscan pattern).
      std::lock_guard<std::mutex> lock(connect_mutex_);
      outputs_.advertise(nh, config_.online.doppler.enabled,
                         boost::bind(&CoralNodelet::connectCb, this));
    }
    NODELET_INFO("CoralNodelet: input %s, fixed frame '%s', CorAl %dD r = %.2f m",
                 source_->topic().c_str(), config_.fixed_frame.c_str(),
                 config_.online.coral.dimension, config_.online.coral.radius);
  }

  // Keys in the private namespace that are not NodeConfig's, so not unknown: the values
  // dynamic_reconfigure's server writes there (cfg/Coral.cfg; present when the nodelet is
  // loaded again under the same name), diagnostic_updater's ~diagnostic_period, and
  // nodelet::Loader's ~num_worker_threads (coral_node runs the loader in the same namespace).
  static std::vector<std::string> namespaceKeys() {
    std::vector<std::string> keys = {"diagnostic_period", "num_worker_threads"};
    for (const auto& p : ReconfigureConfig::__getParamDescriptions__()) keys.push_back(p->name);
    return keys;
  }

  // Input is subscribed only while someone listens to an output (lazy, like
  // pointcloud_to_laserscan); the pairing restarts after a gap in subscribers.
  void connectCb() {
    guarded("connect callback", [&] {
      std::lock_guard<std::mutex> lock(connect_mutex_);
      const bool wanted = outputs_.subscribed();
      if (wanted == subscribed_) return;
      source_->subscribe(wanted);
      if (!wanted) reset_requested_ = true;
      subscribed_ = wanted;
    });
  }

  // Validated here; the worker picks the new config up at its next scan.
  void reconfigureCb(ReconfigureConfig& rc, uint32_t) {
    guarded("dynamic_reconfigure callback", [&] {
      std::lock_guard<std::mutex> lock(config_mutex_);
      warnAtLimits(rc, ros_adapters::toReconfigure<ReconfigureConfig>(config_));
      NodeConfig c = config_;
      ros_adapters::applyReconfigure(rc, &c);
      if (const std::string err = c.validate(); !err.empty()) {
        NODELET_WARN("dynamic_reconfigure change rejected: %s", err.c_str());
        return;
      }
      config_ = c;
      config_changed_ = true;
    });
  }

  // dynamic_reconfigure clamps a request outside the .cfg range to the range before this
  // callback sees it, so the requested value is unknown here; a change that lands exactly
  // on a limit is the trace of such a clamp and is said aloud.
  void warnAtLimits(const ReconfigureConfig& rc, const ReconfigureConfig& current) {
    const ReconfigureConfig lo = ReconfigureConfig::__getMin__();
    const ReconfigureConfig hi = ReconfigureConfig::__getMax__();
    for (const auto& p : ReconfigureConfig::__getParamDescriptions__()) {
      if (p->type != "double" && p->type != "int") continue;
      auto value = [&](const ReconfigureConfig& c) {
        boost::any v;
        p->getValue(c, v);
        return p->type == "double" ? boost::any_cast<double>(v) : boost::any_cast<int>(v);
      };
      const double v = value(rc);
      if (v == value(current) || (v != value(lo) && v != value(hi))) continue;
      NODELET_WARN(
          "dynamic_reconfigure: %s = %g is the %s limit of cfg/Coral.cfg; a request beyond it "
          "is clamped to it without notice, so a larger change you asked for was not applied",
          p->name.c_str(), v, v == value(hi) ? "upper" : "lower");
    }
  }

  // The only thread that touches introspector_: the stream state needs no lock.
  void work() {
    while (std::optional<ScanEvent> job = mailbox_.take()) {
      guarded("worker", [&] { handle(*job); });
      stats_.idle();
    }
  }

  void handle(ScanEvent& job) {
    NodeConfig cfg;
    {
      std::lock_guard<std::mutex> lock(config_mutex_);
      if (config_changed_) introspector_.setConfig(config_.online, nullptr);  // valid
      config_changed_ = false;
      cfg = config_;
    }
    if (reset_requested_.exchange(false)) introspector_.reset();
    stats_.started(job.header);
    const ros::WallTime start = ros::WallTime::now();
    ros_adapters::WorkDone done;
    std::optional<online::Report> r;  // lives until stats_.finished (done.counters)
    if (job.kind == ScanEvent::Kind::kRefused || job.kind == ScanEvent::Kind::kDropped) {
      done.status = job.kind == ScanEvent::Kind::kRefused ? AlignmentQuality::REFUSED
                                                          : AlignmentQuality::DROPPED;
      done.reason = job.reason;
      done.problem = job.kind == ScanEvent::Kind::kRefused;  // dropped: counted apart
      done.latency = outputs_.publishNoVerdict(done.status, job.reason, job.header, job.receipt,
                                               cfg.fixed_frame);
    } else {
      const online::ProcessOptions opt = outputs_.options(cfg, job.scan.is_radar);
      r = introspector_.process(std::move(job.scan), opt);
      if (r->judged && cfg.testing_pair_delay > 0.0)
        ros::WallDuration(cfg.testing_pair_delay).sleep();
      const bool restart = r->action == online::PairAction::kBackwardsReset ||
                           r->action == online::PairAction::kDuplicateReset;
      if (!r->has_pose || restart)
        NODELET_WARN_THROTTLE(5.0, "%s", r->reason.c_str());
      else if (r->action == online::PairAction::kGapReset)
        NODELET_INFO_THROTTLE(10.0, "%s", r->reason.c_str());
      done.counters = &r->counters;
      done.status = ros_adapters::reportStatus(*r, job.kind == ScanEvent::Kind::kNoPose);
      done.reason = r->reason;
      done.problem = !r->has_pose || restart;
      done.latency = outputs_.publish(*r, done.status, job.header, job.receipt, cfg.fixed_frame,
                                      opt, cfg.online.verdict);
    }
    done.seconds = (ros::WallTime::now() - start).toSec();
    stats_.finished(done);
    // Self-calibration after the verdict is published: it delays only the next scan (which
    // waits in the newest-wins mailbox), on average by calibration/fraction_of_pairs x
    // 2 x axes CorAl evaluations per pair.
    if (r && introspector_.calibrate()) {
      stats_.calibrated(introspector_.calibration().status());
      std::lock_guard<std::mutex> lock(config_mutex_);  // check_alignment judges alike
      calibrated_ = introspector_.calibration().status().in_use
                        ? std::optional(introspector_.calibration().classifier())
                        : std::nullopt;
      const std::string& e = introspector_.calibration().status().last_error;
      if (!e.empty()) NODELET_WARN_THROTTLE(30.0, "self-calibration: %s", e.c_str());
    }
    // After the verdict is out, rate-limited: the freed memory of all threads' malloc
    // arenas goes back to the system (RSS stays flat, heap_release.hpp says why).
    const ros::SteadyTime now = ros::SteadyTime::now();
    if (heap_release_.due(now.toSec(), cfg.heap_release_interval)) {
      const bool released = ros_adapters::releaseFreeHeap();
      NODELET_DEBUG("heap release (%s): %.3f ms", released ? "malloc_trim" : "unavailable",
                    (ros::SteadyTime::now() - now).toSec() * 1e3);
    }
  }

  // A refused request is answered with `error` set; a failed call means an internal error.
  bool checkAlignment(CheckAlignment::Request& req, CheckAlignment::Response& res) {
    bool answered = false;
    guarded("check_alignment", [&] {
      if (!ros_adapters::answerCheckAlignment(req, config(), &res)) {
        stats_.count(&ros_adapters::InputCounters::bad_inputs, "check_alignment " + res.error);
        NODELET_WARN_THROTTLE(5.0, "check_alignment %s", res.error.c_str());
      }
      answered = true;
    });
    return answered;
  }

  void timerCb(const ros::WallTimerEvent&) {
    guarded("diagnostics timer", [&] {
      source_->expirePending();
      source_->checkInputTopic();
      updater_->force_update();
    });
  }

  // The parameters with the self-calibrated classifier when it judges (check_alignment).
  NodeConfig config() {
    std::lock_guard<std::mutex> lock(config_mutex_);
    NodeConfig c = config_;
    if (calibrated_) c.online.verdict.classifier = *calibrated_;
    return c;
  }

  template <class F>
  void guarded(const char* what, F&& f) noexcept {
    ros_adapters::guarded(what, f, [this](const std::string& e) {
      stats_.count(&ros_adapters::InputCounters::errors, e);
      NODELET_ERROR_THROTTLE(5.0, "%s", e.c_str());
    });
  }

  std::mutex config_mutex_;  // config_, config_changed_ (every thread, briefly)
  NodeConfig config_;
  bool config_changed_ = false;
  std::optional<coral::ClassifierConfig> calibrated_;  // self-calibration in use (config_mutex_)
  std::atomic<bool> reset_requested_{false};
  online::Mailbox<ScanEvent> mailbox_{100, &CoralNodelet::dropNotice};
  online::Introspector introspector_;            // worker thread only
  ros_adapters::HeapReleaseTimer heap_release_;  // worker thread only
  std::thread worker_;
  ros_adapters::Stats stats_;  // thread-safe: everything diagnostics reads
  std::unique_ptr<ros_adapters::ScanSource> source_;
  std::mutex connect_mutex_;  // held across advertise so connectCb sees the publishers
  bool subscribed_ = false;
  ros_adapters::Outputs outputs_;
  ros::ServiceServer service_;
  ros::WallTimer timer_;
  std::shared_ptr<diagnostic_updater::Updater> updater_;
  boost::recursive_mutex reconfigure_mutex_;
  std::shared_ptr<dynamic_reconfigure::Server<ReconfigureConfig>> reconfigure_;
};

}  // namespace coral_introspection

PLUGINLIB_EXPORT_CLASS(coral_introspection::CoralNodelet, nodelet::Nodelet)
