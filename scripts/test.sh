#!/usr/bin/env bash
# README command 2: set up (install what is missing, build), then every test with ctest.
# The last lines are ctest's summary; a failing test fails the script.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cd build
ctest --output-on-failure --timeout 900 -j"$(nproc 2>/dev/null || echo 2)" "$@"
