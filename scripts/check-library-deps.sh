#!/usr/bin/env bash
# Fails when the library's normal dependency tree (what `cargo add splinegpu` compiles) holds
# one of the command line's dependencies: those belong to crates/splinegpu-cli.
set -euo pipefail
cd "$(dirname "$0")/.."
tree=$(cargo tree -p splinegpu -e normal --prefix none --format '{p}')
status=0
for tool_dep in clap indicatif signal-hook tempfile serde_json kurbo; do
  if grep -q "^$tool_dep v" <<<"$tree"; then
    echo "the library depends on $tool_dep (a command-line dependency)" >&2
    status=1
  fi
done
exit $status
