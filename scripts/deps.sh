#!/usr/bin/env bash
# Installs the Debian packages dqkit builds and tests with, if any is missing (idempotent).
set -euo pipefail
packages=(cmake g++ make pkg-config libgtest-dev libbenchmark-dev libeigen3-dev libglm-dev
  libassimp-dev assimp-testmodels liborocos-kdl-dev libtbb-dev libcli11-dev nlohmann-json3-dev clang libclang-rt-14-dev lld
  libtinygltf-dev libstb-dev libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri libglfw3-dev xvfb xauth imagemagick libimgui-dev xdotool x11-apps ccache
  pybind11-dev python3-pybind11 python3-numpy python3-pytest python3-hypothesis python3-scipy python3-transforms3d
  python3-pip python3-setuptools python3-wheel python3-matplotlib)
missing=()
for p in "${packages[@]}"; do
  dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "dqkit: installing ${missing[*]}"
  sudo_cmd=()
  [ "$(id -u)" -ne 0 ] && sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
