"""Many worlds: `tumble.rollout` of B copies of a 100-body pile against the Rust
batch (crates/tumble/examples/batch_rollout.rs) doing the same work (step,
record every position), on 1 and 2 threads, in one invocation. The final
positions of both sides are hashed and must be equal (else the script fails:
the two sides did not simulate the same worlds).

    .venv/bin/python bench/rollout_overhead.py [--worlds 64] [--steps 120] [--repeats 3] [--quick]

Goals (issue 18): 2 threads >= 1.8x faster than 1; Python overhead <= 10 %
over the Rust batch. The JSON summary goes to out/rollout_overhead.json.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import time
from pathlib import Path

import tumble

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "bench" / "scenes" / "pile100.toml"
RUST_EXAMPLE = ROOT / "target" / "release" / "examples" / "batch_rollout"


def fnv1a(data: bytes) -> int:
    h = 0xCBF29CE484222325
    for b in data:
        h = ((h ^ b) * 0x100000001B3) & 0xFFFFFFFFFFFFFFFF
    return h


def python_run(base: tumble.World, worlds: int, steps: int, threads: int) -> tuple[float, str]:
    copies = [base.copy() for _ in range(worlds)]
    start = time.perf_counter()
    out = tumble.rollout(copies, steps, record=["positions"], threads=threads)
    seconds = time.perf_counter() - start
    final = out["positions"][:, -1].copy()  # (B, N, 3), world by world, body by body
    return seconds, f"{fnv1a(final.tobytes()):016x}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--worlds", type=int, default=64)
    parser.add_argument("--steps", type=int, default=120)
    parser.add_argument("--repeats", type=int, default=3, help="rounds; the best is kept")
    parser.add_argument("--quick", action="store_true", help="8 worlds, 20 steps, one round")
    args = parser.parse_args()
    if args.quick:
        args.worlds, args.steps, args.repeats = 8, 20, 1
    if not RUST_EXAMPLE.exists():
        subprocess.run(
            ["cargo", "build", "--release", "-p", "tumble", "--example", "batch_rollout"],
            cwd=ROOT,
            check=True,
        )
    base = tumble.load_scene(SCENE)
    rust: dict[int, dict] = {}
    python: dict[int, tuple[float, str]] = {}
    # Rounds alternate the Rust process and the Python calls, so that both see
    # the same machine load; the best time of each side is kept.
    for _ in range(args.repeats):
        cmd = [str(RUST_EXAMPLE), str(SCENE), str(args.worlds), str(args.steps), "1", "1", "2"]
        for line in subprocess.run(
            cmd, check=True, capture_output=True, text=True
        ).stdout.splitlines():
            r = json.loads(line)
            best = rust.setdefault(r["threads"], r)
            best["seconds"] = min(best["seconds"], r["seconds"])
        for threads in (1, 2):
            t, h = python_run(base, args.worlds, args.steps, threads)
            if threads not in python or t < python[threads][0]:
                python[threads] = (t, h)

    rows = []
    print(f"{args.worlds} worlds of {len(base)} bodies, {args.steps} steps, best of {args.repeats}")
    print(f"{'threads':>7} {'rust s':>8} {'python s':>9} {'overhead':>9}")
    for threads in (1, 2):
        py_seconds, py_hash = python[threads]
        r = rust[threads]
        if py_hash != r["hash"]:
            raise SystemExit(
                f"{threads} threads: final positions differ (python {py_hash}, rust {r['hash']}): "
                "the two sides did not simulate the same worlds"
            )
        overhead = py_seconds / r["seconds"] - 1.0
        print(f"{threads:>7} {r['seconds']:8.3f} {py_seconds:9.3f} {100 * overhead:8.2f}%")
        rows.append(
            {
                "threads": threads,
                "rust_seconds": r["seconds"],
                "python_seconds": py_seconds,
                "overhead": overhead,
            }
        )
    if python[1][1] != python[2][1]:
        raise SystemExit("1 and 2 threads gave different final positions")
    speedup_rust = rust[1]["seconds"] / rust[2]["seconds"]
    speedup_python = python[1][0] / python[2][0]
    print(f"speed-up 1 -> 2 threads: rust {speedup_rust:.2f}x, python {speedup_python:.2f}x")
    out = ROOT / "out" / "rollout_overhead.json"
    out.parent.mkdir(exist_ok=True)
    summary = {
        "worlds": args.worlds,
        "bodies": len(base),
        "steps": args.steps,
        "rounds": args.repeats,
        "rows": rows,
        "speedup_rust": speedup_rust,
        "speedup_python": speedup_python,
        "hash": python[1][1],
    }
    out.write_text(json.dumps(summary, indent=2) + "\n")


if __name__ == "__main__":
    main()
