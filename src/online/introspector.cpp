#include "coral_introspection/online/introspector.hpp"

#include <sstream>

#include "coral_introspection/radar/radar_uncertainty.hpp"

namespace coral_introspection {
namespace online {

namespace {
std::string noVerdictReason(const coral::CoralResult& r, const coral::CoralConfig& cfg) {
  std::ostringstream s;
  if (r.num_points_a == 0 || r.num_points_b == 0)
    s << "a scan has no finite point (" << r.num_points_a << " and " << r.num_points_b << ")";
  else if (r.overlap < cfg.min_overlap)
    s << "overlap " << r.overlap << " below coral/min_overlap " << cfg.min_overlap
      << " (wrong transform or too far apart?)";
  else if (!r.reason.empty())  // degenerate input, refused size, ... (computeCoral's words)
    s << r.reason;
  else
    s << "no point with finite entropies (" << r.num_overlap
      << " overlapping; check coral/radius, coral/epsilon, coral/dimension)";
  // Input hygiene that explains an empty or degenerate pair (identical points, far points).
  if (r.num_merged > 0) s << "; " << r.num_merged << " coincident points merged";
  if (r.num_non_finite + r.num_out_of_range > 0)
    s << "; " << r.num_non_finite << " non-finite and " << r.num_out_of_range
      << " out-of-range points dropped";
  if (r.num_beyond_max_range > 0)
    s << "; " << r.num_beyond_max_range << " points beyond coral/max_range dropped";
  return s.str();
}
}  // namespace

PairJudgement judgePair(coral::Scan ref, const coral::Scan& cur, const Eigen::Isometry3d& T_ref_cur,
                        const IntrospectorConfig& cfg, bool per_point, bool keep_scans) {
  PairJudgement j;
  ref.origin = coral::Vec3::Zero();
  coral::CoralConfig cc = cfg.coral;
  cc.per_point = per_point;
  // The one verdict function (coral/verdict.hpp), as coral_train evaluates it: classifier
  // (Eq. 9-10), relative check at the tolerance, or both, as classifier/method says.
  j.prepared = coral::prepareVerdictPair(ref, cur, cc, cfg.verdict);
  j.verdict = coral::judgeAlignment(*j.prepared, T_ref_cur, cfg.verdict);
  if (keep_scans) {
    j.ref = std::move(ref);
    j.cur = coral::transformScan(cur, T_ref_cur);  // origin = cur's sensor (dynamic radius)
  }
  if (!j.verdict.coral.valid)
    j.reason = noVerdictReason(j.verdict.coral, cfg.coral);
  else if (!j.verdict.valid)
    j.reason = j.verdict.reason;
  return j;
}

Introspector::Introspector(const IntrospectorConfig& cfg)
    : cfg_(cfg),
      judging_(cfg),
      calibration_(cfg.calibration, cfg.verdict.classifier),
      pairing_(cfg.pairing),
      velocity_(cfg.deskew.window) {}

void Introspector::updateJudgingConfig() {
  judging_ = cfg_;
  if (cfg_.calibration.enabled) judging_.verdict.classifier = calibration_.classifier();
}

bool Introspector::setConfig(const IntrospectorConfig& cfg, std::string* error) {
  if (std::string e = cfg.validate(); !e.empty()) {
    if (error) *error = e;
    return false;
  }
  if (cfg.deskew.window != cfg_.deskew.window)
    velocity_ = radar::VelocityHistory(cfg.deskew.window);
  // Samples describe CorAl's features at one radius, dimension, floor and tolerance: other
  // settings start the calibration afresh.
  const coral::CoralConfig &o = cfg_.coral, &n = cfg.coral;
  if (o.radius != n.radius || o.dimension != n.dimension || o.epsilon != n.epsilon ||
      cfg_.verdict.tolerance.translation != cfg.verdict.tolerance.translation ||
      cfg_.verdict.tolerance.rotation_deg != cfg.verdict.tolerance.rotation_deg) {
    calibration_.clearSamples();
    pending_.reset();  // a pair prepared with the old settings would add old features
  }
  calibration_.setPrior(cfg.verdict.classifier);
  cfg_ = cfg;
  updateJudgingConfig();
  pairing_.setConfig(cfg.pairing);
  return true;
}

void Introspector::reset() {
  pairing_.reset();
  velocity_.reset();
  reference_.reset();
}

Report Introspector::process(ScanInput in, const ProcessOptions& options) {
  Report rep;
  rep.stamp = in.stamp;
  rep.id = in.id;
  ++counters_.scans;
  auto finish = [&](std::string reason) {
    rep.reason = std::move(reason);
    rep.counters = counters_;
    return rep;
  };
  if (!in.T_fixed_sensor) {
    ++counters_.pose_failures;
    return finish("no pose: " + (in.pose_error.empty() ? "unknown" : in.pose_error));
  }
  if (in.features.points.empty()) {
    ++counters_.empty_scans;
    return finish("empty scan (no points)");
  }
  rep.has_pose = true;
  Held cur;
  cur.T_fixed_sensor = *in.T_fixed_sensor;
  cur.stamp = in.stamp;
  cur.id = in.id;
  const double ref_stamp = pairing_.referenceStamp();
  rep.action = pairing_.offer(in.stamp, cur.T_fixed_sensor.translation());
  const bool sequence_start =
      rep.action == PairAction::kFirst || rep.action == PairAction::kGapReset ||
      rep.action == PairAction::kBackwardsReset || rep.action == PairAction::kDuplicateReset;
  if (sequence_start) velocity_.reset();
  const bool have_velocity = velocity_.add(in.stamp, cur.T_fixed_sensor);

  // The one de-skew policy (radar/deskew.hpp), exactly as deskewVelocities() in training; a
  // lidar scan whose beams carry their times is de-skewed the same way.
  if ((in.is_radar || in.point_stamps) && cfg_.deskew.enabled) {
    if (have_velocity) {
      const radar::Twist v = velocity_.deskewVelocity();
      radar::compensateMotion(v, in.stamp, &in.features);
      rep.deskewed = true;
      if (reference_ && reference_->needs_deskew) {  // first scan of the sequence
        radar::compensateMotion(v, reference_->stamp, &reference_->features);
        reference_->needs_deskew = false;
      }
    } else {
      cur.needs_deskew = true;
    }
  }
  if (cfg_.doppler.enabled && have_velocity && !in.radial_velocity.empty()) checkDoppler(in, &rep);
  if (options.keep_features) rep.features = in.features;
  cur.features = std::move(in.features);

  std::ostringstream why;
  switch (rep.action) {
    case PairAction::kPair:
      judge(cur, options, &rep);
      break;
    case PairAction::kFirst:
      why << "first scan of a sequence (becomes the reference)";
      break;
    case PairAction::kTooClose:
      ++counters_.too_close;
      why << "travelled less than pairing/min_distance = " << cfg_.pairing.min_distance
          << " m from the reference";
      break;
    case PairAction::kGapReset:
      ++counters_.gap_resets;
      why << "reference " << in.stamp - ref_stamp
          << " s old > pairing/max_time_gap = " << cfg_.pairing.max_time_gap
          << " s: pairing restarts";
      break;
    case PairAction::kBackwardsReset:
      ++counters_.time_resets;
      why << "time jumped backwards (" << ref_stamp << " s -> " << in.stamp
          << " s, looping bag?): pairing restarts";
      break;
    case PairAction::kDuplicateReset:
      ++counters_.duplicate_stamps;
      why << "two scans with stamp " << in.stamp << " s: pairing restarts";
      break;
  }
  if (rep.action != PairAction::kTooClose) reference_ = std::move(cur);
  return finish(rep.judged ? rep.pair.reason : why.str());
}

void Introspector::judge(Held& cur, const ProcessOptions& options, Report* rep) {
  Held& ref = *reference_;
  coral::Scan a, b;
  a.points = std::move(ref.features.points);  // ref is replaced by cur afterwards
  b.points = cur.features.points;
  rep->judged = true;
  rep->stamp_ref = ref.stamp;
  rep->id_ref = ref.id;
  rep->T_fixed_ref = ref.T_fixed_sensor;
  const Eigen::Isometry3d T_ref_cur = ref.T_fixed_sensor.inverse() * cur.T_fixed_sensor;
  rep->pair =
      judgePair(std::move(a), b, T_ref_cur, judging_, options.per_point, options.keep_scans);
  // Self-calibration: set the prepared pair aside for calibrate() (newest wins if not
  // called); its extra poses then cost only the other-cloud searches.
  if (cfg_.calibration.enabled && rep->pair.verdict.coral.valid && calibration_.select()) {
    CalibrationJob job;
    job.pair = rep->pair.prepared;
    job.T_ref_cur = T_ref_cur;
    job.at_pose = rep->pair.verdict.coral;
    job.at_pose.per_point.clear();
    pending_ = std::move(job);
  }
  rep->pair.prepared.reset();  // freed now unless calibration holds it
  ++counters_.pairs;
  counters_.coral_seconds += rep->pair.verdict.coral.seconds;
  counters_.coral_evaluations += 1 + rep->pair.verdict.relative.coral_evaluations;
  if (rep->pair.verdict.valid) {
    ++counters_.valid_pairs;
    if (!rep->pair.verdict.aligned) ++counters_.misaligned;
  }
}

bool Introspector::calibrate() {
  if (!pending_) return false;
  const CalibrationJob job = std::move(*pending_);
  pending_.reset();
  // Features at the configured CorAl settings and tolerance; the relative check's margin
  // settings decide acceptance (never the classifier being calibrated).
  calibration_.addPair(*job.pair, job.T_ref_cur, job.at_pose, cfg_.verdict);
  updateJudgingConfig();
  return true;
}

// Doppler (paper 2, Eq. 9-12): the odometry's latest velocity (sensor frame) against the
// radial velocities, each point weighted by its propagated polar covariance.
void Introspector::checkDoppler(const ScanInput& in, Report* rep) {
  DopplerReport d;
  d.velocity_odometry = velocity_.lastTwist().linear;
  d.num_points = in.radial_velocity.size();
  coral::Scan s;
  const coral::Covariances* cov = nullptr;
  if (in.covariances.size() == in.features.points.size()) {
    cov = &in.covariances;
  } else if (cfg_.doppler.point_covariances) {
    s.points = in.features.points;  // sensor frame, sensor at the origin
    if (radar::attachCovariances(s, cfg_.doppler.noise, 3, nullptr)) cov = &s.covariances;
  }
  d.result = radar::checkVelocityConsistency(in.features.points, in.radial_velocity,
                                             d.velocity_odometry, cfg_.doppler.check, cov);
  ++counters_.doppler_checks;
  if (d.result.valid && !d.result.consistent) ++counters_.doppler_inconsistent;
  rep->doppler = std::move(d);
}

}  // namespace online
}  // namespace coral_introspection
