#!/usr/bin/env bash
# Soaks the workbench's window (tests/soak/soak_window.cpp) under Xvfb and prints its memory growth per
# hour of session between resets. Usage: tests/soak/soak.sh [BUILD_DIR] [WALL_MINUTES] [CSV]
# (defaults: build, 30, BUILD_DIR/soak.csv). Results go in docs/benchmarks.md.
set -euo pipefail
here=$(cd "$(dirname "$0")/../.." && pwd)
build=$(cd "${1:-$here/build}" && pwd)
export VAW_SOAK_MINUTES=${2:-30}
export VAW_SOAK_CSV=${3:-$build/soak.csv}
export QT3D_RENDERER=opengl QT_QPA_PLATFORM=xcb
export VAW_RESOURCE_DIR=$build/share/vaw VAW_PLUGIN_PATH=$build/lib/vaw/plugins
export XDG_CONFIG_HOME=$(mktemp -d)
trap 'rm -rf "$XDG_CONFIG_HOME"' EXIT
exec xvfb-run -a -s '-screen 0 1280x800x24' "$build/bin/vaw_soak_window"
