#!/usr/bin/env bash
# real-rooms.sh DIR [OUT]: the real-room benchmark (issue #29). Runs `ltm eval` over every scene in
# DIR — each DIR/*/scene-v4.pbrt, and any *.pbrt, *.gltf, *.glb, *.obj or *.json one folder down —
# plus builtin:cornell-box, at 128² against a 1 024-spp reference of ltm's own path tracer, and
# writes OUT/report.json and OUT/table.md (`ltm eval`'s summary over rooms), OUT/rooms.md (one row
# per room and method: MSE, SSIM, level, chroma, beats flat), and a grid per room (OUT/<room>_main.png:
# albedo | reference | model | … | error).
#
# The rows: the model (MODEL, default the shipped one), each ABLATION (NAME=weights, e.g. the model
# before a change), the closed-form priors, PT at 64 spp and at the model's time, and the flat
# oracle (every pixel the reference's mean colour: the floor). References are cached in REF_CACHE
# (default refs-real/) and reused when scene, view, spp and seed match.
#
# Never train on these rooms (../shared/scenes/README.md). Env: LTM, MODEL, ABLATION (space-separated),
# SIZE (128), REF_SPP (1024), REF_CACHE (refs-real), EXTRA (more scenes, e.g. builtin:NAME; default
# builtin:cornell-box), EVAL_ARGS (more `ltm eval` options, e.g. "--scene-points auto" or
# "--baseline-spp 256").
set -euo pipefail
DIR=${1:?usage: scripts/real-rooms.sh DIR [OUT]}
OUT=${2:-real-rooms}
LTM=${LTM:-build/apps/ltm/ltm}
MODEL=${MODEL:-models/ltm-cpu.safetensors}
SIZE=${SIZE:-128}
REF_SPP=${REF_SPP:-1024}
REF_CACHE=${REF_CACHE:-refs-real}
EXTRA=${EXTRA-builtin:cornell-box}
[[ -d "$DIR" ]] || { echo "real-rooms.sh: $DIR is not a folder" >&2; exit 1; }
scenes=()
for f in "$DIR"/*/*; do
  case "$f" in
    *.pbrt|*.gltf|*.glb|*.obj) ;;
    *) continue ;;
  esac
  # A room that ships several pbrt files (scene.pbrt and scene-v4.pbrt): its v4 file only.
  if [[ "$f" == *.pbrt && -f "$(dirname "$f")/scene-v4.pbrt" && "$(basename "$f")" != scene-v4.pbrt ]]; then continue; fi
  scenes+=("$f")
done
for e in $EXTRA; do scenes+=("$e"); done
((${#scenes[@]})) || { echo "real-rooms.sh: no scenes in $DIR" >&2; exit 1; }
ablations=()
for a in ${ABLATION:-}; do ablations+=(--ablation "$a"); done
mkdir -p "$OUT"
echo "real-rooms.sh: ${#scenes[@]} scenes, ${SIZE}², reference $REF_SPP spp -> $OUT" >&2
"$LTM" eval --model "$MODEL" "${ablations[@]}" --scenes "${scenes[@]}" --width "$SIZE" --height "$SIZE" \
  --ref-spp "$REF_SPP" --ref-cache "$REF_CACHE" ${EVAL_ARGS:-} -o "$OUT"
# One row per room and method, from report.json.
python3 - "$OUT/report.json" > "$OUT/rooms.md" <<'EOF'
import json, sys
r = json.load(open(sys.argv[1]))
print("| room | method | MSE ↓ | SSIM ↑ | level | chroma err ↓ | beats flat |")
print("|---|---|---|---|---|---|---|")
for v in r["views"]:
    flat = next(m["metrics"]["mse"] for m in v["methods"] if m["method"] == "flat-oracle")
    for m in v["methods"]:
        x = m["metrics"]
        beats = "—" if m["method"] == "flat-oracle" else ("yes" if x["mse"] < flat else "no")
        print(f"| {v['scene']} | {m['method']} | {x['mse']:.4f} | {x['ssim']:.3f} | {x['level_ratio']:.2f} | {x['chroma_error']:.3f} | {beats} |")
EOF
cat "$OUT/rooms.md"
