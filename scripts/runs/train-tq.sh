#!/usr/bin/env bash
# train-tq.sh: issue #30's traced-queries runs (sessions 37–38), resumable. small-pi-traced-q widened
# from the held weights in git, started at its prior (step 0 = the prior exactly), trained on both
# generators' houses (data/mix 410000–410127, data/plain 420000–420127; baked here if missing).
# Env: RUN (runs/tq), LTM (a copy of the binary, so the frame cache survives rebuilds), STEPS (300),
# FRAMES (data/frames-tq), EXTRA (more `ltm train` options: e.g. "--set freeze=encoder",
# "--set output_decay=10").
# Session 37's runs/tq: EXTRA="" ; runs/tq-od: EXTRA="--set output_decay=10".
set -euo pipefail
LTM=${LTM:-build/apps/ltm/ltm-torch}
RUN=${RUN:-runs/tq}
STEPS=${STEPS:-300}
FRAMES=${FRAMES:-data/frames-tq}
[[ -f data/plain/.done ]] || { "$LTM" dataset build --config configs/data/cpu-s64v.json --seed-range 420000:420128 -o data/plain && touch data/plain/.done; }
LTM="$LTM" MODEL=configs/model/small-pi-traced-q.json RUN="$RUN" SEEDS=410000:410128 STEPS="$STEPS" LR=3e-4 \
  SELECT=0 THREADS=2 POINT_SETS=2 AT_PRIOR=1 FRAMES="$FRAMES" \
  INIT=models/experimental/small-pi-rays-held.safetensors \
  EXTRA="--data data/plain --set val_every=50 --set warmup_steps=20 --set grad_clip=0.1 --set target_cap=8 --set skip_lr_scale=100 ${EXTRA:-}" \
  scripts/train-mix.sh
