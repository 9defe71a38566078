#!/usr/bin/env bash
# The README's demo command: installs what is needed, builds, and runs the paper's experiment
# (the four scenes, previous vs enhanced, side by side), then renders a still of each scene
# framed like the README's pictures, the bounding spheres over the falling spheres (as the
# paper's Fig. 3), and a short video of the spheres. Idempotent. Finishes in a few minutes on a
# 2-core machine.
#   scripts/demo.sh [--frames N] [--out DIR] [--pictures]
# --pictures renders the pictures only, with the tool already built (FFDAABB=path/to/ffdaabb
# picks another build than build/release).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
frames=300
out=out/demo
only_pictures=0
usage="usage: scripts/demo.sh [--frames N] [--out DIR] [--pictures]"
while [ $# -gt 0 ]; do
  case "$1" in
    --frames) [ $# -ge 2 ] || { echo "$usage" >&2; exit 2; }; frames=$2; shift 2 ;;
    --out) [ $# -ge 2 ] || { echo "$usage" >&2; exit 2; }; out=$2; shift 2 ;;
    --pictures) only_pictures=1; shift ;;
    *) echo "$usage" >&2; exit 2 ;;
  esac
done
ffdaabb=${FFDAABB:-build/release/bin/ffdaabb}

# --camera for a view of the pile from azimuth 30 degrees and elevation $3 (default 25) degrees,
# $1 metres from the point $2 metres above the floor's centre: "eye x,y,z:target x,y,z".
camera() {
  awk -v d="$1" -v y="$2" -v el="${3:-25}" 'BEGIN {
    r = atan2(0, -1) / 180; e = el * r; a = 30 * r
    printf "%.2f,%.2f,%.2f:0,%s,0", d * cos(e) * sin(a), y + d * sin(e), d * cos(e) * cos(a), y
  }'
}

# Stills as in the README (docs/images), 800 x 450 and without overlays: each scene after it
# has fallen (scene:frames simulated:camera distance:target height), then one of the spheres
# falling with the bounding spheres drawn (--overlay spheres, as docs/images/spheres_fig3.png),
# then a video of the spheres falling (framed automatically).
pictures() {
  echo "== Pictures"
  local still scene steps distance height
  for still in alphabets:150:12:0.5 spheres:300:13:0.5 teapots:240:11:0.4 buddhas:240:9:0.5; do
    IFS=: read -r scene steps distance height <<<"$still"
    "$ffdaabb" render --scene "$scene" --frames 1 --steps "$steps" --width 800 --height 450 \
      --camera "$(camera "$distance" "$height")" --out "$out/$scene.png" --quiet
  done
  "$ffdaabb" render --scene spheres --frames 1 --steps 40 --width 800 --height 450 \
    --camera "$(camera 11.5 1.6 22)" --overlay spheres --out "$out/spheres_fig3.png" --quiet
  "$ffdaabb" render --scene spheres --frames 180 --width 640 --height 360 --out "$out/spheres.mp4" \
    --quiet
}

if [ "$only_pictures" -eq 1 ]; then
  mkdir -p "$out"
  pictures
  echo "Pictures in $out/: alphabets.png spheres.png teapots.png buddhas.png spheres_fig3.png" \
    "spheres.mp4"
  exit 0
fi

scripts/setup.sh
cmake --preset release >/dev/null
cmake --build --preset release -j "$(nproc)"
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
pictures

echo
echo "Done. Results in $out/:"
echo "  bench/table1.md, bench/table1.csv   Table 1 (ms per frame by stage, ours beside the paper's)"
echo "  bench/table2.md                     Table 2 (vertices, triangles, FFD cells)"
echo "  bench/fig4.png, bench/fig4.csv      Fig. 4 (frames per second, previous vs enhanced)"
echo "  bench/summary.json                  everything, machine-readable"
echo "  alphabets.png ... buddhas.png       the four scenes, framed like the README's"
echo "  spheres_fig3.png                    the bounding spheres over the falling spheres (Fig. 3)"
echo "  spheres.mp4                         the spheres falling"
