#!/usr/bin/env bash
# The README's demo command: installs what is needed, builds, and runs the paper's experiment
# (the four scenes, previous vs enhanced, side by side), then renders a still of each scene and
# a short video of the spheres. Idempotent. Finishes in a few minutes on a 2-core machine.
#   scripts/demo.sh [--frames N] [--out DIR]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
frames=300
out=out/demo
while [ $# -gt 0 ]; do
  case "$1" in
    --frames) frames=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    *) echo "usage: scripts/demo.sh [--frames N] [--out DIR]" >&2; exit 2 ;;
  esac
done

scripts/setup.sh
cmake --preset release >/dev/null
cmake --build --preset release -j "$(nproc)"
ffdaabb=build/release/bin/ffdaabb
mkdir -p "$out"

echo
echo "== Table 2: the paper's objects, ours beside the paper's"
for object in alphabet sphere teapot dragon; do
  "$ffdaabb" mesh-info --generate "$object" | sed -n '1,5p'
done

echo
echo "== Tables 1 and Fig. 4: the four scenes, previous vs enhanced ($frames frames each)"
"$ffdaabb" bench --frames "$frames" --warmup 60 --out "$out/bench"

echo
echo "== Pictures"
for scene in alphabets spheres teapots buddhas; do
  "$ffdaabb" render --scene "$scene" --frames 1 --steps 120 --width 960 --height 540 \
    --overlay spheres --out "$out/$scene.png" --quiet
done
"$ffdaabb" render --scene spheres --frames 180 --width 640 --height 360 --out "$out/spheres.mp4" --quiet

echo
echo "Done. Results in $out/:"
echo "  bench/table1.md, bench/table1.csv   Table 1 (ms per frame by stage, ours beside the paper's)"
echo "  bench/table2.md                     Table 2 (vertices, triangles, FFD cells)"
echo "  bench/fig4.png, bench/fig4.csv      Fig. 4 (frames per second, previous vs enhanced)"
echo "  bench/summary.json                  everything, machine-readable"
echo "  alphabets.png spheres.png teapots.png buddhas.png spheres.mp4"
