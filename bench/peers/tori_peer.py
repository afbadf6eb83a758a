"""Tori collision-query peers (scenes.md "tori"): python-fcl (OBBRSS), native FCL (OBBRSS, the
same library called from C++: target/release/peer-fcl, built by bench/setup.sh) and coal
(OBBRSS, OBB).

For each of the 200 poses of torus B, each query runs from scratch (new result object,
no cached guess): (1) first contact, boolean, early exit; (2) all intersecting triangle
pairs (no contact data); (3) all pairs with contact data; (4) minimum distance, at the
poses the ground truth says are separated. Pair counts are checked per pose against
/work/shared/data/tori_pairs.json (exact predicates). Times are perf_counter around the
single binding call, so they include the Python-binding overhead (~1-2 us); native FCL's are
steady_clock around the single C++ call (python-fcl's calls also build a Python object per
contact, which the native peer shows).
"""

import argparse
import json
import os
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common as C  # noqa: E402
import numpy as np  # noqa: E402

TRUTH = os.environ.get(
    "TORI_TRUTH",
    os.path.join(
        os.path.dirname(os.path.abspath(__file__)),
        "..",
        "..",
        "..",
        "shared",
        "data",
        "tori_pairs.json",
    ),
)
BIG = 1_000_000  # "all pairs": far above the 416 pairs of the worst pose


def rotation_matrix(q):
    """3x3 matrix of the unit quaternion (x, y, z, w)."""
    x, y, z, w = q
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def tori_arrays(t):
    """The tori scene (its one definition in tumble, `tumble bench --scene tori --export-scene
    -`) as the bindings take it: the torus as (vertices, triangles) arrays and the poses of B
    as [(index, rotation, translation)]."""
    v = np.array(t["mesh"]["vertices"], dtype=np.float64)
    tris = np.array(t["mesh"]["triangles"], dtype=np.int64)
    return (v, tris), [
        (p["index"], rotation_matrix(p["rotation"]), np.array(p["position"])) for p in t["poses"]
    ]


def split_stats(times, colliding):
    return {
        "all": C.timing_stats(times, "us"),
        "colliding": C.timing_stats([t for t, c in zip(times, colliding) if c], "us"),
        "separated": C.timing_stats([t for t, c in zip(times, colliding) if not c], "us"),
    }


def pair_check(counts, truth):
    diffs = [c - t for c, t in zip(counts, truth)]
    return {
        "total_pairs": sum(counts),
        "truth_total_pairs": sum(truth),
        "colliding_poses": sum(1 for c in counts if c > 0),
        "truth_colliding_poses": sum(1 for t in truth if t > 0),
        "poses_differing": sum(1 for d in diffs if d != 0),
        "max_abs_pose_difference": max(abs(d) for d in diffs),
        "within_two_pairs": abs(sum(counts) - sum(truth)) <= 2,
    }


def query_figures(truth, first, hit, allp, counts, withc, counts_c, dist, dvals, tree_bytes):
    """The record's figures from one library's timings (s) and answers at the poses run."""
    col = [c > 0 for c in truth]
    return {
        "first_contact": split_stats(first, col),
        "first_contact_colliding_poses": sum(hit),
        "all_pairs": split_stats(allp, col),
        "all_pairs_check": pair_check(counts, truth),
        "all_pairs_with_contacts": split_stats(withc, col),
        "all_pairs_with_contacts_check": pair_check(counts_c, truth),
        "distance_separated": C.timing_stats(dist, "us"),
        "distance_min_m": min(dvals) if dvals else None,
        "distance_negative_at_separated_poses": sum(1 for d in dvals if d < 0),
        "tree_memory_bytes": tree_bytes,
    }


def run_fcl(mesh, ps, truth):
    from importlib.metadata import version

    import fcl

    v, t = mesh

    def model():
        m = fcl.BVHModel()
        m.beginModel(len(v), len(t))
        m.addSubModel(v, t)
        m.endModel()
        return m

    ma, mb = model(), model()
    oa = fcl.CollisionObject(ma, fcl.Transform())
    ob = fcl.CollisionObject(mb, fcl.Transform())
    first, allp, withc, dist = [], [], [], []
    hit, counts, counts_c, dvals = [], [], [], []
    for (rot, tr), tp in zip(ps, truth):
        ob.setTransform(fcl.Transform(rot, tr))
        req = fcl.CollisionRequest(num_max_contacts=1, enable_contact=False)
        res = fcl.CollisionResult()
        t0 = time.perf_counter()
        fcl.collide(oa, ob, req, res)
        first.append(time.perf_counter() - t0)
        hit.append(res.is_collision)
        req = fcl.CollisionRequest(num_max_contacts=BIG, enable_contact=False)
        res = fcl.CollisionResult()
        t0 = time.perf_counter()
        fcl.collide(oa, ob, req, res)
        allp.append(time.perf_counter() - t0)
        counts.append(len(res.contacts))
        req = fcl.CollisionRequest(num_max_contacts=BIG, enable_contact=True)
        res = fcl.CollisionResult()
        t0 = time.perf_counter()
        fcl.collide(oa, ob, req, res)
        withc.append(time.perf_counter() - t0)
        counts_c.append(len(res.contacts))
        if tp == 0:
            dreq = fcl.DistanceRequest()
            dres = fcl.DistanceResult()
            t0 = time.perf_counter()
            d = fcl.distance(oa, ob, dreq, dres)
            dist.append(time.perf_counter() - t0)
            dvals.append(d)
    return [
        {
            "engine": "python-fcl",
            "version": version("python-fcl"),
            "bv": "OBBRSS",
            "figures": query_figures(
                truth, first, hit, allp, counts, withc, counts_c, dist, dvals, tree_bytes=None
            ),
            "notes": "python-fcl exposes only OBBRSS BVH models; tree memory is not exposed",
        }
    ]


PEER_FCL = os.path.join(
    os.path.dirname(os.path.abspath(__file__)), "..", "..", "target", "release", "peer-fcl"
)


def run_fcl_native(scene, truth):
    """FCL through its C++ API (bench/peers/fcl_native/peer_fcl.cpp): the same queries, timed
    natively; its raw answers become the record's figures here, as every library's do."""
    if not os.path.exists(PEER_FCL):
        raise ModuleNotFoundError(f"{PEER_FCL} missing: bash bench/setup.sh builds it (libfcl-dev)")
    request = {"scene": scene, "distance_at": [t == 0 for t in truth]}
    p = subprocess.run(
        [PEER_FCL], input=json.dumps(request), capture_output=True, text=True, timeout=3600
    )
    if p.returncode != 0:
        raise RuntimeError(f"{PEER_FCL} failed: {p.stderr.strip()}")
    r = json.loads(p.stdout)
    figures = query_figures(
        truth,
        r["first"],
        r["hit"],
        r["all_pairs"],
        r["counts"],
        r["with_contacts"],
        r["counts_with_contacts"],
        r["distance"],
        r["distances"],
        tree_bytes=r["tree_memory_bytes"],
    )
    return [
        {
            "engine": "fcl (native)",
            "version": r["version"],
            "bv": "OBBRSS",
            "figures": figures,
            "notes": "FCL's C++ API (Debian libfcl-dev), g++ -O2; tree memory: BV nodes, "
            "vertices and triangles (memUsage's sum; FCL 0.7's memUsage returns 0)",
        }
    ]


def run_coal(mesh, ps, truth, bv):
    from importlib.metadata import version

    import coal

    v, t = mesh

    def model():
        m = coal.BVHModelOBBRSS() if bv == "OBBRSS" else coal.BVHModelOBB()
        m.beginModel(len(t), len(v))
        m.addVertices(v)
        m.addTriangles(t)
        m.endModel()
        return m

    ma, mb = model(), model()
    ident = coal.Transform3s()
    first, allp, withc, dist = [], [], [], []
    hit, counts, counts_c, dvals = [], [], [], []
    dist_note = None
    for (rot, tr), tp in zip(ps, truth):
        tb = coal.Transform3s(rot, tr)
        req = coal.CollisionRequest(coal.CollisionRequestFlag.NO_REQUEST, 1)
        res = coal.CollisionResult()
        t0 = time.perf_counter()
        coal.collide(ma, ident, mb, tb, req, res)
        first.append(time.perf_counter() - t0)
        hit.append(res.isCollision())
        req = coal.CollisionRequest(coal.CollisionRequestFlag.NO_REQUEST, BIG)
        res = coal.CollisionResult()
        t0 = time.perf_counter()
        coal.collide(ma, ident, mb, tb, req, res)
        allp.append(time.perf_counter() - t0)
        counts.append(res.numContacts())
        req = coal.CollisionRequest(coal.CollisionRequestFlag.CONTACT, BIG)
        res = coal.CollisionResult()
        t0 = time.perf_counter()
        coal.collide(ma, ident, mb, tb, req, res)
        withc.append(time.perf_counter() - t0)
        counts_c.append(res.numContacts())
        if tp == 0 and dist_note is None:
            dreq = coal.DistanceRequest()
            dres = coal.DistanceResult()
            try:
                t0 = time.perf_counter()
                d = coal.distance(ma, ident, mb, tb, dreq, dres)
                dist.append(time.perf_counter() - t0)
                dvals.append(d)
            except Exception as e:  # coal has no OBB-OBB distance traversal
                dist_note = f"distance not supported: {e}".splitlines()[0][:200]
    return [
        {
            "engine": "coal",
            "version": version("coal"),
            "bv": bv,
            # Tree bytes of both models (BVs + vertices + triangles).
            "figures": query_figures(
                truth,
                first,
                hit,
                allp,
                counts,
                withc,
                counts_c,
                dist,
                dvals,
                tree_bytes=int(ma.memUsage(False)) * 2,
            ),
            "notes": dist_note or "",
        }
    ]


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument(
        "--engine", required=True, choices=["fcl", "fcl-native", "coal-obbrss", "coal-obb"]
    )
    ap.add_argument(
        "--poses", type=int, default=200, help="N poses spread evenly over the 200 (quick mode)"
    )
    a = ap.parse_args()
    if not 1 <= a.poses <= 200:
        ap.error("--poses must be in 1..200")
    with open(TRUTH) as f:
        truth_all = json.load(f)["pairs_per_pose"]
    # --poses N takes N poses spread evenly over k = 0..199 (all 200 when N = 200): tumble's choice.
    scene = C.load_scene("tori", poses=a.poses)
    mesh, chosen = tori_arrays(scene)
    truth = [truth_all[k] for k, _, _ in chosen]
    ps = [(rot, x) for _, rot, x in chosen]
    peak_rss = None
    if a.engine == "fcl":
        out = run_fcl(mesh, ps, truth)
    elif a.engine == "fcl-native":
        out = run_fcl_native(scene, truth)
        # The native process's own peak, not this driver's.
        peak_rss = C.children_peak_rss_bytes()
    else:
        out = run_coal(mesh, ps, truth, "OBBRSS" if a.engine == "coal-obbrss" else "OBB")
    for o in out:
        C.emit(
            o["engine"],
            o["version"],
            "tori",
            {
                "bv": o["bv"],
                "poses": a.poses,
                "mesh": "torus_mesh(1.0, 0.3, 50, 50), 5000 triangles",
                "notes": o["notes"],
            },
            o["figures"],
            peak_rss=peak_rss,
        )


if __name__ == "__main__":
    main()
