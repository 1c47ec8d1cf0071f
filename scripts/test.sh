#!/usr/bin/env bash
# README command 2: set up (install what is missing, build), then every test with ctest.
# The last lines are ctest's summary; a failing test fails the script.
#
# Under CI (CI=true), or with WIREFUR_TEST_SANITIZE=1, the library's tests first run once more in
# a second build, build-asan/, made with AddressSanitizer and UndefinedBehaviorSanitizer
# (-DWIREFUR_SANITIZE=ON), without the command and the CAD module: the core suite, the
# robustness suite's library cases (not its mesh-file and --memory-budget cases, which run the
# command) and the VTK module's (459 tests); any report fails the run. The parsers of untrusted
# input (scenes, meshes, CAD files) are under the same sanitizers in every run, in-process,
# through the fuzz tests' own clang build (tests/fuzz; findings inside the libraries are listed,
# not failed). Only WIREFUR_TEST_SANITIZE=full puts the rest there: the command, its reader and
# CAD worker processes (core/worker_process.cpp's memory cap, the allocator of worker_malloc.cpp)
# and the suites that run them (tests/apps, tests/cad, the robustness suite's command cases); it
# runs the whole suite but the fuzz targets, the benchmarks' smoke runs, the ParaView plugin's
# tests and (not built with the sanitizers) the Python and install tests: about ten minutes more
# on two cores, which CI's budget of 35 minutes on a fresh machine does not leave (measured on
# the CI machine: its build 701 s and tests 451 s, against 403 s and 118 s for the library's).
# WIREFUR_TEST_SANITIZE=0 skips the pass.
# That build is -O1 -g1 (line tables for the reports' stacks): it compiles in half the time of
# -O2 -g (measured: 14 s against 26 s for apps/mesh_io.cpp, 22 s against 44 s for
# apps/render_command.cpp).
set -euo pipefail
cd "$(dirname "$0")/.."
sanitize="${WIREFUR_TEST_SANITIZE:-}"
if [ -z "$sanitize" ] && [ "${CI:-}" = "true" ]; then sanitize=1; fi
case "$sanitize" in
  ""|0|1|full) ;;
  *) echo "test.sh: WIREFUR_TEST_SANITIZE must be 0, 1 or full (it is '$sanitize')" >&2; exit 2 ;;
esac
bash scripts/setup.sh
echo "== set-up and build: ${SECONDS} s =="
jobs="$(nproc 2>/dev/null || echo 2)"
# The ParaView plugin (docs/paraview.md): its own build tree, against Debian's ParaView 5.11, which
# this installs beside the system VTK when missing; its tests run in the suite below
# (paraview.plugin_suite). WIREFUR_TEST_PARAVIEW=0 leaves it out.
if [ "${WIREFUR_TEST_PARAVIEW:-1}" != "0" ]; then
  echo "== the ParaView plugin (build-paraview/), from ${SECONDS} s =="
  mkdir -p build-paraview
  bash scripts/paraview_plugin.sh build-paraview >build-paraview/build.log 2>&1 || { tail -30 build-paraview/build.log >&2; echo "test.sh: the ParaView plugin build failed (build-paraview/build.log)" >&2; exit 1; }
fi
case "$sanitize" in
  1) parts=(-DWIREFUR_BUILD_APPS=OFF -DWIREFUR_WITH_CAD=OFF) what="the library's tests" ;;
  full) parts=(-DWIREFUR_BUILD_APPS=ON -DWIREFUR_WITH_CAD=ON) what="the test suite" ;;
esac
if [ -n "$sanitize" ] && [ "$sanitize" != "0" ]; then
  echo "== ${what} under AddressSanitizer + UndefinedBehaviorSanitizer (build-asan/), from ${SECONDS} s =="
  cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG" -DWIREFUR_SANITIZE=ON -DWIREFUR_UNITY_BUILD=ON -DWIREFUR_BUILD_BENCH=OFF -DWIREFUR_WRAP_PYTHON=OFF "${parts[@]}" >/dev/null
  if ! cmake --build build-asan -j"$jobs" >build-asan/build.log 2>&1; then
    grep -E -B2 -A8 "error|Error" build-asan/build.log | tail -60
    echo "test.sh: the sanitizer build failed (build-asan/build.log)" >&2
    exit 1
  fi
  echo "== its build done at ${SECONDS} s =="
  (cd build-asan && ctest --output-on-failure --timeout 900 -j"$jobs" -LE "fuzz|bench|paraview")
fi
echo "== the test suite (build/), from ${SECONDS} s =="
cd build
ctest --output-on-failure --timeout 900 -j"$jobs" "$@"
