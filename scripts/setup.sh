#!/usr/bin/env bash
# Installs the Debian 12 packages mfv needs, only those that are missing.
# On a machine without apt-get it names what is missing and stops.
set -euo pipefail

packages=(
  build-essential cmake ninja-build ccache pkg-config
  libeigen3-dev libgsl-dev libvtk9-dev
  libgtest-dev libbenchmark-dev
  libnanoflann-dev libcli11-dev libtomlplusplus-dev libfmt-dev nlohmann-json3-dev
  voro++-dev libsuitesparse-dev libspectra-dev
  petsc-dev openmpi-bin
  gnuplot-nox
  python3-jsonschema python3-numpy python3-scipy
  python3-pysph
  libxml2-utils libsqlite3-dev
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done 2>/dev/null || missing=("${packages[@]}")

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} required packages are installed"
  exit 0
fi

if ! command -v apt-get >/dev/null 2>&1 || ! command -v dpkg-query >/dev/null 2>&1; then
  echo "setup: this is not a Debian system; install the equivalents of these packages and re-run:" >&2
  printf '  %s\n' "${missing[@]}" >&2
  exit 1
fi

sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then sudo_cmd=(sudo); else
    echo "setup: missing packages and not root (no sudo): ${missing[*]}" >&2
    exit 1
  fi
fi

echo "setup: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "setup: done"
