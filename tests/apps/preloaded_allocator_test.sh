#!/bin/bash
# The wirefur command under an allocator preloaded with LD_PRELOAD (jemalloc replaces malloc,
# free and C++'s new and delete): src/core/worker_malloc.cpp defines the whole family in the
# program, so no block is allocated by one allocator and freed by the other. With malloc, calloc
# and realloc alone the command died in free. A scene and a CAD part (read in the worker) give the
# same images, bit for bit, as without the preloaded allocator.
# Usage: preloaded_allocator_test.sh WIREFUR SOURCE_DIR LIBJEMALLOC
set -euo pipefail
exe=$1 source=$2 jemalloc=$3
work=$(mktemp -d "${TMPDIR:-/tmp}/wirefur-preload-test-XXXXXX")
trap 'rm -rf "$work"' EXIT
for input in data/scenes/oscar_fur.json data/cad/product.step; do
  name=$(basename "$input")
  "$exe" render "$source/$input" -o "$work/$name.plain.png" --quiet
  LD_PRELOAD="$jemalloc" "$exe" render "$source/$input" -o "$work/$name.preloaded.png" --quiet \
    || { echo "FAILED: $input under LD_PRELOAD=$jemalloc (status $?)"; exit 1; }
  cmp -s "$work/$name.plain.png" "$work/$name.preloaded.png" || { echo "FAILED: $input: the images differ"; exit 1; }
  echo "$input: the same image under LD_PRELOAD=$jemalloc"
done
