"""Brute-force numpy oracles for the query tests, independent of tumble's
Rust code: triangle-triangle intersection by the separating axis theorem,
point-triangle and segment-segment distances (Ericson, Real-Time Collision
Detection 5.1.2, 5.1.5, 5.1.9), quaternion and matrix poses."""

from __future__ import annotations

import numpy as np

#: Separations within this band (m) are too close to call in floating point.
AMBIGUOUS = 1e-9


def rotation(q: np.ndarray) -> np.ndarray:
    """Rotation matrix of a unit quaternion (x, y, z, w)."""
    x, y, z, w = np.asarray(q, dtype=float) / np.linalg.norm(q)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def matrix(position, q) -> np.ndarray:
    """4x4 homogeneous matrix of a pose."""
    m = np.eye(4)
    m[:3, :3] = rotation(q)
    m[:3, 3] = position
    return m


def world_triangles(vertices, faces, position=(0, 0, 0), q=(0, 0, 0, 1)) -> np.ndarray:
    """(M, 3, 3) triangle corners placed by the pose."""
    v = np.asarray(vertices, dtype=float) @ rotation(q).T + np.asarray(position, dtype=float)
    return v[np.asarray(faces)]


def random_quaternion(rng: np.random.Generator) -> np.ndarray:
    q = rng.normal(size=4)
    return q / np.linalg.norm(q)


def triangle_separation(ta: np.ndarray, tb: np.ndarray) -> np.ndarray:
    """(Na, Nb) largest gap (m) over the separating axes of every pair of
    closed triangles: > 0 separated, <= 0 intersecting (SAT: both normals, the
    9 edge cross products, and the 6 in-plane edge normals for coplanar pairs)."""
    ea = np.roll(ta, -1, axis=1) - ta  # (Na, 3, 3) edges k -> k + 1
    eb = np.roll(tb, -1, axis=1) - tb
    na = np.cross(ea[:, 0], ea[:, 1])  # (Na, 3)
    nb = np.cross(eb[:, 0], eb[:, 1])
    Na, Nb = len(ta), len(tb)
    axes = [
        np.broadcast_to(na[:, None, None], (Na, Nb, 1, 3)),
        np.broadcast_to(nb[None, :, None], (Na, Nb, 1, 3)),
        np.cross(ea[:, None, :, None], eb[None, :, None, :]).reshape(Na, Nb, 9, 3),
        np.broadcast_to(np.cross(na[:, None], ea)[:, None], (Na, Nb, 3, 3)),
        np.broadcast_to(np.cross(nb[:, None], eb)[None], (Na, Nb, 3, 3)),
    ]
    axes = np.concatenate(axes, axis=2)  # (Na, Nb, 17, 3)
    length = np.linalg.norm(axes, axis=-1)
    pa = np.einsum("abkd,avd->abkv", axes, ta)  # (Na, Nb, 17, 3 corners)
    pb = np.einsum("abkd,bvd->abkv", axes, tb)
    gap = np.maximum(pb.min(-1) - pa.max(-1), pa.min(-1) - pb.max(-1))
    with np.errstate(invalid="ignore", divide="ignore"):
        gap = np.where(length > 1e-12, gap / length, -np.inf)
    return gap.max(axis=-1)


def point_segment_distance(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distance from points p to segments ab (broadcasting over leading axes)."""
    d = b - a
    t = np.clip(np.einsum("...d,...d->...", p - a, d) / np.einsum("...d,...d->...", d, d), 0, 1)
    return np.linalg.norm(p - (a + t[..., None] * d), axis=-1)


def point_triangle_distance(p: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """(Np, Nt) distance from points (Np, 3) to closed triangles (Nt, 3, 3)."""
    p = p[:, None, :]
    a, b, c = tri[None, :, 0], tri[None, :, 1], tri[None, :, 2]
    n = np.cross(b - a, c - a)
    n = n / np.linalg.norm(n, axis=-1, keepdims=True)
    height = np.einsum("ptd,ptd->pt", p - a, n)
    foot = p - height[..., None] * n
    # Inside when the foot is on the inner side of every edge.
    inside = np.ones(height.shape, dtype=bool)
    for u, v in ((a, b), (b, c), (c, a)):
        inside &= np.einsum("ptd,ptd->pt", np.cross(v - u, foot - u), n) >= 0
    edges = np.minimum.reduce(
        [
            point_segment_distance(p, a, b),
            point_segment_distance(p, b, c),
            point_segment_distance(p, c, a),
        ]
    )
    return np.where(inside, np.abs(height), edges)


def segment_distance(p1, q1, p2, q2) -> np.ndarray:
    """Distance between segments p1q1 and p2q2 (broadcasting; non-degenerate)."""
    d1, d2, r = q1 - p1, q2 - p2, p1 - p2
    a = np.einsum("...d,...d->...", d1, d1)
    e = np.einsum("...d,...d->...", d2, d2)
    f = np.einsum("...d,...d->...", d2, r)
    c = np.einsum("...d,...d->...", d1, r)
    b = np.einsum("...d,...d->...", d1, d2)
    denom = a * e - b * b
    with np.errstate(invalid="ignore", divide="ignore"):
        s = np.where(denom > 1e-300, np.clip((b * f - c * e) / denom, 0, 1), 0.0)
        t = (b * s + f) / e
        s = np.where(t < 0, np.clip(-c / a, 0, 1), np.where(t > 1, np.clip((b - c) / a, 0, 1), s))
    t = np.clip(t, 0, 1)
    return np.linalg.norm(p1 + s[..., None] * d1 - p2 - t[..., None] * d2, axis=-1)


def soup_distance(ta: np.ndarray, tb: np.ndarray) -> float:
    """Minimum distance between two triangle soups that do not intersect: the
    minimum over vertex-triangle and edge-edge pairs (a disjoint pair's closest
    points always include a vertex or lie on two edges)."""
    vertex_face = min(
        point_triangle_distance(ta.reshape(-1, 3), tb).min(),
        point_triangle_distance(tb.reshape(-1, 3), ta).min(),
    )
    pa, qa = ta.reshape(-1, 3), np.roll(ta, -1, axis=1).reshape(-1, 3)
    pb, qb = tb.reshape(-1, 3), np.roll(tb, -1, axis=1).reshape(-1, 3)
    edge_edge = segment_distance(pa[:, None], qa[:, None], pb[None], qb[None]).min()
    return float(min(vertex_face, edge_edge))
