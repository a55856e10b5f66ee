#!/usr/bin/env bash
# select-by-views.sh RUN [BASELINE.safetensors]: choose a run's weights by what a camera sees.
# Validation during training compares whole houses against a whole-house flat colour, which a model
# beats easily while missing each room's level (docs/results.md, session 6). This script exports
# every kept step (RUN/step-*.ltmckpt, from `--set keep_val_checkpoints=true`; else RUN/last.ltmckpt),
# evaluates each with `ltm eval` on the validation houses' camera views (seeds disjoint from
# training and test; references cached in refs-val/), and prints one line per candidate, best
# (lowest view MSE) last. Env: LTM, SEEDS (100000:100032), SIZE (64), REF_SPP (256), GEN (a generator
# config for the seeds, e.g. configs/gen/real-mix.json; default the built-in), REF_CACHE (refs-val),
# REF_NOISE=1 (also the references' own noise, the floor under every line: `ltm eval --ref-noise`; it
# does not change the ranking, only what a ratio between two lines means).
set -euo pipefail
RUN=$1
BASELINE=${2:-}
LTM=${LTM:-build/apps/ltm/ltm}
SEEDS=${SEEDS:-100000:100032}
SIZE=${SIZE:-64}
REF_SPP=${REF_SPP:-256}
GEN=${GEN:-}
REF_CACHE=${REF_CACHE:-refs-val}
out="$RUN/select"
mkdir -p "$out"
candidates=()
kept=("$RUN"/step-*.ltmckpt)
[[ -f "${kept[0]}" ]] || kept=("$RUN/last.ltmckpt")   # the last step validates, so it is kept when any is
for ck in "${kept[@]}"; do
  [[ -f "$ck" ]] || continue
  name=$(basename "$ck" .ltmckpt)
  "$LTM" export -q "$ck" -o "$out/$name.safetensors"
  candidates+=("$name=$out/$name.safetensors")
done
[[ -n "$BASELINE" ]] && candidates+=("baseline=$BASELINE")
((${#candidates[@]})) || { echo "select-by-views.sh: no checkpoints in $RUN" >&2; exit 1; }
first=${candidates[0]#*=}
ablations=()
for c in "${candidates[@]:1}"; do ablations+=(--ablation "$c"); done
"$LTM" eval -q --model "$first" "${ablations[@]}" --scenes "$SEEDS" ${GEN:+--gen-config "$GEN"} --width "$SIZE" --height "$SIZE" --ref-spp "$REF_SPP" \
    --baseline-spp 4 --ref-cache "$REF_CACHE" --no-grids ${REF_NOISE:+--ref-noise} -o "$out/eval"
# One line per model row of the table (model:ours is the first candidate), sorted by MSE, best last.
first_name=${candidates[0]%%=*}
grep '^| model:' "$out/eval/table.md" | sed "s/model:ours/model:$first_name/" | sort -t'|' -k4,4gr
grep '^Reference noise' "$out/eval/table.md" || true
