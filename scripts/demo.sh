#!/usr/bin/env bash
# demo.sh: the main job on a bundled default: generate an indoor scene, sample its surfaces,
# and render a preview, into demo-out/. Prints where everything is.
set -euo pipefail
BUILD=${BUILD:-build}
LTM="$BUILD/apps/ltm/ltm"
OUT=${OUT:-demo-out}
SEED=${SEED:-7}
mkdir -p "$OUT"
start=$(date +%s%N)
"$LTM" generate --seed "$SEED" -o "$OUT/scene.json"
"$LTM" sample "$OUT/scene.json" --scene-points 8192 --query-points 65536 --seed "$SEED" \
    --exclude-enclosed -o "$OUT/points"
"$LTM" preview "$OUT/scene.json" --mode shaded -o "$OUT/preview.png"
"$LTM" preview "$OUT/scene.json" --mode albedo -o "$OUT/albedo.png"
"$LTM" preview "$OUT/scene.json" --mode normal -o "$OUT/normal.png"
"$LTM" preview builtin:cornell-box -o "$OUT/cornell-box.png"
end=$(date +%s%N)
ms=$(( (end - start) / 1000000 ))
cat <<MSG

ltm demo finished in $((ms / 1000)).$(( (ms % 1000) / 100 )) s. Outputs in $OUT/:
  scene.json                  procedural indoor scene (seed $SEED), ltm scene JSON
  points/scene_points.ply     8192 scene points   (x y z nx ny nz albedo_* emission_*)
  points/query_points.ply     65536 query points  (x y z nx ny nz albedo_*)
  preview.png albedo.png normal.png   views from the scene's camera
  cornell-box.png             the built-in Cornell box
Open the PLY files in MeshLab/CloudCompare, the PNGs in any viewer.
MSG
