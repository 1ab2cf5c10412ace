#!/usr/bin/env bash
# The main job: tessellates the bundled example document on the GPU (lavapipe where there is no
# GPU) and writes out/curves.csv (the samples) and out/curves.svg (a picture of them).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/ensure-vulkan.sh
mkdir -p out
cargo run --quiet --bin splinegpu -- tessellate crates/splinegpu-cli/examples/curves.json -o out/curves.csv --backend gpu
cargo run --quiet -p splinegpu-cli --example svg -- crates/splinegpu-cli/examples/curves.json out/curves.svg
echo "wrote out/curves.csv ($(($(wc -l < out/curves.csv) - 1)) samples) and out/curves.svg"
