"""Plain records returned by tumble: named tuples, so they unpack, compare,
pickle and print like tuples. Built by the native module."""

from __future__ import annotations

from typing import TYPE_CHECKING, NamedTuple

import numpy as np

if TYPE_CHECKING:
    from ._tumble import Body


class MassProperties(NamedTuple):
    """Mass properties of a solid (from :func:`tumble.mass_properties`).

    Attributes:
        volume: volume of the solid (m^3); for a shell fallback, the area (m^2).
        mass: total mass (kg).
        com: centre of mass (m), shape (3,).
        inertia: inertia tensor about the centre of mass in the mesh's axes
            (kg m^2), shape (3, 3), symmetric.
        principal_moments: principal moments of inertia, ascending (kg m^2),
            shape (3,).
        principal_axes: principal axes as columns, shape (3, 3), a rotation:
            ``inertia == principal_axes @ diag(principal_moments) @ principal_axes.T``.
        method: "solid", or the fallback used: "convex_hull" or "shell".
    """

    volume: float
    mass: float
    com: np.ndarray
    inertia: np.ndarray
    principal_moments: np.ndarray
    principal_axes: np.ndarray
    method: str


class ContactEvent(NamedTuple):
    """Two bodies started ("begin") or stopped ("end") touching during a step.

    Attributes:
        kind: "begin" or "end".
        body_a: one body (handles of removed bodies are stale).
        body_b: the other body.
        time: simulated time at the end of the step that saw it (s).
    """

    kind: str
    body_a: Body
    body_b: Body
    time: float
