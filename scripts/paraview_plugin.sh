#!/usr/bin/env bash
# Builds the ParaView plugin (paraview/, docs/paraview.md) against Debian 12's ParaView 5.11, beside
# the system-VTK build and without touching it: usage scripts/paraview_plugin.sh [BUILD_DIR]
# (default build-paraview). Installs paraview and paraview-dev with --no-install-recommends when
# missing (never python3-paraview, which would remove python3-vtk9 and libvtk9-dev), unpacks
# python3-paraview privately into BUILD_DIR/pvpython (pvbatch needs its modules), and makes a copy
# of ParaView's CMake package whose paths to that package's files point at the unpacked copy.
# Links the main build's core (build/src/libwirefur_core.a) when there is one. Then
# `ctest --test-dir BUILD_DIR` runs the pvbatch tests (serial, and on 2 MPI ranks).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(realpath -m "${1:-$root/build-paraview}")
arch=$(dpkg-architecture -qDEB_HOST_MULTIARCH 2>/dev/null || gcc -print-multiarch 2>/dev/null || echo x86_64-linux-gnu)
is511() { case "$1" in 5.11.*) return 0;; *) return 1;; esac; }
if ! dpkg -s paraview paraview-dev >/dev/null 2>&1; then
  if [ "$(id -u)" != 0 ]; then
    echo "paraview_plugin.sh: ParaView is missing; as root: apt-get install -y --no-install-recommends paraview paraview-dev" >&2
    exit 2
  fi
  candidate=$(apt-cache policy paraview 2>/dev/null | awk '/Candidate:/ {print $2}')
  if ! is511 "$candidate"; then echo "paraview_plugin.sh: the plugin is made for ParaView 5.11; apt offers paraview '$candidate'" >&2; exit 2; fi
  # --no-remove: never let apt resolve anything by removing packages (python3-paraview, which
  # --no-install-recommends keeps out, would remove python3-vtk9 and libvtk9-dev).
  DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends --no-remove paraview paraview-dev >/dev/null
fi
version=$(dpkg-query -W -f='${Version}' paraview)
if ! is511 "$version"; then echo "paraview_plugin.sh: the plugin is made for ParaView 5.11; Debian's paraview is $version" >&2; exit 2; fi
mkdir -p "$build"
py="$build/pvpython"
# Unpacked again when ParaView's version changes (the modules must match its libraries).
if [ ! -x "$py/usr/bin/pvpython" ] || [ "$(cat "$py/version" 2>/dev/null)" != "$version" ]; then
  rm -rf "$build/download" "$py" && mkdir -p "$build/download" && chmod 777 "$build/download"
  (cd "$build/download" && apt-get download -q "python3-paraview=$version" >/dev/null)
  dpkg-deb -x "$build"/download/python3-paraview_*.deb "$py"
  rm -rf "$build/download"
  echo "$version" >"$py/version"
fi
# A prefix that looks like /usr to ParaView's CMake package, with the python3-paraview files in it.
prefix="$build/prefix"
rm -rf "$prefix" && mkdir -p "$prefix/lib/$arch/cmake"
ln -s /usr/include "$prefix/include"
ln -s /usr/share "$prefix/share"
ln -s "$py/usr/lib/$arch/vtk" "$prefix/lib/$arch/vtk"
ln -s "/usr/lib/$arch/paraview-5.11" "$prefix/lib/$arch/paraview-5.11"
cmakedir="$prefix/lib/$arch/cmake/paraview-5.11"
cp -r "/usr/lib/$arch/cmake/paraview-5.11" "$cmakedir"
pyesc=$(printf '%s' "$py" | sed -e 's/[\\|&]/\\&/g')  # for the right-hand side of s|||
grep -rlZ '_IMPORT_PREFIX\|dist-packages\|pvpython' "$cmakedir" | xargs -0 sed -i \
  -e "s|\${_IMPORT_PREFIX}/lib/python3/dist-packages|$pyesc/usr/lib/python3/dist-packages|g" \
  -e "s|\${_IMPORT_PREFIX}/bin/pvpython|$pyesc/usr/bin/pvpython|g" \
  -e "s|\${_IMPORT_PREFIX}|/usr|g"
# The main build's core, unless that build is sanitised (its core would not load in pvbatch).
core=()
if [ -f "$root/build/src/libwirefur_core.a" ] && ! grep -q '^WIREFUR_SANITIZE:BOOL=ON' "$root/build/CMakeCache.txt" 2>/dev/null; then
  core=(-DWIREFUR_CORE_LIBRARY="$root/build/src/libwirefur_core.a")
fi
cmake -S "$root/paraview" -B "$build" -DParaView_DIR="$cmakedir" -DPython3_EXECUTABLE=/usr/bin/python3 \
  -DWIREFUR_PVPYTHON_PATH="$py/usr/lib/python3/dist-packages" "${core[@]}" >"$build/configure.log" 2>&1 ||
  { tail -20 "$build/configure.log" >&2; exit 1; }
cmake --build "$build" -j"$(nproc)"
