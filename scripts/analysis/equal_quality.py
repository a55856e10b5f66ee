#!/usr/bin/env python3
"""equal_quality.py LOW.json HIGH.json [METHOD]: how long the path tracer needs to match a model.

Two `ltm eval` reports of the same views whose PT baselines ran at two sample counts (--baseline-spp
s1 and s2; the method rows named pt<spp>). Per view, PT's MSE against the reference is modelled as
    e(spp) = a / spp + b
(a: PT's variance per sample, b: what stays, mostly the reference's own noise), fitted through the two
baselines. The spp where PT meets the model's MSE is a / (m - b) (none when m <= b: the model is below
what PT converges to against this reference; none either when a <= 0, PT no better at s2 than at s1), its time that spp at PT's measured rate (the HIGH run's
seconds per spp), and the ratio that time over the model's own seconds (both runs' mean). Prints a
markdown table, the geometric mean of the ratios, and the same on the views' mean MSE. Issue #31's
equal-quality target reads off it: PT needs >= 10x the model's time on generated houses.
"""
import json
import math
import sys


def rows(path):
    """{(scene, view): {method: row}} of one report."""
    with open(path) as f:
        report = json.load(f)
    return {(v['scene'], v['view']): {m['method']: m for m in v['methods']} for v in report['views']}


def pt_row(methods):
    """The PT baseline row (pt<spp>), not pt-equal-time."""
    for name, row in methods.items():
        if name.startswith('pt') and name[2:].isdigit():
            return row
    sys.exit('equal_quality.py: a view has no pt<spp> row')


def fit(s1, e1, s2, e2):
    """a, b of e = a/spp + b through (s1, e1) and (s2, e2)."""
    a = (e1 - e2) / (1.0 / s1 - 1.0 / s2)
    return a, e1 - a / s1


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    low, high = rows(sys.argv[1]), rows(sys.argv[2])
    model = sys.argv[3] if len(sys.argv) > 3 else 'model:ours'
    if set(low) != set(high):
        sys.exit('equal_quality.py: the two reports hold different views')
    print('| view | model MSE | PT %d / %d spp | PT matches at | PT time there | model time | ratio |'
          % (pt_row(next(iter(low.values())))['spp'], pt_row(next(iter(high.values())))['spp']))
    print('|---|---|---|---|---|---|---|')
    ratios, means = [], {'m': 0.0, 'e1': 0.0, 'e2': 0.0, 't': 0.0, 'rate': 0.0}
    for key in sorted(low):
        lo, hi = low[key], high[key]
        if model not in lo or model not in hi:
            sys.exit('equal_quality.py: no row %s for %s' % (model, key[0]))
        p1, p2 = pt_row(lo), pt_row(hi)
        m = 0.5 * (lo[model]['metrics']['mse'] + hi[model]['metrics']['mse'])
        t = 0.5 * (lo[model]['seconds'] + hi[model]['seconds'])
        rate = p2['seconds'] / p2['spp']
        e1, e2 = p1['metrics']['mse'], p2['metrics']['mse']
        a, b = fit(p1['spp'], e1, p2['spp'], e2)
        for k, v in (('m', m), ('e1', e1), ('e2', e2), ('t', t), ('rate', rate)):
            means[k] += v / len(low)
        name = '%s/%s' % key
        if a <= 0:
            print('| %s | %.4f | %.4f / %.4f | — (PT no better at more spp: no fit) | — | %.2f s | — |' % (name, m, e1, e2, t))
        elif m <= b:
            print('| %s | %.4f | %.4f / %.4f | — (below PT\'s limit %.4f) | — | %.2f s | — |' % (name, m, e1, e2, b, t))
        else:
            spp = a / (m - b)
            ratios.append(spp * rate / t)
            print('| %s | %.4f | %.4f / %.4f | %.0f spp | %.1f s | %.2f s | %.1f× |'
                  % (name, m, e1, e2, spp, spp * rate, t, spp * rate / t))
    if ratios:
        print('\ngeometric mean ratio %.1f× over %d of %d views (%.1f–%.1f×)'
              % (math.exp(sum(map(math.log, ratios)) / len(ratios)), len(ratios), len(low), min(ratios), max(ratios)))
    s1, s2 = pt_row(next(iter(low.values())))['spp'], pt_row(next(iter(high.values())))['spp']
    a, b = fit(s1, means['e1'], s2, means['e2'])
    if a > 0 and means['m'] > b:
        spp = a / (means['m'] - b)
        print('mean MSE: model %.4f, PT %d %.4f, PT %d %.4f: PT matches at %.0f spp, %.1f s against %.2f s: %.1f×'
              % (means['m'], s1, means['e1'], s2, means['e2'], spp, spp * means['rate'], means['t'],
                 spp * means['rate'] / means['t']))
    else:
        print('mean MSE: model %.4f, no crossing (PT\'s fitted limit %.4f, slope %.4g)' % (means['m'], b, a))


if __name__ == '__main__':
    main()
