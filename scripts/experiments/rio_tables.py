#!/usr/bin/env python3
"""Tables I and II of the point-uncertainty paper for the radar-inertial odometry.

Table I: full uncertainty model vs none / without its range part / without its bearing part
(uncertainty/mode). Table II: every point covariance scaled by 2^alpha, alpha = -3..3
(uncertainty/covariance_scale). Simulated sequences (coral_rio_simulate, ground truth: APE /
RPE RMSE) and the TI loop (rio_offline on the bag: end-point error, no ground truth).

  scripts/experiments/rio_tables.py --bin $CORAL_WS/devel/lib/coral_introspection \
      [--bag ../shared/data/ti_mmwave_demo/ti_mmwave_rospkg_demo.bag] [--work /tmp/rio_tables] \
      [--barometer]
Prints Markdown (the tables of doc/rio.md). Every row runs with barometer/enabled=false (the TI
config turns it on), or with --barometer: sequences simulated with a barometer, every row run
with barometer/enabled=true (plus a "barometer off" row in Table I), and a third figure per
cell: vertical APE RMSE (m) / the TI loop's vertical end-point error (m).
"""
import argparse
import os
import re
import subprocess
import sys

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SIMS = [("handheld", 1), ("handheld", 2), ("vehicle", 1), ("vehicle", 2)]
# Table I rows. The paper removes a part by "setting sigma_r or Sigma_Omega to a very small
# value" (Sec. IV-B; uncertainty/ablation_shrink); the last two rows replace it by the
# isotropic sigma instead (a variant of this package).
MODES = [("full model", ["uncertainty/mode=full"]),
         ("no uncertainty model", ["uncertainty/mode=none"]),
         ("without range part", ["uncertainty/mode=no_range"]),
         ("without bearing part", ["uncertainty/mode=no_bearing"]),
         ("range part replaced by isotropic sigma",
          ["uncertainty/mode=no_range", "uncertainty/ablation_replace=true"]),
         ("bearing part replaced by isotropic sigma",
          ["uncertainty/mode=no_bearing", "uncertainty/ablation_replace=true"])]
FLOAT = r"([-+0-9.eE]+|nan|inf)"


def run(cmd):
    out = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if out.returncode != 0:
        sys.exit("failed: %s\n%s" % (" ".join(cmd), out.stdout))
    return out.stdout


def sim_metrics(args, seq, kind, sets):
    cmd = [os.path.join(args.bin, "coral_rio_run"), "--sequence", seq, "--config",
           os.path.join(REPO, "config", "rio_sim_%s.yaml" % kind)]
    for s in baro_sets(args) + sets:
        cmd += ["--set", s]
    out = run(cmd)
    m = re.search(r"APE RMSE: %s m, %s deg; RPE RMSE: %s m, %s deg" % ((FLOAT,) * 4), out)
    if not m:
        return "fail"
    cell = "%.3f / %.4f" % (float(m.group(1)), float(m.group(3)))
    v = re.search(r"vertical APE RMSE: %s m" % FLOAT, out)
    return cell + (" / %.3f" % float(v.group(1)) if args.barometer and v else "")


def baro_sets(args):
    # Without --barometer explicitly off: config/rio_ti_mmwave.yaml turns it on.
    return ["barometer/enabled=%s" % ("true" if args.barometer else "false")]


def ti_metrics(args, sets):
    config = os.path.join(REPO, "config", "rio_ti_mmwave.yaml")
    if args.bag:
        cmd = [args.rio_offline, "--bag", args.bag, "--config", config, "--output",
               os.path.join(args.work, "ti.tum")]
    else:  # the bag converted to a text sequence (trigger times already applied)
        cmd = [os.path.join(args.bin, "coral_rio_run"), "--sequence", args.ti_sequence,
               "--config", config, "--loop"]
    for s in baro_sets(args) + sets:
        cmd += ["--set", s]
    out = run(cmd)
    m = re.search(r"horizontal %s m, vertical %s m, yaw %s deg" % ((FLOAT,) * 3), out)
    if not m:
        return "fail"
    cell = "%.3f / %.2f" % (float(m.group(1)), abs(float(m.group(3))))
    return cell + (" / %+.3f" % float(m.group(2)) if args.barometer else "")


def table(args, seqs, rows):
    vert = " / vertical APE" if args.barometer else ""
    head = ["setting"] + ["%s %d (APE / RPE%s m)" % (k, s, vert) for k, s in SIMS]
    if args.bag or args.ti_sequence:
        head.append("TI loop (end-point m / yaw deg%s)" % (" / vertical m" if vert else ""))
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for label, sets in rows:
        cells = [label] + [sim_metrics(args, seq, k, sets) for (k, _), seq in zip(SIMS, seqs)]
        if args.bag or args.ti_sequence:
            cells.append(ti_metrics(args, sets))
        lines.append("| " + " | ".join(cells) + " |")
        print(lines[-1], file=sys.stderr)
    return "\n".join(lines)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--bin", required=True, help="directory of coral_rio_simulate / coral_rio_run")
    p.add_argument("--rio-offline", default="", help="rio_offline (default: --bin/rio_offline)")
    p.add_argument("--bag", default="", help="the TI bag; empty = simulated sequences only")
    p.add_argument("--ti-sequence", default="",
                   help="instead of --bag: the TI bag as a coral_rio_run text sequence")
    p.add_argument("--work", default="/tmp/rio_tables")
    p.add_argument("--tables", default="1,2", help="which tables: 1, 2 or 1,2")
    p.add_argument("--barometer", action="store_true",
                   help="simulate a barometer and run every row with it (vertical APE)")
    args = p.parse_args()
    args.rio_offline = args.rio_offline or os.path.join(args.bin, "rio_offline")
    os.makedirs(args.work, exist_ok=True)
    seqs = []
    for kind, seed in SIMS:
        seq = os.path.join(args.work, "%s_%d.seq" % (kind, seed))
        run([os.path.join(args.bin, "coral_rio_simulate"), "--trajectory", kind, "--seed",
             str(seed), "--output", seq] + (["--barometer"] if args.barometer else []))
        seqs.append(seq)
    if "1" in args.tables:
        print("### Table I: uncertainty model ablation\n")
        off = [("full model, barometer off", ["barometer/enabled=false"])]
        print(table(args, seqs, MODES + (off if args.barometer else [])))
    if "2" in args.tables:
        print("\n### Table II: point covariances scaled by 2^alpha\n")
        print(table(args, seqs, [("alpha = %+d" % a, ["uncertainty/covariance_scale=%g" % 2.0 ** a])
                                 for a in range(-3, 4)]))


if __name__ == "__main__":
    main()
