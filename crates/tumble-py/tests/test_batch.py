"""Many worlds: World.copy, World.states / set_states and tumble.rollout.

Every check compares a rollout against the same worlds stepped one by one
with World.step (bit for bit), or against physics (free fall under a force).
"""

from __future__ import annotations

import copy
import pathlib
import pickle

import numpy as np
import pytest

import tumble

ROOT = pathlib.Path(__file__).resolve().parents[3]
DOMINO = ROOT / "examples" / "scenes" / "domino.toml"


def ball_world(height: float = 1.0, restitution: float = 0.5) -> tumble.World:
    w = tumble.World(dt=1 / 120)
    w.add_body(tumble.HalfSpace(), kind="static", name="ground")
    w.add_body(
        tumble.Sphere(0.1), mass=1.0, position=(0, 0, height), restitution=restitution, name="ball"
    )
    w.add_body(
        tumble.Box((0.1, 0.2, 0.05)),
        mass=2.0,
        position=(0.5, 0, 0.3),
        angular_velocity=(1, 2, 3),
        name="box",
    )
    return w


def step_alone(world: tumble.World, steps: int, record: str = "states") -> np.ndarray:
    rows = []
    for _ in range(steps):
        world.step()
        rows.append(getattr(world, record).copy())
    return np.array(rows)


def test_a_copy_steps_as_the_original_and_is_independent():
    w = ball_world()
    w.step(30)
    c = w.copy()
    assert np.array_equal(c.states, w.states)
    a = step_alone(w, 50)
    b = step_alone(c, 50)
    assert np.array_equal(a, b)
    c.bodies[1].apply_impulse((1, 0, 0))
    c.step()
    assert not np.array_equal(c.positions, w.positions), "the copy is a separate world"
    assert np.array_equal(copy.deepcopy(w).states, w.states)
    assert np.array_equal(copy.copy(w).states, w.states)


def test_states_round_trip_and_bad_states_leave_the_world_unchanged():
    w = ball_world()
    w.step(10)
    s = w.states
    assert s.shape == (3, 13)
    assert np.array_equal(s[:, :3], w.positions)
    assert np.array_equal(s[:, 7:10], w.velocities)
    other = ball_world(height=3.0)
    other.set_states(s)
    # The body frame (centre of mass, principal axes) is stored, not the
    # model frame: a round trip is exact to rounding.
    assert np.allclose(other.states, s, rtol=0, atol=1e-12)
    before = other.states
    bad = s.copy()
    bad[2, 8] = np.nan
    with pytest.raises(tumble.InvalidArgument, match="row 2"):
        other.set_states(bad)
    bad = s.copy()
    bad[0, 7] = 1.0  # the static ground cannot move
    with pytest.raises(tumble.InvalidArgument, match="static"):
        other.set_states(bad)
    bad = s.copy()
    bad[1, 3:7] = (0, 0, 0, 2)
    with pytest.raises(tumble.InvalidArgument, match="row 1"):
        other.set_states(bad)
    with pytest.raises(tumble.InvalidArgument, match=r"\(3, 13\)"):
        other.set_states(s[:2])
    assert np.array_equal(other.states, before)


@pytest.mark.parametrize("threads", [1, 2, 3, 8])
def test_rollout_of_copies_equals_the_worlds_stepped_one_by_one(threads):
    worlds = [ball_world(height=0.5 + 0.25 * k, restitution=0.1 * k) for k in range(6)]
    alone = [step_alone(w.copy(), 90) for w in worlds]
    out = tumble.rollout(worlds, 90, record=("states", "positions"), threads=threads)
    assert out["states"].shape == (6, 90, 3, 13)
    assert out["time"].shape == (6, 90)
    for k in range(6):
        assert np.array_equal(out["states"][k], alone[k]), f"world {k}"
        assert np.array_equal(out["positions"][k], alone[k][:, :, :3])
    # The worlds were stepped in place.
    assert np.array_equal(worlds[0].states, alone[0][-1])
    assert np.allclose(out["time"][:, -1], 90 / 120)


def test_rollout_from_a_scene_with_states():
    base = tumble.load_scene(DOMINO)
    n = len(base)
    states = np.repeat(base.states[None], 4, axis=0)
    dominoes = [k for k, b in enumerate(base.bodies) if b.kind == "dynamic"]
    first = dominoes[0]
    for k in range(4):
        states[k, first, 7] = 0.2 * (k + 1)  # the first domino pushed at four speeds
    out = tumble.rollout(DOMINO, 60, states=states, record=["positions"], threads=2)
    assert out["positions"].shape == (4, 60, n, 3)
    for k in range(4):
        w = tumble.load_scene(DOMINO)
        w.set_states(states[k])
        assert np.array_equal(out["positions"][k], step_alone(w, 60, "positions"))
    # One world given: copies are stepped, the world is left as it was.
    before = base.states
    tumble.rollout(base, 10, states=states[:2])
    assert np.array_equal(base.states, before)


def test_controls_push_as_forces_do():
    # A ball in free fall (no gravity) under a constant force F: x = F t^2 / (2 m),
    # to the integrator's accuracy, and exactly what apply_forces gives.
    def floating():
        w = tumble.World(gravity=(0, 0, 0), dt=0.01)
        w.add_body(tumble.Sphere(0.1), mass=2.0, name="ball")
        return w

    forces = np.zeros((2, 100, 1, 6))
    forces[0, :, 0, 0] = 4.0  # 4 N along x
    forces[1, :, 0, 5] = 0.5  # 0.5 N m about z
    out = tumble.rollout(
        [floating(), floating()], 100, controls=forces, record=["positions", "angular_velocities"]
    )
    t = out["time"][0, -1]
    assert out["positions"][0, -1, 0, 0] == pytest.approx(4.0 / (2 * 2.0) * t * t, rel=0.02)
    inertia = 2.0 / 5.0 * 2.0 * 0.1**2
    assert out["angular_velocities"][1, -1, 0, 2] == pytest.approx(0.5 / inertia * t, rel=1e-9)
    by_hand = floating()
    rows = []
    for _ in range(100):
        by_hand.apply_forces(forces[0, 0, :, :3])
        by_hand.step()
        rows.append(by_hand.positions.copy())
    assert np.array_equal(out["positions"][0], np.array(rows))


def test_callable_controls_are_called_between_chunks():
    calls = []

    def controller(step, worlds):
        calls.append(step)
        # A feedback law: pull each ball back towards x = 0.
        return np.array([[[-10.0 * w.positions[0, 0], 0, 0, 0, 0, 0]] for w in worlds])

    def world():
        w = tumble.World(gravity=(0, 0, 0), dt=0.01)
        w.add_body(tumble.Sphere(0.1), mass=1.0, position=(1, 0, 0))
        return w

    out = tumble.rollout([world(), world()], 40, controls=controller, chunk=8, record=["positions"])
    assert calls == [0, 8, 16, 24, 32]
    assert out["positions"].shape == (2, 40, 1, 3)
    x = out["positions"][0, :, 0, 0]
    assert x[-1] < 1.0 and np.all(np.diff(x) < 0), "the controller pulls the ball back"
    assert np.array_equal(out["positions"][0], out["positions"][1])


def test_bad_rollouts_are_refused_before_anything_moves():
    w = ball_world()
    before = w.states
    with pytest.raises(tumble.InvalidArgument, match="record"):
        tumble.rollout([w], 5, record=["speed"])
    with pytest.raises(tumble.InvalidArgument, match="controls"):
        tumble.rollout([w], 5, controls=np.zeros((5, 2, 6)))
    with pytest.raises(tumble.InvalidArgument, match="not dynamic"):
        c = np.zeros((3, 6))
        c[0, 0] = 1.0
        tumble.rollout([w], 5, controls=c)
    with pytest.raises(tumble.InvalidArgument, match="not finite"):
        c = np.zeros((3, 6))
        c[1, 2] = np.inf
        tumble.rollout([w], 5, controls=c)
    with pytest.raises(tumble.InvalidArgument, match="appears twice"):
        tumble.rollout([w, w], 5)
    with pytest.raises(tumble.InvalidArgument, match="bodies"):
        small = tumble.World()
        small.add_body(tumble.Sphere(0.1), mass=1.0)
        tumble.rollout([w, small], 5)
    with pytest.raises(tumble.InvalidArgument, match="steps"):
        tumble.rollout([w], -1)
    with pytest.raises(tumble.InvalidArgument, match="worlds_or_scene"):
        tumble.rollout([], 5)
    assert np.array_equal(w.states, before)
    assert tumble.rollout([w], 0)["time"].shape == (1, 0)


def test_a_rolled_out_world_pickles_and_goes_on_as_the_original():
    worlds = [ball_world() for _ in range(2)]
    tumble.rollout(worlds, 20)
    restored = pickle.loads(pickle.dumps(worlds[0]))
    assert np.array_equal(step_alone(restored, 20), step_alone(worlds[1], 20))


def test_a_callable_drives_joint_motors_between_chunks():
    # Two pendulums on motorised hinges; the controller asks world k for the
    # speed 0.5 (k + 1) rad/s and returns no forces: each arm turns at its rate.
    def arm():
        w = tumble.World(gravity=(0, 0, 0), dt=0.01, sleeping=False)
        b = w.add_body(tumble.Box((0.05, 0.05, 0.05)), mass=1.0, position=(0.5, 0, 0))
        w.add_joint("hinge", b, None, anchor=(0, 0, 0), axis=(0, 0, 1), name="j")
        return w

    def controller(step, worlds):
        for k, w in enumerate(worlds):
            w.joints()[0].motor = {"target_velocity": 0.5 * (k + 1), "max_force": 50.0}
        return None

    worlds = [arm(), arm()]
    out = tumble.rollout(worlds, 100, controls=controller, chunk=25, record=["angular_velocities"])
    rates = out["angular_velocities"][:, -1, 0, 2]
    assert rates == pytest.approx([0.5, 1.0], rel=1e-3)
