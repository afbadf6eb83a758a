"""Parameter sweeps: :func:`sweep` runs one world per combination of scene
parameters, on every core of this machine or as Ray tasks, into a table.

The runs, the metrics, the journal of finished runs and the table's columns
are the Rust sweep's (``tumble::sweep``, the same as ``tumble sweep`` on the
command line); this module chooses where the runs go and shows progress. A
run's row depends only on its parameters, so the Ray backend's table equals
the local one bit for bit.
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Mapping, Sequence
from typing import Any

from ._tumble import InvalidArgument, _SweepPlan

#: Default metrics of a sweep.
DEFAULT_METRICS = ("max_penetration", "energy_drift")


def _param_list(params: Mapping[str, Any]) -> list[tuple[str, str]]:
    if not isinstance(params, Mapping) or not params:
        raise InvalidArgument(
            "params: expected a non-empty dict of parameter path -> list of values, "
            'e.g. {"bodies[ball].restitution": [0.2, 0.5]}'
        )
    out = []
    for path, values in params.items():
        if hasattr(values, "tolist"):  # numpy arrays (and scalars)
            values = values.tolist()
        if isinstance(values, (str, bytes)) or not isinstance(values, Sequence):
            values = [values]
        values = [_plain(v) for v in values]
        bad = [v for v in values if isinstance(v, float) and not math.isfinite(v)]
        if bad:
            raise InvalidArgument(f"params[{path!r}]: values must be finite, got {bad[0]}")
        try:
            text = json.dumps(values, allow_nan=False)
        except (TypeError, ValueError) as e:
            raise InvalidArgument(
                f"params[{path!r}]: values must be numbers, text, booleans or lists: {e}"
            ) from None
        out.append((str(path), text))
    return out


def _plain(v: Any) -> Any:
    """numpy scalars and arrays as plain Python values."""
    if hasattr(v, "tolist"):
        return v.tolist()
    return v


def _run_chunk(
    scene: str,
    text: str,
    params: list[tuple[str, str]],
    steps: Any,
    duration: Any,
    metrics: list[str],
    indices: list[int],
    trajectories: str | None = None,
) -> list[tuple]:
    """One chunk of runs, serially (a Ray task): the plan is rebuilt from the scene's text."""
    plan = _SweepPlan(scene, params, steps, duration, metrics, text, trajectories)
    return plan.run(indices, 1)


def _progress(total: int, done: int, enabled: bool | None):
    if enabled is False:
        return None
    try:
        from tqdm.auto import tqdm
    except ImportError:  # pragma: no cover - tqdm is a dependency
        return None
    return tqdm(
        total=total, initial=done, unit="run", desc="sweep", disable=enabled is None and total < 16
    )


def sweep(
    scene: str | os.PathLike[str],
    params: Mapping[str, Any],
    *,
    steps: int | None = None,
    duration: float | None = None,
    metrics: Sequence[str] = DEFAULT_METRICS,
    backend: str = "local",
    address: str | None = None,
    threads: int | None = None,
    chunk_size: int | None = None,
    progress: bool | None = None,
    out: str | os.PathLike[str] | None = None,
    resume: bool = False,
    trajectories: str | os.PathLike[str] | None = None,
) -> Any:
    """Runs ``scene`` once per combination of parameter values and returns a table.

    Args:
        scene: a scene file (.toml or .json, docs/scenes.md).
        params: parameter path -> values. A path names a value of the scene
            file: ``settings.dt``, ``bodies[ball].restitution`` (a body by
            name, or ``bodies[2]``), ``bodies[ball].position[2]``,
            ``materials.rubber.friction``. One run per combination, the first
            parameter varying slowest.
        steps, duration: length of each run (steps, or simulated seconds in
            steps of the run's own dt); default the scene's.
        metrics: names of measures, each a column: ``max_penetration``,
            ``energy_start``, ``energy_end``, ``energy_drift``,
            ``kinetic_energy_end``, ``max_joint_error``, ``time``, and per body
            ``NAME.x``/``.y``/``.z``/``.max_z``/``.min_z``/``.speed``/``.rebound_z``.
        backend: ``"local"`` (every core of this machine) or ``"ray"`` (Ray
            tasks; needs ``pip install .[ray]``).
        address: the Ray cluster (``ray.init(address=...)``); None starts or
            joins a local one.
        threads: local threads (None or 0: every core).
        chunk_size: runs per task (Ray) or per progress update (local).
        progress: a tqdm progress bar (None: for 16 runs or more).
        out: also write the table there (.parquet, .csv or .json); finished
            runs are journaled to ``OUT.part`` as they end.
        resume: with ``out``, run only the runs not in ``OUT.part``.
        trajectories: a directory: each finished run's trajectory is written
            there as ``run_00007.csv`` (run 7; the CSV of ``tumble run
            --trajectory``) and named in a ``trajectory`` column. With Ray, a
            directory every worker can write (one machine, or shared storage).

    Returns:
        pyarrow.Table: one row per run: ``run``, the parameters, ``status``
        (ok, failed, cancelled), ``error``, ``steps``, the metrics. A run that
        fails is a row with its error; the others go on.

    Raises:
        SceneError: the scene file, or a parameter path it does not have
            (naming the path and the file).
        InvalidArgument: bad parameters, metrics, lengths or backend.
        KeyboardInterrupt: Ctrl-C; the running runs are cancelled, the
            finished ones are in ``OUT.part`` and (with ``out``) the table.
    """
    if backend not in ("local", "ray"):
        raise InvalidArgument(f'backend: expected "local" or "ray", got {backend!r}')
    if resume and out is None:
        raise InvalidArgument("resume: needs out= (the journal OUT.part of the earlier sweep)")
    if steps is not None and duration is not None:
        raise InvalidArgument("give steps or duration, not both")
    if threads is not None and (not isinstance(threads, int) or threads < 0):
        raise InvalidArgument(f"threads: expected an integer >= 0 (0: every core), got {threads!r}")
    if chunk_size is not None and (not isinstance(chunk_size, int) or chunk_size < 1):
        raise InvalidArgument(f"chunk_size: expected an integer >= 1, got {chunk_size!r}")
    scene = os.fspath(scene)
    plist = _param_list(params)
    metrics = [metrics] if isinstance(metrics, str) else [str(m) for m in metrics]
    traj = None if trajectories is None else os.fspath(trajectories)
    plan = _SweepPlan(scene, plist, steps, duration, metrics, None, traj)
    if out is not None:
        plan.open_journal(os.fspath(out) + ".part", resume)
    pending = plan.pending()
    bar = _progress(len(plan), len(plan) - len(pending), progress)
    try:
        if backend == "local":
            _run_local(plan, pending, threads or 0, chunk_size, bar)
        else:
            _run_ray(
                plan,
                scene,
                plist,
                steps,
                duration,
                metrics,
                pending,
                address,
                chunk_size,
                bar,
                traj,
            )
    except KeyboardInterrupt:
        if out is not None:
            plan.write(os.fspath(out))
        raise
    finally:
        if bar is not None:
            bar.close()
    if out is not None:
        plan.write(os.fspath(out))
        if not plan.pending():
            plan.close_journal()
    return _arrow(plan.table())


def _arrow(columns: dict[str, Any]) -> Any:
    """The plan's columns as a pyarrow Table, as a Parquet reader sees the
    file `tumble sweep` writes: text as strings, NaN (no value) as null."""
    import pyarrow as pa

    return pa.table(
        {
            name: pa.array(col, type=pa.string())
            if isinstance(col, list)
            else pa.array(col, from_pandas=True)
            for name, col in columns.items()
        }
    )


def _run_local(
    plan: _SweepPlan, pending: list[int], threads: int, chunk_size: int | None, bar
) -> None:
    cores = threads or os.cpu_count() or 1
    chunk = chunk_size or max(4 * cores, 16)
    for start in range(0, len(pending), chunk):
        rows = plan.run(pending[start : start + chunk], threads)
        if bar is not None:
            bar.update(len(rows))


def _run_ray(
    plan, scene, plist, steps, duration, metrics, pending, address, chunk_size, bar, traj
) -> None:
    try:
        import ray
    except ImportError:
        raise InvalidArgument(
            'backend="ray" needs Ray: pip install ".[ray]" (or pip install ray)'
        ) from None
    started = not ray.is_initialized()
    if started:
        ray.init(
            address=address, include_dashboard=False, log_to_driver=False, configure_logging=False
        )
    try:
        with open(scene, encoding="utf-8") as f:
            text = f.read()
        cpus = max(1, int(ray.cluster_resources().get("CPU", 1)))
        chunk = chunk_size or max(1, math.ceil(len(pending) / (4 * cpus)))
        task = ray.remote(num_cpus=1)(_run_chunk)
        refs = [
            task.remote(scene, text, plist, steps, duration, metrics, pending[i : i + chunk], traj)
            for i in range(0, len(pending), chunk)
        ]
        try:
            while refs:
                ready, refs = ray.wait(refs, num_returns=1)
                for rows in ray.get(ready):
                    plan.add_rows(rows)
                    if bar is not None:
                        bar.update(len(rows))
        except KeyboardInterrupt:
            for r in refs:
                ray.cancel(r, force=True)
            raise
    finally:
        if started:
            ray.shutdown()
