#!/usr/bin/env bash
# Runs every URDF file below a directory with `tumble run` (the robot on a
# ground plane, its lowest point on it; 10 s unless STEPS is set) and prints
# a line per file: loaded with its deepest overlap and largest joint error,
# or refused with the loader's error; then how many loaded. For trying the
# URDF loader on files written for other engines, e.g. PyBullet's data set:
#   git clone --depth 1 https://github.com/bulletphysics/bullet3 /tmp/bullet3
#   scripts/urdf_corpus.sh /tmp/bullet3/data
# Extra `tumble run` flags pass through (--self-collision, --balance-inertia).
# Builds target/release/tumble first.
set -euo pipefail
usage="usage: scripts/urdf_corpus.sh DIR [tumble run flags...]"
dir=${1:?$usage}
shift
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cargo build --release -q -p tumble-cli --manifest-path "$root/Cargo.toml"
tumble="$root/target/release/tumble"
steps=${STEPS:-600}
total=0
loaded=0
while IFS= read -r -d '' file; do
    total=$((total + 1))
    name=${file#"$dir"/}
    if out=$(cd "$(dirname "$file")" && timeout 120 "$tumble" run "$(basename "$file")" --steps "$steps" "$@" 2>&1); then
        loaded=$((loaded + 1))
        depth=$(grep -o 'max penetration [0-9.]* mm' <<< "$out" || true)
        joints=$(grep -o 'largest joint error [0-9.]* mm, [0-9.]* rad' <<< "$out" || true)
        echo "ok      $name: ${depth:-}${joints:+; $joints}"
    else
        echo "refused $name: $(grep -m1 'error' <<< "$out" | cut -c1-200)"
    fi
done < <(find "$dir" -name '*.urdf' -print0 | sort -z)
echo "$loaded of $total loaded"
