#!/usr/bin/env bash
# Instructions executed by one profile_stages run, counted by valgrind's
# callgrind: the same count on every run, so two builds compare to a fraction
# of a per cent on a shared machine whose wall clock drifts by 10-50 % from one
# minute to the next (a change worth 3 % cannot be timed there). Not a
# substitute for the benchmark harness: instructions are not time (cache
# misses, SIMD width), so a change that counts fewer is then timed as usual.
#
# Builds an x86-64-v2 profile_stages into a target directory of its own
# (valgrind 3.19 stops at an AVX instruction of the native build, whose
# lanes are wider: the counts are this build's), runs SCENE for STEPS steps
# on one thread, and prints the total and the TOP heaviest functions,
# inclusive of what they call. Extra environment (JITTER, TRACE_*, ...)
# passes through to profile_stages.
#
#   scripts/instructions.sh ragdoll_pile 30        # total and top 25
#   scripts/instructions.sh pile1000 60 40
#
# Needs valgrind (a developer's tool, not the project's: `apt-get install
# valgrind`). The callgrind file stays in $CALLGRIND_OUT for
# `callgrind_annotate --auto=yes` (line by line).
set -euo pipefail
scene=${1:?usage: scripts/instructions.sh SCENE STEPS [TOP]}
steps=${2:?usage: scripts/instructions.sh SCENE STEPS [TOP]}
top=${3:-25}
out=${CALLGRIND_OUT:-/tmp/tumble-callgrind.out}
target=${INSTRUCTIONS_TARGET:-/tmp/tumble-instructions}
for tool in valgrind callgrind_annotate; do
    command -v "$tool" > /dev/null || { echo "$tool not found (apt-get install valgrind)" >&2; exit 1; }
done
root=$(cd "$(dirname "$0")/.." && pwd)
(cd "$root" && CARGO_TARGET_DIR="$target" RUSTFLAGS="-C target-cpu=x86-64-v2" \
    cargo build -q --release --example profile_stages -p tumble)
valgrind --tool=callgrind --callgrind-out-file="$out" \
    "$target/release/examples/profile_stages" "$scene" "$steps" 1 > /dev/null 2> "$out.log" || {
    tail -20 "$out.log" >&2
    exit 1
}
total=$(sed -n 's/.*Collected : //p' "$out.log")
echo "$scene, $steps steps, one thread: $total instructions (x86-64-v2 build)"
# Functions of the workspace, inclusive, heaviest first.
callgrind_annotate --inclusive=yes "$out" 2> /dev/null |
    grep -E "^ *[0-9,]+ \( *[0-9.]+%\)  $root/crates" |
    sed -e "s|$root/||" -e 's/ \[.*\]$//' | head -n "$top"
