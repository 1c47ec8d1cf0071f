#!/usr/bin/env bash
# Issue 7's measurements in one command, on a quiet machine (the timings are wall-clock):
#   1. peer_raycast: the A-buffer (each mask) against Embree 3 casting 1 ... 64 stratified rays
#      per pixel and VTK's RenderLinesAsTubes (Mesa llvmpipe under Xvfb), on the furry torus at
#      7,000 / 70,000 / 700,000 hairs, the spider and 1,000,000 curved hairs at 1920x1080:
#      error against time, the speed-up at equal RMS error, plots;
#   2. bench_scaling: time against segments (10,000 ... 4,000,000, fitted exponent) and peak
#      memory against depth complexity.
# Writes out/bench/README.md (the tables), the JSON and the PNG plots beside it. Extra arguments
# go to peer_raycast (e.g. --scenes torus7k,spider --repeats 5).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh >/dev/null
mkdir -p out/bench
xvfb-run -a -s "-screen 0 1920x1200x24 -noreset" ./build/peer_raycast --out out/bench "$@"
./build/bench_scaling --repeats 3 --markdown out/bench/scaling.md --json out/bench/scaling.json --plots out/bench
{
  echo "# WireFur against its peers ($(date -u +%Y-%m-%d), $(nproc) cores: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'))"
  echo
  cat out/bench/peer_raycast.md
  echo
  cat out/bench/scaling.md
} > out/bench/README.md
echo "wrote out/bench/README.md"
