"""tumble.load_scene: every example scene loads and steps, rows follow the
file's order (checked against the layouts of shared/scenes.md), the world is
the one `tumble run` simulates, and scene errors carry their place in the file."""

from __future__ import annotations

import csv
import json
import pickle
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

import tumble

ROOT = Path(__file__).resolve().parents[3]
SCENES = sorted((ROOT / "examples" / "scenes").glob("*.*ml")) + sorted(
    (ROOT / "examples" / "scenes").glob("*.json")
)
CLI = ROOT / "target" / "release" / "tumble"


def test_the_example_scenes_are_all_found() -> None:
    names = {p.name for p in SCENES}
    assert {"pyramid.toml", "pile.toml", "chain.toml", "mixed_shapes.json"} <= names
    assert len(SCENES) >= 10


@pytest.mark.parametrize("path", SCENES, ids=lambda p: p.name)
def test_every_example_scene_loads_and_steps(path: Path) -> None:
    world = tumble.load_scene(path)
    n = len(world)
    assert n > 0 and world.positions.shape == (n, 3) and world.time == 0.0
    assert [b.index for b in world.bodies] == list(range(n))
    for body in world.bodies:
        if body.name:
            assert world.find(body.name) is not None
    world.step(2)
    assert world.step_count == 2
    assert world.time == pytest.approx(2 * world.dt)
    assert np.isfinite(world.poses()).all()


def test_pyramid_rows_follow_the_file() -> None:
    world = tumble.load_scene(ROOT / "examples" / "scenes" / "pyramid.toml")
    assert len(world) == 211 and world.bodies[0].name == "ground"
    assert world.find("ground").kind == "static"
    # scenes.md: layer i holds 20 - i boxes at ((k - (n - 1) / 2) * 1.05, 0, 0.5 + i),
    # added layer by layer, k ascending.
    expected = [((k - (19 - i) / 2) * 1.05, 0.0, 0.5 + i) for i in range(20) for k in range(20 - i)]
    np.testing.assert_allclose(world.positions[1:], expected, atol=1e-12)
    assert world.bodies[-1].name == "box_19_0"
    assert world.find("box_3_5").index == 1 + 20 + 19 + 18 + 5
    assert world.settings["dt"] == pytest.approx(1 / 60)


def test_pile_grid_order_is_k_then_j_then_i() -> None:
    world = tumble.load_scene(ROOT / "examples" / "scenes" / "pile.toml")
    dynamic = [b for b in world.bodies if b.kind == "dynamic"]
    assert len(dynamic) == 1000
    rows = [b.index for b in dynamic]
    expected = []
    for k in range(10):
        o = 0.1 if k % 2 else 0.0
        for j in range(10):
            for i in range(10):
                expected.append((-2.7 + 0.6 * i + o, -2.7 + 0.6 * j + o, 1.0 + 0.6 * k))
    np.testing.assert_allclose(world.positions[rows], expected, atol=1e-12)
    # Spheres where i + j + k is even, cubes elsewhere: same mass only if density 1
    # gives (4/3) pi r^3 and (2 r)^3.
    masses = np.array([b.mass for b in dynamic])
    parity = np.array([(i + j + k) % 2 for k in range(10) for j in range(10) for i in range(10)])
    np.testing.assert_allclose(masses[parity == 0], 4 / 3 * np.pi * 0.25**3, rtol=1e-12)
    np.testing.assert_allclose(masses[parity == 1], 0.5**3, rtol=1e-12)


def last_frame(csv_path: Path) -> dict[str, list[float]]:
    with csv_path.open() as f:
        rows = list(csv.DictReader(f))
    t_end = rows[-1]["t"]
    return {r["body"]: [float(r[k]) for k in ("x", "y", "z")] for r in rows if r["t"] == t_end}


@pytest.mark.skipif(not CLI.exists(), reason="target/release/tumble not built")
@pytest.mark.parametrize("name", ["mixed_shapes.json", "domino.toml", "cradle.toml"])
def test_the_world_is_the_one_tumble_run_simulates(name: str, tmp_path: Path) -> None:
    # mixed_shapes has initial forces and torques, a kinematic body, compound
    # bodies and an OBJ file. The trajectory file of `tumble run` holds the
    # model frames (World.positions, where the scene placed each body); after
    # 30 steps its positions and Python's must agree bit for bit.
    path = ROOT / "examples" / "scenes" / name
    out = tmp_path / "run.csv"
    subprocess.run(
        [str(CLI), "run", str(path), "--steps", "30", "--trajectory", str(out), "--quiet"],
        check=True,
    )
    world = tumble.load_scene(path)
    world.step(30)
    frame = last_frame(out)
    assert len(frame) == len(world)
    for body, position in zip(world.bodies, world.positions):
        assert frame[body.name] == position.tolist(), body.name
    start = tumble.load_scene(path)
    assert np.abs(world.centers_of_mass - start.centers_of_mass).max() > 0.01  # things moved


BAD_MASS = """
[[bodies]]
kind = "static"
shapes = [{ type = "half_space" }]
[[bodies]]
shapes = [{ type = "sphere", radius = 0.1 }]
mass = -1
position = [0, 0, 1]
"""


def test_scene_errors_carry_file_line_column_and_field(tmp_path: Path) -> None:
    path = tmp_path / "drop.toml"
    path.write_text(BAD_MASS)
    with pytest.raises(tumble.SceneError) as info:
        tumble.load_scene(path)
    e = info.value
    assert isinstance(e, tumble.TumbleError) and isinstance(e, ValueError)
    assert (e.file, e.line, e.column, e.field) == (str(path), 7, 8, "bodies[1].mass")
    assert e.reason == "must be finite and > 0 kg, got -1"
    assert str(e) == f"{path}:7:8: bodies[1].mass: must be finite and > 0 kg, got -1"
    again = pickle.loads(pickle.dumps(e))
    assert type(again) is tumble.SceneError and str(again) == str(e)
    assert (again.line, again.column, again.field) == (7, 8, "bodies[1].mass")
    # The line and column point at the value in the text.
    assert BAD_MASS.splitlines()[e.line - 1][e.column - 1 :].startswith("-1")
    if CLI.exists():
        cli = subprocess.run(
            [str(CLI), "run", str(path), "--steps", "1", "--quiet"], capture_output=True, text=True
        )
        assert cli.returncode == 2
        assert cli.stderr.strip() == f"tumble: error: {e}"


@pytest.mark.parametrize(
    "name, text, line, column, field, reason",
    [
        ("syntax.toml", "[[bodies]]\nmass = = 1\n", 2, 8, "", ""),
        (
            "unknown.toml",
            '[[bodies]]\nshapes = [{ type = "sphere", radius = 1 }]\ncolour = 1\n',
            3,
            1,
            "bodies[0].colour",
            "unknown field `colour`",
        ),
        ("dt.toml", "[settings]\ndt = -0.01\n", 2, 6, "settings.dt", "must be finite and > 0"),
        (
            "radius.json",
            json.dumps({"bodies": [{"shapes": [{"type": "sphere", "radius": 0}]}]}, indent=1),
            7,
            16,
            "bodies[0].shapes[0].radius",
            "must be finite and > 0 m, got 0",
        ),
        (
            "open.toml",
            '[[bodies]]\ndensity = 1000\nshapes = [{ type = "mesh", mesh = '
            '{ file = "open.obj" } }]\n',
            3,
            11,
            "bodies[0].shapes[0]",
            "mesh is open",
        ),
    ],
)
def test_scene_error_places(tmp_path: Path, name, text, line, column, field, reason) -> None:
    # open.obj: one triangle, not a closed surface, so no mass from a density.
    (tmp_path / "open.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    path = tmp_path / name
    path.write_text(text)
    with pytest.raises(tumble.SceneError) as info:
        tumble.load_scene(path)
    e = info.value
    assert e.file == str(path)
    assert e.field == field
    assert reason in e.reason
    assert (e.line, e.column) == (line, column)
    assert str(e).startswith(f"{path}:{e.line}:{e.column}: ")


def test_missing_files_and_unknown_formats(tmp_path: Path) -> None:
    with pytest.raises(tumble.FileError, match="cannot read"):
        tumble.load_scene(tmp_path / "missing.toml")
    assert issubclass(tumble.FileError, OSError)
    other = tmp_path / "scene.yaml"
    other.write_text("bodies: []\n")
    with pytest.raises(tumble.SceneError) as info:
        tumble.load_scene(other)
    e = info.value
    assert (e.line, e.column, e.field) == (None, None, None)
    assert "unknown scene format (expected a .toml or .json file)" in str(e)
    with pytest.raises(TypeError):
        tumble.load_scene(42)  # type: ignore[arg-type]


def test_scene_with_a_mesh_file_relative_to_it(tmp_path: Path) -> None:
    # Copied elsewhere together with its meshes/ folder, the scene still loads.
    src = ROOT / "examples" / "scenes"
    shutil.copy(src / "mixed_shapes.json", tmp_path / "mixed_shapes.json")
    shutil.copytree(src / "meshes", tmp_path / "meshes")
    world = tumble.load_scene(str(tmp_path / "mixed_shapes.json"))
    assert world.find("mesh_octahedron_obj").mass == pytest.approx(2.0)
    assert "SceneError" in tumble.__all__ and tumble.load_scene.__doc__.count("SceneError")
