"""Meshes from trimesh, simulated by tumble: a torus (an exact triangle mesh
shape) and a pebble (as a convex hull) made with trimesh fall onto a trimesh
box used as a static table. tumble reads
anything with .vertices and .faces; its mass properties agree with trimesh's.

    python examples/python/trimesh_interop.py
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import trimesh

import tumble

OUT = Path(__file__).resolve().parents[2] / "out"


def main() -> None:
    OUT.mkdir(exist_ok=True)
    torus = trimesh.creation.torus(major_radius=0.3, minor_radius=0.08, major_sections=40,
                                   minor_sections=16)
    rock = trimesh.creation.icosphere(subdivisions=1, radius=0.1)
    rock.apply_scale((1.4, 1.0, 0.7))  # a flattened, faceted pebble (convex)
    table = trimesh.creation.box(extents=(2.0, 2.0, 0.2))

    # Mass properties, two independent implementations.
    ours = tumble.mass_properties(torus, density=1000.0)
    torus.density = 1000.0
    theirs = torus.mass_properties
    print(f"torus mass: tumble {ours.mass:.6f} kg, trimesh {theirs['mass']:.6f} kg")
    assert np.isclose(ours.mass, theirs["mass"], rtol=1e-9)
    assert np.allclose(ours.inertia, theirs["inertia"], rtol=1e-8, atol=1e-12)

    world = tumble.World(dt=1 / 240)
    world.add_body(table, kind="static", position=(0, 0, -0.1), name="table")
    tilt = (np.sin(0.3), 0.0, 0.0, np.cos(0.3))
    ring = world.add_body(torus, density=1000.0, position=(0, 0, 0.6), orientation=tilt,
                          name="torus")
    stone = world.add_body(tumble.ConvexHull(rock), density=2500.0, position=(0.2, 0.1, 1.0),
                           name="rock")
    world.start_recording(every=4)
    world.step(480)  # 2 s
    world.export_gltf(OUT / "python_trimesh.glb")

    # The torus lies flat on the table: its axis is vertical, its centre one tube radius up.
    axis = trimesh.transformations.quaternion_matrix(np.roll(ring.orientation, 1))[:3, 2]
    print(f"torus rests at z = {ring.position[2]:.4f} m (tube radius 0.08), "
          f"axis tilt {np.degrees(np.arccos(abs(axis[2]))):.2f} deg; rock at z = "
          f"{stone.position[2]:.3f} m; {len(world.contacts())} contact points")
    assert abs(ring.position[2] - 0.08) < 5e-3
    assert abs(axis[2]) > 0.999
    assert stone.position[2] > 0.0


if __name__ == "__main__":
    main()
