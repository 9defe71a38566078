#!/usr/bin/env bash
# Runs every benchmark on this machine and writes the results where docs/BENCHMARKS.md quotes
# them from: bench/results/<machine>/. Takes about 12 minutes on a 2-core machine.
#   scripts/bench.sh [machine-label]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
machine=${1:-$(uname -m)-$(nproc)cpu}
out=bench/results/$machine
scripts/setup.sh
cmake --preset release >/dev/null
cmake --build --preset release -j "$(nproc)"
mkdir -p "$out"

echo "== micro-benchmarks -> $out/micro.json"
build/release/bin/ffdaabb_micro --benchmark_min_time=0.3 --benchmark_repetitions=3 \
  --benchmark_report_aggregates_only=true --benchmark_out="$out/micro.json" \
  --benchmark_out_format=json | tee "$out/micro.txt"

echo "== the paper's experiment -> $out/paper/"
build/release/bin/ffdaabb bench --frames 300 --warmup 60 --out "$out/paper"

echo "== alphabets beside alphabets_x10 (ten times the floor) -> $out/alphabets_x10/"
build/release/bin/ffdaabb bench --scenes alphabets,alphabets_x10 --frames 300 --warmup 60 \
  --out "$out/alphabets_x10"

echo "== Bullet side by side -> $out/bullet-spheres.json"
build/release/bin/ffdaabb_peer_bullet --scene spheres --frames 600 --warmup 60 \
  --json "$out/bullet-spheres.json" | tee "$out/bullet-spheres.txt"
echo "results in $out"
