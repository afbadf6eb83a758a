#!/usr/bin/env bash
# Longer fuzzing of tumble under libFuzzer (cargo-fuzz, nightly): every
# target of fuzz/fuzz_targets for SECONDS seconds (default 60) each, starting
# from the committed corpus fuzz/corpus/<target> (new inputs go to
# fuzz/corpus-new/<target>, not committed) and the regression inputs in
# fuzz/regressions/<target>. Installs the nightly toolchain and cargo-fuzz
# when they are missing. A crash leaves its input in fuzz/artifacts/<target>/:
# fix it, then copy the input into fuzz/regressions/<target>/ so that the
# stable smoke test (crates/tumble/tests/fuzz_smoke.rs, in `make test`)
# replays it forever.
#   scripts/fuzz.sh 300            five minutes per target
#   scripts/fuzz.sh 60 collide     one target
# Without nightly, the same targets run on stable, as long as you like:
#   TUMBLE_FUZZ_ITERS=100000 cargo test --release -p tumble --test fuzz_smoke
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
seconds="${1:-60}"
shift || true

if ! rustup toolchain list | grep -q '^nightly'; then
    rustup toolchain install nightly --profile minimal
fi
if ! cargo fuzz --version >/dev/null 2>&1; then
    cargo install cargo-fuzz --locked
fi

cd "$root/fuzz"
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
    mapfile -t targets < <(cargo +nightly fuzz list)
fi
for t in "${targets[@]}"; do
    mkdir -p "corpus-new/$t" "regressions/$t"
    echo "== fuzz $t for ${seconds}s"
    # -rss_limit_mb: scene files may build large (valid) worlds.
    # -report_slow_units: valid but large scenes build big meshes (slow
    # under the sanitizer); only crashes, timeouts and OOMs fail the run.
    set +e
    nice -n 10 cargo +nightly fuzz run "$t" "corpus-new/$t" "corpus/$t" "regressions/$t" -- \
        -max_total_time="$seconds" -rss_limit_mb=4096 -timeout=60 -report_slow_units=60 \
        -print_final_stats=1 2>&1 |
        tee "corpus-new/$t.log" | grep -E '^(stat::number_of_executed_units|==[0-9]+==|SUMMARY)'
    status=${PIPESTATUS[0]}
    set -e
    if ls "artifacts/$t"/crash-* "artifacts/$t"/oom-* "artifacts/$t"/timeout-* >/dev/null 2>&1; then
        echo "fuzz $t: failing inputs in fuzz/artifacts/$t/" >&2
        exit 1
    fi
    # Anything else that stops the run (a build that fails) fails it too,
    # rather than passing for a clean run.
    if [ "$status" -ne 0 ]; then
        echo "fuzz $t: cargo fuzz stopped with status $status (fuzz/corpus-new/$t.log)" >&2
        exit 1
    fi
done
