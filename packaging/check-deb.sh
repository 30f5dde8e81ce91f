#!/usr/bin/env bash
# Builds the Debian package from a finished build tree and checks that it carries what a user needs:
# the executables, the core library, the importer plugin, the bundled scenes, the desktop entry,
# the AppStream metainfo and the icon, and that its dependencies were found by dpkg-shlibdeps.
#   packaging/check-deb.sh BUILD_DIR
set -euo pipefail
build=$(cd "$1" && pwd)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
(cd "$build" && cpack -G DEB -B "$out" >"$out/cpack.log" 2>&1) || { cat "$out/cpack.log"; exit 1; }
deb=$(ls "$out"/*.deb)
echo "package: $(basename "$deb") ($(du -h "$deb" | cut -f1))"
contents=$(dpkg-deb -c "$deb" | awk '{print $6}')
missing=0
for want in ./usr/bin/vaw ./usr/bin/vaw-sim /libvaw_core.so. ./usr/lib/vaw/plugins/libvaw_import_assimp.so \
            ./usr/share/vaw/scenes/sleeve-on-shaft.vaw.json ./usr/share/vaw/meshes/ \
            ./usr/share/applications/io.github.vaw.Workbench.desktop \
            ./usr/share/metainfo/io.github.vaw.Workbench.metainfo.xml \
            ./usr/share/icons/hicolor/scalable/apps/io.github.vaw.Workbench.svg; do
  if ! grep -qF -- "$want" <<<"$contents"; then echo "missing from the package: $want"; missing=1; fi
done
depends=$(dpkg-deb -f "$deb" Depends)
echo "depends: $depends"
for lib in libqt6widgets6 libqt63dcore6 libassimp5 qt6-qpa-plugins; do
  grep -q "$lib" <<<"$depends" || { echo "dependency not found by dpkg-shlibdeps: $lib"; missing=1; }
done
[ $missing -eq 0 ] && echo "deb contents and dependencies OK"
exit $missing
