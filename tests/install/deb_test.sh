#!/bin/bash
# The Debian package (docs/install.md): cpack makes wirefur_<version>_amd64.deb from the build;
# its control file declares what it needs (dpkg-shlibdeps: VTK 9.1, OpenCASCADE, oneTBB, libpng,
# libzip, pugixml ...; and python3-vtk9), it holds the command, the modules and their worker, the
# Python package and the CMake package under /usr, and, unpacked into a folder (not installed:
# that is checked by hand, docs/install.md), the command renders a scene and the Python package
# imports from it.
# Usage: deb_test.sh BUILD_DIR
set -euo pipefail
build=$1
work=$(mktemp -d "${TMPDIR:-/tmp}/wirefur-deb-test-XXXXXX")
trap 'rm -rf "$work"' EXIT
fail() { echo "FAILED: $*"; exit 1; }

cpack --config "$build/CPackConfig.cmake" -B "$work" >"$work/cpack.log" 2>&1 || { tail -20 "$work/cpack.log"; fail "cpack"; }
deb=$(ls "$work"/wirefur_*_amd64.deb 2>/dev/null | head -1)
[ -n "$deb" ] || fail "no wirefur_*_amd64.deb made"
echo "made $(basename "$deb"): $(du -h "$deb" | cut -f1)"
info=$(dpkg-deb -I "$deb")
depends=$(echo "$info" | sed -n 's/^ Depends: //p')
echo "Depends: $depends"
for need in libvtk9.1 python3-vtk9 libocct-modeling-algorithms-7.6 libocct-data-exchange-7.6 libtbb12 libzip4 libpugixml1v5 libpng16-16; do
  [[ $depends == *"$need"* ]] || fail "Depends lacks $need"
done
contents=$(dpkg-deb -c "$deb")
for f in ./usr/bin/wirefur ./usr/lib/libWireFurFilters.so ./usr/lib/libWireFurCAD.so ./usr/lib/wirefur-cad-worker \
         ./usr/lib/python3/dist-packages/wirefur/__init__.py ./usr/lib/cmake/WireFur/WireFurConfig.cmake \
         ./usr/include/wirefur/vtkWireFurRenderPass.h ./usr/share/wirefur/scenes/cage_shaded.json ./usr/share/doc/wirefur/README.md \
         ./usr/share/doc/wirefur/docs/install.md; do
  grep -q " $f\$" <<<"$contents" || fail "the package lacks $f"
done
echo "contents: $(grep -c '^-' <<<"$contents") files"
dpkg-deb -x "$deb" "$work/root"
"$work/root/usr/bin/wirefur" render "$work/root/usr/share/wirefur/scenes/product_ghost.json" -o "$work/ghost.png" --quiet \
  || fail "the unpacked wirefur"
[ -s "$work/ghost.png" ] || fail "the unpacked wirefur wrote no PNG"
(cd "$work" && PYTHONPATH="$work/root/usr/lib/python3/dist-packages" /usr/bin/python3 -c \
  "import wirefur; wirefur.vtkWireFurCADReader(); print('import wirefur from the package:', wirefur.__file__)") \
  || fail "import wirefur from the unpacked package"
echo "deb test passed"
