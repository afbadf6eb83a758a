"""The numpy side: array shapes, dtypes and row order; what array-likes are
accepted where; the contacts structured array."""

from __future__ import annotations

import numpy as np
import pytest

import tumble


def small_world() -> tuple[tumble.World, list[tumble.Body]]:
    world = tumble.World(sleeping=False)
    bodies = [world.add_body(tumble.HalfSpace(), kind="static", name="ground")]
    for i in range(4):
        bodies.append(
            world.add_body(
                tumble.Sphere(0.1),
                mass=1.0,
                position=(i, 0, 0.1 + 0.5 * i),
                velocity=(0, i, 0),
                angular_velocity=(i, 0, 0),
                name=f"ball{i}",
            )
        )
    return world, bodies


def test_state_arrays_have_one_row_per_body_in_insertion_order() -> None:
    world, bodies = small_world()
    for name, cols in [
        ("positions", 3),
        ("orientations", 4),
        ("velocities", 3),
        ("angular_velocities", 3),
        ("centers_of_mass", 3),
    ]:
        a = getattr(world, name)
        assert a.shape == (5, cols) and a.dtype == np.float64, name
        assert a.flags.c_contiguous and a.flags.writeable
    np.testing.assert_array_equal(world.positions[:, 0], [0, 0, 1, 2, 3])
    np.testing.assert_array_equal(world.orientations[:, 3], 1.0)
    np.testing.assert_array_equal(world.velocities[:, 1], [0, 0, 1, 2, 3])
    np.testing.assert_array_equal(world.angular_velocities[:, 0], [0, 0, 1, 2, 3])
    poses = world.poses()
    assert poses.shape == (5, 7)
    np.testing.assert_array_equal(poses[:, :3], world.positions)
    np.testing.assert_array_equal(poses[:, 3:], world.orientations)
    for row, body in enumerate(bodies):
        assert body.index == row
        np.testing.assert_array_equal(body.position, world.positions[row])
    assert world.bodies == bodies


def test_rows_follow_insertion_order_after_removal_and_slot_reuse() -> None:
    world, bodies = small_world()
    bodies[2].remove()
    newcomer = world.add_body(tumble.Box((0.1, 0.1, 0.1)), position=(9, 9, 9))  # reuses slot 2
    assert len(world) == 5
    np.testing.assert_array_equal(world.positions[:, 0], [0, 0, 2, 3, 9])
    assert newcomer.index == 4 and bodies[3].index == 2
    assert world.bodies == [bodies[0], bodies[1], bodies[3], bodies[4], newcomer]
    assert world.find("ball3") == bodies[4]
    assert world.find("nobody") is None


def test_arrays_are_copies() -> None:
    world, _ = small_world()
    p = world.positions
    p[:] = 0
    assert world.positions[4, 0] == 3


@pytest.mark.parametrize(
    "value",
    [
        (1, 2, 3),
        [1, 2, 3],
        np.array([1, 2, 3]),
        np.array([1, 2, 3], dtype=np.float32),
        np.array([1, 2, 3], dtype=np.int32),
        (np.float64(1), 2.0, np.int64(3)),
    ],
)
def test_vectors_accept_any_real_sequence(value) -> None:
    world = tumble.World()
    body = world.add_body(tumble.Sphere(0.1), position=value)
    np.testing.assert_array_equal(body.position, [1, 2, 3])


@pytest.mark.parametrize(
    "value",
    [
        np.array([[1, 2, 3]]),
        np.array([1 + 0j, 2, 3]),
        np.array([True, False, True]),
        (1, 2, 3, 4),
        5.0,
        {"x": 1},
    ],
)
def test_vectors_reject_other_shapes_and_dtypes(value) -> None:
    world = tumble.World()
    with pytest.raises(tumble.InvalidArgument) as info:
        world.add_body(tumble.Sphere(0.1), position=value)
    assert "position: expected 3 numbers (x, y, z)" in str(info.value)


@pytest.mark.parametrize("vdtype", [np.float32, np.float64, np.int64])
@pytest.mark.parametrize("fdtype", [np.int32, np.int64, np.uint32, np.uint64])
def test_mesh_arrays_accept_real_vertices_and_integer_faces(vdtype, fdtype) -> None:
    ref = tumble.TriMesh.box((1, 1, 1))
    mesh = tumble.TriMesh(ref.vertices.astype(vdtype), ref.faces.astype(fdtype))
    np.testing.assert_array_equal(mesh.vertices, ref.vertices)
    np.testing.assert_array_equal(mesh.faces, ref.faces)
    assert mesh.vertices.dtype == np.float64 and mesh.faces.dtype == np.int64


def test_mesh_arrays_accept_lists_and_strided_views() -> None:
    ref = tumble.TriMesh.box((1, 2, 3))
    from_lists = tumble.TriMesh(ref.vertices.tolist(), ref.faces.tolist())
    assert from_lists.volume == pytest.approx(48.0)
    wide = np.zeros((ref.vertex_count, 6))
    wide[:, ::2] = ref.vertices  # a non-contiguous (N, 3) view
    strided = tumble.TriMesh(wide[:, ::2], np.asfortranarray(ref.faces))
    np.testing.assert_array_equal(strided.vertices, ref.vertices)


def test_contacts_structured_array() -> None:
    world = tumble.World(sleeping=False)
    world.add_body(tumble.HalfSpace(), kind="static")
    box = world.add_body(tumble.Box((0.5, 0.5, 0.5)), mass=8.0, position=(0, 0, 0.5))
    world.step(30)
    c = world.contacts()
    assert c.dtype == tumble.CONTACT_DTYPE
    assert c.dtype.names == (
        "body_a",
        "body_b",
        "point",
        "normal",
        "distance",
        "depth",
        "normal_impulse",
        "tangent_impulse",
        "kind",
    )
    assert len(c) == 4  # the four bottom corners of the box on the plane
    assert set(c["body_a"]) | set(c["body_b"]) == {0, box.index}
    # The normal points from B towards A; the box is above the ground.
    sign = np.where(c["body_a"] == box.index, 1.0, -1.0)
    np.testing.assert_allclose(c["normal"] * sign[:, None], [[0, 0, 1]] * 4, atol=1e-12)
    np.testing.assert_allclose(c["point"][:, 2], 0.0, atol=2e-3)
    np.testing.assert_array_equal(c["depth"], -c["distance"])
    # Resting: the normal impulses of one step carry the weight, m g dt.
    assert c["normal_impulse"].sum() == pytest.approx(8.0 * 9.81 * world.dt, rel=1e-3)
    assert c["point"].shape == (4, 3)
    assert world.step_report.contacts == 4


def test_contact_kinds_keep_their_whole_names() -> None:
    # The longest kind, "vertex_vertex", once lost its last letter to a
    # 12-character field. Two mesh cubes corner to corner, 1 mm apart along
    # each axis (1.7 mm: within the 2 mm mesh contact margin), in zero
    # gravity: the step's one contact is that corner pair.
    world = tumble.World(gravity=(0, 0, 0), sleeping=False)
    cube = tumble.TriMesh.box((0.5, 0.5, 0.5))
    world.add_body(cube, kind="static")
    world.add_body(cube, mass=1.0, position=(1.001, 1.001, 1.001))
    world.step()
    kinds = set(world.contacts()["kind"])
    assert kinds == {"vertex_vertex"}, kinds
    query = tumble.collide(
        cube, None, cube, ((1.001,) * 3, (0, 0, 0, 1)), report="contacts", contact_margin=0.01
    )
    assert set(query.contacts["kind"]) == {"vertex_vertex"}


def test_empty_world_arrays() -> None:
    world = tumble.World()
    assert world.positions.shape == (0, 3)
    assert world.orientations.shape == (0, 4)
    assert world.contacts().shape == (0,)
    assert world.contact_events() == []
    world.step(3)
    assert world.step_report.steps == 3


def test_step_releases_the_gil() -> None:
    # Another Python thread runs while a long step(n) is in Rust.
    import threading
    import time

    world = tumble.World(sleeping=False)
    world.add_body(tumble.HalfSpace(), kind="static")
    for i in range(200):
        world.add_body(tumble.Box((0.1, 0.1, 0.1)), position=(0.25 * (i % 10), 0.25 * (i // 10), 1))
    ticks = 0
    stop = threading.Event()

    def count() -> None:
        nonlocal ticks
        while not stop.is_set():
            ticks += 1
            time.sleep(0)

    t = threading.Thread(target=count)
    t.start()
    world.step(60)
    stop.set()
    t.join()
    assert ticks > 0
    assert world.step_count == 60


def test_ctrl_c_stops_a_long_step_between_two_steps() -> None:
    import _thread
    import signal
    import threading

    world = tumble.World(sleeping=False)
    world.add_body(tumble.HalfSpace(), kind="static")
    for i in range(100):
        world.add_body(tumble.Box((0.1, 0.1, 0.1)), position=(0.25 * (i % 10), 0.25 * (i // 10), 1))
    # Ctrl-C as interrupt_main() from a timer thread. That only reaches the
    # main thread when Python handles SIGINT: a process started in the
    # background by a non-interactive shell inherits SIGINT ignored, and
    # Python then leaves it ignored (interrupt_main() does nothing). The test
    # installs Python's handler itself, and the step count is finite (a few
    # seconds of work), so a step that ignored Ctrl-C fails the test instead
    # of hanging the suite.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    n = 100_000
    timer = threading.Timer(0.3, _thread.interrupt_main)
    try:
        timer.start()
        with pytest.raises(KeyboardInterrupt):
            world.step(n)
    finally:
        timer.cancel()
        timer.join()
        signal.signal(signal.SIGINT, previous)
    steps = world.step_count
    assert 0 < steps < n
    assert world.time == pytest.approx(steps * world.dt)
    world.step(2)  # whole steps only: the world goes on
    assert world.step_count == steps + 2


def test_repr_and_docs() -> None:
    world, bodies = small_world()
    assert repr(world).startswith("tumble.World(bodies=5")
    assert repr(bodies[0]) == 'tumble.Body(index=0, kind="static", name="ground")'
    assert repr(tumble.Sphere(0.5)) == "tumble.Sphere(radius=0.5)"
    assert repr(tumble.Box((1, 2, 3))) == "tumble.Box(half_extents=(1, 2, 3))"
    assert "Capsule(radius=0.1, half_height=0.2)" in repr(tumble.Capsule(0.1, 0.2))
    assert repr(tumble.HalfSpace()) == "tumble.HalfSpace(normal=(0, 0, 1), offset=0)"
    assert repr(tumble.TriMesh.box((1, 1, 1))) == "tumble.TriMesh(<8 vertices, 12 faces>)"
    assert "StepReport(" in repr(world.step_report)
    for obj in [
        tumble.World,
        tumble.World.add_body,
        tumble.World.step,
        tumble.World.positions,
        tumble.World.contacts,
        tumble.Body,
        tumble.Body.position,
        tumble.Box,
        tumble.TriMesh,
        tumble.TriMesh.torus,
        tumble.mass_properties,
        tumble.Placed,
        tumble.MassProperties,
        tumble.ContactEvent,
        tumble.StepReport,
    ]:
        assert obj.__doc__ and len(obj.__doc__) > 20, obj
