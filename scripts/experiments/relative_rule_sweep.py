#!/usr/bin/python3
"""Variants of the relative check's decision (coral::decideRelative) on coral_train's verdict
samples, chosen on the first half of the pairs and reported on the second half
(doc/verdict_pairs.md). The baseline row reproduces decideRelative (margin 0.2, flat ratio
0.1) and test_preset_verdicts' ACES counts. Variants, per axis k with s_k = (Q - min of its
two neighbours) / S_k (relative_check.hpp):
  margin m        misaligned when max_k s_k > m (the preset's rule, m = 0.2);
  flat floor f    s_k divides by max(S_k, f * largest S): a flat axis needs an absolute drop;
  flat margin m'  flat axes (S_k < 0.1 largest S) use margin m' instead of 0.2;
  ignore flat     flat axes do not decide.

  scripts/experiments/relative_rule_sweep.py /tmp/coral_verdict_samples/lidar_2d_aces.csv
"""
import collections
import csv
import math
import sys

CASES = ['aligned', 'x+', 'x-', 'y+', 'y-']  # the test's five cases (ground truth, 4 offsets)


def misaligned(row, margin=0.2, flat_ratio=0.1, floor=0.0, flat_margin=None, ignore_flat=False):
    q = float(row['Relative/Q'])
    axes = collections.OrderedDict()
    for k, v in row.items():
        if k.startswith('Relative/Q_'):
            axes.setdefault(k[len('Relative/Q_'):-1], []).append(float(v) if v else math.nan)
    sens, low = {}, {}
    for ax, vals in axes.items():
        vals = [v for v in vals if math.isfinite(v)]
        if vals and math.isfinite(q):
            sens[ax] = sum(abs(v - q) for v in vals) / len(vals)
            low[ax] = min(vals)
    if not sens:
        return None
    scale = max(sens.values())
    worst = None
    for ax, s in sens.items():
        flat = s < flat_ratio * scale
        if (flat and ignore_flat) or max(s, floor * scale) <= 0:
            continue
        m = flat_margin if (flat and flat_margin is not None) else margin
        excess = (q - low[ax]) / max(s, floor * scale) - m
        worst = excess if worst is None else max(worst, excess)
    return None if worst is None else worst > 0


def main():
    pairs = collections.OrderedDict()
    for r in csv.DictReader(open(sys.argv[1])):
        pairs.setdefault(int(r['pair']), {})[r['offset']] = r
    ids = sorted(pairs)
    split = ids[len(ids) // 2]  # as verdict_evaluation.cpp's dataParts
    variants = [('baseline: margin 0.2', {})]
    variants += [('margin %g' % m, dict(margin=m)) for m in (0.0, 0.1, 0.3, 0.5)]
    variants += [('flat floor %g' % f, dict(floor=f)) for f in (0.01, 0.02, 0.05, 0.1)]
    variants += [('flat margin %g' % m, dict(flat_margin=m)) for m in (0.0, 0.1, 0.3, 0.5, 1.0)]
    variants += [('ignore flat axes', dict(ignore_flat=True))]
    print('Wrong verdicts of %d x %d cases (ground truth, x+, x-, y+, y-); first half: pairs < %d'
          % (len(ids), len(CASES), split))
    print()
    print('| Variant | first half (choice) | second half (report) | second half: GT, x+, x-, y+, y- |')
    print('|---|---|---|---|')
    for name, kw in variants:
        wrong = {True: collections.Counter(), False: collections.Counter()}
        for p in ids:
            for c in CASES:
                m = misaligned(pairs[p][c], **kw)
                if m is None or m != (c != 'aligned'):
                    wrong[p < split][c] += 1
        print('| %s | %d | %d | %s |' % (name, sum(wrong[True].values()), sum(wrong[False].values()),
                                        ', '.join(str(wrong[False][c]) for c in CASES)))


main()
