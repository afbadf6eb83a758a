#!/usr/bin/env bash
# Runs every Python example (examples/python/*.py) with the .venv of
# scripts/python-env.sh, headless (matplotlib Agg); outputs go to out/.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
mkdir -p out
export MPLBACKEND=Agg
for example in examples/python/*.py; do
    echo "== $example"
    .venv/bin/python "$example"
done
