"""A kinematic paddle (a robot's end effector) pushes a box across a table,
driven by a trapezoidal velocity profile: the Python twin of
crates/tumble/examples/pusher.rs (manual chapter "Demos").

The paddle is kinematic: it moves exactly with the velocity set each step,
pushes the box and is never pushed back. The velocity is the profile's value
at each step's midpoint; the profile's corners fall on step boundaries, so
the paddle's position is the exact integral of the profile.

    python examples/python/pusher.py      (writes out/pusher_python.glb)
"""

from __future__ import annotations

import tumble

DT = 1 / 120
SPEED, RAMP, CRUISE = 0.2, 0.5, 1.5            # m/s, s, s
TABLE_TOP, BOX_HALF, PADDLE_HALF = 0.8, 0.05, (0.02, 0.15, 0.05)
X0, MU = -0.3, 0.5


def speed(t: float) -> float:
    t3 = 2 * RAMP + CRUISE
    if t <= 0 or t >= t3:
        return 0.0
    return SPEED * min(1.0, t / RAMP, (t3 - t) / RAMP)


def position(t: float) -> float:
    """The analytic integral of speed() from 0 to t, plus the start."""
    t1, t2, t3 = RAMP, RAMP + CRUISE, 2 * RAMP + CRUISE
    if t <= t1:
        d = 0.5 * SPEED * max(t, 0.0) ** 2 / RAMP
    elif t <= t2:
        d = 0.5 * SPEED * RAMP + SPEED * (t - t1)
    else:
        left = max(t3 - t, 0.0)
        d = SPEED * RAMP + SPEED * CRUISE - 0.5 * SPEED * left**2 / RAMP
    return X0 + d


def main() -> None:
    world = tumble.World(dt=DT, sleeping=False)
    world.add_body(tumble.Box((1.0, 0.5, TABLE_TOP / 2)), kind="static",
                   position=(0, 0, TABLE_TOP / 2), friction=MU, name="table")
    cube = world.add_body(tumble.Box((BOX_HALF,) * 3), mass=0.5, friction=MU,
                          position=(0, 0, TABLE_TOP + BOX_HALF), name="cube")
    paddle = world.add_body(tumble.Box(PADDLE_HALF), kind="kinematic", friction=MU,
                            position=(X0, 0, TABLE_TOP + PADDLE_HALF[2] + 0.002), name="paddle")
    world.start_recording()
    for k in range(int(round(3.2 / DT))):
        paddle.velocity = (speed((k + 0.5) * DT), 0, 0)
        world.step()
        x = paddle.position[0]
        assert abs(x - position(world.time)) < 1e-9, f"t={world.time}: paddle at {x}"
    world.export_gltf("out/pusher_python.glb")

    end = cube.position
    expected = position(10.0) + PADDLE_HALF[0] + BOX_HALF
    print(f"paddle stopped at x = {paddle.position[0]:.4f} m; cube at x = {end[0]:.4f} m "
          f"(against the paddle: {expected:.4f} m)")
    assert abs(end[0] - expected) < 5e-3, "the cube rests against the paddle"
    assert abs(end[1]) < 0.01 and abs(end[2] - (TABLE_TOP + BOX_HALF)) < 2e-3
    assert abs(cube.velocity).max() < 0.01


if __name__ == "__main__":
    main()
