"""A four-wheeled car drives over bumpy mesh terrain on motorised hinges
(manual chapter "Joints").

The terrain is a triangle mesh (a height field of gentle bumps, built with
numpy); the car is a 400 kg box on four 15 kg wheels (convex hulls of a
cylinder), each on a hinge about its axle with a velocity motor of 150 N m
driving it at 6 rad/s (about 2.1 m/s on 0.35 m wheels). The script checks
that the car drives forward over the bumps, stays upright and keeps its
wheels on their axles, and writes an animation.

    python examples/python/car.py      (writes out/car.glb)
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

import tumble

WHEEL_RADIUS, WHEEL_WIDTH = 0.35, 0.2
TARGET_SPEED = 6.0  # rad/s
TORQUE = 150.0  # N m per wheel


def terrain(size: float = 40.0, n: int = 80) -> tumble.TriMesh:
    """A closed slab whose top is a height field of bumps up to 6 cm."""
    xs = np.linspace(-size / 2, size / 2, n + 1)
    x, y = np.meshgrid(xs, xs, indexing="ij")
    z = 0.06 * np.sin(1.3 * x) * np.cos(0.9 * y)
    top = np.stack([x.ravel(), y.ravel(), z.ravel()], axis=1)
    bottom = top.copy()
    bottom[:, 2] = -1.0
    vertices = np.vstack([top, bottom])
    index = np.arange((n + 1) ** 2).reshape(n + 1, n + 1)
    faces = []
    for i in range(n):
        for j in range(n):
            a, b, c, d = index[i, j], index[i + 1, j], index[i + 1, j + 1], index[i, j + 1]
            faces += [(a, b, c), (a, c, d)]  # top, facing up
            off = (n + 1) ** 2
            faces += [(a + off, c + off, b + off), (a + off, d + off, c + off)]  # bottom
    # The four sides close the slab.
    rim = (
        list(index[:, 0])
        + list(index[n, 1:])
        + list(index[::-1, n][1:])
        + list(index[0, ::-1][1:-1])
    )
    off = (n + 1) ** 2
    for k in range(len(rim)):
        a, b = rim[k], rim[(k + 1) % len(rim)]
        faces += [(a, a + off, b + off), (a, b + off, b)]
    return tumble.TriMesh(vertices, np.array(faces, dtype=np.int64))


def wheel_hull() -> tumble.ConvexHull:
    """A cylinder along y (the axle), as a convex hull of two rings."""
    angles = np.linspace(0, 2 * math.pi, 24, endpoint=False)
    ring = np.stack(
        [WHEEL_RADIUS * np.cos(angles), np.zeros_like(angles), WHEEL_RADIUS * np.sin(angles)], 1
    )
    left, right = ring.copy(), ring.copy()
    left[:, 1], right[:, 1] = -WHEEL_WIDTH / 2, WHEEL_WIDTH / 2
    return tumble.ConvexHull(np.vstack([left, right]))


def build() -> tuple[tumble.World, tumble.Body, list[tumble.Joint]]:
    world = tumble.World(dt=1 / 120, sleeping=False)
    world.add_body(terrain(), kind="static", friction=0.9, name="terrain")
    height = 0.06 + WHEEL_RADIUS + 0.05
    chassis = world.add_body(
        tumble.Box((1.2, 0.6, 0.15)), mass=400.0, position=(0, 0, height + 0.25), name="chassis"
    )
    hinges = []
    for x in (-0.9, 0.9):
        for y in (-0.8, 0.8):
            centre = (x, y, height)
            wheel = world.add_body(
                wheel_hull(), mass=15.0, position=centre, friction=0.9, name="wheel"
            )
            hinges.append(
                world.add_joint(
                    "hinge",
                    wheel,
                    chassis,
                    anchor=centre,
                    axis=(0, 1, 0),
                    motor={"target_velocity": TARGET_SPEED, "max_force": TORQUE},
                )
            )
    return world, chassis, hinges


def main() -> None:
    world, chassis, hinges = build()
    start = chassis.position.copy()
    world.start_recording(every=2)
    for _ in range(600):  # 5 s
        world.step()
        up = tumble_up(chassis)
        assert up > 0.9, f"the car tipped over: up.z = {up}"
    travelled = chassis.position[0] - start[0]
    speed = chassis.velocity[0]
    print(f"car: {travelled:.2f} m in 5 s, now {speed:.2f} m/s")
    # Wheels turn at the motor's speed, rolling without slipping: the
    # car's speed is the wheel's rim speed (a few percent off on bumps).
    assert travelled > 7.0, travelled
    assert abs(speed - TARGET_SPEED * WHEEL_RADIUS) < 0.15 * TARGET_SPEED * WHEEL_RADIUS, speed
    assert max(world.joint_states()["linear_error"]) < 2e-3
    out = Path("out")
    out.mkdir(exist_ok=True)
    world.export_gltf(out / "car.glb")
    print("wrote out/car.glb")


def tumble_up(body: tumble.Body) -> float:
    """z component of the body's up axis."""
    x, y, z, w = body.orientation
    return 1 - 2 * (x * x + y * y)


if __name__ == "__main__":
    main()
