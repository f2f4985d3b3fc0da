#!/usr/bin/env bash
# Installs every Debian package vantage needs to build, test and benchmark.
# Idempotent; run as root (or with sudo available). Chromium is for the HTML report test; clang
# and libclang-rt-14-dev (libFuzzer) for `make fuzz`; pybind11 and the python3 packages for the
# Python module, its tests and examples (docs/python.md), setuptools and pip for `pip install .`;
# Open MPI for `mpirun vantage` (docs/distributed.md), jq for its tests' report comparison.
set -euo pipefail
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
PACKAGES=(
  build-essential cmake pkg-config git
  libembree-dev libassimp-dev libeigen3-dev libtbb-dev libyaml-cpp-dev nlohmann-json3-dev
  libcli11-dev libfmt-dev libspdlog-dev libsdformat-dev liburdfdom-dev coinor-libcbc-dev
  coinor-libclp-dev libnauty2-dev liborocos-kdl-dev libfcl-dev libompl-dev
  libgtest-dev libgmock-dev libbenchmark-dev libpng-dev libstb-dev libjs-three chromium
  clang libclang-rt-14-dev python3
  pybind11-dev python3-dev python3-numpy python3-scipy python3-pytest python3-matplotlib
  python3-setuptools python3-wheel python3-pip python3-venv
  libopenmpi-dev openmpi-bin jq
  python3-jsonschema python3-yaml libexpat1-dev
  libocct-data-exchange-dev libocct-modeling-algorithms-dev libocct-ocaf-dev
)
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ "${#missing[@]}" -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
