#!/usr/bin/env bash
# One profile_stages run per jittered start (JITTER=1..N) of a chaotic scene,
# one line each: ms/step, the deepest overlap, the largest gain of total
# energy in one step and how many steps gained more than 1 mJ. Single runs of
# a chain or a pile differ from build to build by rounding alone; compare
# builds over the same seeds, e.g.
#   scripts/jittered_starts.sh target/release/examples/profile_stages chain 600 8
bin=${1:?profile_stages binary}
scene=${2:-chain}
steps=${3:-600}
seeds=${4:-8}
for seed in $(seq 1 "$seeds"); do
  JITTER=$seed "$bin" "$scene" "$steps" 1 2>&1 | awk -v seed="$seed" '
    /ms\/step/ && /deepest/ { for (i = 1; i <= NF; i++) if ($i == "deepest") d = $(i + 1); t = $2 }
    /total energy/ { for (i = 1; i <= NF; i++) { if ($i == "step") g = $(i + 1); if ($i == "steps") n = $(i - 1) } }
    END { printf "seed %d: %s ms/step, deepest %s m, largest gain in a step %s J, %s steps gaining > 1 mJ\n", seed, t, d, g, n }'
done
