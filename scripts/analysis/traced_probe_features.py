#!/usr/bin/env python3
"""traced_probe_features.py: what do a few traced paths per scene point tell a correction of the prior?
(issue #30, deliverable 4: an input ablation before the input is built.)

Reads the per-pixel tables of bench/traced_correction (TSV=...: reference E⁺, the prior's Ê⁺, the
regathered prior — the prior's nodes re-emitting ρ ⊙ their traced irradiance — and the local gains
Σ T / Σ P over the k nearest probes for each k the bench ran, last the view's one gain), fits the
prior's log error ln(E_ref / Ê⁺) in luminance as a linear function of those features on some views
(weighted like the view metric, prior_error_features.py's fit), and scores other views corrected by
exp(fit) with the eval's MSE. A feature set that lowers held-out views' MSE is information a network
given those inputs can learn at least that much of.

  scripts/analysis/traced_probe_features.py TRAIN.tsv[,TRAIN2.tsv] TEST.tsv [TEST2.tsv ...]
  scripts/analysis/traced_probe_features.py --halves VIEWS.tsv      (fit each half, score the other)

Row columns: 0 pixel, 1-3 ref, 4-6 prior, 7-9 regathered, 10.. the gains for each k the bench ran: the
names below assume the list 64,256,1024,0 (pass it to the bench: its default list is 16,64,256,0).
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import prior_error_features as pef  # noqa: E402

lum = pef.lum
load = pef.load


def log_gain(x):
    return math.log(max(x, 1e-3))


FEATURES = {
    "regather": lambda r, v, d: math.log((lum(*r[7:10]) + d) / (lum(*r[4:7]) + d)),
    "k64": lambda r, v, d: log_gain(r[10]),
    "k256": lambda r, v, d: log_gain(r[11]),
    "k1024": lambda r, v, d: log_gain(r[12]),
    "view": lambda r, v, d: log_gain(r[13]),
}
SETS = [("none", []), ("regather", ["regather"]), ("view", ["view"]), ("k1024", ["k1024"]),
        ("regather + view", ["regather", "view"]), ("regather + view + k256 + k1024", ["regather", "view", "k256", "k1024"]),
        ("all five", list(FEATURES))]


def table(train, tests):
    print("| features | coefficients | " + " | ".join(["train (in-sample)"] + [p for p, _ in tests]) + " |")
    print("|---" * (3 + len(tests)) + "|")
    fits = {}
    for label, names in SETS:
        coef = pef.fit(train, names)
        fits[label] = (names, coef)
        cells = []
        for vs in [train] + [t for _, t in tests]:
            b, c, k = pef.score(vs, names, coef)
            cells.append(f"{b:.5f} → {c:.5f} = {c / b:.3f} ({k}/{len(vs)})")
        print(f"| {label} | {' '.join(f'{c:+.3f}' for c in coef)} | " + " | ".join(cells) + " |")
    return fits


def main():
    pef.FEATURES = FEATURES
    if sys.argv[1] == "--halves":
        views = load(sys.argv[2])
        h = len(views) // 2
        for a, b in ((views[:h], views[h:]), (views[h:], views[:h])):
            print(f"\nfit on {a[0]['name']}…{a[-1]['name']}, held out {b[0]['name']}…{b[-1]['name']}")
            table(a, [("held out", b)])
        return
    train = [v for p in sys.argv[1].split(",") for v in load(p)]
    tests = [(p, load(p)) for p in sys.argv[2:]]
    fits = table(train, tests)
    names, coef = fits["regather + view + k256 + k1024"]
    print("\nper view, regather + view + k256 + k1024 (fitted on the training views):")
    for p, vs in tests:
        for v in vs:
            b = pef.view_mse(v)
            c = pef.view_mse(v, pef.corrected(v, names, coef))
            print(f"  {v['name']}: {b:.5f} → {c:.5f} = {c / b:.3f}")


if __name__ == "__main__":
    main()
