#!/usr/bin/env python3
"""equal-quality.py: how long the path tracer needs to match a model's error, per view (issue #31).

Usage: scripts/equal-quality.py MODEL_REPORT PT_LOW PT_HIGH [--model NAME] [--time-from REPORT]
  MODEL_REPORT  an `ltm eval` report.json holding the model row NAME (default model:ours)
  PT_LOW        report.json:ptS, a report and its path-tracer row at S spp (e.g. runs/a/report.json:pt128)
  PT_HIGH       the same at a higher spp (it may be the same report or an earlier run's: seeded PT against
                the same cached references gives the same errors)
Per view, PT's MSE = a/spp + b (b: what it converges to against the reference, whose own noise it
holds) through the two rows; the spp where it meets the model's MSE; PT's time there at the rate
(seconds per spp) of the PT row that ran in the model's own report (times are compared within one
run), else of the LOW row. Prints a markdown table, the geometric mean of
the time ratios and the same on the mean MSE. A view whose model MSE is at or below b gets no ratio.
"""
import argparse
import json
import math


def rows(path):
    """report.json -> {scene: {method: (mse, seconds)}}"""
    rep = json.load(open(path))
    return {v['scene']: {m['method']: (m['metrics']['mse'], m['seconds']) for m in v['methods']} for v in rep['views']}


def spec(arg):
    path, _, method = arg.rpartition(':')
    if not path or not method.startswith('pt') or not method[2:].isdigit():
        raise SystemExit(f"equal-quality.py: expected REPORT:ptS, got '{arg}'")
    return rows(path), method, int(method[2:]), path


def match(mse, low, high):
    """(spp where PT meets mse, a, b) from (spp, mse) pairs low and high; spp = inf when mse <= b."""
    (s1, m1), (s2, m2) = low, high
    a = (m1 - m2) / (1 / s1 - 1 / s2)
    b = m2 - a / s2
    return (a / (mse - b) if mse > b and a > 0 else math.inf), a, b


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('model_report')
    ap.add_argument('pt_low')
    ap.add_argument('pt_high')
    ap.add_argument('--model', default='model:ours')
    args = ap.parse_args()
    model = rows(args.model_report)
    low, low_name, low_spp, low_path = spec(args.pt_low)
    high, high_name, high_spp, high_path = spec(args.pt_high)
    timed_high = high_path == args.model_report and low_path != args.model_report
    if low_spp >= high_spp:
        raise SystemExit('equal-quality.py: PT_LOW must have fewer spp than PT_HIGH')
    print(f'| view | model MSE (time) | PT {low_spp} (time) | PT {high_spp} (time) | PT matches at | PT time there | ratio |')
    print('|---|---|---|---|---|---|---|')
    ratios, sums, n = [], [0.0] * 5, 0
    for scene, methods in model.items():
        if args.model not in methods or scene not in low or scene not in high:
            raise SystemExit(f"equal-quality.py: view '{scene}' lacks {args.model}, {low_name} or {high_name}")
        (m, tm), (p1, t1), (p2, t2) = methods[args.model], low[scene][low_name], high[scene][high_name]
        rate = t2 / high_spp if timed_high else t1 / low_spp
        spp, _, _ = match(m, (low_spp, p1), (high_spp, p2))
        t = rate * spp
        ratio = t / tm if tm > 0 else math.inf
        if math.isfinite(ratio):
            ratios.append(ratio)
        for i, x in enumerate((m, tm, p1, rate, p2)):
            sums[i] += x
        n += 1
        where = f'{spp:.0f} spp' if math.isfinite(spp) else '— (below what PT converges to)'
        head = f'| {scene} | {m:.4f} ({tm:.1f} s) | {p1:.4f} ({t1:.1f} s) | {p2:.4f} ({t2:.1f} s) | {where} | '
        print(head + (f'{t:.1f} s | {ratio:.2f}× |' if math.isfinite(spp) else '— | — |'))
    m, tm, p1, rate, p2 = (x / n for x in sums)
    spp, _, _ = match(m, (low_spp, p1), (high_spp, p2))
    geo = math.exp(sum(map(math.log, ratios)) / len(ratios)) if ratios else math.nan
    print(f'\ngeometric mean of the ratios {geo:.2f}× over {len(ratios)} of {n} views; on the mean MSE '
          f'(model {m:.4f}, PT {low_spp} {p1:.4f}, PT {high_spp} {p2:.4f}) PT matches at {spp:.0f} spp, '
          f'{rate * spp:.1f} s against {tm:.1f} s: {rate * spp / tm:.2f}×')


if __name__ == '__main__':
    main()
