"""Shared scene data and reporting for the peer-engine scripts.

The scenes follow /work/shared/scenes.md (copied in spirit into docs/benchmarks.md): every
number here (layout, masses, dt, step counts) is the spec's, so each engine script only
translates these plain lists into its own API. Nothing engine-specific lives here.
"""

import json
import math
import platform
import resource
import statistics
import sys
import time

G = (0.0, 0.0, -9.81)
PAIR_FRICTION = 0.5

# Steps per scene at full length (scenes.md); scripts accept --steps to shorten (quick mode).
FULL_STEPS = {"pyramid": 600, "pile": 600, "chain": 600, "cradle": 240}
DT = {"pyramid": 1.0 / 60.0, "pile": 1.0 / 60.0, "chain": 1.0 / 60.0, "cradle": 1.0 / 240.0}


# ---------------------------------------------------------------- torus mesh (scenes.md)
def torus_mesh(big_r, small_r, n_major, n_minor):
    """Vertices and CCW-from-outside triangles exactly as in scenes.md "Torus mesh"."""
    verts = []
    for i in range(n_major):
        u = 2.0 * math.pi * i / n_major
        for j in range(n_minor):
            v = 2.0 * math.pi * j / n_minor
            rho = big_r + small_r * math.cos(v)
            verts.append((rho * math.cos(u), rho * math.sin(u), small_r * math.sin(v)))
    tris = []
    for i in range(n_major):
        i1 = (i + 1) % n_major
        for j in range(n_minor):
            j1 = (j + 1) % n_minor
            a = i * n_minor + j
            b = i1 * n_minor + j
            c = i1 * n_minor + j1
            d = i * n_minor + j1
            tris.append((a, b, c))
            tris.append((a, c, d))
    return verts, tris


# ---------------------------------------------------------------- rotations as quaternions (x, y, z, w)
def quat_axis_angle(axis, angle):
    s = math.sin(angle / 2.0)
    return (axis[0] * s, axis[1] * s, axis[2] * s, math.cos(angle / 2.0))


def quat_mul(a, b):
    """a * b (applies b first, then a), quaternions as (x, y, z, w)."""
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
        aw * bw - ax * bx - ay * by - az * bz,
    )


def quat_rotate(q, v):
    x, y, z, w = q
    # v' = v + 2 w (q x v) + 2 q x (q x v)
    cx = y * v[2] - z * v[1]
    cy = z * v[0] - x * v[2]
    cz = x * v[1] - y * v[0]
    ccx = y * cz - z * cy
    ccy = z * cx - x * cz
    ccz = x * cy - y * cx
    return (v[0] + 2 * (w * cx + ccx), v[1] + 2 * (w * cy + ccy), v[2] + 2 * (w * cz + ccz))


def rx(a):
    return quat_axis_angle((1.0, 0.0, 0.0), a)


def ry(a):
    return quat_axis_angle((0.0, 1.0, 0.0), a)


def rz(a):
    return quat_axis_angle((0.0, 0.0, 1.0), a)


# ---------------------------------------------------------------- scenes
def pyramid_boxes():
    """210 box centres, layer by layer, k ascending (top box last)."""
    out = []
    for i in range(20):
        n = 20 - i
        for k in range(n):
            out.append(((k - (n - 1) / 2.0) * 1.05, 0.0, 0.5 + i))
    return out


PYRAMID_GROUND = {"half": (50.0, 50.0, 0.5), "centre": (0.0, 0.0, -0.5)}
PYRAMID_HALF = 0.5
PYRAMID_MASS = 1.0


def pile_layers(n):
    if n % 100 != 0 or n <= 0:
        raise ValueError(f"pile: N must be a positive multiple of 100, got {n}")
    return n // 100


def pile_bodies(n):
    """(kind, centre, size, mass) for the N-body pile; kind 'sphere' (radius) or 'box' (half extent)."""
    out = []
    for k in range(pile_layers(n)):
        o = 0.1 if k % 2 == 1 else 0.0
        for j in range(10):
            for i in range(10):
                c = (-2.7 + 0.6 * i + o, -2.7 + 0.6 * j + o, 1.0 + 0.6 * k)
                if (i + j + k) % 2 == 0:
                    out.append(("sphere", c, 0.25, 4.0 / 3.0 * math.pi * 0.25**3))
                else:
                    out.append(("box", c, 0.25, 0.5**3))
    return out


def pile_container(n):
    """Static boxes (half extents, centre). Walls are 8 m high (half 4) for N <= 1000 and
    raised for taller grids so that they reach 1 m above the top layer's centre."""
    top = 1.0 + 0.6 * (pile_layers(n) - 1)
    hz = max(4.0, (top + 1.0) / 2.0)
    return [
        ((3.5, 3.5, 0.5), (0.0, 0.0, -0.5)),
        ((0.25, 3.5, hz), (3.25, 0.0, hz)),
        ((0.25, 3.5, hz), (-3.25, 0.0, hz)),
        ((3.0, 0.25, hz), (0.0, 3.25, hz)),
        ((3.0, 0.25, hz), (0.0, -3.25, hz)),
    ]


def pile_outside(positions):
    return sum(1 for p in positions if abs(p[0]) > 3.01 or abs(p[1]) > 3.01 or p[2] < 0.0)


CHAIN_R = 1.0
CHAIN_r = 0.2
CHAIN_MASS = 2.0 * math.pi**2 * CHAIN_R * CHAIN_r**2
CHAIN_INERTIA = (
    CHAIN_MASS * (CHAIN_R**2 / 2.0 + 5.0 * CHAIN_r**2 / 8.0),
    CHAIN_MASS * (CHAIN_R**2 / 2.0 + 5.0 * CHAIN_r**2 / 8.0),
    CHAIN_MASS * (CHAIN_R**2 + 3.0 * CHAIN_r**2 / 4.0),
)
CHAIN_MAX_GAP = 2.0 * CHAIN_R - 2.0 * CHAIN_r + 0.2  # 1.8 m


def chain_links():
    """21 (centre, quat xyzw); link 0 is the static anchor."""
    th = math.radians(60.0)
    e = (-math.sin(th), 0.0, -math.cos(th))
    out = []
    for k in range(21):
        c = (1.5 * k * e[0], 1.5 * k * e[1], 1.5 * k * e[2])
        if k % 2 == 0:
            q = quat_mul(ry(th), rx(math.pi / 2))
        else:
            q = quat_mul(ry(th), quat_mul(rz(math.pi / 2), rx(math.pi / 2)))
        out.append((c, q))
    return out


def chain_link_pieces(n_major=32, n_minor=12):
    """Convex decomposition of the link for peers that need one: piece i is the tube segment
    between rings i and i + 1 (its 2 n_minor vertices, whose hull every engine computes) and
    the 2 n_minor mesh triangles of that segment. 32 pieces as in scenes.md."""
    verts, tris = torus_mesh(CHAIN_R, CHAIN_r, n_major, n_minor)
    pieces = []
    for i in range(n_major):
        i1 = (i + 1) % n_major
        ids = [i * n_minor + j for j in range(n_minor)] + [i1 * n_minor + j for j in range(n_minor)]
        local = {g: k for k, g in enumerate(ids)}
        ptris = [tuple(local[x] for x in tris[2 * (i * n_minor + j) + h]) for j in range(n_minor) for h in (0, 1)]
        pieces.append(([verts[g] for g in ids], ptris))
    return pieces


class ChainMonitor:
    """Interlock check of scenes.md: adjacent link centres never further apart than 1.8 m."""

    def __init__(self):
        self.max_gap = 0.0

    def sample(self, centres):
        for a, b in zip(centres, centres[1:]):
            self.max_gap = max(self.max_gap, dist(a, b))

    @staticmethod
    def broken(centres):
        return sum(1 for a, b in zip(centres, centres[1:]) if dist(a, b) > CHAIN_MAX_GAP)


CRADLE_R = 0.1


def cradle_spheres():
    """(centre, velocity) for the 6 spheres: 5 at rest in a row, the striker last."""
    out = [((0.2 * i, 0.0, 0.0), (0.0, 0.0, 0.0)) for i in range(5)]
    out.append(((-0.5, 0.0, 0.0), (1.0, 0.0, 0.0)))
    return out


def cradle_figures(velocities, masses):
    p0 = 1.0  # striker: 1 kg at 1 m/s
    e0 = 0.5
    p = [sum(m * v[a] for m, v in zip(masses, velocities)) for a in range(3)]
    e = sum(0.5 * m * (v[0] ** 2 + v[1] ** 2 + v[2] ** 2) for m, v in zip(masses, velocities))
    return {
        "final_velocities_x": [v[0] for v in velocities],
        "last_sphere_vx": velocities[4][0],
        "momentum_error": math.sqrt((p[0] - p0) ** 2 + p[1] ** 2 + p[2] ** 2) / p0,
        "energy_error": (e - e0) / e0,
    }


def dist(a, b):
    return math.sqrt((a[0] - b[0]) ** 2 + (a[1] - b[1]) ** 2 + (a[2] - b[2]) ** 2)


# ---------------------------------------------------------------- timing and output
class StepTimer:
    """Wall time of the step call only (perf_counter around it)."""

    def __init__(self):
        self.samples = []

    def time(self, fn, *args):
        t0 = time.perf_counter()
        r = fn(*args)
        self.samples.append(time.perf_counter() - t0)
        return r

    def figures(self, unit="ms"):
        return timing_stats(self.samples, unit)


def timing_stats(samples, unit="ms"):
    """Median, spread (10th..90th percentile) and mean of a list of seconds, in `unit`."""
    scale = {"ms": 1e3, "us": 1e6}[unit]
    if not samples:
        return {"count": 0}
    s = sorted(samples)
    n = len(s)

    def pct(q):
        return s[min(n - 1, int(q * (n - 1) + 0.5))] * scale

    return {
        "unit": unit,
        "count": n,
        "median": statistics.median(s) * scale,
        "mean": statistics.fmean(s) * scale,
        "p10": pct(0.10),
        "p90": pct(0.90),
        "min": s[0] * scale,
        "max": s[-1] * scale,
    }


def peak_rss_bytes():
    """Peak resident set size of this process (Linux reports KiB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


def emit(engine, version, scene, settings, figures, status="ok"):
    obj = {
        "engine": engine,
        "version": version,
        "scene": scene,
        "status": status,
        "settings": settings,
        "figures": figures,
        "peak_rss_bytes": peak_rss_bytes(),
        "python": platform.python_version(),
    }
    json.dump(obj, sys.stdout, allow_nan=False, default=float)
    sys.stdout.write("\n")
    sys.stdout.flush()


def parse_args(scenes, description, extra=()):
    import argparse

    ap = argparse.ArgumentParser(description=description)
    ap.add_argument("--scene", required=True, help="one of: " + ", ".join(scenes))
    ap.add_argument("--steps", type=int, default=None, help="override step count (quick mode)")
    ap.add_argument("--n", type=int, default=1000, help="pile: number of bodies (multiple of 100)")
    ap.add_argument("--decomposed", action="store_true",
                    help="chain: links as 32 convex pieces (chain_link_pieces) instead of the plain mesh")
    for flag, typ, help_text in extra:
        ap.add_argument(flag, type=typ, default=None, help=help_text)
    args = ap.parse_args()
    if args.scene not in scenes:
        ap.error(f"unknown scene {args.scene!r}; expected one of {', '.join(scenes)}")
    if args.steps is not None and args.steps <= 0:
        ap.error("--steps must be positive")
    return args
