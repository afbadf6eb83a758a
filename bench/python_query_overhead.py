"""Overhead of tumble.collide from Python on the tori (shared/scenes.md): the
first-contact query (report="bool") and the all-pairs query at each of the 200
poses, each from scratch and timed per call, in Python and by
`tumble bench --scene tori` in Rust (the same queries through the same API),
plus the binding's own cost per call: a query whose trees are rejected at the
root box test, so that nearly all of its time is argument parsing, the GIL
release and building the result.

    make python-bench            (builds the CLI and the .venv first)
    .venv/bin/python bench/python_query_overhead.py [--rounds 5] [--quick]

Rounds alternate the Rust process and the Python loops so that both see the
same machine load; the best round median of each side is kept. The JSON
summary goes to out/python_query_overhead.json.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import subprocess
import time
from pathlib import Path

import numpy as np

import tumble

ROOT = Path(__file__).resolve().parents[1]
CLI = ROOT / "target" / "release" / "tumble"


def load_example():
    """examples/python/collision_query.py: the tori meshes and poses."""
    path = ROOT / "examples" / "python" / "collision_query.py"
    spec = importlib.util.spec_from_file_location("collision_query", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def medians(us: np.ndarray, colliding: np.ndarray) -> dict[str, float]:
    return {"all": float(np.median(us)), "colliding": float(np.median(us[colliding])),
            "separated": float(np.median(us[~colliding]))}


def python_round(torus, poses) -> tuple[dict, dict, np.ndarray]:
    """Per-call times (us) of first contact and all pairs over the poses."""
    first, pairs, hits = [], [], []
    clock = time.perf_counter
    for pose in poses:
        start = clock()
        r = tumble.collide(torus, None, torus, pose, report="bool")
        first.append(clock() - start)
        start = clock()
        tumble.collide(torus, None, torus, pose)
        pairs.append(clock() - start)
        hits.append(r.intersect)
    colliding = np.array(hits)
    return (medians(np.array(first) * 1e6, colliding), medians(np.array(pairs) * 1e6, colliding),
            colliding)


def rust_round() -> tuple[dict, dict]:
    out = subprocess.run([str(CLI), "bench", "--scene", "tori"], check=True,
                         capture_output=True, text=True).stdout
    figures = json.loads(out)["figures"]
    pick = {k: figures["first_contact"][k]["median"] for k in ("all", "colliding", "separated")}
    pairs = {k: figures["all_pairs"][k]["median"] for k in ("all", "colliding", "separated")}
    return pick, pairs


def best(a: dict | None, b: dict) -> dict:
    return b if a is None else {k: min(a[k], b[k]) for k in a}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=5, help="rounds; the best is kept")
    parser.add_argument("--quick", action="store_true", help="one round (smoke test)")
    args = parser.parse_args()
    rounds = 1 if args.quick else args.rounds
    if not CLI.exists():
        subprocess.run(["cargo", "build", "--release", "-p", "tumble-cli"], cwd=ROOT, check=True)

    example = load_example()
    torus, poses = example.torus(), example.tori_poses()
    tumble.within_tolerance(torus, None, torus, None, 0.0)  # builds the tree once

    py_first = py_pairs = rs_first = rs_pairs = None
    for _ in range(rounds):
        f, p = rust_round()
        rs_first, rs_pairs = best(rs_first, f), best(rs_pairs, p)
        f, p, colliding = python_round(torus, poses)
        py_first, py_pairs = best(py_first, f), best(py_pairs, p)
    if int(colliding.sum()) != example.COLLIDING_POSES:
        raise SystemExit(f"{colliding.sum()} colliding poses, expected {example.COLLIDING_POSES}")

    # The binding alone: B far away, one box test in Rust (tens of ns).
    far = ((100.0, 0.0, 0.0), poses[0][1])
    calls, binding = 5000, float("inf")
    for _ in range(5 * rounds):
        start = time.perf_counter()
        for _ in range(calls):
            tumble.collide(torus, None, torus, far, report="bool")
        binding = min(binding, (time.perf_counter() - start) / calls * 1e6)

    print(f"tori, 200 poses, median per query (us); best of {rounds} round(s)")
    print(f"{'query':<14} {'poses':<10} {'rust':>7} {'python':>7} {'diff':>6} {'ratio':>6}")
    results = {"rounds": rounds, "binding_us_per_call": binding, "queries": []}
    for name, rs, py in (("first contact", rs_first, py_first), ("all pairs", rs_pairs, py_pairs)):
        for part in ("all", "colliding", "separated"):
            print(f"{name:<14} {part:<10} {rs[part]:7.2f} {py[part]:7.2f} "
                  f"{py[part] - rs[part]:6.2f} {py[part] / rs[part]:6.2f}")
            results["queries"].append({"query": name, "poses": part, "rust_median_us": rs[part],
                                       "python_median_us": py[part]})
    print(f"binding cost per collide() call (trees rejected at the root): {binding:.2f} us = "
          f"{100 * binding / rs_first['all']:.0f}% of Rust's median first-contact query, "
          f"{100 * binding / rs_pairs['colliding']:.1f}% of an all-pairs query at a colliding pose")
    (ROOT / "out").mkdir(exist_ok=True)
    (ROOT / "out" / "python_query_overhead.json").write_text(json.dumps(results, indent=2) + "\n")


if __name__ == "__main__":
    main()
