"""Two textbook checks, printed next to their analytic values: a ball that
bounces with restitution e (each apex is e^2 of the one before), and a box
sliding down a 30 degree slope with Coulomb friction mu (a = g (sin - mu cos)).

    python examples/python/bounce_incline.py
"""

from __future__ import annotations

import math

import numpy as np

import tumble

G = 9.81


def bounce(e: float = 0.7) -> None:
    world = tumble.World(dt=1 / 240, sleeping=False)
    world.add_body(tumble.HalfSpace(), kind="static", restitution=e)
    ball = world.add_body(tumble.Sphere(0.1), mass=1.0, position=(0, 0, 1.1), restitution=e)
    heights, last_vz = [1.0], 0.0
    while len(heights) < 4:
        world.step()
        vz = ball.velocity[2]
        if last_vz > 0 >= vz:
            heights.append(ball.position[2] - 0.1)
        last_vz = vz
    for k in range(1, len(heights)):
        ratio = heights[k] / heights[k - 1]
        print(f"bounce {k}: apex {heights[k]:.4f} m, ratio {ratio:.4f} (e^2 = {e * e:.4f})")
        assert abs(ratio - e * e) < 0.02 * e * e


def incline(mu: float, theta_deg: float = 30.0) -> float:
    theta = math.radians(theta_deg)
    q = (0.0, math.sin(theta / 2), 0.0, math.cos(theta / 2))
    normal = np.array([math.sin(theta), 0.0, math.cos(theta)])
    down = np.array([math.cos(theta), 0.0, -math.sin(theta)])
    world = tumble.World(dt=1 / 240, sleeping=False)
    world.add_body(tumble.Box((10, 10, 0.5)), kind="static", orientation=q, friction=mu)
    box = world.add_body(tumble.Box((0.25, 0.25, 0.25)), mass=1.0, position=0.75 * normal,
                         orientation=q, friction=mu)
    world.step(48)
    t0, v0 = world.time, box.velocity @ down
    world.step(192)
    a = (box.velocity @ down - v0) / (world.time - t0)
    expected = max(0.0, G * (math.sin(theta) - mu * math.cos(theta)))
    print(f"incline mu = {mu}: a = {a:.4f} m/s^2, analytic {expected:.4f} m/s^2")
    return a - expected


def main() -> None:
    bounce()
    assert abs(incline(0.2)) < 0.02 * G * (0.5 - 0.2 * math.cos(math.radians(30)))
    assert abs(incline(0.7)) < 1e-3  # tan 30 deg = 0.577 < 0.7: it sticks


if __name__ == "__main__":
    main()
