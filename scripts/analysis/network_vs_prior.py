#!/usr/bin/env python3
"""network_vs_prior.py REPORT.json [NAME ...]: what the network adds over its own prior, view by view.

For every model NAME in an `ltm eval` report (default: all), compares the rows model:NAME and
model-prior:NAME (the same model with the network silenced): mean MSE ratio, views the network
improves, and the per-view ratios. Issue #30's targets read off this: MSE <= 0.75x the prior's,
better on >= 70 % of views, no room worse than the prior.
"""
import json
import sys


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    report = json.load(open(sys.argv[1]))
    names = sys.argv[2:] or sorted({m["method"].split(":", 1)[1] for v in report["views"] for m in v["methods"]
                                    if m["method"].startswith("model:")})
    print("| model | views | MSE network | MSE its prior | ratio | views better | worst view ratio |")
    print("|---|---|---|---|---|---|---|")
    for name in names:
        pairs = []
        for v in report["views"]:
            by = {m["method"]: m["metrics"]["mse"] for m in v["methods"]}
            if f"model:{name}" in by and f"model-prior:{name}" in by:
                pairs.append((v["scene"] + "/" + v["view"], by[f"model:{name}"], by[f"model-prior:{name}"]))
        if not pairs:
            continue
        net = sum(p[1] for p in pairs) / len(pairs)
        pri = sum(p[2] for p in pairs) / len(pairs)
        better = sum(p[1] < p[2] for p in pairs)
        worst = max(pairs, key=lambda p: p[1] / max(p[2], 1e-30))
        print(f"| {name} | {len(pairs)} | {net:.5f} | {pri:.5f} | {net / max(pri, 1e-30):.3f} | {better}/{len(pairs)} "
              f"| {worst[1] / max(worst[2], 1e-30):.2f} ({worst[0]}) |")


if __name__ == "__main__":
    main()
