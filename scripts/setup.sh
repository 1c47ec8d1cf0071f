#!/usr/bin/env bash
# Installs the Debian 12 packages WireFur needs (only those missing), then configures and
# builds everything into build/. Idempotent: a second run installs nothing and rebuilds only
# what changed.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(
  cmake make g++                    # toolchain (CMake >= 3.25, C++20)
  libglm-dev libtbb-dev             # the core: GLM vectors, oneTBB parallel loops
  libvtk9-dev                       # apps and VTK module: image I/O, windows, pipeline
  nlohmann-json3-dev                # JSON reports and scene files
  libcli11-dev                      # the wirefur command line (CLI11, header only)
  libpng-dev                        # PNG textures (libpng's simplified reader)
  gnuplot-nox                       # error-against-time plots (wirefur accuracy)
  libgtest-dev libbenchmark-dev     # tests and benchmarks
  xvfb xauth libgl1-mesa-dri        # OpenGL without a display (Mesa llvmpipe): render pass, viewer, peer benchmark
  libx11-dev                        # the viewer checks the X display before VTK would abort on it
  libocct-modeling-algorithms-dev   # CAD input (docs/cad.md): OpenCASCADE 7.6 meshing and shapes,
  libocct-data-exchange-dev         #   STEP and IGES through XCAF,
  libocct-visualization-dev         #   iso-parametric lines (StdPrs_Isolines)
  libzip-dev libpugixml-dev pkgconf # FreeCAD documents: the zip (found with pkg-config) and its XML
  clang libclang-rt-14-dev          # libFuzzer targets (tests/fuzz)
  libembree-dev                     # Embree 3: the ray-cast peer of the benchmarks only (tests/bench/peer)
  locales                           # a decimal-comma locale, compiled by a test (tests/cad/worker_test.cpp)
  dpkg-dev                          # the .deb's dependencies (cpack runs dpkg-shlibdeps; docs/install.md)
  libjemalloc2                      # a preloaded allocator for a test (tests/apps/preloaded_allocator_test.sh)
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  if [ "$(id -u)" -ne 0 ]; then
    echo "wirefur setup: these Debian packages are missing: ${missing[*]}" >&2
    echo "wirefur setup: install them as root with:" >&2
    echo "  apt-get update && apt-get install -y --no-install-recommends ${missing[*]}" >&2
    exit 1
  fi
  echo "wirefur setup: installing ${missing[*]}" >&2
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release ${WIREFUR_CMAKE_ARGS:-} >/dev/null
cmake --build build -j"$jobs"
