#!/usr/bin/env bash
# timing.sh WEIGHTS...: #30's time target as ratios within one run. The demo frame (512², --gi-stride 2)
# with the shipped model and each WEIGHTS, alternating, ROUNDS rounds (2); prints each render's
# wall time and its timings.json breakdown. Pause background training first (kill -STOP).
set -euo pipefail
LTM=${LTM:-build/apps/ltm/ltm-torch}
ROUNDS=${ROUNDS:-2}
out=$(mktemp -d)
models=(models/ltm-cpu.safetensors "$@")
for r in $(seq "$ROUNDS"); do
  for i in "${!models[@]}"; do
    m=${models[$i]}
    t0=$(date +%s.%N)
    "$LTM" render examples/indoor-900012/scene.json --method neural --model "$m" --width 512 --height 512 --gi-stride 2 \
      -o "$out/r$i.png" > /dev/null 2>&1
    t1=$(date +%s.%N)
    printf '%s round %s wall %.2f s  %s\n' "$m" "$r" "$(echo "$t1 - $t0" | bc)" \
      "$(python3 -c 'import json,sys; t=json.load(open(sys.argv[1]))["timings"]; print(" ".join(f"{k[:-2]} {v:.2f}" for k,v in t.items()))' "$out/r$i.timings.json" 2>/dev/null || echo)"
  done
done
rm -rf "$out"
