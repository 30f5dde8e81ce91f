#!/usr/bin/env bash
# Installs every build, test and run dependency of vaw from Debian 12's own packages.
# Idempotent: packages already present are skipped by apt, and apt is not touched at all when
# nothing is missing (so a repeat run is fast and works offline).
set -euo pipefail

packages=(
  # toolchain
  build-essential cmake ninja-build pkg-config file
  # core libraries (zlib: the evaluation report's PNG pictures)
  libeigen3-dev libfcl-dev libassimp-dev nlohmann-json3-dev libcli11-dev zlib1g-dev
  # a CAD file's bytes hashed (XXH3) for the scene that refers to it and the reads kept for reopening
  libxxhash-dev
  # STEP import (the Open CASCADE 7.6 plugin): XDE reader, modelling, meshing
  libocct-data-exchange-dev libocct-ocaf-dev libocct-modeling-algorithms-dev libocct-modeling-data-dev
  libocct-foundation-dev libocct-visualization-dev
  # OCCT's CMake targets link /usr/lib/x86_64-linux-gnu/libtbb.so, which only the -dev package provides
  libtbb-dev
  # Qt 6: Qt3D's CMake package also needs the OpenGL, xkbcommon and Vulkan headers
  qt6-base-dev qt6-3d-dev qt6-charts-dev qt6-svg-dev
  libqt6opengl6-dev libqt6openglwidgets6 libxkbcommon-dev libvulkan-dev libgl-dev
  qt6-qpa-plugins qt6-3d-defaultgeometryloader-plugin qt6-3d-assimpsceneimport-plugin
  # tests and benchmarks
  libbenchmark-dev libgtest-dev
  # VR mode: the OpenXR loader (the plugin links it); its core validation layer checks the VR tests
  libopenxr-dev openxr-layer-corevalidation
  # the fuzzers (clang's libFuzzer and sanitizer runtimes), and the format and lint configurations
  clang libclang-rt-dev clang-format clang-tidy
  # optional peers for the work-precision chart
  libbullet-dev libode-dev
  # headless display for the Qt3D viewport: Xvfb with Mesa's software OpenGL (llvmpipe); EGL's headers for
  # the headset renderer's benchmark (no X server)
  xvfb xauth libgl1-mesa-dri libglx-mesa0 libegl-mesa0 libegl-dev
  # the evaluation report is opened in a real browser by its test (headless); three.js draws its 3D view
  chromium libjs-three
  # videos of a session or an order: FFmpeg's libraries (libavcodec has the libx264 H.264 encoder); ffprobe
  # reads the videos back in the tests
  libavcodec-dev libavformat-dev libswscale-dev libavutil-dev ffmpeg
  # packaging checks
  desktop-file-utils appstream
  # regenerating docs/states.svg from docs/states.dot
  graphviz
  # a decimal-comma locale (de_DE.UTF-8, generated below): the tests check that what vaw writes keeps its
  # point wherever Qt applies the user's locale
  locales
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

has_locale() { locale -a 2>/dev/null | grep -qix 'de_DE.utf8'; }

if [ ${#missing[@]} -eq 0 ] && has_locale; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO=sudo; else
    echo "install-deps: need root or sudo to install: ${missing[*]} (and the de_DE.UTF-8 locale)" >&2; exit 1
  fi
else
  SUDO=
fi

if [ ${#missing[@]} -gt 0 ]; then
  echo "install-deps: installing ${#missing[@]} packages: ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" </dev/null
fi
if ! has_locale; then
  echo "install-deps: generating the de_DE.UTF-8 locale"
  $SUDO sed -i 's/^# *\(de_DE.UTF-8 UTF-8\)/\1/' /etc/locale.gen
  grep -qx 'de_DE.UTF-8 UTF-8' /etc/locale.gen || echo 'de_DE.UTF-8 UTF-8' | $SUDO tee -a /etc/locale.gen >/dev/null
  $SUDO locale-gen >/dev/null
fi
echo "install-deps: done"
