"""A ragdoll tumbles down a flight of stairs (manual chapter "Joints").

Eleven bodies (pelvis, torso, head, upper and lower arms and legs as
capsules) on ball joints with swing cones (neck, shoulders, hips, spine) and
hinges with angle limits (elbows, knees), pushed off the top of eight steps.
The script checks that the ragdoll reaches the foot of the stairs in one
piece: every joint within millimetres of its anchor, every elbow and knee
within its limits, nothing quarantined, and writes an animation.

    python examples/python/ragdoll.py      (writes out/ragdoll.glb)
"""

from __future__ import annotations

import math
from pathlib import Path

import tumble

STEPS, RISE, RUN = 8, 0.18, 0.3  # stairs: count, step height and depth (m)
TOP = STEPS * RISE


def stairs(world: tumble.World) -> None:
    world.add_body(tumble.HalfSpace(), kind="static", name="floor")
    for k in range(STEPS):
        # Step k spans x in [k RUN, (k + 1) RUN], from the floor to its tread.
        height = TOP - k * RISE
        world.add_body(
            tumble.Box((RUN / 2, 1.0, height / 2)),
            kind="static",
            position=((k + 0.5) * RUN, 0, height / 2),
            friction=0.6,
            name=f"step{k}",
        )


def ragdoll(
    world: tumble.World, x: float, z: float
) -> tuple[list[tumble.Joint], list[tumble.Joint]]:
    """The ragdoll standing with its feet at (x, 0, z); returns its
    hinges (elbows, knees) and its other joints."""

    def capsule(
        name: str, mass: float, top: tuple[float, float, float], length: float, radius: float
    ):
        # A capsule hanging down from `top`.
        centre = (top[0], top[1], top[2] - length / 2)
        return world.add_body(
            tumble.Capsule(radius, length / 2 - radius),
            mass=mass,
            position=centre,
            friction=0.6,
            name=name,
        )

    hip_z, shoulder_z = z + 0.9, z + 1.45
    pelvis = world.add_body(tumble.Box((0.15, 0.1, 0.08)), mass=10.0, position=(x, 0, hip_z + 0.05))
    torso = world.add_body(
        tumble.Box((0.17, 0.1, 0.22)), mass=25.0, position=(x, 0, shoulder_z - 0.2)
    )
    head = world.add_body(tumble.Sphere(0.11), mass=5.0, position=(x, 0, shoulder_z + 0.17))
    hinges, balls = [], []
    balls.append(
        world.add_joint(
            "ball",
            torso,
            pelvis,
            anchor=(x, 0, hip_z + 0.12),
            axis=(0, 0, 1),
            swing_limit=0.6,
            limits=(-0.5, 0.5),
        )
    )
    balls.append(
        world.add_joint(
            "ball", head, torso, anchor=(x, 0, shoulder_z + 0.04), axis=(0, 0, 1), swing_limit=0.7
        )
    )
    for side in (-1, 1):
        y = 0.24 * side
        upper = capsule("upper_arm", 2.5, (x, y, shoulder_z), 0.3, 0.05)
        fore = capsule("forearm", 1.5, (x, y, shoulder_z - 0.3), 0.28, 0.045)
        balls.append(
            world.add_joint(
                "ball", upper, torso, anchor=(x, y, shoulder_z), axis=(0, 0, -1), swing_limit=2.0
            )
        )
        # Elbow: bends forward (about -y on the right arm, +y on the left).
        hinges.append(
            world.add_joint(
                "hinge",
                fore,
                upper,
                anchor=(x, y, shoulder_z - 0.3),
                axis=(0, side, 0),
                limits=(0.0, 2.5),
            )
        )
        y = 0.1 * side
        thigh = capsule("thigh", 7.0, (x, y, hip_z), 0.45, 0.07)
        shin = capsule("shin", 4.0, (x, y, hip_z - 0.45), 0.45, 0.055)
        balls.append(
            world.add_joint(
                "ball",
                thigh,
                pelvis,
                anchor=(x, y, hip_z),
                axis=(0, 0, -1),
                swing_limit=1.4,
                limits=(-0.4, 0.4),
            )
        )
        # Knee: bends backwards only.
        hinges.append(
            world.add_joint(
                "hinge",
                shin,
                thigh,
                anchor=(x, y, hip_z - 0.45),
                axis=(0, -side, 0),
                limits=(0.0, 2.4),
            )
        )
    return hinges, balls


def main() -> None:
    world = tumble.World(dt=1 / 120, sleeping=False)
    stairs(world)
    hinges, balls = ragdoll(world, x=0.15, z=TOP)
    pelvis = world.bodies[STEPS + 1]
    # A push forward, off the top step.
    for body in world.bodies[STEPS + 1 :]:
        body.velocity = (1.5, 0.0, 0.0)
    world.start_recording(every=2)
    worst = 0.0
    for _ in range(600):  # 5 s
        world.step()
        assert not world.step_report.quarantined
        worst = max(worst, max(world.joint_states()["linear_error"]))
        for h in hinges:
            assert -0.03 < h.position < h_limit(h) + 0.03, h.position
    x, z = pelvis.position[0], pelvis.position[2]
    print(
        f"ragdoll: pelvis at x = {x:.2f} m, z = {z:.2f} m; largest joint gap {1000 * worst:.2f} mm"
    )
    assert x > STEPS * RUN * 0.75, f"it did not get down the stairs: x = {x}"
    assert z < TOP / 2, f"it is still high up: z = {z}"
    assert worst < 0.01, worst
    out = Path("out")
    out.mkdir(exist_ok=True)
    world.export_gltf(out / "ragdoll.glb")
    print("wrote out/ragdoll.glb")


def h_limit(hinge: tumble.Joint) -> float:
    """Upper limit of an elbow (2.5 rad) or knee (2.4 rad)."""
    return 2.5 if math.isclose(hinge.body_a.mass, 1.5) else 2.4


if __name__ == "__main__":
    main()
