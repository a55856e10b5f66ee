#!/usr/bin/env python3
"""equal-quality.py: how long the path tracer needs to match a model's error, per view (issue #31).

Usage: scripts/equal-quality.py MODEL_REPORT PT_LOW PT_HIGH [--model NAME]
  MODEL_REPORT  an `ltm eval` report.json holding the model row NAME (default model:ours)
  PT_LOW        report.json:ptS, a report and its path-tracer row at S spp (e.g. runs/a/report.json:pt128)
  PT_HIGH       the same at a higher spp (it may be the same report or an earlier run's: seeded PT against
                the same cached references gives the same errors)
Per view, PT's MSE = a/spp + b (b: what it converges to against the reference, whose own noise it
holds) through the two rows, and the spp where it meets the model's MSE. PT's time there: with both
rows in the model's report (times compared within one run), the line t = t0 + r·spp through their
times; with one, that row's seconds per spp. Prints a markdown table, the geometric mean of the time
ratios and the same on the mean MSE. A view whose model MSE is at or below b gets no ratio.
"""
import argparse
import json
import math
import os


def rows(path):
    """report.json -> {(scene, view): {method: (mse, seconds)}}"""
    rep = json.load(open(path))
    return {(v['scene'], v.get('view', '')): {m['method']: (m['metrics']['mse'], m['seconds']) for m in v['methods']}
            for v in rep['views']}


def spec(arg):
    path, _, method = arg.rpartition(':')
    if not path or not method.startswith('pt') or not method[2:].isdigit():
        raise SystemExit(f"equal-quality.py: expected REPORT:ptS, got '{arg}'")
    return rows(path), method, int(method[2:]), os.path.realpath(path)


def match(mse, low, high):
    """(spp where PT meets mse, a, b) from (spp, mse) pairs low and high; None when the fit fails
    (a <= 0: more samples did not lower the error), inf when mse <= b."""
    (s1, m1), (s2, m2) = low, high
    a = (m1 - m2) / (1 / s1 - 1 / s2)
    b = m2 - a / s2
    if not a > 0:
        return None, a, b
    return (a / (mse - b) if mse > b else math.inf), a, b


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('model_report')
    ap.add_argument('pt_low')
    ap.add_argument('pt_high')
    ap.add_argument('--model', default='model:ours')
    args = ap.parse_args()
    model = rows(args.model_report)
    here = os.path.realpath(args.model_report)
    low, low_name, low_spp, low_path = spec(args.pt_low)
    high, high_name, high_spp, high_path = spec(args.pt_high)
    if low_spp >= high_spp:
        raise SystemExit('equal-quality.py: PT_LOW must have fewer spp than PT_HIGH')
    if here not in (low_path, high_path):
        print('equal-quality.py: warning: neither PT row ran in the model\'s report; PT\'s times come from another run')

    def pt_time(spp, t1, t2):
        if low_path == here and high_path == here:   # t = t0 + r·spp through both rows
            r = (t2 - t1) / (high_spp - low_spp)
            return t1 + r * (spp - low_spp)
        return t2 * spp / high_spp if high_path == here else t1 * spp / low_spp

    print(f'| view | model MSE (time) | PT {low_spp} (time) | PT {high_spp} (time) | PT matches at | PT time there | ratio |')
    print('|---|---|---|---|---|---|---|')
    ratios, sums, n = [], [0.0] * 6, 0
    for key, methods in model.items():
        name = key[0] + (f' / {key[1]}' if key[1] not in ('', 'main') else '')
        for what, table, row in ((args.model, model, args.model), (low_name, low, low_name), (high_name, high, high_name)):
            if row not in table.get(key, {}):
                raise SystemExit(f"equal-quality.py: view '{name}' has no row {what}")
        (m, tm), (p1, t1), (p2, t2) = methods[args.model], low[key][low_name], high[key][high_name]
        spp, _, _ = match(m, (low_spp, p1), (high_spp, p2))
        for i, x in enumerate((m, tm, p1, t1, p2, t2)):
            sums[i] += x
        n += 1
        head = f'| {name} | {m:.4f} ({tm:.1f} s) | {p1:.4f} ({t1:.1f} s) | {p2:.4f} ({t2:.1f} s) | '
        if spp is None:
            print(head + 'fit failed (PT no better at more spp) | — | — |')
        elif not math.isfinite(spp):
            print(head + '— (below what PT converges to) | — | — |')
        else:
            t = pt_time(spp, t1, t2)
            ratios.append(t / tm)
            print(head + f'{spp:.0f} spp | {t:.1f} s | {t / tm:.2f}× |')
    if n == 0:
        raise SystemExit('equal-quality.py: no views')
    m, tm, p1, t1, p2, t2 = (x / n for x in sums)
    spp, _, _ = match(m, (low_spp, p1), (high_spp, p2))
    geo = math.exp(sum(map(math.log, ratios)) / len(ratios)) if ratios else math.nan
    line = f'\ngeometric mean of the ratios {geo:.2f}× over {len(ratios)} of {n} views; on the mean MSE (model {m:.4f}, PT {low_spp} {p1:.4f}, PT {high_spp} {p2:.4f})'
    if spp is not None and math.isfinite(spp):
        t = pt_time(spp, t1, t2)
        line += f' PT matches at {spp:.0f} spp, {t:.1f} s against {tm:.1f} s: {t / tm:.2f}×'
    print(line)


if __name__ == '__main__':
    main()
