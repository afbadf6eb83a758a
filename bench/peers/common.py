"""Shared scene loading and reporting for the peer-engine scripts.

Every scene is defined once, in Rust (`tumble::scenes`): `load_scene` asks the tumble binary
for its plain form (`tumble bench --scene S --export-scene -`: every body in its body frame,
i.e. centre of mass and principal axes, with the mass and principal inertia tumble computed,
its shapes posed in that frame, materials, velocities, dt, gravity, steps and the scene's pass
marks). Each engine script only translates that data into its own API. Nothing
engine-specific lives here.
"""

import json
import math
import os
import platform
import resource
import statistics
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PLAIN_SCENE_FORMAT = "tumble-plain-scene/1"
TORI_PLAIN_FORMAT = "tumble-tori-queries/1"


# ---------------------------------------------------------------- scenes (from tumble::scenes)
def tumble_binary():
    """The tumble CLI that exports the scenes: $TUMBLE_BIN, else target/release/tumble."""
    return os.environ.get("TUMBLE_BIN") or os.path.join(ROOT, "target", "release", "tumble")


def load_scene(name, n=None, poses=None):
    """The plain form of a standard scene (see the module doc); `n`: the pile's body count; for
    "tori" the torus and `poses` poses of torus B instead (format tumble-tori-queries/1).
    Raises RuntimeError naming the command when the binary is missing or refuses."""
    exe = tumble_binary()
    cmd = [exe, "bench", "--scene", name, "--export-scene", "-"]
    cmd += ([] if n is None else ["--n", str(n)]) + (
        [] if poses is None else ["--poses", str(poses)]
    )
    if not os.path.exists(exe):
        raise RuntimeError(
            f"{exe} missing (cargo build --release -p tumble-cli): cannot export scene {name}"
        )
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed: {p.stderr.strip()}")
    scene = json.loads(p.stdout)
    want = TORI_PLAIN_FORMAT if name == "tori" else PLAIN_SCENE_FORMAT
    if scene.get("format") != want:
        raise RuntimeError(f"{' '.join(cmd)}: format {scene.get('format')!r}, expected {want!r}")
    return scene


def scene_for(args):
    """The scene a peer's parsed arguments ask for (`--scene`, `--n`, `--decomposed`)."""
    if args.scene == "pile":
        return load_scene("pile", args.n)
    if args.scene == "chain" and args.decomposed:
        return load_scene("chain_decomposed")
    return load_scene(args.scene)


def dynamic_indices(scene):
    """Indices of the scene's dynamic bodies, in order."""
    return [i for i, b in enumerate(scene["bodies"]) if b["kind"] == "dynamic"]


def pile_outside(scene, positions):
    """Centres outside the pile's container (|x| or |y| beyond the scene's limit, z < 0, NaN)."""
    w = scene["limits"]["inside_half_width"]
    return sum(
        1
        for p in positions
        if not all(math.isfinite(c) for c in p) or abs(p[0]) > w or abs(p[1]) > w or p[2] < 0.0
    )


def pyramid_figures(starts, ends):
    """Displacement of the top box (the last body) and the largest one, start to end (m)."""
    disp = [dist(a, b) for a, b in zip(starts, ends)]
    return {"top_box_displacement_m": disp[-1], "largest_displacement_m": max(disp)}


def pile_figures(scene, ends, contact_points):
    """Bodies outside the container, mean final height (m) and the engine's contact count."""
    return {
        "bodies_outside": pile_outside(scene, ends),
        "mean_final_height_m": sum(e[2] for e in ends) / len(ends),
        "contact_points": contact_points,
    }


def momentum_and_energy(masses, velocities):
    """Linear momentum (3-vector) and translational kinetic energy of point masses."""
    p = [sum(m * v[a] for m, v in zip(masses, velocities)) for a in range(3)]
    e = sum(0.5 * m * (v[0] ** 2 + v[1] ** 2 + v[2] ** 2) for m, v in zip(masses, velocities))
    return p, e


class ChainMonitor:
    """Interlock check of scenes.md: adjacent link centres never further apart than the
    scene's limit (1.8 m)."""

    def __init__(self, scene):
        self.limit = scene["limits"]["max_adjacent_centre_distance"]
        self.max_gap = 0.0

    def sample(self, centres):
        for a, b in zip(centres, centres[1:]):
            self.max_gap = max(self.max_gap, dist(a, b))

    def broken(self, centres):
        return sum(1 for a, b in zip(centres, centres[1:]) if dist(a, b) > self.limit)


def cradle_figures(scene, velocities):
    """Final velocities and the momentum and energy errors against the scene's start."""
    masses = [b["mass"] for b in scene["bodies"]]
    p0, e0 = momentum_and_energy(masses, [b["linear_velocity"] for b in scene["bodies"]])
    p, e = momentum_and_energy(masses, velocities)
    return {
        "final_velocities_x": [v[0] for v in velocities],
        "last_sphere_vx": velocities[4][0],
        "momentum_error": dist(p, p0) / math.sqrt(sum(x * x for x in p0)),
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


def children_peak_rss_bytes():
    """Peak resident set size of the largest finished child process (a native peer)."""
    return resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss * 1024


def emit(engine, version, scene, settings, figures, status="ok", peak_rss=None):
    """Prints one record; `peak_rss` (bytes) replaces this process's own peak when the work
    ran in a child."""
    obj = {
        "engine": engine,
        "version": version,
        "scene": scene,
        "status": status,
        "settings": settings,
        "figures": figures,
        "peak_rss_bytes": peak_rss_bytes() if peak_rss is None else peak_rss,
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
    ap.add_argument(
        "--decomposed",
        action="store_true",
        help="chain: the scene chain_decomposed (each link as 32 convex pieces), "
        "not the plain mesh",
    )
    for flag, typ, help_text in extra:
        ap.add_argument(flag, type=typ, default=None, help=help_text)
    args = ap.parse_args()
    if args.scene not in scenes:
        ap.error(f"unknown scene {args.scene!r}; expected one of {', '.join(scenes)}")
    if args.steps is not None and args.steps <= 0:
        ap.error("--steps must be positive")
    return args
