"""URDF robots through Python: the shipped arm reaches a target under PD
motors set through ``Joint.motor``, the robot's bodies join the world's
arrays, and bad files are refused with file, line and element."""

from __future__ import annotations

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
