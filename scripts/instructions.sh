#!/usr/bin/env bash
# Instructions executed by one profile_stages run, counted by valgrind's
# callgrind: the same count on every run to a few thousandths of a per cent,
# so two builds compare to a tenth of a per cent on a shared machine whose
# wall clock drifts by 10-50 % from one minute to the next (a change worth
# 3 % cannot be timed there). Not a
# substitute for the benchmark harness: instructions are not time (cache
# misses, SIMD width), so a change that counts fewer is then timed as usual.
#
# Builds an x86-64-v2 profile_stages into a target directory of its own
# (valgrind 3.19 stops at an AVX instruction of the native build, whose
# lanes are wider: the counts are this build's), runs SCENE for STEPS steps
# on one thread, and prints the total and the TOP heaviest functions,
# inclusive of what they call. With `--base REV`, also builds REV (a git
# worktree kept beside the target directory, so later builds are
# incremental; `git worktree remove` it when done), runs it the same way and
# prints both totals and the change.
# Extra environment (JITTER, TRACE_*, ...) passes through to profile_stages.
#
#   scripts/instructions.sh ragdoll_pile 30            # total and top 25
#   scripts/instructions.sh --base HEAD pile1000 60 10 # the working tree against HEAD
#
# Needs valgrind (a developer's tool, not the project's: `apt-get install
# valgrind`). The callgrind file stays in $CALLGRIND_OUT (the base's in
# $CALLGRIND_OUT.base) for `callgrind_annotate --auto=yes` (line by line).
set -euo pipefail
usage="usage: scripts/instructions.sh [--base REV] SCENE STEPS [TOP]"
base=
if [ "${1:-}" = --base ]; then
    base=${2:?$usage}
    shift 2
fi
scene=${1:?$usage}
steps=${2:?$usage}
top=${3:-25}
out=${CALLGRIND_OUT:-/tmp/tumble-callgrind.out}
target=${INSTRUCTIONS_TARGET:-/tmp/tumble-instructions}
for tool in valgrind callgrind_annotate; do
    command -v "$tool" > /dev/null || { echo "$tool not found (apt-get install valgrind)" >&2; exit 1; }
done
root=$(cd "$(dirname "$0")/.." && pwd)

# build SOURCE_DIR TARGET_DIR: the x86-64-v2 profile_stages of that tree.
build() {
    (cd "$1" && CARGO_TARGET_DIR="$2" RUSTFLAGS="-C target-cpu=x86-64-v2" \
        cargo build -q --release --example profile_stages -p tumble)
}

# count TARGET_DIR OUT: runs the scene under callgrind, prints the total.
count() {
    valgrind --tool=callgrind --callgrind-out-file="$2" \
        "$1/release/examples/profile_stages" "$scene" "$steps" 1 > /dev/null 2> "$2.log" || {
        tail -20 "$2.log" >&2
        exit 1
    }
    sed -n 's/.*Collected : //p' "$2.log"
}

build "$root" "$target"
total=$(count "$target" "$out")
echo "$scene, $steps steps, one thread: $total instructions (x86-64-v2 build of the working tree)"
if [ -n "$base" ]; then
    rev=$(git -C "$root" rev-parse --verify "$base^{commit}")
    tree="$target-base-src"
    if [ -d "$tree" ]; then
        git -C "$tree" checkout -q --detach "$rev"
    else
        git -C "$root" worktree add -q --detach "$tree" "$rev"
    fi
    build "$tree" "$target-base"
    base_total=$(count "$target-base" "$out.base")
    echo "base $base ($(git -C "$root" rev-parse --short "$rev")): $base_total instructions"
    awk -v a="$base_total" -v b="$total" 'BEGIN { printf "change: %+.2f %%\n", 100 * (b - a) / a }'
fi
# Functions of the workspace, inclusive, heaviest first (awk reads to the
# end: `head` would close the pipe early, which pipefail reports).
callgrind_annotate --inclusive=yes "$out" 2> /dev/null |
    grep -E "^ *[0-9,]+ \( *[0-9.]+%\)  $root/crates" |
    sed -e "s|$root/||" -e 's/ \[.*\]$//' | awk -v n="$top" 'NR <= n'
