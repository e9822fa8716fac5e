#!/usr/bin/env bash
# Installs the Debian 12 packages pwsim needs, only those missing. Run as root (or with sudo).
set -euo pipefail
packages=(
  build-essential cmake pkg-config git
  libeigen3-dev libyaml-cpp-dev nlohmann-json3-dev libceres-dev libtbb-dev
  libopenscenegraph-dev libosmesa6-dev libopencv-dev ffmpeg
  libgtest-dev libgmock-dev googletest libbenchmark-dev
  python3 python3-numpy python3-scipy python3-yaml
  can-utils iproute2 clang libclang-rt-14-dev
  gnuplot-nox libmatio-dev r-base-core r-cran-sandwich libsdl2-dev stress-ng libboost-dev libalglib-dev libsodium-dev r-cran-quadprog
  slurmctld slurmd slurm-client munge
)
missing=()
for package in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$package")
  fi
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
