#!/usr/bin/env bash
# Installs what the project needs on Debian 12 (as root; only what is missing), then
# configures and builds it in ./build with two jobs. Called by demo.sh and test.sh;
# `setup.sh --install-only [package...]` (scripts/test_ros.sh) installs those packages
# too and stops after installing.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(cmake g++ make pkg-config libpcl-dev libeigen3-dev libnanoflann-dev libsuitesparse-dev libopenblas0-pthread libcgal-dev libtbb-dev libgtest-dev xvfb xauth doxygen)
install_only=false
if [ "${1:-}" = "--install-only" ]; then
  install_only=true
  packages+=("${@:2}")
fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "== installing: ${missing[*]}"
  if [ "$(id -u)" -ne 0 ]; then
    echo "error: packages are missing and installing them needs root: ${missing[*]}" >&2
    exit 1
  fi
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

if $install_only; then
  exit 0
fi

echo "== configuring and building (Release, 2 jobs)"
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build --parallel 2
