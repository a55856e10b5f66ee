#!/usr/bin/env python3
"""prior_error_features.py: does the transport prior know where it errs? (issue #30, deliverable 4)

Reads the per-pixel tables of bench/prior_features (reference E⁺, the prior's Ê⁺ and quantities the
prior computes on the way) and fits the prior's log error, ln(E_ref / Ê⁺) in luminance, as a linear
function of per-pixel features on one set of views (weighted like the view metric: by the prior's
tone-mapped luminance squared). Then it scores every set's views, corrected by exp(fit), with the
eval's MSE (tone-mapped by the reference's 99th percentile, clamped to [0, 1], over all pixels).

  scripts/analysis/prior_error_features.py TRAIN.tsv[,TRAIN2.tsv] TEST.tsv [TEST2.tsv ...]
  scripts/analysis/prior_error_features.py --local-oracle VIEWS.tsv [VIEWS2.tsv ...]

--local-oracle bounds what any correction by smooth local levels could do: each pixel's prior is
scaled by Σ E_ref / Σ Ê⁺ (luminance) over the hit pixels within ±w of it, w a fraction of the view's
width; w = W/2 is about the view's own level. It reads the reference, so it is an oracle; at small w
it starts to fit the reference's noise (read it beside the references' own noise).

A feature set that lowers held-out views' MSE is information the prior has and does not use: a
network given those inputs can learn at least that much. One that does not (or only in-sample)
says the error is not visible in them. Pure Python (no numpy on the build machine).
"""
import math
import sys

LUM = (0.2126, 0.7152, 0.0722)


def lum(r, g, b):
    return LUM[0] * r + LUM[1] * g + LUM[2] * b


def load(path):
    views = []
    with open(path) as f:
        for line in f:
            if line.startswith("# view"):
                t = line.split()
                # tables without the prior inputs' normaliser (bench/traced_correction) read it as 1
                norm = lum(float(t[8]), float(t[9]), float(t[10])) if len(t) > 10 else 1.0
                views.append({"name": t[2], "pixels": int(t[4]), "scale": float(t[6]), "norm": norm, "rows": []})
            elif line.startswith("#"):
                continue
            else:
                v = [float(x) for x in line.split()]
                views[-1]["rows"].append(v)
    return views


# Row columns: 0 pixel, 1-3 ref, 4-6 e, 7-9 e1, 10-12 eu, 13 closure, 14-16 albedo, 17-19 ef (the part
# of e that came through the tree's far aggregates; tables written before session 35 lack it).
FEATURES = {
    "occlusion": lambda r, v, d: math.log((lum(*r[10:13]) + d) / (lum(*r[4:7]) + d)),
    "open": lambda r, v, d: 1.0 - r[13],
    "first": lambda r, v, d: lum(*r[7:10]) / (lum(*r[4:7]) + d),
    "level": lambda r, v, d: math.log(lum(*r[4:7]) / v["norm"] + 1e-3),
    "albedo": lambda r, v, d: lum(*r[14:17]),
    "far": lambda r, v, d: lum(*r[17:20]) / (lum(*r[4:7]) + d),
    "far-level": lambda r, v, d: math.log(max(0.0, lum(*r[17:20])) / v["norm"] + 1e-3),
}


def design(view, names):
    le = [lum(*r[4:7]) for r in view["rows"]]
    d = 0.05 * sum(le) / max(1, len(le))
    xs, ys, ws = [], [], []
    for r, l in zip(view["rows"], le):
        x = [1.0] + [FEATURES[n](r, view, d) for n in names]
        xs.append(x)
        ys.append(math.log((lum(*r[1:4]) + d) / (l + d)))
        t = min(1.0, l * view["scale"])
        ws.append(t * t)
    return xs, ys, ws


def solve(a, b):
    """Gaussian elimination with partial pivoting: a x = b (a small, square)."""
    n = len(b)
    m = [row[:] + [b[i]] for i, row in enumerate(a)]
    for c in range(n):
        p = max(range(c, n), key=lambda i: abs(m[i][c]))
        m[c], m[p] = m[p], m[c]
        for i in range(n):
            if i != c and m[c][c] != 0:
                f = m[i][c] / m[c][c]
                m[i] = [x - f * y for x, y in zip(m[i], m[c])]
    return [m[i][n] / m[i][i] if m[i][i] != 0 else 0.0 for i in range(n)]


def fit(views, names, ridge=1e-3):
    k = len(names) + 1
    a = [[0.0] * k for _ in range(k)]
    b = [0.0] * k
    for v in views:
        xs, ys, ws = design(v, names)
        # each view weighs alike: its weights sum to 1
        tw = sum(ws) or 1.0
        for x, y, w in zip(xs, ys, ws):
            w /= tw
            for i in range(k):
                b[i] += w * x[i] * y
                for j in range(k):
                    a[i][j] += w * x[i] * x[j]
    for i in range(1, k):
        a[i][i] += ridge
    return solve(a, b)


def view_mse(view, gain=None):
    s = view["scale"]
    se = 0.0
    for i, r in enumerate(view["rows"]):
        g = 1.0 if gain is None else gain[i]
        for c in range(3):
            t = min(1.0, max(0.0, r[4 + c] * g * s))
            q = min(1.0, max(0.0, r[1 + c] * s))
            se += (t - q) ** 2
    return se / (3 * view["pixels"])


def corrected(view, names, coef):
    xs, _, _ = design(view, names)
    return [math.exp(max(-1.0, min(1.0, sum(c * x for c, x in zip(coef, row))))) for row in xs]


def score(views, names, coef):
    base = sum(view_mse(v) for v in views) / len(views)
    corr = [view_mse(v, corrected(v, names, coef)) for v in views]
    better = sum(1 for v, c in zip(views, corr) if c < view_mse(v))
    return base, sum(corr) / len(views), better


def local_gains(view, w):
    """Per hit: Σ ref / Σ prior (luminance) over the hit pixels in the (2w+1)² window around it."""
    size = math.isqrt(view["pixels"])
    sr = [[0.0] * (size + 1) for _ in range(size + 1)]
    se = [[0.0] * (size + 1) for _ in range(size + 1)]
    for r in view["rows"]:
        y, x = divmod(int(r[0]), size)
        sr[y + 1][x + 1] = lum(*r[1:4])
        se[y + 1][x + 1] = lum(*r[4:7])
    for t in (sr, se):   # summed-area tables
        for y in range(1, size + 1):
            for x in range(1, size + 1):
                t[y][x] += t[y - 1][x] + t[y][x - 1] - t[y - 1][x - 1]
    gains = []
    for r in view["rows"]:
        y, x = divmod(int(r[0]), size)
        y0, y1, x0, x1 = max(0, y - w), min(size, y + w + 1), max(0, x - w), min(size, x + w + 1)
        a = sr[y1][x1] - sr[y0][x1] - sr[y1][x0] + sr[y0][x0]
        b = se[y1][x1] - se[y0][x1] - se[y1][x0] + se[y0][x0]
        gains.append(a / b if b > 0 else 1.0)
    return gains


def local_oracle(paths):
    fractions = [0.5, 0.25, 0.125, 0.0625, 0.03]
    print("| views | prior | " + " | ".join(f"local levels ±{f:g}·W" for f in fractions) + " |")
    print("|---" * (2 + len(fractions)) + "|")
    for p in paths:
        views = load(p)
        cells = [f"{sum(view_mse(v) for v in views) / len(views):.5f}"]
        for f in fractions:
            mse = [view_mse(v, local_gains(v, max(1, int(f * math.isqrt(v["pixels"]))))) for v in views]
            cells.append(f"{sum(mse) / len(views):.5f}")
        print(f"| {p} ({len(views)}) | " + " | ".join(cells) + " |")


def main():
    if sys.argv[1] == "--local-oracle":
        local_oracle(sys.argv[2:])
        return
    train = [v for p in sys.argv[1].split(",") for v in load(p)]
    tests = [(p, load(p)) for p in sys.argv[2:]]
    # Tables written before session 35 have no far part (17 columns): their fits leave it out.
    has_far = all(len(v["rows"][0]) >= 20 for _, vs in [("", train)] + tests for v in vs if v["rows"])
    names = [n for n in FEATURES if has_far or not n.startswith("far")]
    sets = [("none", [])] + [(n, [n]) for n in names]
    if has_far:
        sets += [("level + far", ["level", "far"]), ("level + far-level", ["level", "far-level"])]
    sets += [("all", names)]
    print(f"fit on {sys.argv[1]} ({len(train)} views); MSE prior -> corrected (views better)")
    print("| features | coefficients | " + " | ".join(["train (in-sample)"] + [p for p, _ in tests]) + " |")
    print("|---" * (3 + len(tests)) + "|")
    for label, names in sets:
        coef = fit(train, names)
        cells = []
        for vs in [train] + [t for _, t in tests]:
            b, c, k = score(vs, names, coef)
            cells.append(f"{b:.5f} -> {c:.5f} ({k}/{len(vs)})")
        print(f"| {label} | {' '.join(f'{c:+.3f}' for c in coef)} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
