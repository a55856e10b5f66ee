#!/usr/bin/env bash
# eval-steps.sh STEP...: a training run's kept steps (RUN/step-N.ltmckpt, exported here) as ablations of
# R alone (models/experimental/small-pi-regather: the silent traced-queries body, 16 384 points), each
# row then compared view by view with R (scripts/analysis/vs_base.py). Sessions 42–43 (issue #30).
#   HOUSES=1 (default): the 16 Table-1 houses (900100–900115), 96², 1 024 spp, with the references' noise
#   VAL=1: the validation houses' own views (440060–440063, four each; scripts/runs/train-clean.sh's)
#   ROOMS=1: the real rooms (scripts/real-rooms.sh ../shared/scenes; never trained on)
# Env: LTM (the binary; a copy keeps a training's frame cache valid), RUN (runs/rp), TAG (output names).
set -euo pipefail
export OMP_WAIT_POLICY=PASSIVE   # libgomp's spinning threads starve a second job on 2 cores
LTM=${LTM:-build/apps/ltm/ltm-torch}
RUN=${RUN:-runs/rp}
BASE=models/experimental/small-pi-regather.safetensors
abl=(); names=""
for s in "$@"; do
  [[ -f $RUN/step-$s.safetensors ]] || "$LTM" export -q "$RUN/step-$s.ltmckpt" -o "$RUN/step-$s.safetensors"
  abl+=(--ablation "step$s=$RUN/step-$s.safetensors"); names+="step$s=$RUN/step-$s.safetensors "
done
tag=${TAG:-$(basename "$RUN")-$(echo "$@" | tr ' ' '-')}
common=(--width 96 --height 96 --ref-spp 1024 --ref-noise --no-grids)
if [[ "${HOUSES:-1}" == 1 ]]; then
  "$LTM" eval -q --model "$BASE" "${abl[@]}" --scenes 900100:900116 "${common[@]}" --ref-cache refs-t1 -o "runs/eval/t1-$tag"
  python3 scripts/analysis/vs_base.py "runs/eval/t1-$tag/report.json"
fi
if [[ "${VAL:-0}" == 1 ]]; then
  "$LTM" eval -q --model "$BASE" "${abl[@]}" --scenes 440060:440064 --views 4 "${common[@]}" --ref-cache refs-val -o "runs/eval/val-$tag"
  python3 scripts/analysis/vs_base.py "runs/eval/val-$tag/report.json"
fi
if [[ "${ROOMS:-0}" == 1 ]]; then
  LTM="$LTM" MODEL="$BASE" ABLATION="$names" scripts/real-rooms.sh ../shared/scenes "runs/eval/rooms-$tag" > /dev/null
  python3 scripts/analysis/vs_base.py "runs/eval/rooms-$tag/report.json"
fi
