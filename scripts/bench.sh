#!/usr/bin/env bash
# bench.sh: the foundation benchmarks plus the end-to-end "generate + sample 100 scenes" timing
# (the CLI path a dataset build takes: M = 8192 scene points, N = 65536 query points each).
set -euo pipefail
BUILD=${BUILD:-build}
LTM="$BUILD/apps/ltm/ltm"
"$BUILD/bench/foundation_bench" --benchmark_min_time=0.5
"$BUILD/bench/render_bench"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
start=$(date +%s%N)
for seed in $(seq 0 99); do
  "$LTM" generate --seed "$seed" -o "$tmp/s$seed.json" -q
  "$LTM" sample "$tmp/s$seed.json" -M 8192 -N 65536 --seed "$seed" --exclude-enclosed -o "$tmp/p$seed" -q
done
end=$(date +%s%N)
echo "generate + sample (--exclude-enclosed, M=8192, N=65536) x 100 scenes: $(( (end - start) / 1000000 )) ms"
