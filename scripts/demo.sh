#!/usr/bin/env bash
# The main job: tessellates the bundled example document (every family on its control polygon)
# on the GPU (lavapipe, Mesa's software Vulkan, where there is no GPU), writes the samples to
# out/curves.csv, and draws them with their control polygons in out/curves.svg.
#
# One build (the binary and the drawing example together); on a fresh 2-core machine the
# first run spends about 2 minutes compiling (124 s measured), later runs a few seconds.
set -euo pipefail
cd "$(dirname "$0")/.."
# Mesa's device-select layer warns about XDG_RUNTIME_DIR on headless machines unless told not to.
export NODEVICE_SELECT=1
started=$SECONDS
say() { echo "demo [$((SECONDS - started)) s]: $*" >&2; }

say "checking for a Vulkan driver (installs mesa-vulkan-drivers when there is none)"
scripts/ensure-vulkan.sh
say "building splinegpu and its drawing example (the first build takes about 2 minutes)"
cargo build --release -p splinegpu-cli --bin splinegpu --example svg
input=crates/splinegpu-cli/examples/curves.json
mkdir -p out
say "tessellating $input on the GPU into out/curves.csv"
target/release/splinegpu tessellate "$input" -o out/curves.csv --backend gpu
say "drawing out/curves.svg"
target/release/examples/svg "$input" out/curves.svg
say "done: out/curves.csv ($(($(wc -l < out/curves.csv) - 1)) samples) and out/curves.svg (open it in a browser)"
