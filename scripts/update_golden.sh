#!/usr/bin/env bash
# Regenerates tests/data/golden_hashes.json: the state hash of each of the paper's four scenes
# after 300 frames, as `ffdaabb run` reports it (tests/determinism checks them). Run it after a
# deliberate change of the simulation's results and commit the file with that change.
#
#   scripts/update_golden.sh [--preset release|dev|asan]    (builds the CLI first)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
preset=release
while [ $# -gt 0 ]; do
  case "$1" in
    --preset) preset=$2; shift 2 ;;
    *) echo "usage: scripts/update_golden.sh [--preset release|dev|asan]" >&2; exit 2 ;;
  esac
done

# Fewer objects than the paper's runs keep the test cheap; each count still fills at least two
# layers of the scene's layout, so the objects pile and collide.
# No interpenetration samples (--measure-every 0): they do not change the hash, and the dragons'
# take minutes each.
frames=300
scenes=("alphabets 40" "spheres 30" "teapots 24" "buddhas 10")

cmake --preset "$preset" >/dev/null
cmake --build --preset "$preset" --target ffdaabb_cli -j "$(nproc)" >/dev/null
cli="build/$preset/bin/ffdaabb"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

out=tests/data/golden_hashes.json
{
  echo "{"
  echo "  \"comment\": \"State hashes after 'ffdaabb run --scene NAME --objects N --frames F --threads 1'. Regenerate with scripts/update_golden.sh after a deliberate change of the simulation's results.\","
  echo "  \"frames\": $frames,"
  echo "  \"scenes\": ["
  for i in "${!scenes[@]}"; do
    read -r name objects <<<"${scenes[$i]}"
    "$cli" run --scene "$name" --objects "$objects" --frames "$frames" --threads 1 --quiet \
      --measure-every 0 --stats "$tmp/$name.json"
    hash=$(sed -n 's/.*"state_hash": "\([0-9a-f]*\)".*/\1/p' "$tmp/$name.json")
    [ -n "$hash" ] || { echo "update_golden: no state_hash for $name" >&2; exit 1; }
    comma=","
    [ "$i" -eq $((${#scenes[@]} - 1)) ] && comma=""
    echo "    {\"scene\": \"$name\", \"objects\": $objects, \"state_hash\": \"$hash\"}$comma"
    echo "update_golden: $name ($objects objects, $frames frames): $hash" >&2
  done
  echo "  ]"
  echo "}"
} >"$tmp/golden.json"
mv "$tmp/golden.json" "$out"
echo "update_golden: wrote $out"
