#!/usr/bin/env bash
# Installs what clipray needs from Debian 12 packages, and only what is missing.
# Idempotent. Not root: prints the apt line to run instead and exits 1.
set -euo pipefail
packages=(
  build-essential cmake ninja-build pkg-config clang-format
  libosmesa6-dev libegl-dev libgl-dev libglfw3-dev libglm-dev python3-glad libstb-dev libdeflate-dev
  libgtest-dev libgmock-dev libbenchmark-dev nlohmann-json3-dev libcli11-dev
  libembree-dev
  libtinygltf-dev libtinyobjloader-dev clang-14 libclang-rt-14-dev
  libimgui-dev xvfb xauth
  assimp-testmodels chromium fonts-liberation
  apitrace apitrace-tracers mesa-utils glmark2-x11
  python3-renderdoc librenderdoc librenderdoc-dev
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi
line="apt-get update && apt-get install -y --no-install-recommends ${missing[*]}"
if [ "$(id -u)" -ne 0 ]; then
  echo "install-deps: missing packages; run as root:" >&2
  echo "  $line" >&2
  exit 1
fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${missing[@]}"
