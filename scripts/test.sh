#!/usr/bin/env bash
# The test suite: installs the Vulkan driver if missing, then runs every test (unit, integration,
# GPU-vs-CPU on whatever adapter wgpu finds, CLI, doc tests) in one build, then the Python
# package's (scripts/test-python.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/ensure-vulkan.sh
cargo test "$@"
scripts/test-python.sh
