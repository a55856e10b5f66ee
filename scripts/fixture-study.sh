#!/usr/bin/env bash
# fixture-study.sh [OUT]: what each real-room fixture (GenConfig::Fixtures, procgen/fixtures.h) does
# to the model, one at a time (issue #29, deliverable 2's analytic cases): the same held-out houses
# generated as they are, then with windows onto nothing, sky windows alone (ceiling lights off),
# sky windows with curtains, lit lamps alone, sconces and strips alone, every light recessed, and the
# real-mix preset. Each case runs `ltm eval` (the model, its prior rows, PT 64, PT at equal time,
# the flat oracle) and OUT/study.md gets one row per case: MSE of the model, PT 64 and the flat
# oracle, the model's level ratio (views in [0.8, 1.25]) and how many views beat flat.
#
# Env: LTM, MODEL (default the shipped one), SEEDS (950000:950006: disjoint from every training and
# validation range), SIZE (96), REF_SPP (1024), REF_CACHE (refs-fixtures), CASES (space-separated
# subset of the case names below).
set -euo pipefail
OUT=${1:-fixture-study}
LTM=${LTM:-build/apps/ltm/ltm}
MODEL=${MODEL:-models/ltm-cpu.safetensors}
SEEDS=${SEEDS:-950000:950006}
SIZE=${SIZE:-96}
REF_SPP=${REF_SPP:-1024}
REF_CACHE=${REF_CACHE:-refs-fixtures}
mkdir -p "$OUT"
declare -A cfg=(
  [base]='{}'
  [window-void]='{"fixtures": {"p_windows": 1, "p_window_sky": 0, "p_curtains": 0}}'
  [window-sky]='{"fixtures": {"p_windows": 1, "p_window_sky": 1, "p_curtains": 0, "p_ceiling_off": 1}}'
  [window-curtains]='{"fixtures": {"p_windows": 1, "p_window_sky": 1, "p_curtains": 1, "p_ceiling_off": 1}}'
  [lamps]='{"furniture": {"archetypes": {"floor_lamp": {"weight": 4}}}, "fixtures": {"p_lamp_lit": 1, "p_table_lamp": 1, "p_ceiling_off": 1}}'
  [wall-lights]='{"fixtures": {"p_sconces": 1, "p_strip": 1, "p_ceiling_off": 1}}'
  [recessed]='{"fixtures": {"p_recessed": 1, "recess_depth": [0.1, 0.25]}}'
  [real-mix]="$(cat configs/gen/real-mix.json)"
)
order=(base window-void window-sky window-curtains lamps wall-lights recessed real-mix)
cases=(${CASES:-${order[@]}})
for c in "${cases[@]}"; do
  [[ -n "${cfg[$c]:-}" ]] || { echo "fixture-study.sh: unknown case '$c'" >&2; exit 1; }
  echo "${cfg[$c]}" > "$OUT/$c.gen.json"
  echo "fixture-study.sh: $c" >&2
  "$LTM" eval --model "$MODEL" --scenes "$SEEDS" --gen-config "$OUT/$c.gen.json" --width "$SIZE" --height "$SIZE" \
    --ref-spp "$REF_SPP" --ref-cache "$REF_CACHE" --no-grids -o "$OUT/$c" -q
done
python3 - "$OUT" "${cases[@]}" > "$OUT/study.md" <<'EOF'
import json, math, sys
out, cases = sys.argv[1], sys.argv[2:]
print("| case | views | model MSE | prior (model-prior) | PT 64 | flat oracle | model level (in band) | model beats flat |")
print("|---|---|---|---|---|---|---|---|")
for c in cases:
    r = json.load(open(f"{out}/{c}/report.json"))
    views = r["views"]
    def mean(name):
        xs = [m["metrics"]["mse"] for v in views for m in v["methods"] if m["method"].split(":")[0] == name]
        return sum(xs) / len(xs) if xs else float("nan")
    lv = [m["metrics"]["level_ratio"] for v in views for m in v["methods"] if m["method"].split(":")[0] == "model"]
    flat = {v["scene"]: next(m["metrics"]["mse"] for m in v["methods"] if m["method"] == "flat-oracle") for v in views}
    beats = sum(1 for v in views for m in v["methods"] if m["method"].split(":")[0] == "model" and m["metrics"]["mse"] < flat[v["scene"]])
    geo = math.exp(sum(math.log(x) for x in lv) / len(lv))
    band = sum(1 for x in lv if 0.8 <= x <= 1.25)
    print(f"| {c} | {len(views)} | {mean('model'):.4f} | {mean('model-prior'):.4f} | {mean('pt64'):.4f} | {mean('flat-oracle'):.4f} | {geo:.2f} ({band}) | {beats}/{len(views)} |")
EOF
cat "$OUT/study.md"
