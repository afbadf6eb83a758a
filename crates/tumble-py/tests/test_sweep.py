"""tumble.sweep: one run per combination of scene parameters, into a table.

Checked against physics (a ball's rebound rises e^2 of its drop height), for
independence from threads and chunking, against `tumble sweep` on the command
line (the same table), and for an interrupted sweep resumed to the table of
an uninterrupted one. Ray's backend has its own file (test_sweep_ray.py).
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pyarrow.csv as pacsv
import pyarrow.parquet as pq
import pytest

import tumble

ROOT = Path(__file__).resolve().parents[3]
CLI = ROOT / "target" / "release" / "tumble"

BOUNCE = ROOT / "examples" / "scenes" / "bounce.toml"


@pytest.fixture
def drop() -> Path:
    """A ball dropped from 1 m (its lowest point) onto the ground, 2 s."""
    return BOUNCE


def test_a_restitution_sweep_bounces_to_e_squared_of_the_drop(drop: Path):
    es = [0.3, 0.5, 0.7, 0.9]
    table = tumble.sweep(
        drop,
        {"bodies[ball].restitution": es, "settings.substeps": [4, 8]},
        metrics=["ball.rebound_z", "time"],
        progress=False,
    )
    assert table.num_rows == 8
    assert table.column_names == [
        "run",
        "bodies[ball].restitution",
        "settings.substeps",
        "status",
        "error",
        "steps",
        "ball.rebound_z",
        "time",
    ]
    rows = table.to_pylist()
    for k, row in enumerate(rows):
        e = es[k // 2]
        assert row["run"] == k
        assert row["bodies[ball].restitution"] == e
        assert row["settings.substeps"] == [4, 8][k % 2]
        assert row["status"] == "ok" and row["error"] is None
        # Dropped from 1 m: the rebound rises e^2 of it.
        assert row["ball.rebound_z"] - 0.1 == pytest.approx(e * e, rel=0.03, abs=0.005)
        assert row["time"] == pytest.approx(2.0)


def test_rows_do_not_depend_on_threads_or_chunks(drop: Path):
    # numpy values are values like any others.
    params = {
        "bodies[ball].position[2]": np.linspace(0.5, 1.7, 5),
        "bodies[ball].restitution": [0.2, 0.6],
    }
    metrics = ["ball.max_z", "ball.rebound_z", "energy_drift", "max_penetration"]
    one = tumble.sweep(drop, params, metrics=metrics, threads=1, progress=False)
    many = tumble.sweep(drop, params, metrics=metrics, threads=3, chunk_size=2, progress=False)
    assert one.equals(many)
    assert one.num_rows == 10
    assert one.num_rows == 10


def test_the_table_is_the_one_tumble_sweep_writes(drop: Path, tmp_path: Path):
    assert CLI.exists(), "make python-test builds target/release/tumble first"
    params = {"bodies[ball].restitution": [0.25, 0.75], "settings.dt": [0.004, 0.01]}
    metrics = ["ball.rebound_z", "energy_drift"]
    out = tmp_path / "py.parquet"
    table = tumble.sweep(drop, params, metrics=metrics, out=out, progress=False)
    assert pq.read_table(out).equals(table)
    assert not Path(str(out) + ".part").exists()
    cli_out = tmp_path / "cli.parquet"
    subprocess.run(
        [
            CLI,
            "sweep",
            drop,
            "--param",
            "bodies[ball].restitution=0.25,0.75",
            "--param",
            "settings.dt=0.004,0.01",
            "--metric",
            ",".join(metrics),
            "--quiet",
            "--out",
            cli_out,
        ],
        check=True,
    )
    assert pq.read_table(cli_out).equals(table)
    csv = tmp_path / "py.csv"
    tumble.sweep(drop, params, metrics=metrics, out=csv, progress=False)
    read = pacsv.read_csv(csv)
    assert read.column("ball.rebound_z").to_pylist() == table.column("ball.rebound_z").to_pylist()


def test_bad_sweeps(drop: Path):
    with pytest.raises(
        tumble.SceneError, match=r"bounce\.toml.*bodies\[rock\]\.mass.*no element named"
    ):
        tumble.sweep(drop, {"bodies[rock].mass": [1.0]})
    with pytest.raises(tumble.InvalidArgument, match="unknown metric"):
        tumble.sweep(drop, {"settings.dt": [0.01]}, metrics=["ball.colour"])
    with pytest.raises(tumble.InvalidArgument, match="backend"):
        tumble.sweep(drop, {"settings.dt": [0.01]}, backend="spark")
    with pytest.raises(tumble.InvalidArgument, match="params"):
        tumble.sweep(drop, {})
    with pytest.raises(tumble.InvalidArgument, match="steps or duration"):
        tumble.sweep(drop, {"settings.dt": [0.01]}, steps=3, duration=1.0)
    with pytest.raises(tumble.InvalidArgument, match="resume"):
        tumble.sweep(drop, {"settings.dt": [0.01]}, resume=True)
    with pytest.raises(tumble.FileError):
        tumble.sweep(drop.parent / "missing.toml", {"settings.dt": [0.01]})
    # A bad value fails its own row; the others run.
    with pytest.raises(tumble.InvalidArgument, match="finite"):
        tumble.sweep(drop, {"bodies[ball].mass": [1.0, float("inf")]})
    with pytest.raises(tumble.InvalidArgument, match="values"):
        tumble.sweep(drop, {"bodies[ball].mass": [object()]})


def test_bad_value_rows_name_the_parameter(drop: Path):
    table = tumble.sweep(drop, {"bodies[ball].mass": [1.0, -2.0]}, steps=5, progress=False)
    rows = table.to_pylist()
    assert [r["status"] for r in rows] == ["ok", "failed"]
    assert "bodies[ball].mass=-2" in rows[1]["error"] and "bounce.toml" in rows[1]["error"]
    assert rows[1]["energy_drift"] is None and rows[1]["steps"] == 0


# The child takes Python's own SIGINT handler whatever it inherits: a test run
# started in the background by a non-interactive shell inherits SIGINT
# ignored, and Python then installs no handler, so the interrupt was lost and
# the sweep ran to its end (exit 0).
SLOW_SWEEP = """
import signal, sys, tumble
signal.signal(signal.SIGINT, signal.default_int_handler)
heights = [0.5 + 0.01 * k for k in range(40)]
tumble.sweep(sys.argv[1], {{"bodies[ball].position[2]": heights}}, duration=100.0, threads=2,
             metrics=["ball.max_z"], out=sys.argv[2], progress=False{resume})
"""


def test_an_interrupted_sweep_keeps_its_rows_and_resumes_to_the_same_table(
    drop: Path, tmp_path: Path
):
    out = tmp_path / "r.parquet"
    part = Path(str(out) + ".part")
    child = subprocess.Popen([sys.executable, "-c", SLOW_SWEEP.format(resume=""), drop, out])
    start = time.monotonic()
    while not part.exists() or len(part.read_text().splitlines()) < 3:
        assert time.monotonic() - start < 120, "no run finished"
        assert child.poll() is None, "the sweep ended before it could be interrupted"
        time.sleep(0.02)
    os.kill(child.pid, signal.SIGINT)
    assert child.wait(timeout=120) != 0
    partial = pq.read_table(out).to_pylist()
    assert len(partial) == 40
    finished = [r for r in partial if r["status"] == "ok"]
    assert 3 <= len(finished) < 40
    assert {r["status"] for r in partial} <= {"ok", "cancelled"}
    assert part.exists()
    subprocess.run(
        [sys.executable, "-c", SLOW_SWEEP.format(resume=", resume=True"), drop, out], check=True
    )
    assert not part.exists()
    whole = tmp_path / "whole.parquet"
    subprocess.run([sys.executable, "-c", SLOW_SWEEP.format(resume=""), drop, whole], check=True)
    assert pq.read_table(out).equals(pq.read_table(whole))


def test_trajectories_are_written_per_run_as_tumble_run_writes_them(drop: Path, tmp_path: Path):
    assert CLI.exists(), "make python-test builds target/release/tumble first"
    table = tumble.sweep(
        drop,
        {"bodies[ball].restitution": [0.3, 0.8]},
        steps=50,
        metrics=["ball.z"],
        trajectories=tmp_path / "runs",
        progress=False,
    )
    paths = table.column("trajectory").to_pylist()
    assert [Path(p).name for p in paths] == ["run_00000.csv", "run_00001.csv"]
    # Run 1's trajectory is the one `tumble run` writes for the same scene and value.
    scene = tmp_path / "e08.toml"
    scene.write_text(drop.read_text().replace("restitution = 0.5", "restitution = 0.8"))
    by_run = tmp_path / "by_run.csv"
    subprocess.run(
        [CLI, "run", scene, "--steps", "50", "--quiet", "--trajectory", by_run], check=True
    )
    assert Path(paths[1]).read_text() == by_run.read_text()
    last_z = float(Path(paths[1]).read_text().splitlines()[-1].split(",")[4])
    assert last_z == pytest.approx(table.column("ball.z").to_pylist()[1], abs=1e-12)
