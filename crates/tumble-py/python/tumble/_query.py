"""Results of the collision queries :func:`tumble.collide` and
:func:`tumble.distance`: small frozen dataclasses holding numpy arrays, built
by the native module. Fields cannot be reassigned; the arrays are the
caller's own copies. Equality is identity (arrays have no single truth value)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class QueryStats:
    """Work done by one query (as PQP reports it).

    Attributes:
        bv_tests: bounding-volume tests (box-box, or box against the primitive).
        triangle_tests: exact triangle tests (overlap, distance or contacts).
        stopped_early: the walk ended early (first contact found, distance 0).
    """

    bv_tests: int
    triangle_tests: int
    stopped_early: bool


@dataclass(frozen=True, eq=False)
class CollisionResult:
    """Result of :func:`tumble.collide`; true when the shapes intersect.

    Attributes:
        intersect: some closed triangle of A shares a point with some closed
            triangle of B (touching counts); for a primitive, with the solid.
        pairs: intersecting triangle pairs, int64 array of shape (K, 2), rows
            (triangle of A, triangle of B), sorted, no repeats; the index of a
            primitive is 0. With ``stop_at_first`` at most one row; with
            ``report="bool"`` empty.
        contacts: with ``report="contacts"`` a structured array of dtype
            :data:`tumble.QUERY_CONTACT_DTYPE` (world frame, normal from B
            to A, ``distance < 0`` / ``depth > 0`` for penetration, the
            features of A and B); otherwise ``None``.
        stats: the work counters.
    """

    intersect: bool
    pairs: np.ndarray
    contacts: np.ndarray | None
    stats: QueryStats

    def __bool__(self) -> bool:
        return self.intersect

    def __repr__(self) -> str:
        contacts = "None" if self.contacts is None else f"<{len(self.contacts)} contacts>"
        return (
            f"CollisionResult(intersect={self.intersect}, pairs=<{len(self.pairs)} pairs>, "
            f"contacts={contacts}, stats={self.stats!r})"
        )


@dataclass(frozen=True, eq=False)
class DistanceResult:
    """Result of :func:`tumble.distance`.

    Attributes:
        distance: distance between the shapes (m); 0 when they intersect. With
            ``rel_err`` or ``abs_err`` an upper bound within that error.
        point_a: closest point on A (world frame, m), shape (3,); a common
            point when they intersect.
        point_b: closest point on B (world frame, m), shape (3,).
        tri_a: triangle of A holding ``point_a`` (0 for a primitive).
        tri_b: triangle of B holding ``point_b`` (0 for a primitive).
        stats: the work counters.
    """

    distance: float
    point_a: np.ndarray
    point_b: np.ndarray
    tri_a: int
    tri_b: int
    stats: QueryStats

    def __float__(self) -> float:
        return self.distance

    def __repr__(self) -> str:
        a = np.array2string(self.point_a, precision=6, separator=", ")
        b = np.array2string(self.point_b, precision=6, separator=", ")
        return (
            f"DistanceResult(distance={self.distance!r}, point_a={a}, point_b={b}, "
            f"tri_a={self.tri_a}, tri_b={self.tri_b}, stats={self.stats!r})"
        )
