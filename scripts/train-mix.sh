#!/usr/bin/env bash
# train-mix.sh: issue #30's recipe on the 2-core machine, as one resumable script. Every stage skips
# what is already done, so re-running it after an interruption (or in the next session, on the same
# machine) continues: the dataset build skips finished records, training resumes from last.ltmckpt.
#   1. DATA   real-mix houses (configs/data/cpu-s64v-mix.json: the real-looking generator, 64 spp,
#             16 384 queries, 75 % camera queries), seeds SEEDS (disjoint from every validation and
#             test range: 100000+, 900000+, 930000+, 930100+)
#   2. RUN    small-pi fine-tuned from INIT (the last experimental weights), level-l2 with level_cap 4,
#             POINT_SETS fresh scene-point sets per house, every 200 steps kept for the view selection
#   3. select by views on real-mix validation houses (scripts/select-by-views.sh), best last
# A fresh machine has lost DATA and RUN: the script starts them again from INIT, which lives in git.
# Usage: nohup nice scripts/train-mix.sh > mix.log 2>&1 &   (env: BUILD or LTM, SEEDS, DATA, RUN,
# INIT, STEPS, LR, POINT_SETS, THREADS (worker threads for training; 0 = all cores), MODEL (the config to train into; default small-pi: records baked
# at another M than the model's have their points sampled afresh at its M), SELECT=0 to skip step 3,
# EXTRA: more `ltm train` options, e.g. "--set region_weight=20"; AT_PRIOR=1: a fresh run zeroes the decoder's output
# after INIT (`--start-at-prior`), so it starts as its own prior, e.g. MODEL=configs/model/small-pi-rays.json;
# FRAMES: the houses' prepared draws kept across runs (`ltm train --frame-cache`, default data/frames; a
# rebuilt program starts a new cache, so long runs use a copy of the binary: LTM=runs/bin/…/ltm-torch)
set -euo pipefail
BUILD=${BUILD:-build}
LTM=${LTM:-$BUILD/apps/ltm/ltm}
SEEDS=${SEEDS:-410000:410256}
DATA=${DATA:-data/mix}
RUN=${RUN:-runs/mix}
INIT=${INIT:-models/experimental/small-pi-mix.safetensors}
STEPS=${STEPS:-4800}
LR=${LR:-5e-4}
POINT_SETS=${POINT_SETS:-4}
MODEL=${MODEL:-configs/model/small-pi.json}
SELECT=${SELECT:-1}
THREADS=${THREADS:-0}
FRAMES=${FRAMES:-data/frames}
"$LTM" dataset build --config configs/data/cpu-s64v-mix.json --seed-range "$SEEDS" -o "$DATA"
train=("$LTM" train --threads "$THREADS" --model "$MODEL" --data "$DATA" --out "$RUN"
       --config configs/train/physics.json --steps "$STEPS" --set lr="$LR" --set warmup_steps=50
       --set scenes_per_step=1 --set batch_queries=4096 --set val_fraction=0.03 --set loss=level-l2 --set level_cap=4
       --set point_sets="$POINT_SETS" --set resample_points=true --set val_scenes=8 --set val_every=200 --set ckpt_every=50
       --set keep_val_checkpoints=true --frame-cache "$FRAMES" ${EXTRA:-})
if [[ -f "$RUN/last.ltmckpt" ]]; then "${train[@]}" --resume; else
  at_prior=()
  [[ "${AT_PRIOR:-0}" == 1 ]] && at_prior=(--start-at-prior)
  "${train[@]}" --init "$INIT" "${at_prior[@]}"
fi
if [[ "$SELECT" == 1 ]]; then
  SEEDS=930100:930108 GEN=configs/gen/real-mix.json REF_CACHE=refs-mixval LTM="$LTM" \
    scripts/select-by-views.sh "$RUN" "$INIT"
fi
