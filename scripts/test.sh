#!/usr/bin/env bash
# The README's test command. Idempotent.
#
#   scripts/test.sh                  what CI runs (.ci/run): every stage below
#   scripts/test.sh --preset NAME    one build and its suite only (release, dev, asan or tsan)
#
# Stages: setup (packages, models); the release build and the whole suite (the Python module's
# pytest suite among it); the library installed to a temporary prefix with the examples built and
# run against it; the Python package installed with `pip install .` into a virtual environment
# (build/python-venv) and its examples run with it; the short soaks
# (600 frames of each paper scene, every check); the asan build (ASan +
# UBSan) and the whole suite under it; the tsan build (ThreadSanitizer) and the threaded tests
# under it (the step at 1-4 threads, task systems); each libFuzzer target on 100,000 inputs from a fixed seed
# (at most 120 s).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
preset=""
while [ $# -gt 0 ]; do
  case "$1" in
    --preset)
      [ $# -ge 2 ] || { echo "usage: scripts/test.sh [--preset release|dev|asan|tsan]" >&2; exit 2; }
      preset=$2; shift 2 ;;
    *) echo "usage: scripts/test.sh [--preset release|dev|asan|tsan]" >&2; exit 2 ;;
  esac
done
case "$preset" in
  "" | release | dev | asan | tsan) ;;
  *) echo "test.sh: unknown preset '$preset' (expected release, dev, asan or tsan)" >&2; exit 2 ;;
esac
jobs=$(nproc)
start=$(date +%s)
stage() { echo "test.sh: [$(($(date +%s) - start)) s] $*"; }

suite() { # build and run the suite of one preset (tsan: the tests labelled threads)
  stage "$1 build"
  # Debian's interpreter: the one setup.sh installs NumPy and pytest for (another python3 may
  # come first on PATH), so that the module is built for it and ctest's pytest runs with it.
  cmake --preset "$1" -DPython3_EXECUTABLE=/usr/bin/python3 >/dev/null
  cmake --build --preset "$1" -j "$jobs"
  stage "$1 suite"
  ctest --preset "$1" -j "$jobs" --timeout 900
}

examples() { # the installed package, as a user meets it: find_package(ffdaabb) from examples/
  stage "examples against the installed package ($1)"
  prefix=$(mktemp -d)
  trap 'rm -rf "$prefix"' EXIT
  cmake --install "build/$1" --prefix "$prefix" >/dev/null
  cmake -S examples -B "$prefix/examples-build" -G Ninja -DCMAKE_PREFIX_PATH="$prefix" \
    -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$prefix/examples-build" -j "$jobs" >/dev/null
  "$prefix/examples-build/hello_world" >/dev/null
  "$prefix/examples-build/drop_three"
  "$prefix/examples-build/own_threads"
  "$prefix/examples-build/save_restore"
  "$prefix/examples-build/pins"
  "$prefix/examples-build/queries"
  "$prefix/examples-build/colliders" >/dev/null
  # The core alone: its package component finds the threading library and nothing else, and
  # its program links nothing of the content's.
  cmake -S examples/core_only -B "$prefix/core-only-build" -G Ninja -DCMAKE_PREFIX_PATH="$prefix" \
    -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$prefix/core-only-build" >/dev/null
  "$prefix/core-only-build/stacked_boxes" >/dev/null
  if grep -E '^ *LINK_LIBRARIES' "$prefix/core-only-build/build.ninja" |
    grep -Eiq 'content|assimp|meshopt|freetype|glu|libz|json'; then
    echo "examples: the core-only program links content libraries:" >&2
    grep -E '^ *LINK_LIBRARIES' "$prefix/core-only-build/build.ninja" >&2
    exit 1
  fi
  # The installed program finds the installed scenes (its data folder, beside its bin/).
  (cd / && env -u FFDAABB_DATA -u FFDAABB_SCENES "$prefix/bin/ffdaabb" run --scene spheres \
    --frames 2 --quiet)
  "build/$1/bin/ffdaabb" mesh-info --generate teapot --json >/dev/null
  "build/$1/bin/ffdaabb" run --scene examples/mixed.json --frames 30 --quiet
  "build/$1/bin/ffdaabb" run --scene examples/one_spot.json --frames 10 --quiet
  "build/$1/bin/ffdaabb" run --scene examples/pinned.json --frames 60 --quiet
  echo "examples: built against the installed package and ran (the core-only one linking the core and the threading library alone)"
}

python_package() { # the Python package as a user installs it: `pip install .` into a venv
  stage "the Python package: pip install . into a virtual environment, its examples"
  local venv="build/python-venv"
  [ -x "$venv/bin/python" ] || /usr/bin/python3 -m venv --system-site-packages "$venv"
  "$venv/bin/pip" install --quiet --no-input --disable-pip-version-check . >"build/python-install.log" 2>&1 ||
    { tail -n 40 build/python-install.log >&2; echo "pip install . failed" >&2; exit 1; }
  local out
  out=$(mktemp -d)
  (cd "$out" && env -u PYTHONPATH -u FFDAABB_DATA "$root/$venv/bin/python" -c \
    'import ffdaabb, sys; w = ffdaabb.World.from_scene("spheres"); w.step(30); print("import ffdaabb:", ffdaabb.__file__, f"{w.state_hash:016x}")')
  for example in examples/python/*.py; do
    (cd "$out" && MPLBACKEND=Agg env -u PYTHONPATH "$root/$venv/bin/python" "$root/$example" --quick \
      >"$out/$(basename "$example").log" 2>&1) ||
      { cat "$out/$(basename "$example").log" >&2; echo "$example failed" >&2; exit 1; }
    echo "examples/python: $(basename "$example") ran"
  done
  rm -rf "$out"
}

stage setup
scripts/setup.sh

if [ -n "$preset" ]; then
  suite "$preset"
  case "$preset" in asan | tsan) ;; *) examples "$preset"; python_package ;; esac
  stage "all tests passed ($preset)"
  exit 0
fi

suite release
examples release
python_package
stage "short soaks: the four paper scenes, 600 frames each, default tolerances; no body rising faster than 2 m/s after 2 s, energy never 1 % of its scale over the start"
for scene in spheres alphabets teapots buddhas; do
  build/release/bin/ffdaabb soak --scene "$scene" --frames 600 --launch-tolerance 2 --energy-tolerance 0.01
done
suite asan
suite tsan
# Repeatable: a fixed seed and at most 100,000 inputs per target (about 40 s for mesh_load here),
# from a fresh corpus in a fresh clone, so CI tries the inputs a run here tried.
stage "fuzzing, ${FUZZ_RUNS:-100000} inputs per target (seed ${FUZZ_SEED:-1})"
FUZZ_SEED=${FUZZ_SEED:-1} FUZZ_RUNS=${FUZZ_RUNS:-100000} scripts/fuzz.sh "${FUZZ_SECONDS:-120}"
stage "all stages passed: release, asan and tsan suites, examples, soaks, fuzzing"
