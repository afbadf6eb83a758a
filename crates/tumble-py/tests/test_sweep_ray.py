"""tumble.sweep on Ray: a cluster started by the test on this machine (2 CPUs,
loopback) runs a 16-run sweep whose table equals the local backend's bit for
bit, from Python and from `tumble sweep --ray`. Ray is a test dependency
(requirements-dev.txt): if it is missing, this file fails, it does not skip.
"""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

import pyarrow.parquet as pq
import pytest
import ray

import tumble

ROOT = Path(__file__).resolve().parents[3]
CLI = ROOT / "target" / "release" / "tumble"
DOMINO = ROOT / "examples" / "scenes" / "domino.toml"
PARAMS = {
    "settings.dt": [1 / 240, 1 / 120, 1 / 60, 1 / 30],
    "materials.default.friction": [0.2, 0.4, 0.6, 0.8],
}
METRICS = ["max_penetration", "energy_drift", "kinetic_energy_end", "domino9.z", "domino0.max_z"]


@pytest.fixture(scope="module")
def cluster():
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False, configure_logging=False)
    yield
    ray.shutdown()


def test_a_ray_sweep_equals_the_local_one_bit_for_bit(cluster):
    local = tumble.sweep(DOMINO, PARAMS, duration=1.0, metrics=METRICS, progress=False)
    assert local.num_rows == 16
    assert local.column("status").to_pylist() == ["ok"] * 16
    on_ray = tumble.sweep(
        DOMINO, PARAMS, duration=1.0, metrics=METRICS, backend="ray", chunk_size=3, progress=False
    )
    assert on_ray.equals(local)
    # The dominoes fell differently with different settings: the table is not 16 copies.
    assert len(set(local.column("energy_drift").to_pylist())) == 16


def test_tumble_sweep_on_ray_writes_the_local_table(cluster, tmp_path: Path):
    assert CLI.exists(), "make python-test builds target/release/tumble first"
    local = tmp_path / "local.parquet"
    on_ray = tmp_path / "ray.parquet"
    args = [
        CLI,
        "sweep",
        DOMINO,
        "--param",
        "settings.substeps=4,8",
        "--param",
        "materials.default.friction=0.3,0.7",
    ]
    args += ["--duration", "0.5", "--metric", ",".join(METRICS), "--quiet"]
    subprocess.run(args + ["--out", local], check=True)
    env = dict(os.environ, TUMBLE_PYTHON=str(Path(os.sys.executable)))
    address = ray.get_runtime_context().gcs_address
    subprocess.run(args + ["--out", on_ray, "--ray", address], check=True, env=env)
    assert pq.read_table(on_ray).equals(pq.read_table(local))
