"""Export round trips: the glTF written by export_gltf is decoded here (GLB
container, JSON, accessors) and its animation must replay the positions
read from the world at each recorded step; the CSV must parse back to them."""

from __future__ import annotations

import csv
import json
import struct

import numpy as np
import pytest

import tumble


def read_glb(path) -> tuple[dict, bytes]:
    data = path.read_bytes()
    magic, version, length = struct.unpack_from("<4sII", data, 0)
    assert (magic, version, length) == (b"glTF", 2, len(data))
    json_len, json_type = struct.unpack_from("<II", data, 12)
    assert json_type == 0x4E4F534A
    doc = json.loads(data[20 : 20 + json_len])
    bin_len, bin_type = struct.unpack_from("<II", data, 20 + json_len)
    assert bin_type == 0x004E4942
    start = 28 + json_len
    return doc, data[start : start + bin_len]


def accessor(doc: dict, blob: bytes, index: int) -> np.ndarray:
    acc = doc["accessors"][index]
    view = doc["bufferViews"][acc["bufferView"]]
    assert acc["componentType"] == 5126  # float32
    width = {"SCALAR": 1, "VEC3": 3, "VEC4": 4}[acc["type"]]
    offset = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
    values = np.frombuffer(blob, dtype="<f4", count=acc["count"] * width, offset=offset)
    return values.reshape(acc["count"], width) if width > 1 else values


def falling_world() -> tuple[tumble.World, tumble.Body]:
    world = tumble.World(dt=1 / 60)
    world.add_body(tumble.HalfSpace(), kind="static", name="ground")
    ball = world.add_body(
        tumble.Sphere(0.2),
        mass=1.0,
        position=(0.5, -0.25, 2.0),
        velocity=(1.0, 0.5, 0.0),
        angular_velocity=(0, 0, 3.0),
        name="ball",
    )
    return world, ball


def test_gltf_animation_replays_the_recorded_steps(tmp_path) -> None:
    world, ball = falling_world()
    world.start_recording(every=2)
    times, positions = [world.time], [ball.position]
    for k in range(1, 61):
        world.step()
        if k % 2 == 0:
            times.append(world.time)
            positions.append(ball.position)
    assert world.recorded_frames == len(times) == 31
    path = tmp_path / "fall.glb"
    world.export_gltf(path)
    doc, blob = read_glb(path)
    names = [node.get("name") for node in doc["nodes"]]
    assert "ball" in names and "ground" in names
    ball_node = names.index("ball")
    anim = doc["animations"][0]
    channels = {(c["target"]["node"], c["target"]["path"]): c["sampler"] for c in anim["channels"]}
    sampler = anim["samplers"][channels[(ball_node, "translation")]]
    np.testing.assert_allclose(accessor(doc, blob, sampler["input"]), times, rtol=1e-6)
    replay = accessor(doc, blob, sampler["output"])
    np.testing.assert_allclose(replay, np.array(positions), atol=1e-5)  # float32
    assert doc["extras"]["tumble"]["frame_times"] == pytest.approx(times)


def test_export_without_recording_writes_the_current_state(tmp_path) -> None:
    world, ball = falling_world()
    world.step(10)
    world.export_gltf(tmp_path / "now.glb")
    doc, _ = read_glb(tmp_path / "now.glb")
    node = doc["nodes"][[n.get("name") for n in doc["nodes"]].index("ball")]
    np.testing.assert_allclose(node["translation"], ball.position, atol=1e-6)
    assert doc["extras"]["tumble"]["frame_times"] == pytest.approx([world.time])


def test_csv_trajectory_round_trip(tmp_path) -> None:
    world, ball = falling_world()
    world.start_recording()
    rows = [np.concatenate([ball.position, ball.orientation])]
    for _ in range(5):
        world.step()
        rows.append(np.concatenate([ball.position, ball.orientation]))
    world.export_csv(tmp_path / "t.csv")
    with open(tmp_path / "t.csv") as f:
        table = list(csv.DictReader(f))
    ball_rows = [r for r in table if r["body"] == "ball"]
    assert len(table) == 2 * 6 and len(ball_rows) == 6
    for row, expected in zip(ball_rows, rows):
        got = [float(row[k]) for k in ["x", "y", "z", "qx", "qy", "qz", "qw"]]
        # The export holds the model frame (position, orientation), as read here.
        np.testing.assert_allclose(got, expected, rtol=0, atol=1e-12)


def test_recording_stops_and_restarts() -> None:
    world, _ = falling_world()
    world.start_recording()
    world.step(3)
    assert world.recorded_frames == 4
    world.stop_recording()
    assert world.recorded_frames == 0
    with pytest.raises(tumble.InvalidArgument):
        world.start_recording(every=0)
