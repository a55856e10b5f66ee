#!/usr/bin/env bash
# train-physics.sh: the physics-exact model (issue #10) on the 2-core machine, as one resumable
# script: every stage skips what is done, so re-running it after an interruption (a session's
# end) continues — dataset builds skip finished records, training resumes from last.ltmckpt.
#   1. data/cpu-s32  seeds 0..N-1 at `cpu-s32` (16 384 queries, 32-spp labels: ~8× cheaper than
#      256 spp; the relative-l2 loss's minimiser is the mean of noisy targets, so they train an
#      unbiased model).
#   1b. data/val-s256 seeds 100000..100031 at `cpu-q16k` (256 spp): a fixed validation set
#      (--val-data) that stays the same while the training data grows between sessions.
#   2. runs/cpu-phys configs/model/cpu.json (emission- and unit-normalised, power-balance prior)
#      from scratch with configs/train/physics.json; best.ltmckpt = lowest MSE / flat-oracle MSE.
#   3. export best.ltmckpt as F16 safetensors to $EXPORT.
# Usage: nohup nice scripts/train-physics.sh > train-physics.log 2>&1 &
#   (BUILD or LTM, SEEDS (a:b, default 0:1200), DATA (a configs/data preset name, default cpu-s32;
#   the records go to data/$DATA), RUN, EXPORT, THREADS, MODEL (a model config) override; INIT=weights.safetensors
#   fine-tunes from them, e.g. the shipped model; extra args after the script go to `ltm train`,
#   e.g. --set steps=2400 --set warmup_steps=100)
set -euo pipefail
BUILD=${BUILD:-build}
LTM=${LTM:-$BUILD/apps/ltm/ltm}
SEEDS=${SEEDS:-0:1200}
INIT=${INIT:-}
RUN=${RUN:-runs/cpu-phys}
EXPORT=${EXPORT:-runs/ltm-cpu-phys.safetensors}
THREADS=${THREADS:-0}
MODEL=${MODEL:-configs/model/cpu.json}
DATA=${DATA:-cpu-s32}
"$LTM" dataset build --config configs/data/cpu-q16k.json --seed-range 100000:100032 -o data/val-s256 --threads "$THREADS"
"$LTM" dataset build --config "configs/data/$DATA.json" --seed-range "$SEEDS" -o "data/$DATA" --threads "$THREADS"
train=("$LTM" train --threads "$THREADS" --model "$MODEL" --data "data/$DATA" --val-data data/val-s256 --out "$RUN"
       --config configs/train/physics.json "$@")
if [[ -f "$RUN/last.ltmckpt" ]]; then "${train[@]}" --resume
elif [[ -n "$INIT" ]]; then "${train[@]}" --init "$INIT"
else "${train[@]}"; fi
"$LTM" export "$RUN/best.ltmckpt" --half -o "$EXPORT" \
    --note "cpu config with exact emission/unit normalisation and power-balance prior; data/$DATA seeds $SEEDS${INIT:+, fine-tuned from $INIT}, 2-core CPU"
