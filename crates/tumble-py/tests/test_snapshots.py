"""World.save / load / to_bytes / from_bytes / pickling: the state
round-trips exactly (the same steps give bit-identical arrays), the rows keep
their insertion order, and bad snapshot files raise the right exceptions."""

from __future__ import annotations

import copy
import pickle

import numpy as np
import pytest

import tumble


def make_world() -> tumble.World:
    world = tumble.World(dt=1 / 120)
    world.add_body(tumble.HalfSpace(), kind="static", name="ground")
    balls = [
        world.add_body(
            tumble.Sphere(0.2), mass=1.0, position=(0.5 * i, 0, 0.4 + 0.45 * i), name=f"ball{i}"
        )
        for i in range(4)
    ]
    world.add_body(
        tumble.Box((0.3, 0.2, 0.1)),
        density=500.0,
        position=(2, 0, 1),
        orientation=(0.0, 0.0, np.sin(0.2), np.cos(0.2)),
        angular_velocity=(0, 0, 3),
        name="box",
    )
    world.add_body(
        tumble.TriMesh.torus(1.0, 0.2, 16, 8), mass=1.0, position=(-3, 0, 0.5), name="torus"
    )
    world.add_body(
        tumble.ConvexHull(tumble.TriMesh.box((0.2, 0.2, 0.2)).vertices),
        mass=1.0,
        position=(0, 2, 0.5),
        name="hull",
    )
    world.add_body(
        tumble.Box((1, 1, 0.05)),
        kind="kinematic",
        position=(0, -3, 0.2),
        velocity=(0, 0.1, 0),
        name="platform",
    )
    # A hole in the slots: the late body reuses ball1's slot but is the last row.
    balls[1].remove()
    world.add_body(tumble.Sphere(0.1), mass=0.5, position=(0, 2, 2), name="late")
    return world


def state_bits(world: tumble.World) -> np.ndarray:
    arrays = [world.positions, world.orientations, world.velocities, world.angular_velocities]
    return np.concatenate([a.ravel() for a in arrays]).view(np.uint64)


def test_save_load_and_pickle_continue_bit_for_bit(tmp_path) -> None:
    world = make_world()
    world.step(60)
    world.save(tmp_path / "w.snap")
    world.save(tmp_path / "w.json")
    data = world.to_bytes()
    pickled = pickle.dumps(world)
    twin = copy.deepcopy(world)
    names = [b.name for b in world.bodies]
    assert names[-1] == "late"
    world.step(60)
    expected = state_bits(world)
    restored_worlds = {
        "binary file": tumble.World.load(tmp_path / "w.snap"),
        "json file": tumble.World.load(str(tmp_path / "w.json")),
        "bytes": tumble.World.from_bytes(data),
        "pickle": pickle.loads(pickled),
        "deepcopy": twin,
    }
    for how, restored in restored_worlds.items():
        assert [b.name for b in restored.bodies] == names, how
        assert restored.step_count == 60 and restored.time == pytest.approx(0.5), how
        assert repr(restored.settings) == repr(world.settings), how
        restored.step(60)
        assert np.array_equal(state_bits(restored), expected), f"{how}: trajectories differ"
        assert restored.time == world.time, how


def test_handles_of_a_loaded_world_address_the_same_rows() -> None:
    world = make_world()
    loaded = tumble.World.from_bytes(world.to_bytes())
    for a, b in zip(world.bodies, loaded.bodies):
        assert a.name == b.name and a.index == b.index
        assert np.array_equal(a.position, b.position)
    assert loaded.find("late").index == len(loaded) - 1


def test_a_loaded_world_is_independent() -> None:
    world = make_world()
    copy_ = tumble.World.from_bytes(world.to_bytes())
    copy_.step(10)
    assert world.step_count == 0 and copy_.step_count == 10


def test_bad_snapshot_files(tmp_path) -> None:
    world = make_world()
    with pytest.raises(tumble.FileError):
        tumble.World.load(tmp_path / "missing.snap")
    (tmp_path / "empty.snap").write_bytes(b"")
    with pytest.raises(tumble.FileError) as info:
        tumble.World.load(tmp_path / "empty.snap")
    assert "empty" in str(info.value)
    with pytest.raises(tumble.FileError):
        world.save(tmp_path / "no" / "such" / "dir" / "w.snap")
    with pytest.raises(tumble.InvalidArgument) as info:
        tumble.World.from_bytes(b"PK\x03\x04 not a snapshot")
    assert "not a tumble snapshot" in str(info.value)
    data = world.to_bytes()
    with pytest.raises(tumble.InvalidArgument) as info:
        tumble.World.from_bytes(data[: len(data) // 2])
    assert "corrupt snapshot" in str(info.value)
    newer = bytearray(data)
    version = newer[8]  # the format version follows the 8-byte magic (a one-byte varint)
    newer[8] += 1
    with pytest.raises(tumble.InvalidArgument) as info:
        tumble.World.from_bytes(bytes(newer))
    assert f"snapshot format version {version + 1} is not supported" in str(info.value)
    world.save(tmp_path / "w.json")
    text = (tmp_path / "w.json").read_text()
    assert f'"format_version":{version}' in text
    old = text.replace(f'"format_version":{version}', '"format_version":0', 1)
    (tmp_path / "old.json").write_text(old)
    with pytest.raises(tumble.InvalidArgument) as info:
        tumble.World.load(tmp_path / "old.json")
    assert "version 0 is not supported" in str(info.value)
    # A negative friction (material is [restitution, friction]).
    assert '"material":[0.0,0.5]' in text
    bad = text.replace('"material":[0.0,0.5]', '"material":[0.0,-0.5]', 1)
    (tmp_path / "bad.json").write_text(bad)
    with pytest.raises(tumble.InvalidArgument) as info:
        tumble.World.load(tmp_path / "bad.json")
    assert "invalid snapshot" in str(info.value)
