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
    # Parts of a scene no peer here builds a twin of: refused, not left out (that would be
    # other work than tumble's).
    for key, what in [
        ("gears", "joints held at a ratio of another's coordinate"),
        ("no_contact", "pairs of bodies kept apart"),
    ]:
        if scene.get(key):
            raise RuntimeError(f"scene {name}: {what} ({key}) have no twin in the peers")
    return scene


def scene_for(args):
    """The scene a peer's parsed arguments ask for (`--scene`, `--n`, `--decomposed`)."""
    if args.scene == "pile":
        return load_scene("pile", args.n)
    if args.scene == "chain" and args.decomposed:
        return load_scene("chain_decomposed")
    if args.scene == "concave_pile":
        # No peer engine here collides two dynamic concave meshes: CoACD's pieces always.
        return decomposed(load_scene("concave_pile"))[0]
    return load_scene(args.scene)


# CoACD (Wei et al., SIGGRAPH 2022; PyPI `coacd`, pinned in bench/requirements.txt) cuts the
# concave pile's meshes into convex pieces for the peers without concave-concave collision: its
# default concavity threshold, and a fixed seed so that every run gets the same pieces.
COACD_THRESHOLD = 0.05
COACD_SEED = 0
CACHE_DIR = os.path.join(ROOT, "target", "bench-cache")


def convex_pieces(mesh):
    """CoACD's convex pieces of a plain mesh ({"vertices", "triangles"}) as vertex lists, cached
    under target/bench-cache by the mesh and the settings (the 4,000-triangle blob takes ~20 s).
    Raises RuntimeError when coacd is not installed."""
    import hashlib

    try:
        from importlib.metadata import version as v

        import coacd
        import numpy as np
    except ImportError as e:
        raise RuntimeError(f"coacd is not installed (bench/setup.sh): {e}") from e
    key = json.dumps([mesh["vertices"], mesh["triangles"], COACD_THRESHOLD, COACD_SEED, v("coacd")])
    path = os.path.join(CACHE_DIR, f"coacd-{hashlib.sha256(key.encode()).hexdigest()[:20]}.json")
    if os.path.exists(path):
        with open(path) as f:
            return json.load(f)
    coacd.set_log_level("error")
    vertices = np.array(mesh["vertices"], dtype=float)
    triangles = np.array(mesh["triangles"], dtype=np.int64)
    parts = coacd.run_coacd(
        coacd.Mesh(vertices, triangles),
        threshold=COACD_THRESHOLD,
        seed=COACD_SEED,
    )
    pieces = [np.asarray(verts, dtype=float).tolist() for verts, _ in parts]
    os.makedirs(CACHE_DIR, exist_ok=True)
    tmp = f"{path}.{os.getpid()}"
    with open(tmp, "w") as f:
        json.dump(pieces, f)
    os.replace(tmp, path)
    return pieces


def decomposed(scene):
    """The scene with each triangle-mesh shape replaced by its CoACD pieces (convex hull shapes at
    the mesh shape's pose in its body frame), static meshes too (MuJoCo collides any mesh as its
    hull). Returns the scene and the pieces per mesh index."""
    pieces = {}
    for b in scene["bodies"]:
        shapes = []
        for s in b["shapes"]:
            if s["type"] != "mesh":
                shapes.append(s)
                continue
            if s["mesh"] not in pieces:
                pieces[s["mesh"]] = convex_pieces(scene["meshes"][s["mesh"]])
            frame = {"position": s["position"], "rotation": s["rotation"]}
            shapes += [dict(type="convex_hull", vertices=v, **frame) for v in pieces[s["mesh"]]]
        b["shapes"] = shapes
    # No shape names a mesh any more (an engine need not load them).
    scene["meshes"] = []
    return scene, pieces


def pieces_note(scene, unit):
    """What a decomposed scene's bodies are made of (its `collision` setting), `unit` naming an
    engine's pieces: CoACD's threshold and the fewest and most pieces of a body."""
    counts = [len(b["shapes"]) for b in scene["bodies"]]
    return (
        f"CoACD convex pieces (threshold {COACD_THRESHOLD}), the bin's too: "
        f"{min(counts)}-{max(counts)} {unit} per body"
    )


def concave_pile_figures(scene, ends, at_five, motions):
    """The concave pile's figures besides time and depth: bodies escaped from the bin (centre
    outside its inside or below its floor), kinetic energy 5 s in (`at_five`, J) and at the end
    (`motions` as for kinetic_energy)."""
    return {
        "bodies_escaped": pile_outside(scene, ends),
        "kinetic_energy_at_5s_j": at_five,
        "final_kinetic_energy_j": kinetic_energy(scene, motions),
    }


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


def pile_figures(scene, ends, contact_points, motions):
    """Bodies outside the container, mean final height (m), the engine's contact count, and the
    kinetic energy left at the end (J; `motions`: (linear velocity, world angular velocity,
    rotation) of each dynamic body, in order): whether the pile came to rest."""
    return {
        "bodies_outside": pile_outside(scene, ends),
        "mean_final_height_m": sum(e[2] for e in ends) / len(ends),
        "contact_points": contact_points,
        "final_kinetic_energy_j": kinetic_energy(scene, motions),
    }


def kinetic_energy(scene, motions):
    """Translational plus rotational kinetic energy (J) of the scene's dynamic bodies, from each
    one's (linear velocity, world angular velocity, rotation) in dynamic_indices order: the
    spin about each principal axis (body frame) against that principal moment."""
    total = 0.0
    for i, (v, w, q) in zip(dynamic_indices(scene), motions):
        b = scene["bodies"][i]
        spin = quat_rotate(quat_conj(q), w)
        total += 0.5 * b["mass"] * sum(c * c for c in v)
        total += 0.5 * sum(m * s * s for m, s in zip(b["principal_inertia"], spin))
    return total


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


class SwingMeter:
    """The bowl scene's swing, one angle per step: crossings of the bottom
    (times interpolated within the step) and turning points after the first
    crossing. The Python twin of tumble::scenes::SwingMeter (the harness runs
    on the standard library alone)."""

    def __init__(self, dt, start):
        self.dt, self.time, self.prev, self.prev_rate = dt, 0.0, start, 0.0
        self.crossings, self.turns = [], []

    def observe(self, angle):
        self.time += self.dt
        if (self.prev > 0.0) != (angle > 0.0):
            self.crossings.append(self.time - self.dt * angle / (angle - self.prev))
        rate = angle - self.prev
        if self.prev_rate != 0.0 and (rate > 0.0) != (self.prev_rate > 0.0) and self.crossings:
            self.turns.append(abs(self.prev))
        self.prev, self.prev_rate = angle, rate

    def period(self):
        return (self.crossings[4] - self.crossings[0]) / 2.0 if len(self.crossings) >= 5 else None

    def amplitude_after_two(self):
        return self.turns[3] if len(self.turns) >= 4 else None


def swing_angle(centre):
    """The bowl ball's angle from straight down about the origin, in the x-z plane (rad)."""
    return math.atan2(centre[0], -centre[2])


def bowl_figures(scene, meter):
    """Period and amplitude kept after two swings, against the rolling period of a
    solid ball (k = 2/5) on the circle of radius R - r at the start's amplitude."""
    start = scene["bodies"][1]["position"]
    path = math.sqrt(sum(x * x for x in start))
    phi0 = swing_angle(start)
    a, b = 1.0, math.sqrt(1.0 - math.sin(phi0 / 2) ** 2)
    while abs(a - b) > 1e-15 * a:
        a, b = (a + b) / 2.0, math.sqrt(a * b)
    want = 4.0 * math.sqrt(1.4 * path / 9.81) * math.pi / (2.0 * a)
    period, amplitude = meter.period(), meter.amplitude_after_two()
    return {
        "period_s": period,
        "rolling_period_s": want,
        "period_error": None if period is None else period / want - 1.0,
        "amplitude_kept": None if amplitude is None else amplitude / phi0,
    }


def dist(a, b):
    return math.sqrt((a[0] - b[0]) ** 2 + (a[1] - b[1]) ** 2 + (a[2] - b[2]) ** 2)


# ---------------------------------------------------------------- quaternions (x, y, z, w)
# (examples/python/collision_query.py has its own quat_mul: an example reads whole on its own,
# and this harness runs on the standard library alone, without tumble's package.)
def quat_mul(a, b):
    """The rotation `a` after `b`."""
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
        aw * bw - ax * bx - ay * by - az * bz,
    )


def quat_conj(q):
    return (-q[0], -q[1], -q[2], q[3])


def quat_rotate(q, v):
    """`v` turned by the unit quaternion `q`."""
    x, y, z, w = q
    cx, cy, cz = y * v[2] - z * v[1], z * v[0] - x * v[2], x * v[1] - y * v[0]
    ccx, ccy, ccz = y * cz - z * cy, z * cx - x * cz, x * cy - y * cx
    return (v[0] + 2 * (w * cx + ccx), v[1] + 2 * (w * cy + ccy), v[2] + 2 * (w * cz + ccz))


def rpy(q):
    """URDF roll, pitch, yaw of the rotation `q` (x, y, z, w): R = Rz(yaw) Ry(pitch) Rx(roll).
    At pitch +-90 degrees only roll -+ yaw is defined: yaw is taken as 0 there."""
    x, y, z, w = q
    r00, r10 = 1 - 2 * (y * y + z * z), 2 * (x * y + w * z)
    r01, r11 = 2 * (x * y - w * z), 1 - 2 * (x * x + z * z)
    r20, r21, r22 = 2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)
    cos_pitch = math.hypot(r00, r10)
    pitch = math.atan2(-r20, cos_pitch)
    if cos_pitch > 1e-9:
        return (math.atan2(r21, r22), pitch, math.atan2(r10, r00))
    # R01 = sin(pitch) sin(roll - sin(pitch) yaw), R11 = cos(roll - sin(pitch) yaw).
    return (math.atan2(-r01 if r20 > 0 else r01, r11), pitch, 0.0)


def to_local(position, rotation, point):
    """A world point in the frame (position, rotation)."""
    return quat_rotate(quat_conj(rotation), [point[k] - position[k] for k in range(3)])


def to_world(position, rotation, point):
    """A point of the frame (position, rotation) in the world."""
    r = quat_rotate(rotation, point)
    return (r[0] + position[0], r[1] + position[1], r[2] + position[2])


# ---------------------------------------------------------------- joints (jointed scenes)
class JointAnchors:
    """Each joint's anchor fixed in each of its bodies (as tumble defines a joint: the frames at
    creation), to measure a peer's joint error from body poses alone: the distance between a
    joint's two anchors, whatever coordinates the engine keeps."""

    def __init__(self, scene):
        bodies = scene["bodies"]
        self.anchors = []
        for j in scene["joints"]:
            a, b = j["body_a"], j["body_b"]
            pa = j["anchor"]
            pb = j["anchor_b"] if j["anchor_b"] is not None else pa
            local_a = to_local(bodies[a]["position"], bodies[a]["rotation"], pa)
            local_b = (
                pb if b is None else to_local(bodies[b]["position"], bodies[b]["rotation"], pb)
            )
            self.anchors.append((a, local_a, b, local_b))

    def largest_error(self, poses):
        """The largest anchor gap (m) for body poses [(position, rotation xyzw)] in scene order."""
        worst = 0.0
        for a, la, b, lb in self.anchors:
            wa = to_world(*poses[a], la)
            wb = lb if b is None else to_world(*poses[b], lb)
            d = dist(wa, wb)
            worst = max(worst, d if math.isfinite(d) else math.inf)
        return worst


def joint_figures(scene, anchors, worst, poses):
    """The jointed scenes' figures as tumble and Rapier report them: the largest anchor gap over
    the run (sampled every 10 steps) and at the end (m); the heavy chain's weight distance from
    the pivot at (0, 0, 2) (2.1 m when nothing stretches); the ragdoll pile's dynamic bodies
    below the ground (z < 0) or lost (NaN)."""
    f = {"largest_joint_error_m": worst, "final_joint_error_m": anchors.largest_error(poses)}
    if scene["name"] == "heavy_chain":
        f["weight_distance_m"] = dist(poses[-1][0], (0.0, 0.0, 2.0))
    else:
        f["bodies_below_ground"] = sum(
            1
            for i in dynamic_indices(scene)
            if not all(math.isfinite(c) for c in poses[i][0]) or poses[i][0][2] < 0.0
        )
    return f


def joint_trees(scene):
    """The scene's joints as kinematic trees, for engines with reduced coordinates: a list of
    (root, children) with `root` a body index (a floating base) or None (the world), and
    `children` the joints in breadth-first order as (parent body or None, child body, joint).
    A joint's child is the body further from the root. Raises ValueError for a loop, or for a
    tree attached to the world by more than one joint."""
    joints = scene["joints"]
    n = len(scene["bodies"])
    around = [[] for _ in range(n)]
    to_world_joints = []
    for k, j in enumerate(joints):
        a, b = j["body_a"], j["body_b"]
        if b is None:
            to_world_joints.append(k)
        else:
            around[b].append((a, k))
            around[a].append((b, k))
    trees, placed, used = [], [False] * n, set()

    def grow(order, queue):
        """Breadth-first from the bodies in `queue` over joints not yet used."""
        head = 0
        while head < len(queue):
            body = queue[head]
            head += 1
            for other, k in around[body]:
                if k in used:
                    continue
                used.add(k)
                if placed[other]:
                    raise ValueError(f"joint {k}: the joints make a loop (no tree)")
                placed[other] = True
                order.append((body, other, k))
                queue.append(other)
        return order

    for k in to_world_joints:
        a = joints[k]["body_a"]
        if placed[a]:
            raise ValueError(f"joint {k}: a second joint to the world on one tree")
        placed[a] = True
        trees.append((None, grow([(None, a, k)], [a])))
    for i in range(n):
        if around[i] and not placed[i]:
            placed[i] = True
            trees.append((i, grow([], [i])))
    return trees


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
        "not the plain mesh (the concave pile is always decomposed, by CoACD)",
    )
    for flag, typ, help_text in extra:
        ap.add_argument(flag, type=typ, default=None, help=help_text)
    args = ap.parse_args()
    if args.scene not in scenes:
        ap.error(f"unknown scene {args.scene!r}; expected one of {', '.join(scenes)}")
    if args.steps is not None and args.steps <= 0:
        ap.error("--steps must be positive")
    return args
