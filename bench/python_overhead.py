"""Overhead of driving tumble from Python: step() plus one pose readback per
step for 1,000 bodies, timed in Python through the bindings and in Rust
(crates/tumble/examples/step_readback.rs) on the same two scenes, reported as
a ratio. The final poses of both sides are hashed and must be identical, so
the two loops are known to have done the same work.

    make python-bench            (builds the Rust example and the .venv first)
    .venv/bin/python bench/python_overhead.py [--repeats 3] [--quick]

Goal (issue 7): under 10% overhead. The JSON summary goes to
out/python_overhead.json.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import time
from pathlib import Path

import numpy as np

import tumble

ROOT = Path(__file__).resolve().parents[1]
RUST_EXAMPLE = ROOT / "target" / "release" / "examples" / "step_readback"
STEPS = 240


def grid(i: int) -> np.ndarray:
    return np.array([i % 10, (i // 10) % 10, i // 100], dtype=float)


def grid_fall() -> tumble.World:
    """1,000 boxes in a 10 x 10 x 10 grid falling onto the ground (as in Rust)."""
    world = tumble.World()
    world.add_body(tumble.HalfSpace(), kind="static")
    cube = tumble.Box((0.1, 0.1, 0.1))
    for i in range(1000):
        world.add_body(cube, position=grid(i) * 0.25 + [0.0, 0.0, 0.5])
    return world


def free_float() -> tumble.World:
    """1,000 spheres drifting in zero gravity without contacts (as in Rust)."""
    world = tumble.World(gravity=(0, 0, 0))
    ball = tumble.Sphere(0.1)
    for i in range(1000):
        g = grid(i)
        v = (g[[1, 2, 0]] - 4.5) * 0.01
        world.add_body(ball, position=g * 0.5, velocity=v)
    return world


def fnv1a(data: bytes) -> int:
    h = 0xCBF29CE484222325
    for b in data:
        h = ((h ^ b) * 0x100000001B3) & 0xFFFFFFFFFFFFFFFF
    return h


def python_run(build) -> tuple[float, str]:
    world = build()
    poses = world.poses()
    start = time.perf_counter()
    for _ in range(STEPS):
        world.step()
        poses = world.poses()  # (N, 7): x, y, z, qx, qy, qz, qw
    seconds = time.perf_counter() - start
    return seconds, f"{fnv1a(poses.tobytes()):016x}"


def best_of(fn, calls: int) -> float:
    """Best mean time of `fn()` over 5 batches of `calls` calls (us)."""
    best = float("inf")
    for _ in range(5):
        start = time.perf_counter()
        for _ in range(calls):
            fn()
        best = min(best, (time.perf_counter() - start) / calls * 1e6)
    return best


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5, help="rounds; the best is kept")
    parser.add_argument("--quick", action="store_true", help="one repeat (smoke test)")
    args = parser.parse_args()
    repeats = 1 if args.quick else args.repeats
    if not RUST_EXAMPLE.exists():
        subprocess.run(["cargo", "build", "--release", "-p", "tumble", "--example",
                        "step_readback"], cwd=ROOT, check=True)
    # Rounds alternate the Rust process and the Python loops, so that both see
    # the same machine load; the best time of each side is kept.
    scenes = [("grid_fall", grid_fall), ("free_float", free_float)]
    rust: dict[str, dict] = {}
    python: dict[str, tuple[float, str]] = {}
    for _ in range(repeats):
        out = subprocess.run([str(RUST_EXAMPLE), "1"], check=True, capture_output=True,
                             text=True).stdout
        for line in out.splitlines():
            r = json.loads(line)
            best = rust.setdefault(r["scene"], r)
            best["seconds"] = min(best["seconds"], r["seconds"])
            best["readback_seconds"] = min(best["readback_seconds"], r["readback_seconds"])
        for name, build in scenes:
            t, h = python_run(build)
            if name not in python or t < python[name][0]:
                python[name] = (t, h)

    # The overhead itself, without the noise of the physics: one step() call
    # on an empty world, and one poses() readback of the 1,000 bodies, against
    # the same readback in Rust.
    empty, world = tumble.World(), free_float()
    calls = 2000
    step_us = best_of(lambda: empty.step(), calls)
    poses_us = best_of(world.poses, calls)

    results = []
    print(f"{'scene':<11} {'rust s':>7} {'python s':>8} {'ratio':>6} | {'rust/step':>9} "
          f"{'binding/step':>12} {'overhead':>8}")
    for name, _ in scenes:
        py_seconds, py_hash = python[name]
        r = rust[name]
        if py_hash != r["hash"]:
            raise SystemExit(f"{name}: final poses differ (python {py_hash}, rust {r['hash']}): "
                             "the two sides did not simulate the same scene")
        ratio = py_seconds / r["seconds"]
        rust_step_us = r["seconds"] / STEPS * 1e6
        # What Python adds per step: the call, and poses() beyond Rust's own readback.
        binding_us = step_us + poses_us - r["readback_seconds"] / STEPS * 1e6
        overhead = binding_us / rust_step_us
        print(f"{name:<11} {r['seconds']:7.3f} {py_seconds:8.3f} {ratio:6.3f} | "
              f"{rust_step_us:7.0f}us {binding_us:10.1f}us {100 * overhead:7.2f}%")
        results.append({"scene": name, "bodies": 1000, "steps": STEPS, "rounds": repeats,
                        "rust_seconds": r["seconds"], "python_seconds": py_seconds,
                        "wall_ratio": ratio, "rust_us_per_step": rust_step_us,
                        "binding_us_per_step": binding_us, "overhead": overhead,
                        "hash": py_hash})
    print(f"binding costs: step() call {step_us:.2f} us (empty world), poses() of 1,000 bodies "
          f"{poses_us:.1f} us; the wall ratio carries the machine's noise, the overhead column "
          "does not")
    results.append({"step_call_us_empty_world": step_us, "poses_readback_us_1000": poses_us})
    (ROOT / "out").mkdir(exist_ok=True)
    (ROOT / "out" / "python_overhead.json").write_text(json.dumps(results, indent=2) + "\n")


if __name__ == "__main__":
    main()
