#!/usr/bin/env bash
# eval-model.sh WEIGHTS NAME: issue #30's two view benchmarks for one weights file (sessions 32–38).
#   houses: the 16 Table-1 houses 900100–900115 at 96², 1 024-spp references (cached in refs-t1/,
#           with their own noise: the floor) -> runs/eval/t1-NAME
#   rooms:  scripts/real-rooms.sh ../shared/scenes (four rooms + the Cornell box, 128²) -> runs/eval/rooms-NAME
# then scripts/analysis/network_vs_prior.py on each (the model against its own prior, view by view).
# Env: LTM, ROOMS=0 (houses only), HOUSES=0 (rooms only), ABLATION (NAME=weights rows for both).
set -euo pipefail
M=${1:?usage: eval-model.sh WEIGHTS NAME}
NAME=${2:?usage: eval-model.sh WEIGHTS NAME}
LTM=${LTM:-build/apps/ltm/ltm-torch}
ablations=()
for a in ${ABLATION:-}; do ablations+=(--ablation "$a"); done
mkdir -p runs/eval
if [[ "${HOUSES:-1}" == 1 ]]; then
  "$LTM" eval -q --model "$M" "${ablations[@]}" --scenes 900100:900116 --width 96 --height 96 --ref-spp 1024 --ref-noise \
    --ref-cache refs-t1 --no-grids -o "runs/eval/t1-$NAME"
  python3 scripts/analysis/network_vs_prior.py "runs/eval/t1-$NAME/report.json"
fi
if [[ "${ROOMS:-1}" == 1 && -d ../shared/scenes ]]; then
  LTM="$LTM" MODEL="$M" ABLATION="${ABLATION:-}" scripts/real-rooms.sh ../shared/scenes "runs/eval/rooms-$NAME" > /dev/null
  python3 scripts/analysis/network_vs_prior.py "runs/eval/rooms-$NAME/report.json"
fi
