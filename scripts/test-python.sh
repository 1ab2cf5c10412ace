#!/usr/bin/env bash
# The Python package (python/): built from source into a virtual environment, then its tests.
# Run after `cargo test` (scripts/test.sh does): its tests compare with the CLI binary it built,
# and the extension is built with the dev profile, whose dependencies (optimised, see
# Cargo.toml) are shared with that build. Users install with `pip install ./python` (release).
set -euo pipefail
cd "$(dirname "$0")/.."
python=${PYTHON:-python3}
if ! "$python" -c "import venv, ensurepip" 2>/dev/null; then
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  echo "installing python3-venv ..." >&2
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq python3-venv >/dev/null
fi
venv=target/python-venv
[ -x "$venv/bin/python" ] || "$python" -m venv "$venv"
"$venv/bin/python" -m pip install -q --upgrade pip
# maturin builds the extension (PEP 517); [test] brings pytest, SciPy and Dask.
MATURIN_PEP517_ARGS="--profile dev" "$venv/bin/python" -m pip install -q "./python[test]"
# The tests compare against the command line in target/debug: built from this tree (in the
# profile `cargo test` builds it in, so that after scripts/test.sh's tests this does nothing),
# so that a binary left from older code cannot answer for it.
cargo build --quiet --profile test --bin splinegpu
# Lints: ruff over the package and its tests (python/pyproject.toml's rules), and mypy's
# stubtest, which checks the type stubs (__init__.pyi) against the installed package.
"$venv/bin/python" -m pip install -q "ruff==0.17.6" "mypy==2.4.1"
"$venv/bin/ruff" check python/
"$venv/bin/python" -m mypy.stubtest splinegpu --ignore-missing-stub \
    --mypy-config-file python/mypy-stubtest.ini
# From the repository root, so that `import splinegpu` finds the installed package, not the
# source folder python/splinegpu (which has no compiled extension).
"$venv/bin/pytest" -q python/tests
