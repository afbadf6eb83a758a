"""Rolling on a tessellated bowl through the Python API (issue 15): a mesh
made smooth with `TriMesh.smooth` holds a swinging ball to the rolling
period 2 pi sqrt(7 (R - r) / 5 g) (corrected for the amplitude by the
complete elliptic integral) and its amplitude; the smooth surface survives
pickling; bad crease angles are refused."""

from __future__ import annotations

import math
import pickle

import numpy as np
import pytest

import tumble

G = 9.81


def elliptic_k(m: float) -> float:
    """K(m) by the arithmetic-geometric mean (Abramowitz & Stegun 17.6)."""
    a, b = 1.0, math.sqrt(1.0 - m)
    while abs(a - b) > 1e-15 * a:
        a, b = (a + b) / 2.0, math.sqrt(a * b)
    return math.pi / (2.0 * a)


def bowl_world(mesh: tumble.TriMesh) -> tuple[tumble.World, tumble.Body]:
    world = tumble.World(dt=1 / 240, sleeping=False)
    world.add_body(mesh, kind="static", friction=0.8)
    path, phi0 = 0.45, math.radians(25)
    ball = world.add_body(
        tumble.Sphere(0.05),
        mass=1.0,
        friction=0.8,
        position=(path * math.sin(phi0), 0.0, -path * math.cos(phi0)),
    )
    return world, ball


def swing(world: tumble.World, ball: tumble.Body) -> tuple[float, float]:
    """Period (first to fifth crossing of the bottom) and the amplitude at
    the fourth turning point after the first crossing (rad)."""
    angle = lambda: math.atan2(ball.position[0], -ball.position[2])  # noqa: E731
    crossings: list[float] = []
    turns: list[float] = []
    prev, prev_rate, t = angle(), 0.0, 0.0
    while (len(crossings) < 5 or len(turns) < 4) and t < 20.0:
        world.step()
        t += world.dt
        now = angle()
        if (prev > 0.0) != (now > 0.0):
            crossings.append(t - world.dt * now / (now - prev))
        rate = now - prev
        if prev_rate != 0.0 and (rate > 0.0) != (prev_rate > 0.0) and crossings:
            turns.append(abs(prev))
        prev, prev_rate = now, rate
    return (crossings[4] - crossings[0]) / 2.0, turns[3]


def test_a_ball_in_a_smooth_bowl_keeps_its_rolling_swing() -> None:
    bowl = tumble.TriMesh.bowl(0.5, 0.05, 96, 48).smooth(30.0)
    assert bowl.crease_angle_deg == pytest.approx(30.0)
    world, ball = bowl_world(bowl)
    period, amplitude = swing(world, ball)
    phi0 = math.radians(25)
    want = 4.0 * math.sqrt(1.4 * 0.45 / G) * elliptic_k(math.sin(phi0 / 2) ** 2)
    assert period == pytest.approx(want, rel=0.01)
    assert 0.95 <= amplitude / phi0 <= 1.005


def test_the_facets_as_they_are_cost_the_ball_its_swing() -> None:
    # The same bowl without a smooth surface: each facet edge is a small
    # step the ball rolls into (the reason `smooth` exists).
    world, ball = bowl_world(tumble.TriMesh.bowl(0.5, 0.05, 96, 48))
    _, amplitude = swing(world, ball)
    assert amplitude / math.radians(25) < 0.9


def test_a_smooth_mesh_pickles_with_its_crease_angle_and_shares_its_triangles() -> None:
    flat = tumble.TriMesh.half_pipe(0.5, 0.05, 1.0, 32)
    smooth = flat.smooth(20.0)
    assert flat.crease_angle_deg is None
    back = pickle.loads(pickle.dumps(smooth))
    assert back.crease_angle_deg == 20.0
    odd = flat.smooth(33.3333)
    assert pickle.loads(pickle.dumps(odd)).crease_angle_deg == odd.crease_angle_deg
    assert back.face_count == flat.face_count
    assert "smooth at" in repr(smooth)
    world, ball = bowl_world(tumble.TriMesh.bowl(0.5, 0.05, 48, 24).smooth())
    for _ in range(30):
        world.step()
    again = pickle.loads(pickle.dumps(world))
    for _ in range(30):
        world.step()
        again.step()
    assert np.array_equal(world.states, again.states)


@pytest.mark.parametrize("angle", [0.0, -5.0, 180.0, float("nan"), float("inf")])
def test_bad_crease_angles_are_refused(angle: float) -> None:
    mesh = tumble.TriMesh.box((1.0, 1.0, 1.0))
    with pytest.raises(ValueError, match="crease_angle_deg"):
        mesh.smooth(angle)
    with pytest.raises(ValueError, match="crease_angle_deg"):
        tumble.TriMesh(mesh.vertices, mesh.faces, crease_angle_deg=angle)
