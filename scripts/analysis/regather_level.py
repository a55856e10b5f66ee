#!/usr/bin/env python3
# regather_level.py FRAMES DATA...: per house, R's level against the record's targets at the same
# camera queries — Σ Y(target) / Σ Y(R) — with R read from a physics.prior_regathered run's frame cache
# (FRAMES, e.g. data/frames-rp: `query_scale` of point set 0 is R at the record's queries). > 1: R is
# dark there. Session 43 (issue #30): what a body trained on these records learns to move.
import array
import glob
import json
import os
import statistics
import struct
import sys


def read(path, key):
    with open(path, "rb") as f:
        n = struct.unpack("<Q", f.read(8))[0]
        h = json.loads(f.read(n))
        s, e = h[key]["data_offsets"]
        f.seek(8 + n + s)
        a = array.array("f")
        a.frombytes(f.read(e - s))
        return a


def luminance(a):
    return [0.2126 * a[i] + 0.7152 * a[i + 1] + 0.0722 * a[i + 2] for i in range(0, len(a), 3)]


frames = sys.argv[1]
for d in sys.argv[2:]:
    levels = []
    for rec in sorted(glob.glob(f"{d}/scene-*.safetensors")):
        stem = os.path.basename(rec)[: -len(".safetensors")]
        cached = glob.glob(f"{frames}/{stem}.set0.*.safetensors")
        if not cached:
            continue
        t, r = luminance(read(rec, "E_indirect")), luminance(read(cached[0], "query_scale"))
        levels.append((sum(t) / sum(r), stem))
    if not levels:
        print(f"{d}: no record with a cached frame in {frames}")
        continue
    v = [x for x, _ in levels]
    levels.sort()
    print(f"{d}: {len(v)} houses, target/R geomean {statistics.geometric_mean(v):.4f}, stdev {statistics.pstdev(v):.4f}, "
          f"R brightest {levels[0][1]} {levels[0][0]:.3f}, R darkest {levels[-1][1]} {levels[-1][0]:.3f}")
