#!/usr/bin/env bash
# train-clean.sh: issue #30's network on clean targets (session 42), resumable: every stage skips
# what is done, so the same command continues after an interruption.
#   1. DATA  1 024-spp records at 8 192 camera queries (configs/data/cpu-s1024c*.json; ~10 s a house
#            on the 2 cores, the same paths as 16 384 queries at 512 spp): the built-in generator's
#            houses 440000–440059 (data/clean), four more for validation (440060–440063,
#            data/clean-val), the real-looking generator's 450000–450031 (data/clean-mix). Seeds
#            disjoint from every test range (900000+, 930000+, 983500+) and from data/mix, data/plain.
#   2. RUN   small-pi-traced-q from small-pi-regather (body silent, skip 1: step 0 is R alone), the
#            skip frozen, 2 point sets a house, level-l2 (the view metric's weighting) capped at 4.
# Env: LTM (a copy of the binary, so the frame cache survives rebuilds), RUN (runs/clean), MODEL (the config
# trained into: configs/model/small-pi-traced-q-held.json holds R's level over 64 points, so the body
# can only correct R's shape — session 42's next run; configs/model/small-pi-rp.json reads R as its
# prior, session 43: with INIT=models/experimental/small-pi.safetensors AT_PRIOR=1: the body silenced, step 0 is R), INIT (the
# weights the run starts from, small-pi-regather), STEPS
# (3000), LR (3e-4), FRAMES (data/frames-clean), EXTRA (more `ltm train` options).
# Then: scripts/runs/eval-model.sh on RUN/step-N (exported), against small-pi-regather.
set -euo pipefail
export OMP_WAIT_POLICY=PASSIVE   # libgomp's spinning threads starve a second job on 2 cores
LTM=${LTM:-build/apps/ltm/ltm-torch}
RUN=${RUN:-runs/clean}
FRAMES=${FRAMES:-data/frames-clean}
"$LTM" dataset build --config configs/data/cpu-s1024c.json --seed-range 440000:440060 -o data/clean
"$LTM" dataset build --config configs/data/cpu-s1024c.json --seed-range 440060:440064 -o data/clean-val
"$LTM" dataset build --config configs/data/cpu-s1024c-mix.json --seed-range 450000:450032 -o data/clean-mix
train=("$LTM" train --threads 2 --model "${MODEL:-configs/model/small-pi-traced-q.json}" --data data/clean --data data/clean-mix
  --val-data data/clean-val --out "$RUN" --config configs/train/physics.json --steps "${STEPS:-3000}" --set lr="${LR:-3e-4}"
  --set warmup_steps=50 --set scenes_per_step=1 --set batch_queries=4096 --set loss=level-l2 --set level_cap=4
  --set target_cap=8 --set grad_clip=0.1 --set point_sets=2 --set resample_points=true --set val_scenes=4 --set val_every=200
  --set ckpt_every=50 --set keep_val_checkpoints=true --set skip_lr_scale=0 --frame-cache "$FRAMES" ${EXTRA:-})
if [[ -f "$RUN/last.ltmckpt" ]]; then "${train[@]}" --resume
else "${train[@]}" --init "${INIT:-models/experimental/small-pi-regather.safetensors}" ${AT_PRIOR:+--start-at-prior}; fi
