#!/usr/bin/env bash
# The README's test command: installs what is needed, builds, and runs the whole test suite,
# then installs the library to a temporary prefix and builds and runs the examples against it.
# Idempotent. Usage: scripts/test.sh [--preset release|dev|asan]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
preset=release
while [ $# -gt 0 ]; do
  case "$1" in
    --preset) preset=$2; shift 2 ;;
    *) echo "usage: scripts/test.sh [--preset release|dev|asan]" >&2; exit 2 ;;
  esac
done
jobs=$(nproc)

scripts/setup.sh
cmake --preset "$preset" >/dev/null
cmake --build --preset "$preset" -j "$jobs"
ctest --preset "$preset" -j "$jobs" --timeout 900

if [ "$preset" != asan ]; then
  # The installed package, as a user meets it: find_package(ffdaabb) from examples/.
  prefix=$(mktemp -d)
  trap 'rm -rf "$prefix"' EXIT
  cmake --install "build/$preset" --prefix "$prefix" >/dev/null
  cmake -S examples -B "$prefix/examples-build" -G Ninja -DCMAKE_PREFIX_PATH="$prefix" \
    -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$prefix/examples-build" -j "$jobs" >/dev/null
  "$prefix/examples-build/hello_world" >/dev/null
  "$prefix/examples-build/drop_three"
  "build/$preset/bin/ffdaabb" mesh-info --generate teapot --json >/dev/null
  echo "examples: built against the installed package and ran"
fi
echo "test.sh: all tests passed ($preset)"
