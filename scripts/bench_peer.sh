#!/usr/bin/env bash
# The A-buffer against VTK 9.1's RenderLinesAsTubes (Mesa llvmpipe under Xvfb) on 300,000
# hair-like segments over a torus at 1024x768, both against the brute-force reference
# (16x16 samples per pixel): time, peak memory and coverage error, into out/peer_hair.json;
# VTK also with 2, 4 and 8 multisamples (--vtk-msaa) and supersampled 2x2, 4x4, 8x8 and 12x12
# (--vtk-ssaa: drawn at k times the size and averaged down), for the comparison at equal error.
# Extra arguments go to peer_hair (e.g. --segments 100000 --frames 9).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh >/dev/null
mkdir -p out
xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" ./build/peer_hair --json out/peer_hair.json "$@"
