#!/usr/bin/env bash
# Installs what vts needs from Debian 12's archive, only what is missing.
# Idempotent: a second run does nothing but check.
set -euo pipefail

packages=(
  cmake ninja-build g++ pkg-config
  libosmesa6-dev libglm-dev libglfw3-dev libeigen3-dev
  libopenexr-dev openexr libembree-dev libtbb-dev
  catch2 libbenchmark-dev
  libimgui-dev libstb-dev libcli11-dev libyaml-cpp-dev nlohmann-json3-dev
  libassimp-dev libpng-dev libopenimageio-dev xvfb xauth
  zlib1g-dev
  python3-dev pybind11-dev python3-numpy python3-pytest python3-openimageio openimageio-tools
  python3-distributed
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages present"
  exit 0
fi

sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
echo "setup: installing ${missing[*]}"
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
