#!/usr/bin/env bash
# viewer_test.sh LTM: the browser viewer (web/, scripts/view.sh) tested in a real browser (issue #32).
# Bakes the Cornell box (path traced at the vertices), opens the viewer in headless Chromium (software
# WebGL) at the scene's camera, and compares its screenshot with ltm's own software view of the same
# .glb (`ltm bake-gi --view`): mean absolute difference ≤ 0.04; the same page at exposure 2⁻¹² must
# differ by ≥ 0.15 (the screenshot shows the bake's light, not a blank canvas). Exit 77 (skipped) when
# Chromium or npm is absent, or the viewer cannot be built (no npm registry).
set -euo pipefail
LTM=${1:?usage: viewer_test.sh path/to/ltm}
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BROWSER=$(command -v chromium || command -v chromium-browser || true)
[[ -n "$BROWSER" ]] || { echo "viewer_test: skipped: no chromium (apt-get install chromium)"; exit 77; }
[[ -f "$ROOT/web/dist/viewer.js" ]] || command -v npm > /dev/null || { echo "viewer_test: skipped: no npm to build the viewer"; exit 77; }
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
# The viewer's bundle: built here once if missing (npm ci + esbuild); without the npm registry, skipped.
if [[ ! -f "$ROOT/web/dist/viewer.js" ]]; then
  (cd "$ROOT/web" && { [[ -d node_modules/three ]] || npm ci --no-audit --no-fund --loglevel=error; } && npm run -s build) > "$T/npm.log" 2>&1 ||
    { echo "viewer_test: skipped: the viewer could not be built (npm ci: no registry?)"; tail -3 "$T/npm.log"; exit 77; }
fi
"$LTM" bake-gi builtin:cornell-box --method pathtrace --spp 16 --max-edge 0.05 -o "$T/cb.glb" --view "$T/soft" --view-size 128 -q
"$ROOT/scripts/view.sh" "$T/cb.glb" "$T/site" 2> /dev/null
shot() {
  timeout 120 "$BROWSER" --headless=new --no-sandbox --disable-gpu-sandbox --use-angle=swiftshader --enable-unsafe-swiftshader \
    --hide-scrollbars --window-size=128,128 --virtual-time-budget=20000 --screenshot="$2" "file://$T/site/index.html#camera=0&bare=1&exposure=$1" \
    > "$T/browser.log" 2>&1 || { cat "$T/browser.log"; exit 1; }
}
shot 1 "$T/shot.png"
shot 0.000244 "$T/dark.png"
same=$(python3 "$ROOT/tests/web/png_diff.py" "$T/shot.png" "$T/soft.png")
dark=$(python3 "$ROOT/tests/web/png_diff.py" "$T/dark.png" "$T/soft.png")
echo "viewer_test: screenshot vs software view: mean |diff| $same (≤ 0.04); at exposure 2^-12: $dark (≥ 0.15)"
python3 -c "import sys; sys.exit(0 if $same <= 0.04 and $dark >= 0.15 else 1)"
