#!/usr/bin/python3
"""A CARMEN log's laser scans as another scanner's beam spacing would give them (doc/loop_closure.md,
"Another beam spacing"). The Radish logs' scans are 180 beams of 1 deg from -90 deg; the loop gate's
bounds were chosen on them. This writes the same log with its FLASER lines resampled:

  --beams 361  0.5 deg (a SICK LMS in 0.5 deg mode): the original readings at the even beams; at
               each odd beam the range where the straight line through its two neighbours' points
               meets the beam (2 r1 r2 cos(0.5 deg) / (r1 + r2)), plus N(0, noise) [m], when both
               neighbours returned and lie within 0.05 m + 5 % of each other (a surface); else
               no return. Beam 360 (+90 deg) has no source: no return.
  --beams 91   2 deg: every second original reading; beam 90 (+90 deg): no return.

No return is written as NO_RETURN (81.83 m, Intel's) which the readers drop (>= 49.9 m). The
other lines (ODOM, PARAM, ...) and every field after the ranges are copied unchanged, so the
benchmark relations and the corrected poses (by stamp and by FLASER line) still apply: the
output's `.relations` is a copy of the input's.

  /usr/bin/python3 scripts/experiments/resample_carmen_beams.py IN.clf.bz2 OUT.clf.bz2 --beams 361
"""
import argparse
import bz2
import math
import os
import random
import shutil
import sys

NO_RETURN = 81.83
VALID = (0.05, 49.9)  # eval::LaserGeometry's min_range, max_range


def valid(r):
    return VALID[0] <= r < VALID[1]


def resample(ranges, beams, noise, rng):
    if beams == 91:
        return [ranges[2 * j] if 2 * j < len(ranges) else NO_RETURN for j in range(91)]
    out = []
    half = math.cos(math.radians(0.5))
    for j in range(361):
        i = j // 2
        if j % 2 == 0:
            out.append(ranges[i] if i < len(ranges) else NO_RETURN)
            continue
        if i + 1 >= len(ranges):
            out.append(NO_RETURN)
            continue
        r1, r2 = ranges[i], ranges[i + 1]
        if valid(r1) and valid(r2) and abs(r1 - r2) <= 0.05 + 0.05 * min(r1, r2):
            out.append(2.0 * r1 * r2 * half / (r1 + r2) + rng.gauss(0.0, noise))
        else:
            out.append(NO_RETURN)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('log_in')
    ap.add_argument('log_out')
    ap.add_argument('--beams', type=int, required=True, choices=[91, 361])
    ap.add_argument('--noise', type=float, default=0.01, help='[m] on interpolated readings')
    ap.add_argument('--seed', type=int, default=1)
    a = ap.parse_args()
    if not a.log_out.endswith('.clf.bz2'):
        sys.exit('log_out must end in .clf.bz2 (its relations go beside it as .relations)')
    rel_in = a.log_in[:-len('.clf.bz2')] + '.relations'
    if not a.log_in.endswith('.clf.bz2') or not os.path.exists(rel_in):
        sys.exit('log_in must be LOG.clf.bz2 with LOG.relations beside it')
    rng = random.Random(a.seed)
    n = 0
    with bz2.open(a.log_in, 'rt') as fin, bz2.open(a.log_out, 'wt') as fout:
        for line in fin:
            f = line.split()
            if not f or f[0] != 'FLASER':
                fout.write(line)
                continue
            count = int(f[1])
            if count != 180:
                sys.exit('expected 180-beam FLASER lines, got %d' % count)
            ranges = [float(x) for x in f[2:2 + count]]
            rest = f[2 + count:]
            new = resample(ranges, a.beams, a.noise, rng)
            fout.write(' '.join(['FLASER', str(len(new))] + ['%.3f' % r for r in new] + rest) + '\n')
            n += 1
    shutil.copyfile(rel_in, a.log_out[:-len('.clf.bz2')] + '.relations')
    print('%d FLASER lines resampled to %d beams: %s' % (n, a.beams, a.log_out))


if __name__ == '__main__':
    main()
