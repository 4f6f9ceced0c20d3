#!/usr/bin/env bash
# Installs the Debian 12 packages sglab needs, if any are missing; extra
# arguments name more packages (scripts/results.sh adds jq and valgrind). The
# Python package builds against Debian's /usr/bin/python3 and these python3-*
# packages (PyTorch for sglab.torch and its tests).
set -euo pipefail
packages=(build-essential cmake ninja-build libceres-dev libeigen3-dev libboost-dev libfmt-dev libgtest-dev
          libbenchmark-dev libcli11-dev nlohmann-json3-dev libtbb-dev gnuplot-nox
          glslang-tools glslang-dev libvulkan-dev mesa-vulkan-drivers spirv-tools vulkan-tools
          libopenexr-dev coinor-libclp-dev pkg-config
          pybind11-dev python3-pybind11 python3-numpy python3-pytest python3-torch "$@")
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "sglab: installing ${missing[*]}" >&2
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
