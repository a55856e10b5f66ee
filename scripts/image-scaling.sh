#!/usr/bin/env bash
# image-scaling.sh: how a neural render's time and memory grow with the image (issue #31's table in
# docs/performance.md). One render per size and GI stride of SCENE with MODEL; prints a markdown row
# each: in-process seconds and their split (from the render's timings.json), outside-the-render
# seconds, wall seconds and peak memory (/usr/bin/time). Env: LTM, SCENE, MODEL, SIZES ("WxH ..."),
# STRIDES ("1 2"), EXTRA (more render options, e.g. "--scene-points 32768 --prior-theta 0.5").
set -euo pipefail
LTM=${LTM:-build/apps/ltm/ltm}
SCENE=${SCENE:-examples/indoor-900012/scene.json}
MODEL=${MODEL:-models/ltm-cpu.safetensors}
SIZES=${SIZES:-"256x256 512x512 1024x1024 2048x2048 2688x1152"}
STRIDES=${STRIDES:-"1 2"}
EXTRA=${EXTRA:-}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo "| size | GI stride | decoded | in process | encode | gather (decode) | direct | outside the render | wall | peak memory |"
echo "|---|---|---|---|---|---|---|---|---|---|"
for size in $SIZES; do
  for stride in $STRIDES; do
    w=${size%x*} h=${size#*x}
    # shellcheck disable=SC2086
    /usr/bin/time -f "%e %M" -o "$out/time" "$LTM" render "$SCENE" --method neural --model "$MODEL" --width "$w" \
      --height "$h" --gi-stride "$stride" -q $EXTRA -o "$out/r"
    read -r wall kb < "$out/time"
    python3 - "$out/r.timings.json" "$size" "$stride" "$wall" "$kb" <<'PY'
import json, sys
j = json.load(open(sys.argv[1])); t = j["timings"]; o = j["outside_render"]
enc = t["sample_s"] + t["geometry_s"] + t["encode_s"]
outside = sum(v for k, v in o.items() if v >= 0)
print(f"| {sys.argv[2].replace('x', '×')} | {sys.argv[3]} | {j['decoded']:,} | {t['total_s']:.2f} s | {enc:.2f} s | "
      f"{t['decode_s']:.2f} s | {t['direct_s']:.2f} s | {outside:.2f} s | {float(sys.argv[4]):.2f} s | {int(sys.argv[5]) / 1024:.0f} MB |")
PY
  done
done
