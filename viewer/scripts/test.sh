#!/usr/bin/env bash
# Builds the viewer, writes the fixture .glb with tumble's exporter, and runs
# the headless-browser test (scripts/test.mjs). Run from anywhere; needs
# scripts/setup.sh to have run (it is called here, and is quiet when nothing
# is missing). Exit code non-zero on failure; the last line reads
# `viewer: N passed, M failed`. Screenshots land in out/viewer-test/.
set -euo pipefail
viewer="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
repo="$(cd "$viewer/.." && pwd)"
out="$repo/out/viewer-test"
mkdir -p "$out"

bash "$viewer/scripts/setup.sh"
(cd "$repo" && cargo run --quiet --release -p tumble --example export_fixture -- "$out/fixture.glb" "$out/fixture.csv")
node "$viewer/scripts/build.mjs"
cd "$viewer" && VIEWER_TEST_OUT="$out" VIEWER_FIXTURE="$out/fixture.glb" node scripts/test.mjs
