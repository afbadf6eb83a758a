"""Many worlds at once: :func:`rollout` steps a batch of worlds side by side.

The stepping is the Rust batch (``tumble::batch``): the worlds are spread over
the threads with the GIL released, each world stepped serially on its thread,
so each world's trajectory is the one it has stepped alone, bit for bit, for
any thread count. This module only shapes the arguments: worlds from a scene
or copies of one world, initial states, controls as an array or a callable.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from typing import Any, Union

import numpy as np

from ._tumble import InvalidArgument, World, _rollout, load_scene

#: Quantities :func:`rollout` can record (``record=``), with their columns per body.
RECORDABLE = {
    "positions": 3,
    "orientations": 4,
    "velocities": 3,
    "angular_velocities": 3,
    "centers_of_mass": 3,
    "states": 13,
}

WorldsLike = Union[World, Sequence[World], str, "os.PathLike[str]"]
Controls = Union[np.ndarray, Callable[[int, list[World]], Any], None]


def _worlds(worlds_or_scene: WorldsLike, states: np.ndarray | None) -> list[World]:
    if isinstance(worlds_or_scene, (str, os.PathLike)):
        base = load_scene(worlds_or_scene)
        count = 1 if states is None else len(states)
        return [base] + [base.copy() for _ in range(count - 1)]
    if isinstance(worlds_or_scene, World):
        count = 1 if states is None else len(states)
        return [worlds_or_scene.copy() for _ in range(count)]
    worlds = list(worlds_or_scene)
    if not worlds or not all(isinstance(w, World) for w in worlds):
        raise InvalidArgument(
            "worlds_or_scene: expected a World, a non-empty sequence of Worlds "
            "or a scene file path, "
            f"got {type(worlds_or_scene).__name__}"
        )
    return worlds


def _control_array(controls: Any, b: int, steps: int, n: int) -> np.ndarray:
    """Controls broadcast to (B, steps, N, 6)."""
    try:
        c = np.asarray(controls, dtype=np.float64)
    except (TypeError, ValueError) as e:
        raise InvalidArgument(f"controls: expected an array of forces and torques: {e}") from None
    shapes = {4: (b, steps, n, 6), 3: (steps, n, 6), 2: (n, 6)}
    want = shapes.get(c.ndim)
    if want is None or c.shape != want:
        raise InvalidArgument(
            f"controls: expected shape ({b}, {steps}, {n}, 6), ({steps}, {n}, 6) or ({n}, 6) "
            f"(force and torque per body, N and N m), got {c.shape}"
        )
    return np.ascontiguousarray(np.broadcast_to(c, (b, steps, n, 6)))


def rollout(
    worlds_or_scene: WorldsLike,
    steps: int,
    *,
    states: Any = None,
    controls: Controls = None,
    record: Sequence[str] = ("positions", "orientations"),
    threads: int | None = None,
    chunk: int = 1,
) -> dict[str, np.ndarray]:
    """Steps B worlds ``steps`` times side by side and returns what was recorded.

    Args:
        worlds_or_scene: a sequence of B distinct worlds (stepped in place:
            use ``world.copy()`` to keep the originals), one world (B copies
            of it are stepped, the world itself is left as it is), or a scene
            file path (B worlds built from it).
        steps: steps per world.
        states: None, or initial states, float (B, N, 13) laid out as
            :attr:`World.states` (position, orientation x y z w, velocity,
            angular velocity); with one world or a scene, B is ``len(states)``.
        controls: None; forces and torques (N, N m, world frame, at the
            centre of mass) applied during each step, float (B, T, N, 6),
            (T, N, 6) for every world or (N, 6) for every step; or a callable
            ``controls(step, worlds) -> array`` called before every ``chunk``
            steps, returning (B, N, 6) or (N, 6) held for those steps, or
            None (no forces: a callable that sets joint motor targets,
            ``joint.motor = {...}``, drives robots this way).
        record: names from :data:`RECORDABLE`.
        threads: threads of the batch (None or 0: every core, 1: serial).
            The results do not depend on it.
        chunk: steps between two calls of a callable ``controls``.

    Returns:
        dict: ``time`` (B, T), and for each recorded name an array
        (B, T, N, k) of its value after each step.

    Raises:
        InvalidArgument: bad worlds, shapes, names or values (nothing is
            stepped); KeyboardInterrupt between two chunks of 16 steps.
    """
    if not isinstance(steps, (int, np.integer)) or isinstance(steps, bool) or steps < 0:
        raise InvalidArgument(f"steps: expected an integer >= 0, got {steps!r}")
    if not isinstance(chunk, (int, np.integer)) or chunk < 1:
        raise InvalidArgument(f"chunk: expected an integer >= 1, got {chunk!r}")
    record = [record] if isinstance(record, str) else list(record)
    for name in record:
        if name not in RECORDABLE:
            raise InvalidArgument(
                f"record: unknown quantity {name!r}; expected some of {sorted(RECORDABLE)}"
            )
    threads = 0 if threads is None else int(threads)
    if threads < 0:
        raise InvalidArgument(f"threads: expected >= 0 (0: every core), got {threads}")
    if states is not None:
        states = np.asarray(states, dtype=np.float64)
        if states.ndim != 3 or states.shape[2] != 13:
            raise InvalidArgument(f"states: expected shape (B, N, 13), got {states.shape}")
    worlds = _worlds(worlds_or_scene, states)
    b, n = len(worlds), len(worlds[0])
    if states is not None:
        if len(states) != b:
            raise InvalidArgument(
                f"states: expected {b} rows of states (one per world), got {len(states)}"
            )
        for w, s in zip(worlds, states):
            w.set_states(s)
    if not callable(controls):
        c = None if controls is None else _control_array(controls, b, steps, n)
        return _rollout(worlds, int(steps), c, record, threads)
    parts: list[dict[str, np.ndarray]] = []
    done = 0
    while done < steps:
        k = min(chunk, steps - done)
        given = controls(done, worlds)
        if given is None:  # the callable set motor targets (or nothing) itself
            parts.append(_rollout(worlds, k, None, record, threads))
            done += k
            continue
        held = np.asarray(given, dtype=np.float64)
        if held.ndim == 2:
            held = held[None]
        if held.ndim != 3 or held.shape[1:] != (n, 6) or held.shape[0] not in (1, b):
            raise InvalidArgument(
                f"controls({done}, worlds) returned shape {held.shape}; "
                f"expected ({b}, {n}, 6) or ({n}, 6)"
            )
        c = np.ascontiguousarray(np.broadcast_to(held[:, None], (b, k, n, 6)))
        parts.append(_rollout(worlds, k, c, record, threads))
        done += k
    if not parts:
        return _rollout(worlds, 0, None, record, threads)
    return {key: np.concatenate([p[key] for p in parts], axis=1) for key in parts[0]}
