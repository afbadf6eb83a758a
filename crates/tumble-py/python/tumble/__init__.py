"""tumble: rigid body dynamics with exact triangle-mesh contact.

Conventions: SI units (m, kg, s), z is up, gravity (0, 0, -9.81) by default,
quaternions are (x, y, z, w), angular velocity is in the world frame.

    >>> import tumble
    >>> world = tumble.World(dt=1 / 240)
    >>> ground = world.add_body(tumble.HalfSpace(), kind="static")
    >>> ball = world.add_body(tumble.Sphere(0.1), mass=1.0, position=(0, 0, 1))
    >>> world.step(240)
    >>> world.positions.shape
    (2, 3)

Collision queries without a world: :func:`collide`, :func:`distance` and
:func:`within_tolerance` on meshes (and primitives against meshes).
Scene files (docs/scenes.md): :func:`load_scene`. Many worlds at once:
:meth:`World.copy` and :func:`rollout`; parameter sweeps (locally or on
Ray): :func:`sweep`. Joints: :meth:`World.add_joint`;
robots from URDF files: :func:`load_urdf`.

Errors: everything tumble raises is a :class:`TumbleError`; bad arguments are
:class:`InvalidArgument` (also a ``ValueError``), handles of removed bodies
:class:`StaleBodyError`, bad scene files :class:`SceneError` (also a
``ValueError``), file problems :class:`FileError` (also an ``OSError``).
"""

from __future__ import annotations

import ast as _ast

import numpy as _np

from ._batch import RECORDABLE, rollout
from ._query import CollisionResult, DistanceResult, QueryStats
from ._records import ContactEvent, MassProperties
from ._sweep import sweep
from ._tumble import CONTACT_DTYPE_SPEC as _CONTACT_DTYPE_SPEC
from ._tumble import QUERY_CONTACT_DTYPE_SPEC as _QUERY_CONTACT_DTYPE_SPEC
from ._tumble import (
    Body,
    Box,
    Capsule,
    ConvexHull,
    FileError,
    HalfSpace,
    InternalError,
    InvalidArgument,
    Joint,
    Placed,
    Robot,
    SceneError,
    Sphere,
    StaleBodyError,
    StepReport,
    TriMesh,
    TumbleError,
    World,
    __version__,
    collide,
    distance,
    load_scene,
    load_urdf,
    mass_properties,
    within_tolerance,
)

#: dtype of the structured array returned by :meth:`World.contacts`.
CONTACT_DTYPE: _np.dtype = _np.dtype(_ast.literal_eval(_CONTACT_DTYPE_SPEC))

#: dtype of the contacts of :func:`collide` with ``report="contacts"``: ``point`` (3),
#: ``normal`` (3, from B to A), ``distance``, ``depth = -distance``, ``kind``, and
#: ``feature_a``, ``feature_b`` as ``(index, part, k)``: the triangle (or primitive
#: feature) index, "vertex", "edge", "face" or "whole", and the corner or edge number
#: within the triangle (edge k joins corners k and k + 1; -1 for a face or whole).
QUERY_CONTACT_DTYPE: _np.dtype = _np.dtype(_ast.literal_eval(_QUERY_CONTACT_DTYPE_SPEC))

#: Integrator names accepted by ``World(integrator=...)``.
INTEGRATORS = ("euler", "midpoint", "rk4", "semi_implicit", "semi_implicit_splitting")

__all__ = [
    "CONTACT_DTYPE",
    "INTEGRATORS",
    "QUERY_CONTACT_DTYPE",
    "RECORDABLE",
    "Body",
    "Joint",
    "Box",
    "Capsule",
    "CollisionResult",
    "ContactEvent",
    "ConvexHull",
    "DistanceResult",
    "FileError",
    "HalfSpace",
    "InternalError",
    "InvalidArgument",
    "MassProperties",
    "Placed",
    "Robot",
    "QueryStats",
    "SceneError",
    "Sphere",
    "StaleBodyError",
    "StepReport",
    "TriMesh",
    "TumbleError",
    "World",
    "__version__",
    "collide",
    "distance",
    "load_scene",
    "load_urdf",
    "mass_properties",
    "rollout",
    "sweep",
    "within_tolerance",
]
