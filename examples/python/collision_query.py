"""Collision queries without a world: the thesis' two tori (shared/scenes.md,
"tori"). Torus B (5,000 triangles) slides through torus A's tube and hole over
200 poses; at each pose a first-contact query and an all-pairs query, each from
scratch. The pair counts are checked against the exact ground truth
(shared/data/tori_pairs.json when it can be found, else the totals of
scenes.md: 36,782 pairs, 122 colliding poses). Then distance, contacts, a 4x4
matrix pose and a primitive against the mesh.

    python examples/python/collision_query.py
"""

from __future__ import annotations

import json
import math
import os
import time
from pathlib import Path

import numpy as np

import tumble

#: Ground truth of scenes.md (exact predicates, independent of any engine).
TOTAL_PAIRS = 36_782
COLLIDING_POSES = 122
POSES = 200


def quat_mul(a: tuple[float, ...], b: tuple[float, ...]) -> tuple[float, float, float, float]:
    """Hamilton product a * b of quaternions (x, y, z, w): b applied first."""
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
        aw * bw - ax * bx - ay * by - az * bz,
    )


def torus() -> tumble.TriMesh:
    """torus_mesh(1.0, 0.3, 50, 50): 2,500 vertices, 5,000 triangles."""
    return tumble.TriMesh.torus(1.0, 0.3, 50, 50)


def tori_poses() -> list[tuple[tuple[float, float, float], tuple[float, ...]]]:
    """The 200 poses of torus B: Rz(0.1) * Rx(pi/2) at (-3 + 6 k / 199, 0.05, 0.02)."""
    rz = (0.0, 0.0, math.sin(0.05), math.cos(0.05))
    rx = (math.sin(math.pi / 4), 0.0, 0.0, math.cos(math.pi / 4))
    q = quat_mul(rz, rx)
    return [((-3.0 + 6.0 * k / 199.0, 0.05, 0.02), q) for k in range(POSES)]


def truth_pairs_per_pose() -> list[int] | None:
    """Pairs per pose from tori_pairs.json ($TORI_TRUTH, or shared/data/ beside the
    repository), or None when it is not there."""
    env = os.environ.get("TORI_TRUTH")
    here = Path(__file__).resolve()
    candidates = [Path(env)] if env else [p / "shared" / "data" / "tori_pairs.json"
                                          for p in here.parents]
    for path in candidates:
        if path.is_file():
            pairs = json.loads(path.read_text())["pairs_per_pose"]
            if len(pairs) == POSES:
                return [int(n) for n in pairs]
    return None


def main() -> None:
    a = torus()
    b = a  # the same object: one OBBTree, built by the first query and kept in it
    poses = tori_poses()
    start = time.perf_counter()
    tumble.within_tolerance(a, None, b, None, 0.0)
    print(f"first query (builds the OBBTree of 5,000 triangles): "
          f"{(time.perf_counter() - start) * 1e3:.1f} ms")

    first, counts, t_first, t_pairs = [], [], [], []
    for pose in poses:
        start = time.perf_counter()
        hit = tumble.collide(a, None, b, pose, report="bool")
        t_first.append(time.perf_counter() - start)
        start = time.perf_counter()
        result = tumble.collide(a, None, b, pose)
        t_pairs.append(time.perf_counter() - start)
        first.append(hit.intersect)
        counts.append(len(result.pairs))
        assert hit.intersect == (len(result.pairs) > 0)

    total, colliding = sum(counts), sum(first)
    print(f"tori, {POSES} poses: {colliding} colliding poses, {total} intersecting triangle pairs")
    us = np.array(t_first) * 1e6
    hits = np.array(first)
    print(f"first contact: median {np.median(us):.1f} us per query "
          f"(colliding {np.median(us[hits]):.1f} us, separated {np.median(us[~hits]):.1f} us)")
    print(f"all pairs:     median {np.median(t_pairs) * 1e6:.1f} us per query, "
          f"{sum(t_pairs) * 1e3:.1f} ms for the {POSES} poses")

    truth = truth_pairs_per_pose()
    if truth is not None:
        differing = [k for k in range(POSES) if counts[k] != truth[k]]
        print(f"ground truth (tori_pairs.json): {sum(truth)} pairs, "
              f"{sum(n > 0 for n in truth)} colliding poses; poses differing: {len(differing)}")
        if differing:
            raise SystemExit(f"pair counts differ from the ground truth at poses {differing}")
    else:
        print("tori_pairs.json not found: checking the totals of scenes.md only")
    if (total, colliding) != (TOTAL_PAIRS, COLLIDING_POSES):
        raise SystemExit(f"expected {TOTAL_PAIRS} pairs at {COLLIDING_POSES} poses, "
                         f"got {total} at {colliding}")

    # The same pose as a 4x4 matrix gives the same pairs.
    k = int(np.argmax(counts))
    (x, y, z), (qx, qy, qz, qw) = poses[k]
    rot = np.array([
        [1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)],
        [2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)],
        [2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)],
    ])
    matrix = np.eye(4)
    matrix[:3, :3], matrix[:3, 3] = rot, (x, y, z)
    by_matrix = tumble.collide(a, np.eye(4), b, matrix)
    print(f"pose {k} as a 4x4 matrix: {len(by_matrix.pairs)} pairs (quaternion: {counts[k]})")

    # Contacts at the deepest pose: points, normals (B to A), depths, features.
    contacts = tumble.collide(a, None, b, poses[k], report="contacts").contacts
    deepest = contacts[np.argmax(contacts["depth"])]
    print(f"contacts at pose {k}: {len(contacts)}, deepest {deepest['depth'] * 1e3:.2f} mm "
          f"({deepest['kind']}, triangle {deepest['feature_a']['index']} of A)")

    # Distance at a separated pose, exact and with 10% relative error.
    d = tumble.distance(a, None, b, poses[0])
    approx = tumble.distance(a, None, b, poses[0], rel_err=0.1)
    print(f"pose 0: distance {d.distance:.6f} m between triangles {d.tri_a} and {d.tri_b} "
          f"({d.stats.triangle_tests} triangle tests); rel_err=0.1 gives "
          f"{approx.distance:.6f} m with {approx.stats.triangle_tests}")
    assert d.distance <= approx.distance <= 1.1 * d.distance
    assert tumble.within_tolerance(a, None, b, poses[0], d.distance)

    # A primitive against the mesh: a ball in the torus' hole touches nothing,
    # one of radius 0.75 reaches the tube (inner radius 0.7).
    for radius in (0.6, 0.75):
        hit = tumble.collide(tumble.Sphere(radius), None, a, None)
        print(f"sphere of radius {radius} at the centre: intersect={hit.intersect}, "
              f"{len(hit.pairs)} triangles")


if __name__ == "__main__":
    main()
