#!/bin/bash
# The install and the package (docs/install.md), as a user of WireFur meets them:
#   1. cmake --install into a staging prefix: bin/wirefur renders a scene from share/wirefur;
#   2. docs/examples/cpp, a C++17 project that includes VTK 9.1's vtkSMPTools.h (which does not
#      compile as C++20), finds WireFur with find_package in the prefix, builds and renders a CAD
#      part with fur through the A-buffer pass (under Xvfb); the same against the build tree;
#   3. PYTHONPATH=<prefix>/lib/python3/dist-packages alone: import wirefur, the CAD reader's
#      class, and the Python example renders.
# Usage: install_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1 source=$2
work=$(mktemp -d "${TMPDIR:-/tmp}/wirefur-install-test-XXXXXX")
trap 'rm -rf "$work"' EXIT
stage=$work/prefix
fail() { echo "FAILED: $*"; exit 1; }

cmake --install "$build" --prefix "$stage" >"$work/install.log" || { cat "$work/install.log"; fail "cmake --install"; }
for f in bin/wirefur lib/libwirefur_core.a lib/libWireFurFilters.so lib/libWireFurCAD.so lib/wirefur-cad-worker \
         lib/cmake/WireFur/WireFurConfig.cmake lib/cmake/WireFur/WireFurConfigVersion.cmake \
         include/wirefur/vtkWireFurRenderPass.h include/wirefur/render/renderer.h \
         lib/python3/dist-packages/wirefur/__init__.py share/wirefur/scenes/cage_shaded.json share/wirefur/cad/product.step \
         share/doc/wirefur/README.md share/doc/wirefur/docs/install.md share/doc/wirefur/docs/examples/cpp/CMakeLists.txt; do
  [ -e "$stage/$f" ] || fail "not installed: $f"
done
echo "installed: $(find "$stage" -type f | wc -l) files"

# 1. The installed command, its data and its CAD module (not the build tree's).
"$stage/bin/wirefur" render "$stage/share/wirefur/scenes/product_ghost.json" -o "$work/ghost.png" --quiet \
  || fail "installed wirefur render"
[ -s "$work/ghost.png" ] || fail "installed wirefur wrote no PNG"
echo "bin/wirefur rendered product_ghost.json from share/wirefur"
# The CAD module it opened (in its worker and in itself): the installed one, not the build's,
# which it would fall back to by its build path.
cad_loaded=$(LD_DEBUG=files "$stage/bin/wirefur" render "$stage/share/wirefur/scenes/product_ghost.json" \
  -o "$work/ghost2.png" --quiet 2>&1 | sed -nE 's/.*file=([^ ]*libWireFurCAD[^ ]*) .*/\1/p' | sort -u)
[ -n "$cad_loaded" ] || fail "the installed wirefur opened no CAD module"
for m in $cad_loaded; do
  case "$(readlink -f "$m")" in
    "$(readlink -f "$stage")"/*) ;;
    *) fail "the installed wirefur opened the CAD module $m, outside the prefix" ;;
  esac
done
echo "bin/wirefur opened the installed CAD module: $cad_loaded"

# 2. The downstream C++17 project, against the prefix and against the build tree.
for where in prefix build; do
  if [ $where = prefix ]; then dir=(-DCMAKE_PREFIX_PATH="$stage"); else dir=(-DWireFur_DIR="$build/lib/cmake/WireFur"); fi
  cmake -S "$source/docs/examples/cpp" -B "$work/example-$where" "${dir[@]}" >"$work/configure-$where.log" 2>&1 \
    || { tail -20 "$work/configure-$where.log"; fail "configuring docs/examples/cpp against the $where"; }
  cmake --build "$work/example-$where" >"$work/build-$where.log" 2>&1 \
    || { grep -E "error|Error" "$work/build-$where.log" | head -20; fail "building docs/examples/cpp against the $where"; }
  grep -q -- "-std=gnu++17\|-std=c++17" "$work/example-$where/CMakeFiles/cad_and_fur.dir/flags.make" \
    || fail "the example was not compiled as C++17 (a C++ standard forced by WireFur's targets)"
  out=$(xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" "$work/example-$where/cad_and_fur" \
        "$source/data/cad/product.step" "$work/example-$where.png") || fail "running the example ($where)"
  echo "docs/examples/cpp against the $where: $out"
  [[ $out == *"6400 hairs"* && $out == *"2 marked props"* ]] || fail "the example's output ($where)"
  [ -s "$work/example-$where.png" ] || fail "the example wrote no PNG ($where)"
done

# 3. Python from the prefix, nothing else set.
cd "$work"
PYTHONPATH="$stage/lib/python3/dist-packages" /usr/bin/python3 -c \
  "import wirefur; wirefur.vtkWireFurFurGenerator(); wirefur.vtkWireFurCADReader(); print('import wirefur from the prefix:', wirefur.__file__)" \
  || fail "import wirefur from the prefix"
PYTHONPATH="$stage/lib/python3/dist-packages" xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" \
  /usr/bin/python3 "$source/docs/examples/shaded_wire_over_surface.py" "$work/python.png" 240 180 || fail "the Python example"
[ -s "$work/python.png" ] || fail "the Python example wrote no PNG"
echo "install test passed"
