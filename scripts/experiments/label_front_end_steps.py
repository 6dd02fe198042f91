#!/usr/bin/python3
"""Labels the odometry steps of a coral_pose_graph --carmen --front_end run (OUT_DIR/front_end.csv)
against a corrected trajectory on the raw log (../shared/data/radish_intel/*_corrected_poses_on_raw.csv),
for doc/loop_closure.md ("The front end's second try"). Only steps whose two keyframes are
themselves corrected scans (the same stamp) are labelled: no odometry is interpolated (a
line's worth of it moved labels by a tolerance). A step is off when its error is a tolerance
or more: max(translation / 0.3 m, rotation / 5 deg), coral::toleranceSize at lidar_2d's
tolerance.

usage: label_front_end_steps.py CORRECTED.csv OUT_DIR
prints, per source (registration, verdict_registration, odometry): steps labelled, off, and the
largest error in tolerances; then each step off."""
import csv
import math
import sys

if len(sys.argv) != 3:
    sys.exit(__doc__)
corrected, out = sys.argv[1], sys.argv[2]
truth = {}
for r in open(corrected):
    if r.startswith('#') or not r.strip(): continue
    v = r.strip().split(',')
    truth[round(float(v[2]), 4)] = tuple(map(float, v[3:6]))
def between(a, b):  # b in a's frame
    c, s = math.cos(a[2]), math.sin(a[2]); dx, dy = b[0] - a[0], b[1] - a[1]
    return (c * dx + s * dy, -s * dx + c * dy, math.atan2(math.sin(b[2] - a[2]), math.cos(b[2] - a[2])))
def tolerances(step, ref):
    e = between(ref, step)
    return max(math.hypot(e[0], e[1]) / 0.3, abs(math.degrees(e[2])) / 5.0)
counts, off = {}, []
for row in csv.DictReader(open(out + '/front_end.csv')):
    a, b = truth.get(round(float(row['stamp_a']), 4)), truth.get(round(float(row['stamp_b']), 4))
    if a is None or b is None: continue
    size = tolerances((float(row['x']), float(row['y']), math.radians(float(row['yaw_deg']))), between(a, b))
    c = counts.setdefault(row['source'], [0, 0, 0.0])
    c[0] += 1; c[1] += size >= 1.0; c[2] = max(c[2], size)
    if size >= 1.0: off.append((row['a'], row['b'], row['source'], round(size, 2)))
for source, (n, k, worst) in sorted(counts.items()):
    print('%s: %d steps labelled, %d off by a tolerance or more, largest %.2f tolerances' % (source, n, k, worst))
for a, b, source, size in off:
    print('off: step %s-%s (%s) %.2f tolerances' % (a, b, source, size))
