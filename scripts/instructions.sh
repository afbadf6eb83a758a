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
# With `--misses`, cachegrind instead: its model of the caches (the first
# level's as this machine's, the last level's `MISSES_LL`, by default 1 MiB
# 16-way: this machine's L2 per core) counts the data misses at the last
# level, reads and writes, and the functions are sorted by them (exclusive).
# A change to how much memory the solver touches (the ragdoll pile's joint
# records, 2026-12-06) shows there, where the wall clock cannot see 6 %.
# Prefetches are not modelled: a prefetch is timed, not counted.
#
#   scripts/instructions.sh ragdoll_pile 30            # total and top 25
#   scripts/instructions.sh --base HEAD pile1000 60 10 # the working tree against HEAD
#   scripts/instructions.sh --misses --base HEAD ragdoll_pile 40
#
# Needs valgrind (a developer's tool, not the project's: `apt-get install
# valgrind`). The callgrind file stays in $CALLGRIND_OUT (the base's in
# $CALLGRIND_OUT.base) for `callgrind_annotate --auto=yes` (line by line);
# with --misses it is cachegrind's, for `cg_annotate --auto=yes`.
set -euo pipefail
usage="usage: scripts/instructions.sh [--misses] [--base REV] SCENE STEPS [TOP]"
base=
misses=
while [ "${1:-}" = --base ] || [ "${1:-}" = --misses ]; do
    if [ "$1" = --misses ]; then
        misses=1
        shift
    else
        base=${2:?$usage}
        shift 2
    fi
done
ll=${MISSES_LL:-1048576,16,64}
scene=${1:?$usage}
steps=${2:?$usage}
top=${3:-25}
out=${CALLGRIND_OUT:-/tmp/tumble-callgrind.out}
target=${INSTRUCTIONS_TARGET:-/tmp/tumble-instructions}
for tool in valgrind callgrind_annotate cg_annotate; do
    command -v "$tool" > /dev/null || { echo "$tool not found (apt-get install valgrind)" >&2; exit 1; }
done
root=$(cd "$(dirname "$0")/.." && pwd)

# build SOURCE_DIR TARGET_DIR: the x86-64-v2 profile_stages of that tree.
build() {
    (cd "$1" && CARGO_TARGET_DIR="$2" RUSTFLAGS="-C target-cpu=x86-64-v2" \
        cargo build -q --release --example profile_stages -p tumble)
}

# count TARGET_DIR OUT: runs the scene under callgrind, prints the total
# (with --misses: under cachegrind, prints the last level's data misses).
count() {
    local tool=(--tool=callgrind --callgrind-out-file="$2")
    [ -n "$misses" ] && tool=(--tool=cachegrind --cache-sim=yes --LL="$ll" --cachegrind-out-file="$2")
    valgrind "${tool[@]}" \
        "$1/release/examples/profile_stages" "$scene" "$steps" 1 > /dev/null 2> "$2.log" || {
        tail -20 "$2.log" >&2
        exit 1
    }
    if [ -n "$misses" ]; then
        sed -n 's/.*LLd misses: *\([0-9,]*\).*/\1/p' "$2.log" | tr -d ,
    else
        sed -n 's/.*Collected : //p' "$2.log"
    fi
}
what=instructions
[ -n "$misses" ] && what="data misses at a last level of $ll (size,ways,line)"

build "$root" "$target"
total=$(count "$target" "$out")
echo "$scene, $steps steps, one thread: $total $what (x86-64-v2 build of the working tree)"
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
    echo "base $base ($(git -C "$root" rev-parse --short "$rev")): $base_total $what"
    awk -v a="$base_total" -v b="$total" 'BEGIN { printf "change: %+.2f %%\n", 100 * (b - a) / a }'
fi
if [ -n "$misses" ]; then
    # Functions by their own misses, reads then writes, heaviest first.
    cg_annotate --show=DLmr,DLmw --sort=DLmr,DLmw "$out" 2> /dev/null |
        grep -E "^ *[0-9,]+ \( *[0-9.]+%\) .*:" | grep -v "PROGRAM TOTALS" |
        sed -e "s|$root/||" | awk -v n="$top" 'NR <= n'
    exit 0
fi
# Functions of the workspace, inclusive, heaviest first (awk reads to the
# end: `head` would close the pipe early, which pipefail reports).
callgrind_annotate --inclusive=yes "$out" 2> /dev/null |
    grep -E "^ *[0-9,]+ \( *[0-9.]+%\)  $root/crates" |
    sed -e "s|$root/||" -e 's/ \[.*\]$//' | awk -v n="$top" 'NR <= n'
