#!/usr/bin/env bash
# results.sh: the measurements behind docs/results.md (about 25 minutes on 2 cores with an empty
# reference cache).
#   1. Table 1: the model vs path tracing on 50 held-out generated scenes (seeds 900100..900149;
#      every training seed is < 900000).
#   2. Edits without retraining: one held-out scene, then the same scene with a light moved, an
#      object moved, and the walls' albedo changed; each evaluated against path tracing of itself.
#   3. View consistency: two views of one scene (the same model, the same latents).
# References (1 024 spp, as the test houses' everywhere in docs/results.md) are kept in REF_CACHE
# (default OUT_DIR/ref-cache): a re-run with another model renders none of them again.
# Usage: scripts/results.sh [OUT_DIR]   (MODEL, ABLATION="name=weights ...", BUILD, REF_CACHE override;
#   e.g. ABLATION="v0.3=<git show 776a646:models/ltm-cpu.safetensors>" REF_CACHE=refs)
set -euo pipefail
BUILD=${BUILD:-build}
LTM="$BUILD/apps/ltm/ltm"
MODEL=${MODEL:-models/ltm-cpu.safetensors}
OUT=${1:-results}
REF_CACHE=${REF_CACHE:-$OUT/ref-cache}
abl=()
for a in ${ABLATION:-}; do abl+=(--ablation "$a"); done
mkdir -p "$OUT/edits"
"$LTM" eval --model "$MODEL" "${abl[@]}" --scenes 900100:900150 --width 96 --height 96 --ref-spp 1024 --gi-stride 2 --ref-cache "$REF_CACHE" -o "$OUT/table1"
"$LTM" generate --seed 900007 -o "$OUT/edits/base.json"
"$LTM" edit "$OUT/edits/base.json" --move light0=-1.3,0,1.6 -o "$OUT/edits/light-moved.json"
"$LTM" edit "$OUT/edits/base.json" --move table0=-0.6,0,0.6 -o "$OUT/edits/table-moved.json"
"$LTM" edit "$OUT/edits/base.json" --albedo room0_walls=0.85,0.15,0.1 -o "$OUT/edits/red-walls.json"
"$LTM" eval --model "$MODEL" --scenes "$OUT"/edits/{base,light-moved,table-moved,red-walls}.json \
    --width 160 --height 160 --ref-spp 1024 --ref-cache "$REF_CACHE" -o "$OUT/edits/eval"
"$LTM" eval --model "$MODEL" --scenes examples/indoor-900012/scene.json --views 2 --width 160 --height 160 \
    --ref-spp 1024 --ref-cache "$REF_CACHE" -o "$OUT/views"
