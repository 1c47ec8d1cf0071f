#!/usr/bin/env bash
# Issue 7: A-buffer render time against segment count (10,000 ... 4,000,000 hairs of the peer
# benchmark's torus at 1920x1080, shaded wire; median of 5 renders, each N in its own process;
# fitted exponent b of time = a N^b) and the tile buffers' peak memory against depth complexity
# (hairs stacked D = 1 ... 5000 deep). Writes out/scaling.md, out/scaling.json and the plots in
# out/scaling/. Extra arguments go to bench_scaling (e.g. --repeats 9 --threads 2
# --segments 100k,1M --no-depth). Run it on a quiet machine: the timings are wall-clock.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh >/dev/null
mkdir -p out/scaling
./build/bench_scaling --repeats 5 --markdown out/scaling.md --json out/scaling.json --plots out/scaling "$@"
