#!/usr/bin/env bash
# README command 1: set up (install what is missing, build), then the main job: the gallery
# of every picture WireFur makes, into out/gallery/ (open out/gallery/index.html).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
./build/wirefur gallery -o out/gallery "$@"
