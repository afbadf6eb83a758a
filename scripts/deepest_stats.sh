#!/usr/bin/env bash
# Statistics of the deepest overlap per step of one profile_stages run, read
# from its TRACE_DEPTH=1 output on stdin: steps, the mean of the per-step
# deepest overlap (m), how many steps went deeper than 2, 5 and 10 mm, and
# the deepest of all. For comparing builds on a chaotic scene over several
# jittered starts, e.g.
#   JITTER=3 TRACE_DEPTH=1 target/release/examples/profile_stages concave_pile 300 1 2>&1 | scripts/deepest_stats.sh
awk '/^steps/ { n++; d = $4 + 0; s += d; if (d > 0.002) a++; if (d > 0.005) b++; if (d > 0.01) c++; if (d > m) m = d }
     END { if (n == 0) { print "no TRACE_DEPTH lines"; exit 1 }
           printf "steps %d mean %.5f >2mm %d >5mm %d >10mm %d max %.4f\n", n, s / n, a + 0, b + 0, c + 0, m }'
