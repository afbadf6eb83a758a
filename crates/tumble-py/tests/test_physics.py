"""Physics through the Python API, against analytic results and conservation
laws (the same laws the Rust tests check, so a binding that scrambles rows,
units or frames fails here)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import tumble

G = 9.81


def ball_drop(e: float, height: float = 1.0) -> tuple[tumble.World, tumble.Body]:
    world = tumble.World(dt=1 / 240, sleeping=False)
    world.add_body(tumble.HalfSpace(), kind="static", restitution=e, name="ground")
    ball = world.add_body(tumble.Sphere(0.1), mass=1.0, position=(0, 0, height), restitution=e)
    return world, ball


@pytest.mark.parametrize("e", [0.5, 0.8])
def test_bounce_heights_follow_e_squared(e: float) -> None:
    world, ball = ball_drop(e)
    r = 0.1
    apexes = []
    last_vz = 0.0
    for _ in range(240 * 6):
        world.step()
        vz = ball.velocity[2]
        if last_vz > 0.0 and vz <= 0.0:
            apexes.append(ball.position[2] - r)
            if len(apexes) == 3:
                break
        last_vz = vz
    assert len(apexes) == 3
    heights = [1.0 - r, *apexes]
    for before, after in zip(heights, heights[1:]):
        assert after / before == pytest.approx(e * e, rel=0.02)


def test_free_fall_follows_the_parabola() -> None:
    # No ground: z(t) = z0 + v0 t - g t^2 / 2 and x(t) = x0 + vx t, exactly up
    # to the semi-implicit Euler offset g h t / 2 of its sub-step h (see
    # crates/tumble/tests/stepping.rs).
    dt, n = 1 / 100, 100
    world = tumble.World(dt=dt, substeps=4)
    body = world.add_body(
        tumble.Box((0.1, 0.2, 0.3)), mass=2.0, position=(1, 2, 3), velocity=(2, -1, 6)
    )
    world.step(n)
    t, h = dt * n, dt / 4
    exact = np.array([1 + 2 * t, 2 - t, 3 + 6 * t - 0.5 * G * t * t])
    offset = np.array([0, 0, -0.5 * G * h * t])
    np.testing.assert_allclose(body.position, exact + offset, atol=1e-9)
    np.testing.assert_allclose(body.velocity, [2, -1, 6 - G * t], atol=1e-9)
    assert world.time == pytest.approx(t)


def incline(mu: float) -> tuple[tumble.World, tumble.Body, np.ndarray]:
    """A cube on a 30 degree slope (the scene `incline` of shared/scenes.md)."""
    theta = math.radians(30)
    q = (0.0, math.sin(theta / 2), 0.0, math.cos(theta / 2))  # about +y
    normal = np.array([math.sin(theta), 0.0, math.cos(theta)])
    down = np.array([math.cos(theta), 0.0, -math.sin(theta)])
    world = tumble.World(dt=1 / 240, sleeping=False)
    world.add_body(tumble.Box((10, 10, 0.5)), kind="static", orientation=q, friction=mu)
    cube = world.add_body(
        tumble.Box((0.25, 0.25, 0.25)), mass=1.0, position=normal * 0.75, orientation=q, friction=mu
    )
    return world, cube, down


def test_incline_slides_with_coulomb_acceleration() -> None:
    mu = 0.2
    theta = math.radians(30)
    world, cube, down = incline(mu)
    world.step(48)  # settle the initial contact
    t0, v0 = world.time, float(cube.velocity @ down)
    world.step(192)
    t1, v1 = world.time, float(cube.velocity @ down)
    a = (v1 - v0) / (t1 - t0)
    assert a == pytest.approx(G * (math.sin(theta) - mu * math.cos(theta)), rel=0.02)


def test_incline_sticks_with_high_friction() -> None:
    world, cube, _ = incline(0.7)  # tan 30 = 0.577 < 0.7
    start = cube.position
    world.step(240)
    assert np.linalg.norm(cube.position - start) < 1e-3
    assert np.linalg.norm(cube.velocity) < 1e-3


def test_free_collision_conserves_momentum() -> None:
    # Two spheres of different mass meet off-centre in zero gravity: total
    # linear momentum and (with restitution 1) kinetic energy are conserved.
    world = tumble.World(gravity=(0, 0, 0), dt=1 / 240, sleeping=False)
    a = world.add_body(
        tumble.Sphere(0.2),
        mass=1.0,
        position=(-1, 0.1, 0),
        velocity=(3, 0, 0),
        restitution=1.0,
        friction=0.0,
    )
    b = world.add_body(
        tumble.Sphere(0.3),
        mass=3.0,
        position=(1, -0.1, 0),
        velocity=(-1, 0, 0),
        restitution=1.0,
        friction=0.0,
    )
    masses = np.array([1.0, 3.0])
    p0 = masses @ world.velocities
    e0 = world.kinetic_energy
    touched = False
    for _ in range(120):
        world.step()
        touched |= any(ev.kind == "begin" for ev in world.contact_events())
    assert touched
    p1 = masses @ world.velocities
    np.testing.assert_allclose(p1, p0, atol=1e-9)
    assert world.kinetic_energy == pytest.approx(e0, rel=1e-3)
    # They did collide: the light sphere bounced back, the heavy one too.
    assert a.velocity[0] < 0 < b.velocity[0]


def test_bounce_raises_begin_and_end_events() -> None:
    world, ball = ball_drop(0.8)
    ground = world.bodies[0]
    events = []
    for _ in range(480):
        world.step()
        events += world.contact_events()
    kinds = [ev.kind for ev in events]
    assert kinds[:4] == ["begin", "end", "begin", "end"]
    assert {events[0].body_a, events[0].body_b} == {ground, ball}
    # The first impact: the ball falls 0.9 m, t = sqrt(2 * 0.9 / g).
    assert events[0].time == pytest.approx(math.sqrt(2 * 0.9 / G), abs=2 / 240)


def test_step_n_keeps_the_events_of_every_step() -> None:
    world, _ = ball_drop(0.8)
    world.step(480)
    kinds = [ev.kind for ev in world.contact_events()]
    assert kinds.count("begin") >= 2 and kinds.count("begin") == kinds.count("end")


def test_identical_worlds_give_identical_arrays() -> None:
    def pile() -> tumble.World:
        world = tumble.World()
        world.add_body(tumble.HalfSpace(), kind="static")
        rng = np.random.default_rng(7)
        for i in range(30):
            shape = [tumble.Box((0.1, 0.15, 0.2)), tumble.Sphere(0.12), tumble.Capsule(0.08, 0.1)][
                i % 3
            ]
            world.add_body(
                shape, density=500.0, position=rng.uniform([-0.5, -0.5, 0.3], [0.5, 0.5, 3.0])
            )
        return world

    w1, w2 = pile(), pile()
    w1.step(120)
    w2.step(60)
    w2.step(60)
    for attr in ["positions", "orientations", "velocities", "angular_velocities"]:
        assert np.array_equal(getattr(w1, attr), getattr(w2, attr)), attr
    assert w1.contacts().tobytes() == w2.contacts().tobytes()


def test_forces_accelerate_as_newton_says() -> None:
    world = tumble.World(gravity=(0, 0, 0), dt=1 / 100)
    body = world.add_body(tumble.Sphere(0.5), mass=2.0)
    world.apply_force(body, (4.0, 0, 0))  # a = 2 m/s^2 for one step
    world.step()
    assert body.velocity[0] == pytest.approx(2.0 * 0.01)
    body.apply_impulse((0, 6.0, 0))  # dv = 3 m/s now
    assert body.velocity[1] == pytest.approx(3.0)
    # A force off the centre adds the torque r x F: L = tau dt.
    point = np.array([0.5, 0, 0])
    lever = point - body.center_of_mass
    body.apply_force((0, 0, 1.0), point=point)
    world.step()
    inertia = 0.4 * 2.0 * 0.25
    expected = np.cross(lever, [0, 0, 1.0]) * 0.01 / inertia
    np.testing.assert_allclose(body.angular_velocity, expected, rtol=1e-9, atol=1e-15)


def test_vectorised_forces_match_single_ones() -> None:
    def make() -> tuple[tumble.World, list[tumble.Body]]:
        w = tumble.World(gravity=(0, 0, 0))
        bodies = [
            w.add_body(tumble.Sphere(0.1), mass=1.0 + i, position=(i, 0, 0)) for i in range(4)
        ]
        return w, bodies

    forces = np.arange(12, dtype=float).reshape(4, 3)
    w1, b1 = make()
    w1.apply_forces(forces)
    w2, b2 = make()
    for body, f in zip(b2, forces):
        body.apply_force(f)
    w1.step()
    w2.step()
    assert np.array_equal(w1.velocities, w2.velocities)


def _box_passes_turned_slab(continuous: bool, ccd: bool = False) -> tuple[bool, int]:
    """Fires a 10 cm box at 600 m/s into a 1 cm slab turned 30 degrees:
    whether its centre crossed the slab's plane inside the slab's square
    (sliding off an edge is not passing through), and how many times
    continuous collision put it back."""
    world = tumble.World(gravity=(0, 0, 0), sleeping=False, continuous=continuous)
    half = math.radians(15)
    turn = (0.0, math.sin(half), 0.0, math.cos(half))
    world.add_body(tumble.Box((1.0, 1.0, 0.005)), kind="static", orientation=turn)
    box = world.add_body(
        tumble.Box((0.05, 0.05, 0.05)), position=(0, 0, 4.2), velocity=(0, 0, -600), ccd=ccd
    )
    normal = np.array([math.sin(2 * half), 0.0, math.cos(2 * half)])
    along = np.array([math.cos(2 * half), 0.0, -math.sin(2 * half)])
    last = np.array(box.position)
    put_back = 0
    for _ in range(30):
        world.step()
        put_back += world.step_report.continuous
        now = np.array(box.position)
        h0, h1 = last @ normal, now @ normal
        if h0 >= 0.0 > h1:
            x = last + (now - last) * (h0 / (h0 - h1))
            if abs(x @ along) < 1.0 and abs(x[1]) < 1.0:
                return True, put_back
        last = now
    return False, put_back


def test_continuous_collision_stops_a_fast_box_at_a_turned_slab() -> None:
    assert tumble.World().settings["continuous"] is True
    passed, put_back = _box_passes_turned_slab(continuous=True)
    assert not passed and put_back >= 1
    # Not vacuous: the discrete step alone lets it through.
    passed, put_back = _box_passes_turned_slab(continuous=False)
    assert passed and put_back == 0
    # The per-body flag is taken (the box is fast anyway: the same answer).
    assert _box_passes_turned_slab(continuous=True, ccd=True) == _box_passes_turned_slab(True)
    with pytest.raises(tumble.InvalidArgument):
        tumble.World(continuous="yes")
    with pytest.raises(TypeError):
        tumble.World().add_body(tumble.Sphere(0.1), ccd="yes")


def _grid_drop(**settings) -> tuple[np.ndarray, set[int]]:
    """200 spheres dropped in a 10 x 10 x 2 grid onto a ground box (enough
    bodies for the step's threads): positions after 40 steps, and the thread
    counts the steps reported."""
    world = tumble.World(sleeping=False, **settings)
    world.add_body(tumble.Box((8, 8, 0.5)), kind="static", position=(0, 0, -0.5))
    for k in range(200):
        i, j, layer = k % 10, (k // 10) % 10, k // 100
        at = (0.45 * i - 2.0, 0.45 * j - 2.0, 0.3 + 0.45 * layer + 0.01 * i)
        world.add_body(tumble.Sphere(0.2), position=at)
    used = set()
    for _ in range(40):
        world.step()
        used.add(world.step_report.threads)
    return np.array(world.positions), used


def test_adaptive_threads_is_a_setting_and_never_changes_the_result() -> None:
    assert tumble.World().settings["adaptive_threads"] is True
    assert tumble.World(adaptive_threads=False).settings["adaptive_threads"] is False
    serial, used = _grid_drop(threads=1)
    assert used == {1}
    pinned, used = _grid_drop(threads=2, adaptive_threads=False)
    assert used == {2}
    adaptive, used = _grid_drop(threads=2)
    assert used <= {1, 2}
    assert serial.tobytes() == pinned.tobytes() == adaptive.tobytes()
    with pytest.raises(tumble.InvalidArgument):
        tumble.World(adaptive_threads="yes")


def test_a_body_with_given_inertia_turns_and_falls_by_it() -> None:
    # A body without shapes (mass and inertia given) falls freely and
    # turns under a torque at tau / I about each principal axis; a box given
    # an inertia other than its own turns by the given one.
    world = tumble.World(dt=1 / 120, sleeping=False)
    free = world.add_body(
        None, mass=2.0, inertia=(1.0, 1.5, 2.0), center_of_mass=(0.1, 0, 0), position=(0, 0, 5)
    )
    assert free.mass == 2.0
    np.testing.assert_allclose(sorted(free.principal_inertia), [1.0, 1.5, 2.0], rtol=1e-12)
    np.testing.assert_allclose(free.center_of_mass, [0.1, 0, 5], atol=1e-12)
    box = world.add_body(
        tumble.Box((0.1, 0.1, 0.1)),
        mass=1.0,
        inertia=np.diag([0.3, 0.3, 0.3]),
        position=(3, 0, 5),
    )
    np.testing.assert_allclose(box.principal_inertia, [0.3, 0.3, 0.3], rtol=1e-12)
    z0 = free.center_of_mass[2]
    for _ in range(60):
        free.apply_torque((0.0, 0.0, 1.0))
        box.apply_torque((0.0, 0.0, 1.0))
        world.step()
    t = 60 / 120
    # Semi-implicit Euler over N sub-steps of h: z = z0 - g h^2 N (N + 1) / 2.
    s = world.settings["substeps"]
    h, n = 1 / 120 / s, 60 * s
    assert free.center_of_mass[2] == pytest.approx(z0 - G * h * h * n * (n + 1) / 2, abs=1e-9)
    np.testing.assert_allclose(free.angular_velocity, [0, 0, t / 2.0], atol=1e-12)
    np.testing.assert_allclose(box.angular_velocity, [0, 0, t / 0.3], atol=1e-12)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"inertia": (1, 1, 1)}, "inertia needs mass"),
        ({"inertia": (1, 1, 1), "density": 5.0}, "not density"),
        ({"mass": 1.0, "inertia": (1, 1, 3)}, "inertia"),
        ({"mass": 1.0, "inertia": [[1, 0.5, 0], [0, 1, 0], [0, 0, 1]]}, "inertia"),
        ({"mass": 1.0, "inertia": (1, 1)}, "3 numbers (a diagonal) or a 3x3 matrix"),
        ({"mass": 1.0, "center_of_mass": (0, 0, 1)}, "center_of_mass is given with inertia"),
        ({"mass": 1.0, "inertia": (1, 1, 1), "kind": "static"}, "mass and density apply"),
    ],
)
def test_bad_given_inertias_are_refused(kwargs, message) -> None:
    world = tumble.World()
    with pytest.raises(tumble.InvalidArgument) as info:
        world.add_body(tumble.Sphere(0.1), **kwargs)
    assert message in str(info.value)
    assert len(world.bodies) == 0
    # Without shapes: a static body needs one, a dynamic one its inertia.
    for kind in ["static", "dynamic"]:
        with pytest.raises(tumble.InvalidArgument) as info:
            world.add_body(None, kind=kind)
        assert "body has no shapes" in str(info.value)
    world.add_body([], kind="kinematic")
    assert len(world.bodies) == 1
