"""URDF robots through Python: the shipped arm reaches a target under PD
motors set through ``Joint.motor``, the robot's bodies join the world's
arrays, and bad files are refused with file, line and element."""

from __future__ import annotations

import pickle
from pathlib import Path

import numpy as np
import pytest

import tumble

ROBOTS = Path(__file__).resolve().parents[3] / "examples" / "robots"


def test_the_arm_reaches_its_targets_under_pd_motors() -> None:
    world = tumble.World(sleeping=False)
    world.add_body(tumble.HalfSpace(), kind="static")
    arm = tumble.load_urdf(ROBOTS / "arm6.urdf", world=world, fixed_base=True)
    assert arm.world is world and arm.root == "base"
    assert sorted(arm.joints) == sorted(
        ["shoulder_pan", "shoulder_lift", "elbow", "wrist_roll", "wrist_pitch", "wrist_yaw"]
    )
    # Seven bodies (the tool tip is merged into the tool) after the ground.
    assert world.positions.shape == (8, 3)
    assert arm.links["tool_tip"] == arm.links["tool"]
    targets = {"shoulder_pan": 0.5, "shoulder_lift": 0.6, "elbow": 0.8}
    for name, joint in arm.joints.items():
        joint.motor = {
            "target_position": targets.get(name, 0.0),
            "stiffness": 4000.0,
            "damping": 200.0,
            "max_force": arm.efforts[name],
        }
    assert arm.joints["elbow"].motor["target_position"] == 0.8
    world.step(180)
    for name, target in targets.items():
        assert arm.joints[name].position == pytest.approx(target, abs=0.01)
    assert max(world.joint_states()["linear_error"]) < 1e-3
    arm.joints["elbow"].motor = None
    assert arm.joints["elbow"].motor is None


def test_a_robot_in_a_new_world_and_a_moved_base() -> None:
    dog = tumble.load_urdf(ROBOTS / "quadruped.urdf", position=(1.0, 2.0, 0.5))
    assert len(dog.joints) == 12
    torso = dog.links["torso"]
    np.testing.assert_allclose(torso.position, (1.0, 2.0, 0.5), atol=1e-12)
    assert len(dog.world.joints()) == 12


def test_bad_files_are_located_and_leave_the_world_unchanged(tmp_path: Path) -> None:
    bad = tmp_path / "bad.urdf"
    box = '<geometry><box size="0.1 0.1 0.1"/></geometry>'
    ball = '<geometry><sphere radius="0.05"/></geometry>'
    bad.write_text(
        '<robot name="r">\n'
        f'  <link name="a"><collision>{box}</collision></link>\n'
        f'  <link name="b"><collision>{ball}</collision></link>\n'
        '  <joint name="j" type="revolute">\n'
        '    <parent link="a"/><child link="c"/>\n'
        "  </joint>\n"
        "</robot>\n"
    )
    world = tumble.World()
    located = r"bad\.urdf:5:23: <child>: no link is named `c`"
    with pytest.raises(tumble.InvalidArgument, match=located):
        tumble.load_urdf(bad, world=world)
    assert len(world.bodies) == 0
    with pytest.raises(tumble.FileError):
        tumble.load_urdf(tmp_path / "missing.urdf")


def _hanging_pair(tmp_path: Path, c_at: str) -> Path:
    """Link c hangs from b, which turns on a: no joint links a and c. With
    c at "0 0 -0.5" c's ball lies inside a's box; at "0.5 0 0" it starts
    beside the box and swings down into it."""
    box = '<geometry><box size="0.4 0.4 0.4"/></geometry>'
    urdf = tmp_path / f"hanging{len(c_at)}.urdf"
    urdf.write_text(
        '<robot name="r">\n'
        f'  <link name="a"><collision>{box}</collision></link>\n'
        '  <link name="b"><collision><origin xyz="0 0 0.5"/>'
        '<geometry><sphere radius="0.05"/></geometry></collision></link>\n'
        f'  <link name="c"><collision><origin xyz="{c_at}"/>'
        '<geometry><sphere radius="0.1"/></geometry></collision></link>\n'
        '  <joint name="j1" type="continuous"><parent link="a"/><child link="b"/></joint>\n'
        '  <joint name="j2" type="continuous"><parent link="b"/><child link="c"/>'
        '<origin xyz="0 0 0.5"/><axis xyz="0 1 0"/></joint>\n'
        "</robot>\n"
    )
    return urdf


def _a_and_c_touch(robot: tumble.Robot) -> bool:
    a, c = robot.links["a"].index, robot.links["c"].index
    contacts = robot.world.contacts()
    pairs = set(zip(contacts["body_a"].tolist(), contacts["body_b"].tolist(), strict=True))
    return (a, c) in pairs or (c, a) in pairs


def test_links_touch_each_other_only_with_self_collision(tmp_path: Path) -> None:
    # Without self-collision (the default, as in PyBullet) c swings down
    # through a; with it, c strikes a.
    urdf = _hanging_pair(tmp_path, "0.5 0 0")
    for self_collision in (False, True):
        robot = tumble.load_urdf(
            urdf, position=(0.0, 0.0, 1.0), fixed_base=True, self_collision=self_collision
        )
        assert robot.no_contact == []
        touched = False
        for _ in range(120):
            robot.world.step()
            touched |= _a_and_c_touch(robot)
        assert touched == self_collision


def test_links_overlapping_in_the_files_pose_never_touch(tmp_path: Path) -> None:
    # Their contacts would fight the joints: with self-collision they are
    # kept apart (Robot.no_contact), until asked otherwise.
    robot = tumble.load_urdf(
        _hanging_pair(tmp_path, "0 0 -0.5"),
        position=(0.0, 0.0, 1.0),
        fixed_base=True,
        self_collision=True,
    )
    a, b, c = (robot.links[name] for name in "abc")
    assert robot.no_contact == [(a, c)]
    world = robot.world
    assert world.excluded_contact_pairs() == [(a, c)]
    assert not world.contacts_allowed(a, c)
    assert not world.contacts_allowed(a, b), "jointed"
    for _ in range(60):
        world.step()
        assert not _a_and_c_touch(robot)
    world.set_contacts_between(c, a, True)
    assert world.contacts_allowed(a, c)
    assert world.excluded_contact_pairs() == []
    world.step()
    assert _a_and_c_touch(robot)
    # Kept apart again, through a pickle too.
    world.set_contacts_between(a, c, False)
    restored = pickle.loads(pickle.dumps(world))
    assert not restored.contacts_allowed(restored.bodies[a.index], restored.bodies[c.index])
    with pytest.raises(tumble.InvalidArgument, match="body_b"):
        world.set_contacts_between(a, a, False)
    world.remove_body(b)
    with pytest.raises(tumble.StaleBodyError):
        world.set_contacts_between(a, b, False)


def test_bodies_of_one_non_colliding_group_pass_through_each_other() -> None:
    world = tumble.World()
    slab = world.add_body(tumble.Box((1.0, 1.0, 0.1)), kind="static", non_colliding_group=2)
    ball = world.add_body(tumble.Sphere(0.1), position=(0, 0, 0.5), non_colliding_group=2)
    for _ in range(60):
        world.step()
    assert ball.position[2] < 0.0, "fell through the slab of its own group"
    assert slab.position[2] == 0.0


def test_an_impossible_inertia_is_refused_or_balanced_on_request(tmp_path: Path) -> None:
    urdf = tmp_path / "disc.urdf"
    urdf.write_text(
        '<robot name="r"><link name="a">'
        '<inertial><mass value="2"/><inertia ixx="0" iyy="0" izz="1.5"/></inertial>'
        '<collision><geometry><sphere radius="0.1"/></geometry></collision>'
        "</link></robot>\n"
    )
    with pytest.raises(tumble.InvalidArgument, match="balance_inertia"):
        tumble.load_urdf(urdf)
    robot = tumble.load_urdf(urdf, balance_inertia=True)
    assert any("balance_inertia" in w for w in robot.warnings)
    assert robot.links["a"].mass == 2.0


def _ring(tmp_path: Path) -> Path:
    """A URDF ring: a torus mesh (major radius 0.3 m, tube 0.08 m) lying
    flat, as an OBJ file beside it."""
    n, m = 32, 16
    u = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)[:, None]
    v = np.linspace(0.0, 2.0 * np.pi, m, endpoint=False)[None, :]
    rho = 0.3 + 0.08 * np.cos(v)
    z = np.broadcast_to(0.08 * np.sin(v), (n, m))
    vertices = np.stack([rho * np.cos(u), rho * np.sin(u), z], axis=-1).reshape(-1, 3)
    lines = [f"v {x:.17g} {y:.17g} {z:.17g}" for x, y, z in vertices]
    for i in range(n):
        for j in range(m):
            a, b = i * m + j + 1, (i + 1) % n * m + j + 1
            c, d = (i + 1) % n * m + (j + 1) % m + 1, i * m + (j + 1) % m + 1
            lines += [f"f {a} {b} {c}", f"f {a} {c} {d}"]
    (tmp_path / "ring.obj").write_text("\n".join(lines) + "\n")
    urdf = tmp_path / "ring.urdf"
    urdf.write_text(
        '<robot name="ring"><link name="ring"><collision><geometry>'
        '<mesh filename="ring.obj"/></geometry></collision></link></robot>\n'
    )
    return urdf


def test_mesh_links_are_exact_or_their_convex_hulls_on_request(tmp_path: Path) -> None:
    # A ball dropped onto the ring's middle falls through its hole onto the
    # ground, or rests on the lid its convex hull puts over the hole.
    urdf = _ring(tmp_path)
    for convex_meshes, rest in ((False, 0.1), (True, 0.5 + 0.08 + 0.1)):
        world = tumble.World(sleeping=False)
        world.add_body(tumble.HalfSpace(), kind="static")
        tumble.load_urdf(
            urdf,
            world=world,
            position=(0.0, 0.0, 0.5),
            fixed_base=True,
            convex_meshes=convex_meshes,
        )
        ball = world.add_body(tumble.Sphere(0.1), position=(0.0, 0.0, 1.0))
        world.step(150)
        assert ball.position[2] == pytest.approx(rest, abs=2e-3), convex_meshes
