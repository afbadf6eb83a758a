"""Every bad input becomes a Python exception of the tumble tree with the
Rust message, leaves the world unchanged, and never kills the process."""

from __future__ import annotations

import math

import numpy as np
import pytest

import tumble

NAN, INF = math.nan, math.inf


def test_exception_tree() -> None:
    assert issubclass(tumble.TumbleError, Exception)
    assert issubclass(tumble.InvalidArgument, tumble.TumbleError)
    assert issubclass(tumble.InvalidArgument, ValueError)
    assert issubclass(tumble.StaleBodyError, tumble.InvalidArgument)
    assert issubclass(tumble.StaleBodyError, LookupError)
    assert issubclass(tumble.FileError, tumble.TumbleError)
    assert issubclass(tumble.FileError, OSError)
    assert issubclass(tumble.InternalError, tumble.TumbleError)
    assert tumble.TumbleError.__module__ == "tumble"


def world_with_ball() -> tuple[tumble.World, tumble.Body]:
    world = tumble.World()
    world.add_body(tumble.HalfSpace(), kind="static")
    ball = world.add_body(tumble.Sphere(0.1), mass=1.0, position=(0, 0, 1))
    return world, ball


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"dt": 0.0}, "settings.dt: must be finite and > 0, got 0"),
        ({"dt": NAN}, "settings.dt: must be finite and > 0, got NaN"),
        ({"dt": 2.0}, "settings.dt: must be at most 1 s, got 2"),
        ({"substeps": 0}, "settings.substeps: must be in 1..=64, got 0"),
        ({"gravity": (0, 0, INF)}, "settings.gravity: must be finite"),
        ({"contact_margin": -1.0}, "settings.contact_margin: must be finite and >= 0, got -1"),
        (
            {"mesh_contact_margin": -1.0},
            "settings.mesh_contact_margin: must be finite and >= 0, got -1",
        ),
        ({"integrator": "leapfrog"}, "integrator: expected one of"),
        ({"solver": "magic"}, 'solver: expected "pgs" or "lemke", got "magic"'),
        ({"substeps": -1}, "substeps: expected a non-negative integer"),
        ({"dt": "fast"}, "dt: expected a number"),
        ({"gravity": (0, 0)}, "gravity: expected 3 numbers (x, y, z)"),
        ({"gravtiy": (0, 0, -1)}, 'unknown world setting "gravtiy"'),
    ],
)
def test_bad_settings(kwargs: dict, message: str) -> None:
    with pytest.raises(tumble.InvalidArgument) as info:
        tumble.World(**kwargs)
    assert message in str(info.value)


def test_settings_round_trip_and_update_is_atomic() -> None:
    world = tumble.World(dt=1 / 120, integrator="rk4", solver="lemke", sleeping=False)
    s = world.settings
    assert s["dt"] == 1 / 120 and s["integrator"] == "rk4" and s["solver"] == "lemke"
    assert s["sleeping"] is False and list(s["gravity"]) == [0, 0, -9.81]
    with pytest.raises(tumble.InvalidArgument):
        world.update_settings(dt=1 / 30, iterations=0)
    assert world.settings["dt"] == 1 / 120
    world.update_settings(dt=1 / 30)
    assert world.dt == 1 / 30
    for name in tumble.INTEGRATORS:
        assert tumble.World(integrator=name).settings["integrator"] == name


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"mass": -1.0}, "mass.mass: must be finite and > 0 kg, got -1"),
        ({"mass": NAN}, "mass.mass: must be finite and > 0 kg, got NaN"),
        ({"density": 0.0}, "mass.density: must be finite and > 0 kg/m^3, got 0"),
        ({"mass": 1.0, "density": 1.0}, "give mass or density, not both"),
        ({"position": (0, NAN, 0)}, "pose"),
        ({"position": (0, 0)}, "position: expected 3 numbers (x, y, z), got tuple (0, 0)"),
        ({"position": "abc"}, "position: expected 3 numbers"),
        ({"orientation": (0, 0, 0, 2)}, "pose"),
        ({"orientation": (0, 0, 1)}, "orientation: expected a quaternion of 4 numbers"),
        ({"velocity": (INF, 0, 0)}, "body.linear_velocity: must be finite"),
        ({"angular_velocity": (0, 0, NAN)}, "body.angular_velocity: must be finite"),
        ({"restitution": 1.5}, "restitution"),
        ({"friction": -0.1}, "friction"),
        ({"kind": "ghost"}, 'kind: expected "dynamic", "static" or "kinematic", got "ghost"'),
        ({"kind": "static", "mass": 1.0}, "mass and density apply to dynamic bodies only"),
        ({"linear_damping": -1.0}, "damping"),
    ],
)
def test_bad_body_arguments_leave_the_world_unchanged(kwargs: dict, message: str) -> None:
    world, _ = world_with_ball()
    before = world.positions
    with pytest.raises(tumble.InvalidArgument) as info:
        world.add_body(tumble.Box((0.1, 0.1, 0.1)), **kwargs)
    assert message in str(info.value)
    assert len(world) == 2
    assert np.array_equal(world.positions, before)
    world.step()  # still usable


@pytest.mark.parametrize(
    "make, message",
    [
        (lambda: tumble.Sphere(-1.0), "sphere: radius must be finite and > 0, got -1"),
        (lambda: tumble.Sphere(NAN), "sphere: radius must be finite and > 0, got NaN"),
        (lambda: tumble.Sphere(1e37), "sphere: radius must be finite and <= 1e36"),
        (lambda: tumble.Box((1, 1e300, 1)), "must be finite and <= 1e36"),
        (lambda: tumble.Box((1, 0, 1)), "must be finite and > 0"),
        (lambda: tumble.Box((1, INF, 1)), "must be finite and > 0"),
        (lambda: tumble.Capsule(0.1, -1.0), "capsule"),
        (lambda: tumble.HalfSpace((0, 0, 0)), "normal must be a finite unit vector"),
        (lambda: tumble.ConvexHull(np.zeros((4, 3))), "convex hull"),
        (lambda: tumble.ConvexHull(np.zeros((4, 2))), "points: expected an (N, 3) array"),
        (lambda: tumble.TriMesh.torus(1.0, -0.2), "torus: minor radius r must be finite and > 0"),
        (lambda: tumble.TriMesh.sphere(1.0, 20), "icosphere"),
    ],
)
def test_bad_shapes(make, message: str) -> None:
    with pytest.raises(tumble.InvalidArgument) as info:
        make()
    assert message in str(info.value)


@pytest.mark.parametrize(
    "vertices, faces, message",
    [
        (
            np.zeros((4, 2)),
            [[0, 1, 2]],
            "vertices: expected an (N, 3) array of float numbers, "
            "got shape [4, 2] and dtype float64",
        ),
        (np.zeros(12), [[0, 1, 2]], "vertices: expected an (N, 3) array"),
        (np.array([["a", "b", "c"]] * 3), [[0, 1, 2]], "dtype <U1"),
        (
            np.eye(3),
            np.array([[0.0, 1.0, 2.0]]),
            "faces: expected an (M, 3) array of integer vertex indices, got shape [1, 3] and dtype "
            "float64",
        ),
        (np.eye(3), np.array([[0, 1]]), "faces: expected an (M, 3) array"),
        (np.eye(3), [[0, 1, 3]], "mesh triangle 0 refers to vertex 3, but there are only 3"),
        (np.eye(3), [[0, -1, 2]], "faces: triangle 0 has a negative vertex index -1"),
        (np.array([[0, 0, 0], [1, 0, NAN], [0, 1, 0]]), [[0, 1, 2]], "mesh vertex 1 is not finite"),
        (np.zeros((0, 3)), np.zeros((0, 3), dtype=int), "mesh is empty"),
        ("not an array", [[0, 1, 2]], "vertices: expected an (N, 3) array"),
    ],
)
def test_bad_mesh_arrays(vertices, faces, message: str) -> None:
    with pytest.raises(tumble.InvalidArgument) as info:
        tumble.TriMesh(vertices, faces)
    assert message in str(info.value)


def test_open_mesh_with_density_is_refused() -> None:
    box = tumble.TriMesh.box((0.5, 0.5, 0.5))
    open_box = tumble.TriMesh(box.vertices, box.faces[:10])
    assert not open_box.is_closed and not open_box.is_solid
    world = tumble.World()
    with pytest.raises(tumble.InvalidArgument) as info:
        world.add_body(open_box, density=1000.0)
    assert "mesh is open" in str(info.value)
    with pytest.raises(tumble.InvalidArgument) as info:
        tumble.mass_properties(open_box, density=1000.0)
    assert "not a closed, consistently outward-wound solid" in str(info.value)
    assert len(world) == 0
    # An open mesh is fine for a static body (no mass needed).
    world.add_body(open_box, kind="static")


def test_stale_handles_raise_and_do_not_alias_reused_slots() -> None:
    world, ball = world_with_ball()
    ball.remove()
    assert not ball.is_alive
    other = world.add_body(tumble.Sphere(0.2), mass=2.0, position=(5, 0, 1))  # reuses the slot
    for action in [
        lambda: ball.position,
        lambda: ball.velocity,
        lambda: ball.apply_force((1, 0, 0)),
        lambda: ball.remove(),
        lambda: world.remove_body(ball),
        lambda: world.apply_force(ball, (1, 0, 0)),
        lambda: setattr(ball, "position", (0, 0, 0)),
    ]:
        with pytest.raises(tumble.StaleBodyError) as info:
            action()
        assert "does not exist" in str(info.value)
    assert other.position[0] == 5.0
    assert ball != other
    assert "removed" in repr(ball)


def test_handles_of_another_world_are_refused() -> None:
    w1, b1 = world_with_ball()
    w2, _ = world_with_ball()
    with pytest.raises(tumble.InvalidArgument) as info:
        w2.apply_force(b1, (1, 0, 0))
    assert "belongs to another world" in str(info.value)


def test_wrong_kind_operations() -> None:
    world, _ = world_with_ball()
    ground = world.bodies[0]
    with pytest.raises(tumble.InvalidArgument) as info:
        ground.apply_force((1, 0, 0))
    assert "forces and impulses act on dynamic bodies only" in str(info.value)
    with pytest.raises(tumble.InvalidArgument) as info:
        ground.velocity = (1, 0, 0)
    assert "a static body has no velocity" in str(info.value)
    with pytest.raises(tumble.InvalidArgument) as info:
        world.add_body(tumble.HalfSpace(), mass=1.0)
    assert "half-space" in str(info.value)


def test_non_finite_forces_are_refused_and_the_state_survives() -> None:
    world, ball = world_with_ball()
    for bad in [(NAN, 0, 0), (0, INF, 0)]:
        with pytest.raises(tumble.InvalidArgument):
            ball.apply_force(bad)
        with pytest.raises(tumble.InvalidArgument):
            ball.apply_impulse(bad)
        with pytest.raises(tumble.InvalidArgument):
            ball.velocity = bad
    with pytest.raises(tumble.InvalidArgument):
        world.apply_forces(np.full((2, 3), NAN))
    with pytest.raises(tumble.InvalidArgument) as info:
        world.apply_forces(np.zeros((3, 3)))
    assert "expected one row per body (2 rows), got 3" in str(info.value)
    world.step(10)
    assert np.isfinite(world.positions).all()


def test_bad_shape_objects() -> None:
    world = tumble.World()
    for bad, message in [
        (42, "shape: expected a tumble shape"),
        ([tumble.Sphere(1.0), "x"], "shapes[1]: expected a tumble shape"),
    ]:
        with pytest.raises(tumble.InvalidArgument) as info:
            world.add_body(bad)
        assert message in str(info.value)


def test_files(tmp_path) -> None:
    with pytest.raises(tumble.FileError) as info:
        tumble.TriMesh.from_file(tmp_path / "missing.obj")
    assert "missing.obj: cannot read" in str(info.value)
    assert isinstance(info.value, OSError)
    (tmp_path / "mesh.xyz").write_text("v 0 0 0\n")
    with pytest.raises(tumble.InvalidArgument) as info:
        tumble.TriMesh.from_file(tmp_path / "mesh.xyz")
    assert "unknown mesh format" in str(info.value)
    world, _ = world_with_ball()
    with pytest.raises(tumble.FileError):
        world.export_gltf(tmp_path / "no" / "such" / "dir" / "out.glb")


def test_a_panic_arrives_as_internal_error() -> None:
    from tumble import _tumble

    for _ in range(2):  # and the process, and the module, go on working
        with pytest.raises(tumble.InternalError) as info:
            _tumble._panic_for_tests("boom")
        assert str(info.value) == "internal error in tumble: boom"
    world, _ = world_with_ball()
    world.step()


def test_step_warnings_arrive_as_runtime_warnings() -> None:
    world, _ = world_with_ball()
    world.add_body(tumble.Box((0.5, 0.5, 0.5)), velocity=(1e300, 0, 1e300))
    # 1e300 m/s: the contact margin overflows, and the body is a runaway
    # (faster than tumble's RUNAWAY_SPEED): stopped and reported.
    with pytest.warns(RuntimeWarning) as record:
        world.step(3)
    messages = [str(w.message) for w in record]
    assert any("tumble step: bodies 0 and 2: contact margin" in m for m in messages), messages
    assert any("runaway state; it was restored and stopped" in m for m in messages), messages
    assert any("contact margin" in w for w in world.step_report.warnings)
    assert world.step_report.steps == 3


@pytest.mark.filterwarnings("ignore::RuntimeWarning")
def test_nasty_numbers_never_crash() -> None:
    # Every combination either works or raises TumbleError; none panics, none
    # leaves a non-finite state behind.
    values = [0.0, -1.0, 1e-300, 1e300, NAN, INF, -INF, 5e-324]
    for v in values:
        for kw in ["mass", "density", "friction", "restitution", "linear_damping"]:
            world, _ = world_with_ball()
            try:
                world.add_body(tumble.Sphere(0.5), **{kw: v})
            except tumble.TumbleError:
                continue
            world.step(3)
            assert np.isfinite(world.positions).all()
        for kw in ["position", "velocity", "angular_velocity"]:
            world, _ = world_with_ball()
            try:
                world.add_body(tumble.Box((0.5, 0.5, 0.5)), **{kw: (v, 0, v)})
            except tumble.TumbleError:
                continue
            world.step(3)
            assert np.isfinite(world.positions).all()
