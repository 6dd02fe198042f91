#!/usr/bin/python3
"""Labels the loop candidates of a coral_pose_graph --carmen run against a corrected trajectory on
the raw log (../shared/data/radish_intel/*_corrected_poses_on_raw.csv), for doc/loop_closure.md
("On a CARMEN log"). Each keyframe is placed by the corrected pose of the nearest corrected scan
and the raw odometry between the two. Labels: true within 0.3 m and 3 deg, false at 0.6 m or
6 deg and more, band between. The corrected poses disagree with the benchmark relations by
decimetres in places, so a label is a diagnosis, not ground truth.

usage: label_pose_graph_candidates.py LOG.clf.bz2 CORRECTED.csv OUT_DIR (coral_pose_graph's)
prints counts as label/acc=accepted:count."""
import bisect
import bz2
import csv
import math
import sys

if len(sys.argv) != 4:
    sys.exit(__doc__)
log, corrected, out = sys.argv[1], sys.argv[2], sys.argv[3]
odo, stamps = [], []
for line in bz2.open(log, 'rt'):
    f = line.split()
    if not f or f[0] != 'FLASER': continue
    n = int(f[1]); x, y, th = map(float, f[2 + n:5 + n])
    odo.append((x, y, th)); stamps.append(float(f[8 + n]))
corr = {}
for r in open(corrected):
    if r.startswith('#') or not r.strip(): continue
    v = r.replace(',', ' ').split()
    corr[int(v[1])] = tuple(map(float, v[3:6]))
ci = sorted(corr)
def comp(a, b):
    return (a[0] + math.cos(a[2]) * b[0] - math.sin(a[2]) * b[1], a[1] + math.sin(a[2]) * b[0] + math.cos(a[2]) * b[1], a[2] + b[2])
def inv(a):
    c, s = math.cos(a[2]), math.sin(a[2])
    return (-c * a[0] - s * a[1], s * a[0] - c * a[1], -a[2])
def ref(line):
    k = bisect.bisect_left(ci, line)
    cands = [ci[j] for j in (k - 1, k) if 0 <= j < len(ci)]
    c = min(cands, key=lambda j: abs(j - line))
    return comp(corr[c], comp(inv(odo[c]), odo[line]))
kf_stamps = [float(l.split()[0]) for l in open(out + '/trajectory.tum')]
idx = {round(s, 4): i for i, s in enumerate(stamps)}
lines = [idx[round(s, 4)] for s in kf_stamps]
tab = {}
for r in csv.DictReader(open(out + '/candidates.csv')):
    a, b = lines[int(r['a'])], lines[int(r['b'])]
    t = comp(inv(ref(a)), ref(b))
    est = (float(r['x']), float(r['y']), math.radians(float(r['yaw_deg'])))
    d = comp(inv(t), est)
    e = math.hypot(d[0], d[1]); ang = abs(math.degrees(math.remainder(d[2], 2 * math.pi)))
    lab = 'true' if e <= 0.3 and ang <= 3 else ('false' if e >= 0.6 or ang >= 6 else 'band')
    key = (lab, r['accepted'])
    tab[key] = tab.get(key, 0) + 1
print(' '.join(f'{k[0]}/acc={k[1]}:{v}' for k, v in sorted(tab.items())))
