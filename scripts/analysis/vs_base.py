#!/usr/bin/env python3
# vs_base.py REPORT: each `model:NAME` row of an `ltm eval` report against `model:ours` (the --model,
# e.g. R alone), view by view: mean MSE ratio, the ratio of the error above the references' own noise
# (with --ref-noise), and the views where NAME is better. Sessions 42–43 (issue #30).
import json
import sys

r = json.load(open(sys.argv[1]))
names = sorted({m["method"].split(":", 1)[1] for v in r["views"] for m in v["methods"] if m["method"].startswith("model:")} - {"ours"})
noise = [v.get("reference_noise_mse") or 0 for v in r["views"]]
nz = sum(noise) / len(noise)
for n in names:
    a, b, better = [], [], 0
    for v in r["views"]:
        by = {m["method"]: m["metrics"]["mse"] for m in v["methods"]}
        a.append(by[f"model:{n}"])
        b.append(by["model:ours"])
        better += by[f"model:{n}"] < by["model:ours"]
    na, nb = sum(a) / len(a), sum(b) / len(b)
    print(f"{n}: {na:.5f} vs ours {nb:.5f} = {na / nb:.3f}x, above the noise {(na - nz) / (nb - nz):.3f}x, better on {better}/{len(a)}")
