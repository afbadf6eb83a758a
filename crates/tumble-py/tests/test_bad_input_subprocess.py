"""Every bad input of docs/validation.md through the Python API, each in its
own interpreter: the call raises the documented exception, the world it was
aimed at is unchanged (its snapshot bytes are equal before and after), the
world still steps to finite states, and the process exits normally (no
abort, no panic crossing into Python)."""

from __future__ import annotations

import subprocess
import sys

import pytest

HARNESS = r"""
import math, sys
import numpy as np
import tumble

NAN, INF = math.nan, math.inf
tmp = sys.argv[2]
world = tumble.World()
ground = world.add_body(tumble.HalfSpace(), kind="static", name="ground")
ball = world.add_body(tumble.Sphere(0.1), mass=1.0, position=(0, 0, 1), name="ball")
gone = world.add_body(tumble.Sphere(0.1), mass=1.0, position=(1, 0, 1))
gone.remove()
cube = tumble.TriMesh.box((0.5, 0.5, 0.5))
before = world.to_bytes()
try:
    exec(sys.argv[1])
except Exception as e:
    outcome = type(e).__name__
else:
    outcome = "no exception"
assert world.to_bytes() == before, "the world changed"
world.step(5)
assert np.isfinite(world.positions).all() and np.isfinite(world.velocities).all()
print(outcome)
"""

INVALID, STALE, FILE = "InvalidArgument", "StaleBodyError", "FileError"

CASES = [
    # World settings (construction and update; the step size is dt).
    ("tumble.World(dt=0.0)", INVALID),
    ("tumble.World(dt=-1 / 60)", INVALID),
    ("tumble.World(dt=NAN)", INVALID),
    ("tumble.World(dt=INF)", INVALID),
    ("tumble.World(dt=10.0)", INVALID),
    ("tumble.World(substeps=0)", INVALID),
    ("tumble.World(iterations=100000)", INVALID),
    ("tumble.World(gravity=(0, 0, NAN))", INVALID),
    ("tumble.World(push_out_fraction=0.0)", INVALID),
    ("world.update_settings(dt=-1.0)", INVALID),
    ("world.update_settings(dt=1e9)", INVALID),
    ("world.update_settings(contact_margin=INF)", INVALID),
    # Bodies: mass, density, pose, velocities, material, kind.
    ("world.add_body(tumble.Sphere(0.1), mass=0.0)", INVALID),
    ("world.add_body(tumble.Sphere(0.1), mass=-1.0)", INVALID),
    ("world.add_body(tumble.Sphere(0.1), mass=NAN)", INVALID),
    ("world.add_body(tumble.Sphere(0.1), mass=5e-324)", INVALID),
    ("world.add_body(tumble.Sphere(0.1), density=0.0)", INVALID),
    ("world.add_body(tumble.Sphere(0.1), density=-5.0)", INVALID),
    ("world.add_body(tumble.Sphere(0.1), density=INF)", INVALID),
    ("world.add_body(tumble.Sphere(0.1), position=(NAN, 0, 0))", INVALID),
    ("world.add_body(tumble.Sphere(0.1), position=(INF, 0, 0))", INVALID),
    ("world.add_body(tumble.Sphere(0.1), orientation=(0, 0, 0, 0))", INVALID),
    ("world.add_body(tumble.Sphere(0.1), orientation=(0, 0, 0, 2))", INVALID),
    ("world.add_body(tumble.Sphere(0.1), orientation=(NAN, 0, 0, 1))", INVALID),
    ("world.add_body(tumble.Sphere(0.1), velocity=(INF, 0, 0))", INVALID),
    ("world.add_body(tumble.Sphere(0.1), angular_velocity=(0, NAN, 0))", INVALID),
    ("world.add_body(tumble.Sphere(0.1), friction=-1.0)", INVALID),
    ("world.add_body(tumble.Sphere(0.1), restitution=1.5)", INVALID),
    ("world.add_body(tumble.Sphere(0.1), restitution=NAN)", INVALID),
    ("world.add_body(tumble.Sphere(0.1), linear_damping=-1.0)", INVALID),
    ("world.add_body(tumble.Sphere(0.1), angular_damping=INF)", INVALID),
    ("world.add_body(tumble.Sphere(0.1), kind='static', velocity=(1, 0, 0))", INVALID),
    ("world.add_body(tumble.Sphere(0.1), kind='ghost')", INVALID),
    ("world.add_body(tumble.HalfSpace())", INVALID),
    ("world.add_body([])", INVALID),
    ("world.add_body(tumble.Sphere(0.1).at(position=(NAN, 0, 0)))", INVALID),
    # Shapes: dimensions, normals, hulls.
    ("tumble.Sphere(0.0)", INVALID),
    ("tumble.Sphere(-1.0)", INVALID),
    ("tumble.Sphere(NAN)", INVALID),
    ("tumble.Box((1, 0, 1))", INVALID),
    ("tumble.Box((1, -1, 1))", INVALID),
    ("tumble.Capsule(0.1, -1.0)", INVALID),
    ("tumble.Capsule(INF, 1.0)", INVALID),
    ("tumble.HalfSpace((0, 0, 0))", INVALID),
    ("tumble.HalfSpace((0, 0, 1), NAN)", INVALID),
    ("tumble.ConvexHull(np.zeros((4, 3)))", INVALID),
    ("tumble.ConvexHull([[0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0]])", INVALID),
    # Meshes: indices, values, emptiness, closedness where mass needs it.
    ("tumble.TriMesh(np.eye(3), [[0, 1, 3]])", INVALID),
    ("tumble.TriMesh(np.eye(3), [[0, -1, 2]])", INVALID),
    ("tumble.TriMesh([[0, 0, 0], [1, 0, NAN], [0, 1, 0]], [[0, 1, 2]])", INVALID),
    ("tumble.TriMesh(np.zeros((0, 3)), np.zeros((0, 3), dtype=int))", INVALID),
    ("world.add_body(tumble.TriMesh(cube.vertices, cube.faces[:10]), density=1000.0)", INVALID),
    ("world.add_body(tumble.TriMesh(cube.vertices, cube.faces[:, ::-1]), density=1000.0)", INVALID),
    (
        "world.add_body(tumble.TriMesh([[0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0]], "
        "[[0, 1, 2], [0, 2, 3], [0, 3, 1], [1, 3, 2]]), density=1000.0)",
        INVALID,
    ),
    (
        "tumble.mass_properties(tumble.TriMesh(cube.vertices, cube.faces[:10]), density=1.0)",
        INVALID,
    ),
    # Mesh files.
    ("tumble.TriMesh.from_file(tmp + '/missing.obj')", FILE),
    ("open(tmp + '/e.obj', 'w').close(); tumble.TriMesh.from_file(tmp + '/e.obj')", INVALID),
    (
        "open(tmp + '/g.stl', 'wb').write(b'\\x00' * 10); tumble.TriMesh.from_file(tmp + '/g.stl')",
        INVALID,
    ),
    (
        "open(tmp + '/g.obj', 'w').write('v 0 0 0\\nf 1 2 3\\n'); "
        "tumble.TriMesh.from_file(tmp + '/g.obj')",
        INVALID,
    ),
    ("tumble.TriMesh.from_file(tmp + '/x.ply')", INVALID),
    # Handles: removed twice, stale, of another world.
    ("world.remove_body(gone)", STALE),
    ("gone.remove()", STALE),
    ("gone.position", STALE),
    ("gone.apply_force((1, 0, 0))", STALE),
    ("gone.velocity = (1, 0, 0)", STALE),
    ("tumble.World().remove_body(ball)", INVALID),
    # Forces, impulses, velocities.
    ("ball.apply_force((NAN, 0, 0))", INVALID),
    ("ball.apply_force((INF, 0, 0))", INVALID),
    ("ball.apply_force((1, 0, 0), point=(NAN, 0, 0))", INVALID),
    ("ball.apply_impulse((0, NAN, 0))", INVALID),
    ("ground.apply_force((1, 0, 0))", INVALID),
    ("ball.velocity = (NAN, 0, 0)", INVALID),
    ("ball.position = (0, 0, INF)", INVALID),
    ("ball.orientation = (0, 0, 0, 0)", INVALID),
    ("world.apply_forces(np.full((2, 3), NAN))", INVALID),
    ("world.apply_forces(np.zeros((3, 3)))", INVALID),
    ("world.step(-1)", "OverflowError"),
    # Snapshots.
    ("tumble.World.load(tmp + '/missing.snap')", FILE),
    ("open(tmp + '/e.snap', 'wb').close(); tumble.World.load(tmp + '/e.snap')", FILE),
    ("tumble.World.from_bytes(b'garbage')", INVALID),
    ("tumble.World.from_bytes(world.to_bytes()[:40])", INVALID),
    ("b = bytearray(world.to_bytes()); b[8] += 1; tumble.World.from_bytes(bytes(b))", INVALID),
    ("world.save(tmp + '/no/such/dir/w.snap')", FILE),
]


@pytest.mark.parametrize("code, expected", CASES, ids=[c[0][:60] for c in CASES])
def test_bad_input_raises_and_the_process_survives(code: str, expected: str, tmp_path) -> None:
    run = subprocess.run(
        [sys.executable, "-c", HARNESS, code, str(tmp_path)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert run.returncode == 0, f"exit {run.returncode}\n{run.stdout}\n{run.stderr}"
    assert run.stdout.strip() == expected, run.stdout + run.stderr
