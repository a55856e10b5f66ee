#!/usr/bin/env bash
# demo.sh: the main job on a bundled default: generate an indoor scene, sample its surfaces,
# bake ground-truth irradiance at the query points, render previews and a path-traced image,
# into demo-out/. Prints where everything is. About a minute on 2 cores.
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
"$LTM" bake "$OUT/scene.json" --points "$OUT/points" --spp 64 --seed "$SEED" -o "$OUT/bake"
"$LTM" render "$OUT/scene.json" --spp 32 --width 320 --height 320 --exposure 0.6 --seed "$SEED" -o "$OUT/render"
"$LTM" render builtin:cornell-box --spp 64 --width 256 --height 256 --seed "$SEED" -o "$OUT/cornell-box"
end=$(date +%s%N)
ms=$(( (end - start) / 1000000 ))
cat <<MSG

ltm demo finished in $((ms / 1000)).$(( (ms % 1000) / 100 )) s. Outputs in $OUT/:
  scene.json                  procedural indoor scene (seed $SEED), ltm scene JSON
  points/scene_points.ply     8192 scene points   (x y z nx ny nz albedo_* emission_*)
  points/query_points.ply     65536 query points  (x y z nx ny nz albedo_*)
  bake/irradiance.safetensors E_direct, E_indirect [65536, 3] at the query points (64 spp, depth 5)
  bake/irradiance.ply         the query points with their irradiance, for a point viewer
  preview.png albedo.png normal.png   quick views from the scene's camera
  render.png render.exr       path-traced image (32 spp) with AOVs: irradiance, direct, albedo, N, P, Z
  cornell-box.png .exr        the built-in Cornell box, path traced (64 spp)
Open the PLY files in MeshLab/CloudCompare, the EXR in any HDR viewer, the PNGs anywhere.
MSG
