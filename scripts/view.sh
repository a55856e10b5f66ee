#!/usr/bin/env bash
# view.sh BAKE.glb OUT [SECOND.glb]: a self-contained viewer folder for `ltm bake-gi` output
# (issue #32): OUT/index.html, OUT/viewer.js (web/, three.js, bundled by esbuild) and OUT/bakes.js
# (the .glb files as base64, so the folder opens from file:// as well as from any static server).
# With SECOND (e.g. `ltm bake-gi --method pathtrace` of the same scene) the two are shown side by
# side with one camera. The viewer is built on first use (npm ci + esbuild; npm packages are the
# only download). Open OUT/index.html; #camera=N&exposure=X&mode=irradiance&bare=1 in the URL.
set -euo pipefail
GLB=${1:?usage: scripts/view.sh BAKE.glb OUT [SECOND.glb]}
OUT=${2:?usage: scripts/view.sh BAKE.glb OUT [SECOND.glb]}
SECOND=${3:-}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
WEB=$ROOT/web
for f in "$GLB" ${SECOND:+"$SECOND"}; do
  [[ -f "$f" ]] || { echo "view.sh: $f: no such file" >&2; exit 1; }
done
if [[ ! -f "$WEB/dist/viewer.js" || "$WEB/src/viewer.js" -nt "$WEB/dist/viewer.js" ]]; then
  command -v npm > /dev/null || { echo "view.sh: the viewer needs npm to build (apt-get install npm)" >&2; exit 1; }
  (cd "$WEB" && { [[ -d node_modules/three ]] || npm ci --no-audit --no-fund --loglevel=error; } && npm run -s build) >&2
fi
mkdir -p "$OUT"
cp "$WEB/dist/viewer.js" "$OUT/viewer.js"
cp "$WEB/index.html" "$OUT/index.html"
python3 - "$OUT/bakes.js" "$GLB" "$SECOND" <<'PY'
import base64, json, os, sys
out, files = sys.argv[1], [f for f in sys.argv[2:] if f]
bakes = [{"name": os.path.basename(f), "glb": base64.b64encode(open(f, "rb").read()).decode("ascii")} for f in files]
tmp = out + ".tmp"
with open(tmp, "w") as fh:
    fh.write("window.LTM_BAKES = " + json.dumps(bakes) + ";\n")
os.replace(tmp, out)
PY
echo "view.sh: open $OUT/index.html" >&2
