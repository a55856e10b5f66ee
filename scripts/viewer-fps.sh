#!/usr/bin/env bash
# viewer-fps.sh BAKE.glb [WIDTH HEIGHT] [FRAMES]: the browser viewer's frame time in headless Chromium
# (software WebGL: SwiftShader on the CPU), at the bake's first camera: prints the page's title,
# "ltm-bench ms_per_frame=… fps=… vertices=… size=…" (web/src/viewer.js, #bench=N).
set -euo pipefail
GLB=${1:?usage: scripts/viewer-fps.sh BAKE.glb [WIDTH HEIGHT] [FRAMES]}
W=${2:-1280}
H=${3:-720}
N=${4:-30}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BROWSER=$(command -v chromium || command -v chromium-browser) || { echo "viewer-fps.sh: no chromium" >&2; exit 1; }
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
"$ROOT/scripts/view.sh" "$GLB" "$T/site" 2> /dev/null
"$BROWSER" --headless=new --no-sandbox --use-angle=swiftshader --enable-unsafe-swiftshader --window-size="$W,$H" \
  --virtual-time-budget=120000 --dump-dom "file://$T/site/index.html#camera=0&bare=1&bench=$N" 2> /dev/null |
  tr '\n' ' ' | sed -n 's/.*<title>\(ltm-bench[^<]*\)<\/title>.*/\1/p'
