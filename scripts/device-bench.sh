#!/usr/bin/env bash
# The crate on a real GPU in one prepared call (issue: "a real GPU in one prepared call").
#
#   scripts/device-bench.sh --prepare   here, with Rust and the network: builds the release
#                                       binary and the GPU test binaries, strips them, and
#                                       fetches the Vulkan loader package, all into .device/
#                                       (ignored by git; about 30 MiB).
#   scripts/device-bench.sh OUTDIR      there (no Rust, no network needed): runs them and writes
#                                       OUTDIR/info.txt, tests.txt, bench.jsonl, bench.stderr and
#                                       summary.md, within about 4 minutes.
#
# The device tool's call, with .device carried:
#   scripts/device-bench.sh "$OUT"
# The script unpacks the loader only where none is installed, and points Vulkan at NVIDIA's
# driver manifest where the loader finds no driver by itself. It says so at the top of
# summary.md when the only adapter it found is a CPU one (lavapipe): then the figures are not a
# GPU's.
set -uo pipefail
cd "$(dirname "$0")/.."
BIN=.device/bin
# The library's GPU tests, which need no source tree at run time: the GPU harness (every
# kernel against the f64 reference, the renderer paths), its integration tests and its unit
# tests (the kernels' twins, their ABI).
TESTS=(splinegpu-gpu splinegpu-it splinegpu-unit)
# Most telling first: a run cut short by the time limit still has them.
WORKLOADS=(w1 tubes strokes w1-x10 eval-at w1-d fit-1m w1-tol w1-arc cli-w1 q1)

if [[ "${1:-}" == "--prepare" ]]; then
    set -e
    mkdir -p "$BIN" .device/gl
    cargo build --release --quiet
    cp target/release/splinegpu "$BIN/"
    # The test binaries cargo builds, by name (their file names carry a hash).
    cargo test --release -p splinegpu --features profiling --lib --test it --test gpu --no-run \
        --message-format=json 2>/dev/null |
        python3 -c '
import json, sys, shutil
names = {"it": "splinegpu-it", "gpu": "splinegpu-gpu", "splinegpu": "splinegpu-unit"}
for line in sys.stdin:
    m = json.loads(line)
    if m.get("reason") == "compiler-artifact" and m.get("executable") \
            and m["profile"]["test"] and m["target"]["name"] in names:
        shutil.copy(m["executable"], ".device/bin/" + names[m["target"]["name"]])
'

    strip "$BIN"/*
    # The Vulkan loader (the driver itself is on the GPU machine), for amd64.
    lists=$(mktemp -d)
    opts=(-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 "-oDir::State::Lists=$lists")
    mkdir -p "$lists/partial"
    apt-get "${opts[@]}" update -qq
    (cd .device/gl && apt-get "${opts[@]}" download -qq libvulkan1)
    rm -rf "$lists"
    du -sh .device
    exit 0
fi

OUTDIR="${1:?usage: scripts/device-bench.sh --prepare | OUTDIR}"
mkdir -p "$OUTDIR"
[[ -x "$BIN/splinegpu" ]] || { echo "no $BIN/splinegpu: run scripts/device-bench.sh --prepare first" >&2; exit 1; }

# The Vulkan loader, where the machine has none.
if ! ldconfig -p | grep -q 'libvulkan.so.1'; then
    for f in .device/gl/*.deb; do dpkg -x "$f" /; done
    ldconfig
fi
# NVIDIA's driver manifest, where the loader's search path holds no driver.
nvidia_icd=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
if ! ls /usr/share/vulkan/icd.d/*.json /etc/vulkan/icd.d/*.json >/dev/null 2>&1 && [[ -f $nvidia_icd ]]; then
    export VK_DRIVER_FILES=$nvidia_icd
fi
export NODEVICE_SELECT=1

"$BIN/splinegpu" info >"$OUTDIR/info.txt" 2>&1
if grep -q '^auto: gpu' "$OUTDIR/info.txt"; then
    verdict="GPU: $(grep '^auto:' "$OUTDIR/info.txt")"
else
    verdict="FELL BACK TO A CPU ADAPTER: no hardware GPU was found, so these figures are not a GPU's ($(grep '^auto:' "$OUTDIR/info.txt"))"
fi
echo "$verdict"

# GPU tests: CI=true makes a missing adapter a failure instead of a skip.
: >"$OUTDIR/tests.txt"
tests_line=""
for t in "${TESTS[@]}"; do
    CI=true timeout 90 "$BIN/$t" >>"$OUTDIR/tests.txt" 2>&1
    rc=$?
    result=$(grep '^test result' "$OUTDIR/tests.txt" | tail -1)
    tests_line+="- $t: exit $rc, ${result:-no result line}"$'\n'
done
echo "$tests_line"

# The bench on the adapter `auto` picks (high performance first), JSON lines as they come.
args=()
for w in "${WORKLOADS[@]}"; do args+=(--workload "$w"); done
timeout 170 "$BIN/splinegpu" bench --json "${args[@]}" >"$OUTDIR/bench.jsonl" 2>"$OUTDIR/bench.stderr"
bench_rc=$?

{
    echo "# splinegpu on $(grep -m1 -v '^ ' "$OUTDIR/info.txt" 2>/dev/null || echo 'an unknown adapter')"
    echo
    echo "$verdict"
    echo
    echo "Bench exit status: $bench_rc (124: cut at its time limit; the lines before it stand)."
    echo
    echo "## GPU tests"
    echo
    echo -n "$tests_line"
    echo
    echo "## Bench"
    echo
    python3 scripts/bench_summary.py "$OUTDIR/bench.jsonl"
} >"$OUTDIR/summary.md"
cat "$OUTDIR/summary.md"
