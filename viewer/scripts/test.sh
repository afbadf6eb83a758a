#!/usr/bin/env bash
# Builds the viewer, writes the fixture .glb with tumble's exporter, and runs
# the headless-browser test (scripts/test.mjs), including `tumble view`
# serving the built page (a tori_pass recording, the same scene live, and
# the tower game: a click throws a ball into the live simulation). Run from anywhere; needs
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
# `tumble view` is tested with the real page: a recording and a live scene.
(cd "$repo" && cargo build --quiet --release -p tumble-cli)
tumble="$repo/target/release/tumble"
"$tumble" run --quiet "$repo/examples/scenes/tori_pass.toml" --out "$out/tori_pass.glb"
node "$viewer/scripts/build.mjs"
cd "$viewer" && VIEWER_TEST_OUT="$out" VIEWER_FIXTURE="$out/fixture.glb" TUMBLE_BIN="$tumble" \
    TUMBLE_RECORDING="$out/tori_pass.glb" TUMBLE_LIVE_SCENE="$repo/examples/scenes/tori_pass.toml" \
    TUMBLE_GAME_SCENE="$repo/examples/scenes/tower_game.toml" \
    node scripts/test.mjs
