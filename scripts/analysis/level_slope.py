#!/usr/bin/python3
"""level_slope.py REPORT.json [METHOD]: does a model correct the closed-form prior's level per view?

For every view, log(model level / prior level) is regressed on log(reference level / prior level)
(levels are `level_ratio`s against the reference, so the reference's own is 1): slope 1 means the
model puts each camera's rooms at their true level, slope 0 means it just follows the house-wide
prior. Also prints the correlation of the model's level with the prior's.
"""
import json
import sys

import numpy as np

report = json.load(open(sys.argv[1]))
method = sys.argv[2] if len(sys.argv) > 2 else "model:ours"
m, p = [], []
for v in report["views"]:
    d = {x["method"]: x["metrics"] for x in v["methods"]}
    m.append(np.log(d[method]["level_ratio"]))
    p.append(np.log(d["flat-prior"]["level_ratio"]))
m, p = np.array(m), np.array(p)
slope, _ = np.polyfit(-p, m - p, 1)
print(f"{method}: {len(m)} views, correction slope {slope:.3f} (1 = per-room level right, 0 = the prior's), "
      f"corr(log level, log prior level) {np.corrcoef(m, p)[0, 1]:.3f}, "
      f"in band {int(np.sum(np.abs(m) <= np.log(1.25)))}")
