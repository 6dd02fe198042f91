// CoralNodelet: the ROS adapter of online::Introspector. The input side (ScanSource)
// converts messages and looks up TF, then hands each posed scan to one worker thread
// through a newest-wins mailbox; the worker runs the Introspector (pairing, de-skew, CorAl,
// classifier, Doppler) and publishes. No lock is held while CorAl runs, so diagnostics,
// dynamic_reconfigure and check_alignment stay responsive.
#include <diagnostic_updater/diagnostic_updater.h>
#include <dynamic_reconfigure/server.h>
#include <nodelet/nodelet.h>

#include <atomic>
#include <boost/thread/recursive_mutex.hpp>
#include <pluginlib/class_list_macros.hpp>
#include <thread>

#include "coral_introspection/CheckAlignment.h"
#include "coral_introspection/CoralConfig.h"
#include "coral_introspection/online/mailbox.hpp"
#include "coral_introspection/ros/check_alignment.hpp"
#include "coral_introspection/ros/diagnostics.hpp"
#include "coral_introspection/ros/guarded.hpp"
#include "coral_introspection/ros/outputs.hpp"
#include "coral_introspection/ros/scan_source.hpp"

namespace coral_introspection {

using ReconfigureConfig = coral_introspection::CoralConfig;  // generated from cfg/Coral.cfg
using ros_adapters::NodeConfig;

class CoralNodelet : public nodelet::Nodelet {
 public:
  ~CoralNodelet() override {
    timer_.stop();
    source_.reset();  // no more scans
    mailbox_.close();
    if (worker_.joinable()) worker_.join();
  }

 private:
  struct Job {  // a converted scan (with or without pose) on its way to the worker
    online::ScanInput scan;
    std_msgs::Header header;
  };

  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    // Whole private namespace at once: validation sees every key (typos are reported).
    XmlRpc::XmlRpcValue tree;
    pnh.getParam(pnh.getNamespace(), tree);
    std::string error;
    std::vector<std::string> warnings;
    if (!ros_adapters::loadNodeConfig(tree, &config_, &error, &warnings)) {
      NODELET_FATAL("invalid parameters in %s: %s", pnh.getNamespace().c_str(), error.c_str());
      throw std::runtime_error("CoralNodelet: invalid parameters: " + error);  // load fails
    }
    for (const auto& w : warnings) NODELET_WARN("%s", w.c_str());
    introspector_ = online::Introspector(config_.online);
    stats_.doppler = config_.online.doppler.enabled;
    worker_ = std::thread(&CoralNodelet::work, this);
    source_ = std::make_unique<ros_adapters::ScanSource>(
        nh, config_, &stats_, [this](online::ScanInput scan, const std_msgs::Header& header) {
          // A posed scan replaces a scan still waiting for the worker (counted); a TF
          // failure notice never replaces anything.
          const bool droppable = scan.T_fixed_sensor.has_value();
          mailbox_.put(Job{std::move(scan), header}, droppable);
        });

    updater_ = std::make_shared<diagnostic_updater::Updater>(nh, pnh, getName());
    updater_->setHardwareID("coral_introspection");
    updater_->add("CorAl alignment", &stats_, &ros_adapters::Stats::diagnose);
    timer_ = nh.createWallTimer(ros::WallDuration(1.0), &CoralNodelet::timerCb, this);
    reconfigure_ =
        std::make_shared<dynamic_reconfigure::Server<ReconfigureConfig>>(reconfigure_mutex_, pnh);
    reconfigure_->updateConfig(  // start from the YAML values, not the .cfg defaults
        ros_adapters::toReconfigure<ReconfigureConfig>(config_));
    reconfigure_->setCallback(boost::bind(&CoralNodelet::reconfigureCb, this,
                                          boost::placeholders::_1, boost::placeholders::_2));
    service_ = nh.advertiseService("check_alignment", &CoralNodelet::checkAlignment, this);
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

  // The only thread that touches introspector_: the stream state needs no lock.
  void work() {
    while (std::optional<Job> job = mailbox_.take()) {
      guarded("worker", [&] {
        NodeConfig cfg;
        {
          std::lock_guard<std::mutex> lock(config_mutex_);
          if (config_changed_) introspector_.setConfig(config_.online, nullptr);  // valid
          config_changed_ = false;
          cfg = config_;
        }
        if (reset_requested_.exchange(false)) introspector_.reset();
        const online::ProcessOptions opt = outputs_.options(cfg, job->scan.is_radar);
        const online::Report r = introspector_.process(std::move(job->scan), opt);
        stats_.processed(r, job->header.stamp, mailbox_.dropped());
        if (!r.has_pose || r.action == online::PairAction::kBackwardsReset ||
            r.action == online::PairAction::kDuplicateReset)
          NODELET_WARN_THROTTLE(5.0, "%s", r.reason.c_str());
        else if (r.action == online::PairAction::kGapReset)
          NODELET_INFO_THROTTLE(10.0, "%s", r.reason.c_str());
        outputs_.publish(r, job->header, cfg.fixed_frame, opt);
      });
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
      updater_->force_update();
    });
  }

  NodeConfig config() {
    std::lock_guard<std::mutex> lock(config_mutex_);
    return config_;
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
  std::atomic<bool> reset_requested_{false};
  online::Mailbox<Job> mailbox_;
  online::Introspector introspector_;  // worker thread only
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
