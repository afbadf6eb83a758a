"""Joints through the Python API: the same physics as the Rust tests (a
pendulum's exact period, a motor's speed, limits, a rope's length), the
arrays and handles, pickling, and bad arguments refused with the world
unchanged."""

from __future__ import annotations

import math
import pickle

import numpy as np
import pytest

import tumble

G = 9.81


def pendulum(**joint) -> tuple[tumble.World, tumble.Body, tumble.Joint]:
    world = tumble.World(sleeping=False, threads=1)
    bob = world.add_body(tumble.Box((0.05, 0.05, 0.05)), mass=1.0, position=(0.5, 0, 0))
    hinge = world.add_joint("hinge", bob, None, anchor=(0, 0, 0), axis=(0, 1, 0), **joint)
    return world, bob, hinge


def test_a_hinge_pendulum_has_the_exact_period() -> None:
    # Released horizontal (90 degrees): T = 4 sqrt(I / (m g d)) K(sin^2(pi/4)).
    world, bob, hinge = pendulum()
    crossings = []
    last = bob.position[0]
    for _ in range(600):
        world.step()
        x = bob.position[0]
        if last > 0 >= x or last < 0 <= x:
            crossings.append(world.time)
        last = x
    period = 2 * (crossings[-1] - crossings[0]) / (len(crossings) - 1)
    i_pivot = (0.1**2 * 2) / 12 + 0.25
    m = math.sin(math.pi / 4) ** 2
    # K(m) by the arithmetic-geometric mean.
    a, b = 1.0, math.sqrt(1 - m)
    for _ in range(30):
        a, b = (a + b) / 2, math.sqrt(a * b)
    exact = 4 * math.sqrt(i_pivot / (G * 0.5)) * math.pi / (2 * a)
    assert period == pytest.approx(exact, rel=0.01)
    assert hinge.linear_error < 1e-4


def test_a_velocity_motor_turns_at_its_target_and_reports_its_torque() -> None:
    world, bob, hinge = pendulum(motor={"target_velocity": -0.5, "max_force": 20.0})
    world.step(60)
    assert hinge.rate == pytest.approx(-0.5, abs=1e-3)
    # Holding the arm against gravity: the torque about the axis is m g d cos(angle).
    about_axis = float(np.dot(hinge.torque, (0, 1, 0)))
    assert abs(about_axis) == pytest.approx(G * 0.5 * math.cos(hinge.position), rel=0.1)


def test_a_hinge_spring_rings_at_its_natural_period_beside_nothing_else() -> None:
    # Zero gravity, a spring of k N m/rad on the hinge: I theta'' = -k theta,
    # T = 2 pi sqrt(I / k); kicked at 1 rad/s, it swings 1 / w either way.
    k = 2.5
    world = tumble.World(gravity=(0, 0, 0), sleeping=False, threads=1)
    bob = world.add_body(
        tumble.Box((0.05, 0.05, 0.05)),
        mass=1.0,
        position=(0.5, 0, 0),
        velocity=(0, 0.5, 0),
        angular_velocity=(0, 0, 1),
    )
    spring = {"stiffness": k, "damping": 0.0}
    hinge = world.add_joint("hinge", bob, None, anchor=(0, 0, 0), axis=(0, 0, 1), spring=spring)
    i_pivot = (0.1**2 * 2) / 12 + 0.25
    w = math.sqrt(k / i_pivot)
    angles = []
    for _ in range(600):
        world.step()
        angles.append(hinge.position)
    crossings = [
        (k + 1) / 60 for k in range(len(angles) - 1) if (angles[k] > 0) != (angles[k + 1] > 0)
    ]
    period = 2 * (crossings[-1] - crossings[0]) / (len(crossings) - 1)
    assert period == pytest.approx(2 * math.pi / w, rel=0.01)
    # Its first swing and its last (after five periods) both 1 / w: no energy lost.
    first, last = max(map(abs, angles[:120])), max(map(abs, angles[-120:]))
    assert first == pytest.approx(1 / w, rel=0.01)
    assert last == pytest.approx(first, rel=1e-3)


def test_a_ball_spring_turns_a_cube_back_at_its_natural_period_about_any_axis() -> None:
    # Zero gravity, a 1 kg cube (I = 1/600 kg m^2 about any axis through its
    # centre) on a ball joint at its centre with a spring of k N m/rad,
    # kicked at 1 rad/s about a slanted axis u: I theta'' = -k theta about u,
    # T = 2 pi sqrt(I / k), swinging 1 / w either way, never off u.
    k, i = 0.1, 1 / 600
    u = np.array([1.0, 2.0, -0.5]) / np.linalg.norm([1.0, 2.0, -0.5])
    world = tumble.World(gravity=(0, 0, 0), sleeping=False, threads=1)
    cube = world.add_body(tumble.Box((0.05, 0.05, 0.05)), mass=1.0, angular_velocity=tuple(u))
    ball = world.add_joint("ball", cube, None, anchor=(0, 0, 0), spring=(k, 0.0))
    assert ball.spring == {"stiffness": k, "damping": 0.0}
    turns = []
    for _ in range(240):
        world.step()
        x, y, z, w = cube.orientation
        angle = 2 * math.atan2(math.sqrt(x * x + y * y + z * z), w)
        axis = np.array([x, y, z]) / max(math.sqrt(x * x + y * y + z * z), 1e-300)
        turn = angle * axis
        assert np.linalg.norm(turn - np.dot(turn, u) * u) < 1e-9
        turns.append(float(np.dot(turn, u)))
    w_n = math.sqrt(k / i)
    crossings = [
        (n + 1) / 60 for n in range(len(turns) - 1) if (turns[n] > 0) != (turns[n + 1] > 0)
    ]
    period = 2 * (crossings[-1] - crossings[0]) / (len(crossings) - 1)
    assert period == pytest.approx(2 * math.pi / w_n, rel=0.005)
    assert max(map(abs, turns)) == pytest.approx(1 / w_n, rel=2e-3)


def test_a_ball_motor_spins_a_cube_up_at_its_torque_and_turns_it_to_a_target() -> None:
    # Zero gravity, a 1 kg cube (I = 1/600 kg m^2) on a ball joint at its
    # centre. A velocity motor towards 3 rad/s about a slanted axis u with
    # at most 0.01 N m spins it up at tau / I = 6 rad/s^2 about u; an
    # orientation motor, critically damped, turns it by the target rotation
    # vector and holds it there.
    i, tau = 1 / 600, 0.01
    u = np.array([1.0, 2.0, -0.5]) / np.linalg.norm([1.0, 2.0, -0.5])
    world = tumble.World(gravity=(0, 0, 0), sleeping=False, threads=1)
    cube = world.add_body(tumble.Box((0.05, 0.05, 0.05)), mass=1.0)
    ball = world.add_joint(
        "ball",
        cube,
        None,
        anchor=(0, 0, 0),
        motor={"target_velocity": tuple(3.0 * u), "max_force": tau},
    )
    assert ball.motor == {"target_velocity": list(3.0 * u), "max_force": tau}
    world.step(12)
    spin = np.asarray(cube.angular_velocity)
    assert np.linalg.norm(spin) == pytest.approx(tau / i * 0.2, rel=1e-3)
    assert np.linalg.norm(spin - np.dot(spin, u) * u) < 1e-9
    world.step(48)
    assert np.asarray(cube.angular_velocity) == pytest.approx(3.0 * u, abs=1e-9)

    k = 0.1
    ball.motor = {
        "target_position": tuple(0.8 * u),
        "stiffness": k,
        "damping": 2 * math.sqrt(k * i),
    }
    cube.angular_velocity = (0, 0, 0)
    cube.orientation = (0, 0, 0, 1)
    world.step(600)
    x, y, z, w = cube.orientation
    turn = 2 * math.atan2(math.sqrt(x * x + y * y + z * z), w)
    axis = np.array([x, y, z]) / math.sqrt(x * x + y * y + z * z)
    assert turn * axis == pytest.approx(0.8 * u, abs=1e-6)
    assert ball.rotation == pytest.approx(0.8 * u, abs=1e-6)
    assert world.joint_states()["rotation"][0] == pytest.approx(0.8 * u, abs=1e-6)
    for bad in (
        {"target_velocity": 1.0},  # a hinge's on a ball joint
        {"target_velocity": (math.nan, 0, 0)},
        {"target_position": (0, 0, 1), "stiffness": -1.0},
        {"target_velocity": (0, 0)},
    ):
        with pytest.raises(tumble.InvalidArgument, match="motor"):
            ball.motor = bad
    with pytest.raises(tumble.InvalidArgument, match="joint.motor"):
        world.add_joint("hinge", cube, None, anchor=(0, 0, 0), motor={"target_velocity": (0, 0, 1)})


def test_slider_friction_holds_below_its_load_and_slips_above_it() -> None:
    # A 1 kg cube on a slider up a 30 degree slope: m g sin(30) = 4.905 N
    # down the axis. 6 N of friction hold it; with 2 N it slides at
    # a = g sin(30) - f / m, x = -a t^2 / 2 after t = 1 s.
    axis = (math.cos(math.pi / 6), 0.0, math.sin(math.pi / 6))

    def slide(friction: float) -> tumble.Joint:
        world = tumble.World(sleeping=False, threads=1)
        cube = world.add_body(tumble.Box((0.05, 0.05, 0.05)), mass=1.0)
        slider = world.add_joint(
            "slider", cube, None, anchor=(0, 0, 0), axis=axis, friction=friction
        )
        assert slider.friction == friction
        world.step(60)
        return slider

    held = slide(6.0)
    assert abs(held.position) < 1e-9 and abs(held.rate) < 1e-9
    a = G * 0.5 - 2.0
    assert slide(2.0).position == pytest.approx(-0.5 * a, rel=0.005)


def test_a_joints_friction_is_set_and_refused_when_bad() -> None:
    world, bob, hinge = pendulum(friction=0.5)
    assert hinge.friction == 0.5
    hinge.friction = None
    assert hinge.friction is None
    for bad in (-1.0, math.nan, math.inf):
        with pytest.raises(tumble.InvalidArgument, match="joint.friction"):
            hinge.friction = bad
    assert hinge.friction is None
    with pytest.raises(tumble.InvalidArgument, match="joint.friction"):
        world.add_joint("fixed", bob, None, anchor=(0, 0, 0), friction=1.0)


def test_a_joints_spring_is_read_set_and_refused_when_bad() -> None:
    world, bob, hinge = pendulum(spring=(2.0, 0.5))
    assert hinge.spring == {"stiffness": 2.0, "damping": 0.5}
    hinge.spring = {"stiffness": 0.0, "damping": 1.0}
    assert hinge.spring == {"stiffness": 0.0, "damping": 1.0}
    with pytest.raises(tumble.InvalidArgument, match="joint.spring"):
        hinge.spring = (-1.0, 0.0)
    assert hinge.spring == {"stiffness": 0.0, "damping": 1.0}
    hinge.spring = None
    assert hinge.spring is None


def test_limits_hold_and_the_state_arrays_match_the_handles() -> None:
    world, bob, hinge = pendulum(limits=(-0.2, 0.8))
    for _ in range(120):
        world.step()
        assert -0.21 < hinge.position < 0.82
    states = world.joint_states()
    assert set(states) >= {"position", "rate", "force", "torque", "linear_error"}
    assert states["position"].shape == (1,) and states["force"].shape == (1, 3)
    assert states["position"][0] == hinge.position
    np.testing.assert_array_equal(states["force"][0], hinge.force)
    assert world.joints() == [hinge]
    assert world.step_report.joints == 1
    assert hinge.kind == "hinge" and hinge.body_a == bob and hinge.body_b is None


def test_a_rope_is_slack_below_its_length_and_holds_at_it() -> None:
    world = tumble.World(sleeping=False)
    weight = world.add_body(tumble.Sphere(0.05), mass=2.0, position=(0, 0, 0))
    rope = world.add_joint(
        "distance", weight, None, anchor=(0, 0, 0), anchor_b=(0, 0, 0.5), limits=(0.0, 1.0)
    )
    world.step(300)
    assert rope.position == pytest.approx(1.0, abs=2e-3)
    assert rope.force[2] == pytest.approx(2.0 * G, rel=0.05)


def test_pickling_keeps_joints_and_continues_bit_for_bit() -> None:
    # With motors: a world with one did not unpickle before (its binary
    # snapshot could not read a motor back).
    world, bob, hinge = pendulum(
        limits=(-1.0, 1.0), motor={"target_velocity": 0.3, "max_force": 2.0}
    )
    other = world.add_body(tumble.Box((0.05, 0.05, 0.05)), mass=1.0, position=(1.0, 0, 0))
    world.add_joint(
        "ball",
        other,
        bob,
        anchor=(0.75, 0, 0),
        motor={"target_position": (0, 0.5, 0), "stiffness": 2.0, "max_force": 0.5},
    )
    world.step(10)
    copy = pickle.loads(pickle.dumps(world))
    assert len(copy.joints()) == 2
    assert copy.joints()[1].motor == world.joints()[1].motor
    world.step(20)
    copy.step(20)
    np.testing.assert_array_equal(world.positions, copy.positions)


def test_removing_a_joint_or_its_body_makes_the_handle_stale() -> None:
    world, bob, hinge = pendulum()
    world.remove_joint(hinge)
    with pytest.raises(tumble.StaleBodyError):
        _ = hinge.position
    again = world.add_joint("ball", bob, None, anchor=(0, 0, 0))
    bob.remove()
    assert world.joints() == []
    with pytest.raises(tumble.StaleBodyError):
        again.remove()


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"kind": "hing"}, "kind"),
        ({"anchor": (math.nan, 0, 0)}, "joint.anchor"),
        ({"axis": (0, 0, 0)}, "joint.axis"),
        ({"limits": (1.0, -1.0)}, "joint.limits"),
        ({"motor": {"target_velocity": 1.0, "max_force": -1.0}}, "max_force"),
        ({"motor": {"target_velocity": 1.0, "target_position": 0.0}}, "exactly one"),
        ({"motor": {"speed": 1.0}}, "motor"),
        ({"kind": "fixed", "spring": (1.0, 1.0)}, "joint.spring"),
        ({"spring": (1.0, -1.0)}, "joint.spring"),
    ],
)
def test_bad_joints_are_refused_and_leave_the_world_unchanged(kwargs, message) -> None:
    world = tumble.World()
    bob = world.add_body(tumble.Sphere(0.1), mass=1.0)
    args = {"kind": "hinge", "anchor": (0, 0, 0), "axis": (0, 1, 0)} | kwargs
    kind = args.pop("kind")
    with pytest.raises(tumble.InvalidArgument, match=message):
        world.add_joint(kind, bob, None, **args)
    assert world.joints() == []


def test_a_joint_to_a_body_of_another_world_is_refused() -> None:
    one, two = tumble.World(), tumble.World()
    a = one.add_body(tumble.Sphere(0.1), mass=1.0)
    b = two.add_body(tumble.Sphere(0.1), mass=1.0)
    with pytest.raises(tumble.InvalidArgument, match="another world"):
        one.add_joint("ball", a, b, anchor=(0, 0, 0))


def gear_pair(ratio: float) -> tuple[tumble.World, tumble.Joint, tumble.Joint]:
    """Two spheres of 1 kg and radius 0.1 m on hinges about z to the world,
    the second following the first at `ratio`."""
    world = tumble.World(sleeping=False, threads=1, gravity=(0, 0, 0))
    wheels = [world.add_body(tumble.Sphere(0.1), mass=1.0, position=(x, 0, 0)) for x in (0.0, 0.3)]
    leader, follower = (
        world.add_joint("hinge", w, None, anchor=w.position, axis=(0, 0, 1)) for w in wheels
    )
    follower.gear = {"leader": leader, "ratio": ratio}
    return world, leader, follower


def test_a_gear_turns_its_follower_in_its_ratio() -> None:
    # The leader driven at 3 rad/s: the follower at -3/2 of it, at the
    # angle the ratio gives (within the push-out's micro-radians), and
    # the gear reads back as it was set.
    world, leader, follower = gear_pair(-1.5)
    assert follower.gear == {"leader": leader, "ratio": -1.5, "offset": 0.0}
    assert leader.gear is None
    leader.motor = {"target_velocity": 3.0, "max_force": 100.0}
    world.step(30)
    assert leader.rate == pytest.approx(3.0, abs=1e-6)
    assert follower.rate == pytest.approx(-4.5, abs=1e-6)
    assert follower.position == pytest.approx(
        math.remainder(-1.5 * leader.position, math.tau), abs=1e-6
    )
    assert follower.gear_error < 1e-6


def test_a_free_gear_pair_shares_its_spin_by_the_reduced_inertia() -> None:
    # The leader spinning alone at w0 meets its follower (equal wheels,
    # ratio r): it then turns at w0 / (1 + r^2), and the pair keeps that
    # energy.
    world, leader, follower = gear_pair(2.0)
    leader.body_a.angular_velocity = (0, 0, 4.0)
    world.step()
    assert leader.rate == pytest.approx(4.0 / 5.0, rel=1e-9)
    energy = world.kinetic_energy
    world.step(120)
    assert follower.rate == pytest.approx(2.0 * leader.rate, rel=1e-9)
    assert world.kinetic_energy == pytest.approx(energy, rel=1e-9)


def test_a_gear_is_pickled_let_go_and_refused_when_bad() -> None:
    world, leader, follower = gear_pair(2.0)
    leader.motor = {"target_velocity": 1.0, "max_force": 10.0}
    world.step(5)
    copy = pickle.loads(pickle.dumps(world))
    assert copy.joints()[1].gear["ratio"] == 2.0
    world.step(20)
    copy.step(20)
    np.testing.assert_array_equal(world.positions, copy.positions)
    for bad, message in [
        ({"leader": follower, "ratio": 1.0}, "gear.leader"),
        ({"leader": leader, "ratio": math.nan}, "gear.ratio"),
        ({"leader": leader}, "ratio"),
        ({"leader": leader, "ratio": 1.0, "teeth": 3}, "unknown key"),
        ({"leader": 3, "ratio": 1.0}, "Joint"),
        ((leader, 1.0), "dict"),
    ]:
        with pytest.raises(tumble.InvalidArgument, match=message):
            follower.gear = bad
        assert follower.gear["ratio"] == 2.0
    other, other_leader, _ = gear_pair(1.0)
    with pytest.raises(tumble.InvalidArgument, match="another world"):
        follower.gear = {"leader": other_leader, "ratio": 1.0}
    follower.gear = None
    assert follower.gear is None and follower.gear_error == 0.0
    # Removing the leader takes the gear with it.
    follower.gear = {"leader": leader, "ratio": 1.0}
    leader.remove()
    assert follower.gear is None
