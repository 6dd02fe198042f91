// coral_error_sweep: the verdict of a preset on every pair of real data sets with known
// relative poses, at ground truth and at errors of every size: 1, 2, 4, 8x the tolerance in
// both directions of each axis, and yaw errors of 5, 15, 45, 90, 180 deg (issue: a verdict
// right for every error size). One CSV row per (pair, error) with the verdict and the terms
// behind it, so decision rules can be compared offline; a summary per error size on stderr.
//   rosrun coral_introspection coral_error_sweep --config PRESET.yaml --data SPEC [--data ...]
//       [--stride N] [--multiples K1,K2,... (default 1,2,4,8)]
//       [--yaw_deg D1,D2,... (default 5,15,45,90,180)] [--turn_axes yaw,roll,pitch,tilted]
//       [--oblique] [--loop_closure] [--rows all|even|odd] [--out FILE.csv]
// --turn_axes: the axes the fixed angles of --yaw_deg turn about (default yaw; roll, pitch and
// tilted, about (1, 1, 1), need a 3D preset): "any rotation", not only yaw.
// --oblique: also errors between the axes at each multiple (eval::sweepErrors): diagonals of two
// translation axes, and a translation with yaw, each of size k tolerances.
// --loop_closure: judge every pose as a loop-closure candidate (coral_check --loop_closure: the
// preset's loop_closure/ gate with its restart check and registration from the pose). The CSV's
// terms and `aligned` are then that verdict's own (method gated), not method both's.
// --rows even|odd: only the pairs of even / odd index (tuning and held-out halves), every
// --stride-th of those.
// SPEC as coral_train: oxford:DIR, keyframes:DIR, carmen:FILE.clf.bz2, cloudlist:FILE.
// "right": ground truth accepted (a valid, aligned verdict), an error not accepted (misaligned
// or no verdict, e.g. no overlap left). Exit 0 on success, 2 with a message for bad arguments
// or unreadable data.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "coral_introspection/config/text_fields.hpp"
#include "coral_introspection/eval/error_sweep.hpp"
#include "coral_introspection/eval/pair_datasets.hpp"
#include "coral_introspection/eval/tool_args.hpp"
#include "coral_introspection/online/introspector.hpp"
#include "coral_introspection/ros_eval/preset_file.hpp"

using namespace coral_introspection;

namespace {

constexpr const char* kUsage =
    "usage: coral_error_sweep --config PRESET.yaml --data SPEC [--data SPEC ...] [--stride N] "
    "[--multiples K1,K2,... (tolerances, >= 1; default 1,2,4,8)] "
    "[--yaw_deg D1,D2,... (deg, (0, 180]; default 5,15,45,90,180)] "
    "[--turn_axes A1,A2,... (yaw, roll, pitch, tilted; default yaw)] [--oblique] "
    "[--loop_closure] [--rows all|even|odd] "
    "[--out FILE.csv]";

int fail(const std::string& msg) { return eval::toolError("coral_error_sweep", msg, kUsage); }

}  // namespace

int main(int argc, char** argv) {
  eval::ToolArgs args;
  std::string err;
  int stride = 1;
  if (!eval::parseToolArgs(argc, argv,
                           {"--config", "--data", "--stride", "--multiples", "--yaw_deg",
                            "--turn_axes", "--rows", "--out"},
                           {"--oblique", "--loop_closure"}, &args, &err) ||
      !eval::positiveInt(args, "--stride", 1, &stride, &err))
    return fail(err);
  if (args.help) {
    std::printf("%s\n", kUsage);
    return 0;
  }
  const std::string config = args.get("--config"), out_path = args.get("--out");
  // --multiples: error sizes off the default grid 1, 2, 4, 8, which the coarse probe's steps
  // (2, 4, 6, 8 tolerances in lidar_2d) mostly coincide with: errors between them test it.
  std::vector<double> multiples;
  if (!eval::numberListOption(args, "--multiples", eval::sweepMultiples(), &multiples, &err))
    return fail(err);
  for (double k : multiples)
    if (k < 1.0 || k > 100.0)
      return fail("--multiples: " + std::to_string(k) +
                  " is not a number of tolerances in [1, 100]");
  // --yaw_deg: fixed yaw errors other than 5..180 deg (the coarse probe turns by a quarter and a
  // half: angles between them are the test of it).
  std::vector<double> yaw_degrees;
  if (!eval::numberListOption(args, "--yaw_deg", eval::sweepYawDegrees(), &yaw_degrees, &err))
    return fail(err);
  for (double d : yaw_degrees)
    if (!(d > 0.0 && d <= 180.0))
      return fail("--yaw_deg: " + std::to_string(d) + " is not an angle in (0, 180] deg");
  // --turn_axes: the axes of those fixed angles (default yaw). Empty fields ("roll,", "")
  // are refused like unknown names (config::splitFields, as numberListOption).
  std::vector<eval::TurnAxis> turn_axes = eval::sweepTurnAxes();
  if (args.has("--turn_axes")) {
    turn_axes.clear();
    for (const std::string& name : config::splitFields(args.get("--turn_axes"), ',')) {
      eval::TurnAxis a;
      if (!eval::parseTurnAxis(name, &a))
        return fail("--turn_axes: '" + name + "' is none of yaw, roll, pitch, tilted");
      turn_axes.push_back(a);
    }
  }
  std::string rows;
  if (!eval::choiceOption(args, "--rows", {"all", "even", "odd"}, &rows, &err)) return fail(err);
  if (config.empty() || !args.has("--data")) return fail("--config and --data are required");
  const std::vector<std::string>& specs = args.values.at("--data");
  ros_adapters::NodeConfig node;
  coral::VerdictConfig verdict;
  if (!ros_eval::loadPresetFile(config, &node, &verdict, &err))
    return fail(err);  // names the file (and line)
  for (eval::TurnAxis a : turn_axes)
    if (a != eval::TurnAxis::kYaw && node.online.coral.dimension != 3)
      return fail(std::string("--turn_axes: ") + eval::turnAxisName(a) + " needs a 3D preset (" +
                  config + " is 2D: its scans turn about yaw only)");
  // Every term of the verdict (classifier and relative check) in the CSV, `aligned` as method
  // both combines them; the summary and the CSV's last column (preset_aligned) count the
  // preset's own method and gate, combined from the same terms.
  // A loop-closure sweep judges with the loop verdict itself: its restart check and
  // registration from the pose are not terms combineVerdict could add afterwards.
  const bool loop_closure = args.flag("--loop_closure");
  online::IntrospectorConfig judge_cfg = node.online;
  if (loop_closure) {
    judge_cfg.verdict = coral::loopClosureVerdict(verdict);
  } else {
    judge_cfg.verdict.method = coral::VerdictMethod::kBoth;
    judge_cfg.verdict.measure_gate_terms = true;  // free space and constraint in the CSV too
  }
  std::ofstream file;
  if (!out_path.empty()) {
    file.open(out_path);
    if (!file) return fail("cannot write " + out_path);
  }
  std::ostream& out = out_path.empty() ? std::cout : file;
  out << eval::errorSweepCsvHeader() << "\n";
  // right / judged per error label, over every data set
  std::map<std::string, std::pair<int, int>> tally;
  for (const std::string& text : specs) {
    eval::DatasetSpec spec;
    if (!eval::parseDatasetSpec(text, &spec, &err)) return fail(err);
    eval::DatasetOptions opt;
    opt.oxford.rip = node.rip;
    opt.oxford.with_cfear = false;
    opt.oxford.motion_compensation = node.online.deskew.enabled;
    eval::PairDataset d;
    if (!eval::loadPairDataset(spec, opt, nullptr, &d, &err)) return fail(err);
    const std::vector<eval::SweepError> errors =
        eval::sweepErrors(verdict.tolerance, node.online.coral.dimension, multiples, yaw_degrees,
                          turn_axes, args.flag("--oblique"));
    const std::size_t first = rows == "odd" ? 1 : 0, step = (rows == "all" ? 1 : 2) * stride;
    for (std::size_t i = first; i < d.pairs.size(); i += step) {
      const eval::ScanPair& p = d.pairs[i];
      for (const eval::SweepError& e : errors) {
        const online::PairJudgement j = online::judgePair(d.scans[p.a].scan, d.scans[p.b].scan,
                                                          p.T_a_b * e.delta, judge_cfg, false);
        coral::AlignmentVerdict v = j.verdict;
        if (v.coral.valid && !loop_closure)
          coral::combineVerdict(verdict.method, v.classifier, v.relative, verdict.relative, &v,
                                verdict.gate, coral::gateTerms(v));
        const bool accepted = v.valid && v.aligned;  // no verdict = not accepted
        out << eval::errorSweepCsvRow(d.name, static_cast<int>(i), e, j.verdict, accepted) << "\n";
        auto& t = tally[e.label];
        t.second += 1;
        t.first += accepted == e.ground_truth;
      }
    }
    std::cerr << d.name << ": " << d.summary << "\n";
  }
  for (const auto& [label, t] : tally)
    std::cerr << "  " << label << ": right " << t.first << " / " << t.second << "\n";
  return 0;
}
