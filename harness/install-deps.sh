#!/usr/bin/env bash
# Installs what clipray needs from Debian 12 packages, and only what is missing.
# Idempotent. Not root: prints the apt line to run instead and exits 1.
# Then three.js for the WebGL test pages (tests/webgl/three/), at the version its package-lock.json
# pins, with `npm ci` where node_modules does not hold that version already (from
# registry.npmjs.org: the one download not from Debian's mirrors).
set -euo pipefail
pages="$(cd "$(dirname "$0")/.." && pwd)/tests/webgl/three"
install_test_pages() {
  local want have
  want=$(node -p "require('$pages/package-lock.json').packages['node_modules/three'].version")
  have=$(node -p "try { require('$pages/node_modules/three/package.json').version } catch (e) { '' }")
  if [ "$want" = "$have" ]; then
    echo "install-deps: three $have present in tests/webgl/three/node_modules"
    return 0
  fi
  echo "install-deps: npm ci in tests/webgl/three (three $want)"
  (cd "$pages" && npm ci --ignore-scripts --no-audit --no-fund)
}
packages=(
  build-essential cmake ninja-build pkg-config clang-format
  libosmesa6-dev libegl-dev libgl-dev libglfw3-dev libglm-dev python3-glad libstb-dev libdeflate-dev
  libgtest-dev libgmock-dev libbenchmark-dev nlohmann-json3-dev libcli11-dev
  libembree-dev
  libtinygltf-dev libtinyobjloader-dev clang-14 libclang-rt-14-dev
  libimgui-dev xvfb xauth
  assimp-testmodels chromium fonts-liberation
  apitrace apitrace-tracers mesa-utils mesa-utils-bin glmark2-x11 glmark2-es2-x11
  renderdoccmd python3-renderdoc librenderdoc librenderdoc-dev
)
# npm (and nodejs) from Debian, unless an npm is there already: NodeSource's nodejs package
# brings its own and conflicts with Debian's npm.
command -v npm >/dev/null 2>&1 || packages+=(npm)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  install_test_pages
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
install_test_pages
