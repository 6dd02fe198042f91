#!/usr/bin/python3
"""Per-pair table of the ACES relations whose default lidar_2d verdict is wrong, with an
independent check of each relation by point-to-line ICP (doc/verdict_pairs.md).

Reads the lines "  pair N (stamps ...) <class>; wrong: ...; ..." that test_preset_verdicts
prints, runs ICP (scans of radish_aces, no CorAl) started at the relation and at the relation
moved by +-0.3 m along x (b's frame), and prints a markdown table. Needs python3-numpy and
python3-scipy (Debian packages).

  devel/lib/coral_introspection/test_preset_verdicts --gtest_filter='*Aces*' \
    | scripts/experiments/aces_relation_icp.py [DATA_DIR]
  scripts/experiments/aces_relation_icp.py [DATA_DIR] --all < /dev/null   # ICP on every relation: summary
"""
import bz2
import math
import re
import sys

import numpy as np
from scipy.spatial import cKDTree

TOL = 0.3  # [m] lidar_2d tolerance
LOW_OVERLAP = 0.6  # below this the pair is a loop closure seen from afar (median ~0.85)


def read_log(path):
    """FLASER ranges by ipc_timestamp (rounded to 1e-4 s), as eval/carmen_log.cpp reads them."""
    scans = {}
    for line in bz2.open(path, 'rt'):
        if line.startswith('FLASER '):
            f = line.split()
            n = int(f[1])
            scans[round(float(f[2 + n + 6]), 4)] = np.array(list(map(float, f[2:2 + n])))
    return scans


def points(ranges):  # LaserGeometry defaults: 180 beams of 1 deg from -90 deg, 0.05-49.9 m
    a = -math.pi / 2 + np.arange(len(ranges)) * math.pi / 180
    ok = (ranges >= 0.05) & (ranges < 49.9)
    return np.c_[ranges[ok] * np.cos(a[ok]), ranges[ok] * np.sin(a[ok])]


def se2(x, y, th):
    c, s = math.cos(th), math.sin(th)
    return np.array([[c, -s, x], [s, c, y], [0, 0, 1.0]])


def xyth(m):
    return m[0, 2], m[1, 2], math.atan2(m[1, 0], m[0, 0])


def normals(a, tree, radius=0.5):
    """Line normal per point of a (NaN where the neighbourhood is not line-like)."""
    n = np.full(a.shape, np.nan)
    for i, nb in enumerate(tree.query_ball_point(a, radius)):
        if len(nb) >= 3:
            d = a[nb] - a[nb].mean(0)
            w, v = np.linalg.eigh(d.T @ d)
            if w[0] < 0.1 * w[1]:
                n[i] = v[:, 0]
    return n


def icp(a, b, m0, iterations=40):
    """Point-to-line ICP of b onto a from T_a_b = m0 (Huber 5 cm, gates 0.5 then 0.3 m).
    Returns T_a_b and the translation information sum (R^T n)(R^T n)^T in b's frame."""
    tree = cKDTree(a)
    nrm = normals(a, tree)
    m = m0.copy()
    for k in range(iterations):
        p = (m[:2, :2] @ b.T).T + m[:2, 2]
        d, j = tree.query(p, distance_upper_bound=0.5 if k < 10 else 0.3)
        ok = np.isfinite(d)
        ok[ok] &= np.isfinite(nrm[j[ok], 0])
        if ok.sum() < 10:
            return None, None
        n, p, q = nrm[j[ok]], p[ok], a[j[ok]]
        r = np.sum(n * (p - q), 1)
        jac = np.c_[n[:, 0], n[:, 1], -n[:, 0] * p[:, 1] + n[:, 1] * p[:, 0]]
        w = np.minimum(1.0, 0.05 / np.maximum(np.abs(r), 1e-9))
        step = -np.linalg.solve(jac.T @ (jac * w[:, None]) + 1e-9 * np.eye(3), jac.T @ (w * r))
        m = se2(*step) @ m
        if np.linalg.norm(step) < 1e-5:
            break
    nb = n @ m[:2, :2]
    return m, nb.T @ nb


def category(row, dx):
    """Why the verdict is wrong, checked in this order (doc/verdict_pairs.md)."""
    if row['overlap'] < LOW_OVERLAP:
        return 'low overlap (loop closure)'
    # Directions in which the pair looks better than the relation: an offset with Q <= Q at
    # the relation, or an offset judged aligned.
    signs = {1 if o.endswith('+') else -1 for o in row['qorder'] if o.startswith('x')}
    signs |= {1 for w in row['wrong'].split(';') if w.strip() == 'forward'}
    signs |= {-1 for w in row['wrong'].split(';') if w.strip() == 'backward'}
    if math.isfinite(dx) and abs(dx) >= TOL / 2 and any(dx * s > 0 for s in signs):
        return 'relation off along x (ICP, same side)'
    if 'x' in row['flat']:
        return ('corridor: Q minimum off the relation along flat x' if row['class'] == 'Q order'
                else 'corridor: Q rise along flat x within the margin')
    return 'other'


def summary_all(data):
    """ICP from every relation: how far along x / y (b's frame) it moves the relation."""
    scans = read_log(data + '/aces.clf.bz2')
    dx, dy = [], []
    for ln in open(data + '/aces.relations'):
        if not ln.strip():
            continue
        t1, t2, x, y, _, _, _, yaw = map(float, ln.split())
        m0 = se2(x, y, yaw)
        m, _ = icp(points(scans[round(t1, 4)]), points(scans[round(t2, 4)]), m0)
        if m is not None:
            d = xyth(np.linalg.inv(m0) @ m)
            dx.append(abs(d[0]))
            dy.append(abs(d[1]))
    for name, v in (('x', np.array(dx)), ('y', np.array(dy))):
        print('|ICP d%s| over %d relations: median %.3f m, 90th percentile %.3f m, >= %.2f m: %d'
              % (name, len(v), np.median(v), np.percentile(v, 90), TOL / 2, int((v >= TOL / 2).sum())))


def main():
    args = [a for a in sys.argv[1:] if a != '--all']
    data = args[0] if args else '../shared/data/radish_aces'
    if '--all' in sys.argv:
        summary_all(data)
        return
    pat = re.compile(r'^\s+pair (\d+) \(stamps ([\d.]+) ([\d.]+)\) ([^;]+); wrong:(.*?); flat:(.*?); '
                     r'Q <= Q\(ground truth\) at:(.*?); \(Q\(x\+\) - Q\)/S (\S+), \(Q\(x-\) - Q\)/S '
                     r'(\S+), S (\S+) nats; overlap (\S+)')
    rows = {}
    for line in sys.stdin:
        mt = pat.match(line)
        if mt:
            g = mt.groups()
            rows[int(g[0])] = dict(t1=float(g[1]), t2=float(g[2]), cls=g[3], wrong=g[4].strip(),
                                   flat=g[5].split(), qorder=g[6].split(), up=float(g[7]),
                                   down=float(g[8]), scale=float(g[9]), overlap=float(g[10]))
            rows[int(g[0])]['class'] = g[3]
    scans = read_log(data + '/aces.clf.bz2')
    rel = [list(map(float, ln.split())) for ln in open(data + '/aces.relations') if ln.strip()]
    print('| pair | stamps [s] | class | wrong | flat | Q <= Q(GT) at | (Q(x+)-Q)/S | (Q(x-)-Q)/S '
          '| overlap | ICP dx [m] (from x+0.3, x-0.3) | ICP info x/y | category |')
    print('|' + '---|' * 12)
    counts = {}
    for i in sorted(rows):
        r = rows[i]
        t1, t2, x, y, _, _, _, yaw = rel[i]
        assert abs(t1 - r['t1']) < 0.01 and abs(t2 - r['t2']) < 0.01, 'pair %d: stamps differ' % i
        a, b = points(scans[round(t1, 4)]), points(scans[round(t2, 4)])
        m0 = se2(x, y, yaw)
        out = []
        for start in (0.0, TOL, -TOL):
            m, info = icp(a, b, m0 @ se2(start, 0, 0))
            out.append((xyth(np.linalg.inv(m0) @ m)[0], info) if m is not None else (math.nan, None))
        dx, info = out[0]
        ratio = info[0, 0] / info[1, 1] if info is not None else math.nan
        cat = category(r, dx)
        n_wrong = len([w for w in r['wrong'].split(';') if w.strip()])
        pairs_, wrong_ = counts.get(cat, (0, 0))
        counts[cat] = (pairs_ + 1, wrong_ + n_wrong)
        print('| %d | %.2f %.2f | %s | %s | %s | %s | %.4f | %.4f | %.2f | %.3f (%.3f, %.3f) | %.3f | %s |'
              % (i, r['t1'], r['t2'], r['class'], r['wrong'].replace(';', ','),
                 ' '.join(r['flat']) or '-', ' '.join(r['qorder']) or '-', r['up'], r['down'],
                 r['overlap'], dx, out[1][0], out[2][0], ratio, cat))
    print()
    for c in sorted(counts):
        print('- %s: %d pairs, %d wrong verdicts' % (c, counts[c][0], counts[c][1]))


main()
