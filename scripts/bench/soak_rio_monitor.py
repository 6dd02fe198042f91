#!/usr/bin/env python3
"""Watches RioNodelet during a soak (scripts/bench/soak_rio.sh): the nodelet manager's RSS
(/proc/PID/status VmRSS) every --interval seconds, the odometry per loop of the played bag and
the nodelet's diagnostics counters. Prints a line every --report seconds and a summary at the end.
  soak_rio_monitor.py --pid-of /rio_manager --duration 1800 [--ready FILE]
Loops: the input's (trigger stamps jumping back by more than 1 s) and the odometry's (its stamps
jumping back). The steady state starts with the first RSS sample after --steady-loops input
loops are complete. Exit 1 when the RSS at the end is more than --max-growth percent above the
steady-state start, when the manager process is gone, when no odometry came for --stall
seconds, when a complete loop had less than --min-loop-fraction of the odometry of the best
loop, or when the nodelet counted callback errors; exit 0 otherwise."""
import argparse
import os
import statistics
import sys
import threading
import time
import xmlrpc.client

import rosgraph
import rospy
from diagnostic_msgs.msg import DiagnosticArray
from nav_msgs.msg import Odometry
from std_msgs.msg import Header

ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
ap.add_argument("--pid-of", default="/rio_manager", help="node whose process RSS is sampled")
ap.add_argument("--duration", type=float, default=1800.0, help="[s] wall time measured")
ap.add_argument("--interval", type=float, default=5.0, help="[s] between RSS samples")
ap.add_argument("--report", type=float, default=60.0, help="[s] between interim lines")
ap.add_argument("--steady-loops", type=int, default=2,
                help="input loops before the steady-state RSS sample")
ap.add_argument("--max-growth", type=float, default=5.0,
                help="[%%] allowed RSS growth from the steady-state start to the end")
ap.add_argument("--stall", type=float, default=30.0,
                help="[s] without odometry (after the first) counted as stopped publishing")
ap.add_argument("--keep-going", action="store_true",
                help="measure for the whole --duration after the odometry stopped (still exit 1)")
ap.add_argument("--min-loop-fraction", type=float, default=0.9,
                help="a complete loop needs this fraction of the best loop's odometry")
ap.add_argument("--odometry", default="/odometry")
ap.add_argument("--trigger", default="/sensor_platform/radar_right/trigger",
                help="input topic whose stamps count the loops (std_msgs/Header)")
ap.add_argument("--diagnostics", default="/diagnostics")
ap.add_argument("--diag-name", default="radar-inertial odometry",
                help="part of the nodelet's diagnostics status name")
ap.add_argument("--ready", default="", help="file written once subscribed and the PID is known")
args = ap.parse_args()

# Diagnostics keys of RioNodelet reported at the end (totals since the nodelet started).
KEYS = ["frames", "tracked frames", "resets", "time jumps back", "failed solves",
        "rejected frames", "imu gaps", "imu out of order", "scans without trigger",
        "trigger sequence restarts", "empty scans", "bad clouds", "bad imu messages",
        "callback errors"]


class State:
    def __init__(self):
        self.lock = threading.Lock()
        self.input_loops = 0          # trigger stamp jumps back seen (= input loops completed)
        self.last_trigger = None
        self.triggers = 0
        self.odom_loop_counts = [0]   # odometry messages per odometry loop (last: running)
        self.last_odom_stamp = None
        self.last_odom_wall = None
        self.odom_total = 0
        self.diag = {}
        self.diag_level = None
        self.diag_message = ""
        self.diag_count = 0


st = State()


def on_trigger(msg):
    t = msg.stamp.to_sec()
    with st.lock:
        if st.last_trigger is not None and t < st.last_trigger - 1.0:
            st.input_loops += 1
        st.last_trigger = t
        st.triggers += 1


def on_odometry(msg):
    t = msg.header.stamp.to_sec()
    with st.lock:
        if st.last_odom_stamp is not None and t < st.last_odom_stamp - 1.0:
            st.odom_loop_counts.append(0)
        st.last_odom_stamp = t
        st.odom_loop_counts[-1] += 1
        st.odom_total += 1
        st.last_odom_wall = time.monotonic()


def on_diagnostics(msg):
    for s in msg.status:
        if args.diag_name not in s.name:
            continue
        with st.lock:
            st.diag = {kv.key: kv.value for kv in s.values}
            st.diag_level = s.level
            st.diag_message = s.message
            st.diag_count += 1


def pid_of(node):
    master = rosgraph.Master("/soak_rio_monitor")
    uri = master.lookupNode(node)
    code, _, pid = xmlrpc.client.ServerProxy(uri).getPid("/soak_rio_monitor")
    if code != 1:
        raise RuntimeError("getPid of %s failed" % node)
    return int(pid)


def rss_kib(pid):
    try:
        with open("/proc/%d/status" % pid) as f:
            for line in f:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1])
    except OSError:
        return None
    return None


def diag_int(d, key):
    try:
        return int(float(d.get(key, "nan")))
    except ValueError:
        return None


def mib(kib):
    return kib / 1024.0


rospy.init_node("soak_rio_monitor", anonymous=True, disable_signals=True)
rospy.Subscriber(args.trigger, Header, on_trigger, queue_size=100)
rospy.Subscriber(args.odometry, Odometry, on_odometry, queue_size=1000)
rospy.Subscriber(args.diagnostics, DiagnosticArray, on_diagnostics, queue_size=100)

pid = None
deadline = time.monotonic() + 60.0
while pid is None:
    try:
        pid = pid_of(args.pid_of)
    except Exception:  # not registered yet
        if time.monotonic() > deadline:
            print("soak: node %s not found within 60 s" % args.pid_of)
            sys.exit(1)
        time.sleep(0.5)
time.sleep(1.0)  # let the subscriptions connect
if args.ready:
    with open(args.ready, "w") as f:
        f.write("%d\n" % pid)

def loadavg():
    with open("/proc/loadavg") as f:
        return " ".join(f.read().split()[:3])


load_start = loadavg()
start = time.monotonic()
samples = []          # (t [s], input loops completed, RSS [kB])
failures = []
next_report = args.report
crashed = False
stalls = 0            # times the odometry stopped for --stall seconds
stalled = False
while True:
    now = time.monotonic() - start
    rss = rss_kib(pid)
    with st.lock:
        loops = st.input_loops
        last_odom = st.last_odom_wall
        odom_total = st.odom_total
        d = dict(st.diag)
        counts = list(st.odom_loop_counts)
    if rss is None:
        crashed = True
        failures.append("the manager (pid %d) is gone at t = %.0f s: crashed" % (pid, now))
        break
    samples.append((now, loops, rss))
    if last_odom is None and now > 60.0:
        failures.append("no odometry within 60 s of the start")
        break
    if last_odom is not None and time.monotonic() - last_odom > args.stall:
        if not stalled:
            stalls += 1
            if stalls == 1:
                failures.append("no odometry for %.0f s at t = %.0f s (input loops %d): stopped "
                                "publishing" % (time.monotonic() - last_odom, now, loops))
            if not args.keep_going:
                break
        stalled = True
    else:
        stalled = False
    if now >= next_report:
        print("t = %6.0f s: input loops %d, odometry %d (this loop %d), RSS %.1f MiB, "
              "resets %s, time jumps back %s, scans without trigger %s, callback errors %s"
              % (now, loops, odom_total, counts[-1], mib(rss), d.get("resets", "?"),
                 d.get("time jumps back", "?"), d.get("scans without trigger", "?"),
                 d.get("callback errors", "?")), flush=True)
        next_report += args.report
    if now >= args.duration:
        break
    time.sleep(min(args.interval, max(0.1, args.duration - now)))
time.sleep(2.0)  # one more diagnostics update

with st.lock:
    loops = st.input_loops
    counts = list(st.odom_loop_counts)
    d = dict(st.diag)
    level, message, ndiag = st.diag_level, st.diag_message, st.diag_count
    triggers, odom_total = st.triggers, st.odom_total

print("\n== soak_rio: %.0f s measured, RSS every %.0f s of /proc/%d/status (%s) ==" %
      (samples[-1][0] if samples else 0.0, args.interval, pid, args.pid_of))
print("load average (1, 5, 15 min): at the start %s, at the end %s" % (load_start, loadavg()))
steady = [s for s in samples if s[1] >= args.steady_loops]
if steady:
    s0, end = steady[0], samples[-1]
    smax = max(steady, key=lambda s: s[2])
    growth = 100.0 * (end[2] - s0[2]) / s0[2]
    print("RSS: first sample %.1f MiB; steady-state start (t = %.0f s, after %d loops) %.1f MiB, "
          "max %.1f MiB (t = %.0f s, %+.1f %%), end %.1f MiB: drift %+.1f %%"
          % (mib(samples[0][2]), s0[0], args.steady_loops, mib(s0[2]), mib(smax[2]), smax[0],
             100.0 * (smax[2] - s0[2]) / s0[2], mib(end[2]), growth))
    if not crashed and growth > args.max_growth:
        failures.append("RSS grew by %.1f %% (> %.1f %%) from the steady-state start"
                        % (growth, args.max_growth))
else:
    print("RSS: no steady state reached (fewer than %d loops); samples %s"
          % (args.steady_loops, ", ".join("%.1f" % mib(s[2]) for s in samples[:5])))
    failures.append("fewer than %d input loops: no steady state" % args.steady_loops)
complete = counts[:-1]  # the last odometry loop is still running
print("loops completed: %d (trigger stamps jumped back %d times, %d triggers); odometry loops "
      "completed %d, odometry messages %d, odometry stopped for %.0f s or longer %d times"
      % (loops, loops, triggers, len(complete), odom_total, args.stall, stalls))
if complete:
    best = max(complete)
    print("odometry per loop: min %d, median %g, max %d (loop by loop: %s; running loop: %d)"
          % (min(complete), statistics.median(complete), best,
             " ".join(str(c) for c in complete), counts[-1]))
    short = [i + 1 for i, c in enumerate(complete) if c < args.min_loop_fraction * best]
    if short:
        failures.append("%d of %d loops (first: loop %d) had less than %.0f %% of the odometry "
                        "of the best loop (%d): stopped publishing"
                        % (len(short), len(complete), short[0], 100 * args.min_loop_fraction,
                           best))
if ndiag:
    jumps = diag_int(d, "time jumps back")
    resets = diag_int(d, "resets")
    print("diagnostics (%d reports; last: level %d, '%s'):" % (ndiag, level, message))
    print("  " + ", ".join("%s %s" % (k, d.get(k, "?")) for k in KEYS))
    n = max(1, len(complete))
    print("resets counted: %s health resets, %s time jumps back (restarts at a loop) in %d "
          "loops; per loop %.2f and %.2f" % (resets, jumps, len(complete), (resets or 0) / n,
                                              (jumps or 0) / n))
    if diag_int(d, "callback errors"):
        failures.append("callback errors: %s" % d.get("callback errors"))
else:
    failures.append("no diagnostics of the nodelet received")
if failures:
    print("FAIL: " + "; ".join(failures))
else:
    print("PASS: RSS within %.1f %%, odometry in every loop, no crash" % args.max_growth)
sys.stdout.flush()
os._exit(1 if failures else 0)  # without waiting for rospy's threads
