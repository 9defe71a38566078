#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (coverage, ASan and UBSan over the whole library) into
# build/fuzz and runs each for a bounded time, starting from its committed seed corpus
# (tests/fuzz/corpus/<target>/; new inputs go to build/fuzz/corpus/<target>/, kept between
# runs). Fails on any crash, leak, timeout, out-of-memory or sanitizer report; the input that
# caused it is written to build/fuzz/artifacts/<target>/ (replay: build/fuzz/bin/fuzz_<target>
# FILE).
#
#   scripts/fuzz.sh [SECONDS [TARGET...]]    default: 60 seconds each, all targets
#
# FUZZ_SEED=N fixes libFuzzer's random seed and FUZZ_RUNS=N stops each target after N inputs
# (still within SECONDS): together they make a run repeatable, which is how CI runs it
# (scripts/test.sh), so that CI reports what a run here would report.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
seconds=${1:-60}
[ $# -gt 0 ] && shift
case "$seconds" in
  '' | *[!0-9]*) echo "usage: scripts/fuzz.sh [SECONDS [TARGET...]]" >&2; exit 2 ;;
esac
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(mesh_load scene_parse)
command -v clang++ >/dev/null || { echo "fuzz.sh: clang++ is missing (scripts/setup.sh)" >&2; exit 1; }

CC=clang CXX=clang++ cmake -S . -B build/fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DFFD_BUILD_FUZZ=ON -DFFD_BUILD_TESTS=OFF -DFFD_BUILD_BENCH=OFF -DFFD_BUILD_APPS=OFF \
  -DFFD_BUILD_RENDER=OFF -DFFD_BUILD_PEERS=OFF >/dev/null
cmake --build build/fuzz -j "$(nproc)" --target "${targets[@]/#/fuzz_}"

export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:symbolize=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
failed=()
for t in "${targets[@]}"; do
  seeds="tests/fuzz/corpus/$t"
  [ -d "$seeds" ] || { echo "fuzz.sh: no seed corpus $seeds" >&2; exit 2; }
  work="build/fuzz/corpus/$t"
  artifacts="build/fuzz/artifacts/$t"
  mkdir -p "$work" "$artifacts"
  dict=()
  [ -f "tests/fuzz/$t.dict" ] && dict=(-dict="tests/fuzz/$t.dict")
  echo "fuzz.sh: $t for $seconds s"
  # -timeout: one input taking 10 s is a hang; -rss_limit_mb: 2 GiB is a leak or a bomb.
  repeat=()
  [ -n "${FUZZ_SEED:-}" ] && repeat+=(-seed="$FUZZ_SEED")
  [ -n "${FUZZ_RUNS:-}" ] && repeat+=(-runs="$FUZZ_RUNS")
  if ! "build/fuzz/bin/fuzz_$t" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 "${repeat[@]}" \
    -print_final_stats=1 -artifact_prefix="$artifacts/" "${dict[@]}" "$work" "$seeds" \
    >"build/fuzz/$t.log" 2>&1; then
    tail -n 60 "build/fuzz/$t.log" >&2
    failed+=("$t")
  else
    grep -E "^stat::(number_of_executed_units|peak_rss_mb)|^Done " "build/fuzz/$t.log" || true
  fi
done
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzz.sh: FAILED: ${failed[*]} (inputs in build/fuzz/artifacts/, logs in build/fuzz/*.log)" >&2
  exit 1
fi
echo "fuzz.sh: ${targets[*]}: no crash, leak, timeout or sanitizer report in $seconds s each"
