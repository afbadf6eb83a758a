"""A pile of boxes and rocks (convex hulls) falls onto the ground; the energies
are plotted (out/python_pile_energy.png) and the motion is exported as an
animated glTF for the viewer (out/python_pile.glb).

    python examples/python/falling_pile.py
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # headless: write files, open no window
import matplotlib.pyplot as plt
import numpy as np

import tumble

OUT = Path(__file__).resolve().parents[2] / "out"


def build(n: int = 60, seed: int = 1) -> tumble.World:
    world = tumble.World(dt=1 / 120)
    world.add_body(tumble.HalfSpace(), kind="static", name="ground", friction=0.6)
    rng = np.random.default_rng(seed)
    # Balls and capsules would roll on forever (there is no rolling resistance),
    # so the pile is made of boxes and rocks, which come to rest.
    rock = tumble.ConvexHull(rng.normal(size=(24, 3)) * [0.07, 0.06, 0.05])
    shapes = [tumble.Box((0.12, 0.08, 0.05)), rock, tumble.Box((0.06, 0.06, 0.06))]
    for i in range(n):
        # Three columns of falling bodies, spaced so that none overlap at the start.
        position = (0.3 * (i % 3) - 0.3, 0.05 * rng.standard_normal(), 0.3 + 0.2 * (i // 3))
        angle = rng.uniform(0, np.pi)
        axis = rng.normal(size=3)
        axis /= np.linalg.norm(axis)
        orientation = (*(axis * np.sin(angle / 2)), np.cos(angle / 2))
        world.add_body(shapes[i % 3], density=600.0, position=position, orientation=orientation,
                       friction=0.6, name=f"body{i}")
    return world


def main() -> None:
    OUT.mkdir(exist_ok=True)
    world = build()
    world.start_recording(every=2)
    times, kinetic, potential = [], [], []
    for _ in range(360):  # 3 s
        world.step()
        times.append(world.time)
        kinetic.append(world.kinetic_energy)
        potential.append(world.potential_energy)
    kinetic, potential = np.array(kinetic), np.array(potential)
    total = kinetic + potential

    fig, ax = plt.subplots(figsize=(7, 4))
    ax.plot(times, kinetic, label="kinetic")
    ax.plot(times, potential - potential[-1], label="potential (above final)")
    ax.plot(times, total - potential[-1], label="total", color="black", lw=1)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("energy (J)")
    ax.set_title(f"falling pile: {len(world) - 1} bodies, dt = {world.dt:.4f} s")
    ax.legend()
    fig.tight_layout()
    fig.savefig(OUT / "python_pile_energy.png", dpi=120)
    world.export_gltf(OUT / "python_pile.glb")

    z = world.positions[1:, 2]
    print(f"{len(world) - 1} bodies after {world.time:.2f} s: highest z = {z.max():.3f} m, "
          f"kinetic energy {kinetic[-1]:.4f} J, {world.step_report.sleeping_bodies} asleep, "
          f"{world.recorded_frames} frames recorded")
    # Sanity: contacts only remove energy, and everything came to rest above the ground.
    assert np.all(np.diff(total) < 1e-6 * abs(total[0]) + 1e-9)
    assert kinetic[-1] < 1e-2 * kinetic.max()
    assert z.min() > 0.0


if __name__ == "__main__":
    main()
