"""PyBullet peer (DIRECT mode) for the dynamics scenes of scenes.md.

Bullet combines friction and restitution by product, so each body gets sqrt(0.5) friction
(pair 0.5) and restitution 0 (cradle: 1 and friction 0). Default solver (sequential
impulses, 50 iterations), no substeps, sleeping disabled per body, damping set to 0 (Bullet's
default 0.04 would otherwise bleed energy that the other engines keep).
"""

import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common as C  # noqa: E402

import pybullet as p  # noqa: E402

SCENES = ["pyramid", "pile", "chain", "cradle"]
FRICTION = math.sqrt(C.PAIR_FRICTION)


def version():
    try:
        from importlib.metadata import version as v

        return v("pybullet")
    except Exception:
        return "unknown"


def setup(dt, gravity=C.G):
    cid = p.connect(p.DIRECT)
    p.resetSimulation()
    p.setGravity(*gravity)
    p.setPhysicsEngineParameter(fixedTimeStep=dt, numSubSteps=0, deterministicOverlappingPairs=1)
    return cid


def settings(dt, steps, extra=None):
    s = {
        "dt": dt,
        "steps": steps,
        "mode": "DIRECT",
        "solver_iterations": p.getPhysicsEngineParameters()["numSolverIterations"],
        "substeps": 0,
        "friction_per_body": FRICTION,
        "friction_combine": "product",
        "damping": 0.0,
        "sleeping": "disabled",
    }
    if extra:
        s.update(extra)
    return s


def body(shape, mass, pos, orn=(0, 0, 0, 1), friction=FRICTION, restitution=0.0, inertia=None):
    b = p.createMultiBody(
        baseMass=mass, baseCollisionShapeIndex=shape, basePosition=pos, baseOrientation=orn
    )
    kw = {}
    if inertia is not None:
        kw["localInertiaDiagonal"] = inertia
    p.changeDynamics(
        b,
        -1,
        lateralFriction=friction,
        restitution=restitution,
        linearDamping=0.0,
        angularDamping=0.0,
        rollingFriction=0.0,
        spinningFriction=0.0,
        activationState=p.ACTIVATION_STATE_DISABLE_SLEEPING,
        **kw,
    )
    return b


def deepest_penetration():
    d = 0.0
    for c in p.getContactPoints():
        d = min(d, c[8])
    return 0.0 - d


def run_pyramid(steps, iterations=None):
    dt = C.DT["pyramid"]
    setup(dt)
    if iterations is not None:
        p.setPhysicsEngineParameter(numSolverIterations=iterations)
    g = p.createCollisionShape(p.GEOM_BOX, halfExtents=C.PYRAMID_GROUND["half"])
    body(g, 0.0, C.PYRAMID_GROUND["centre"])
    cube = p.createCollisionShape(p.GEOM_BOX, halfExtents=[C.PYRAMID_HALF] * 3)
    starts = C.pyramid_boxes()
    ids = [body(cube, C.PYRAMID_MASS, c) for c in starts]
    t = C.StepTimer()
    deepest = 0.0
    for s in range(steps):
        t.time(p.stepSimulation)
        if s % 10 == 9 or s == steps - 1:
            deepest = max(deepest, deepest_penetration())
    ends = [p.getBasePositionAndOrientation(b)[0] for b in ids]
    disp = [C.dist(a, b) for a, b in zip(starts, ends)]
    C.emit(
        "pybullet",
        version(),
        "pyramid" if iterations is None else f"pyramid-it{iterations}",
        settings(dt, steps),
        {
            "step_time": t.figures(),
            "top_box_displacement_m": disp[-1],
            "largest_displacement_m": max(disp),
            "deepest_penetration_m": deepest,
        },
    )


def run_pile(steps, n):
    dt = C.DT["pile"]
    setup(dt)
    for half, centre in C.pile_container(n):
        body(p.createCollisionShape(p.GEOM_BOX, halfExtents=half), 0.0, centre)
    sphere = p.createCollisionShape(p.GEOM_SPHERE, radius=0.25)
    cube = p.createCollisionShape(p.GEOM_BOX, halfExtents=[0.25] * 3)
    ids = [body(sphere if k == "sphere" else cube, m, c) for k, c, _, m in C.pile_bodies(n)]
    t = C.StepTimer()
    for _ in range(steps):
        t.time(p.stepSimulation)
    ends = [p.getBasePositionAndOrientation(b)[0] for b in ids]
    C.emit(
        "pybullet",
        version(),
        f"pile{n}",
        settings(dt, steps, {"n": n}),
        {
            "step_time": t.figures(),
            "bodies_outside": C.pile_outside(ends),
            "mean_final_height_m": sum(e[2] for e in ends) / len(ends),
            "contact_points": len(p.getContactPoints()),
            "deepest_penetration_m": deepest_penetration(),
        },
    )


def decomposed_link_shape():
    """Compound of 32 convex hulls: PyBullet loads each `o` object of an OBJ file as one
    convex hull of a compound shape (the format its own V-HACD output uses)."""
    import tempfile

    lines, base = [], 1
    for i, (pv, pt) in enumerate(C.chain_link_pieces()):
        lines.append(f"o piece{i}")
        lines += [f"v {x!r} {y!r} {z!r}" for x, y, z in pv]
        lines += [f"f {a + base} {b + base} {c + base}" for a, b, c in pt]
        base += len(pv)
    fd, path = tempfile.mkstemp(suffix=".obj", prefix="tumble-link-")
    with os.fdopen(fd, "w") as f:
        f.write("\n".join(lines) + "\n")
    try:
        return p.createCollisionShape(p.GEOM_MESH, fileName=path)
    finally:
        os.unlink(path)


def run_chain(steps, decomposed):
    dt = C.DT["chain"]
    setup(dt)
    if decomposed:
        mesh = decomposed_link_shape()
    else:
        verts, tris = C.torus_mesh(C.CHAIN_R, C.CHAIN_r, 32, 12)
        idx = [i for t in tris for i in t]
        # Plain concave triangle mesh, no decomposition: Bullet builds a BVH triangle mesh
        # shape, which it supports for static bodies only.
        mesh = p.createCollisionShape(
            p.GEOM_MESH, vertices=verts, indices=idx, flags=p.GEOM_FORCE_CONCAVE_TRIMESH
        )
    ids = []
    for k, (c, q) in enumerate(C.chain_links()):
        mass = 0.0 if k == 0 else C.CHAIN_MASS
        ids.append(body(mesh, mass, c, q, inertia=C.CHAIN_INERTIA if k else None))
    mon = C.ChainMonitor()
    t = C.StepTimer()
    deepest = 0.0
    contacts_seen = 0
    for s in range(steps):
        t.time(p.stepSimulation)
        if s % 10 == 9 or s == steps - 1:
            mon.sample([p.getBasePositionAndOrientation(b)[0] for b in ids])
            cs = [c for c in p.getContactPoints() if c[1] in ids and c[2] in ids]
            contacts_seen += len(cs)
            for c in cs:
                deepest = max(deepest, -c[8])
    ends = [p.getBasePositionAndOrientation(b)[0] for b in ids]
    C.emit(
        "pybullet",
        version(),
        "chain-decomposed" if decomposed else "chain",
        settings(dt, steps, {"collision": "compound of 32 convex hulls per link (OBJ objects)" if decomposed
                             else "plain concave mesh (GEOM_FORCE_CONCAVE_TRIMESH), 768 triangles"}),
        {
            "step_time": t.figures(),
            "interlock_held": mon.max_gap <= C.CHAIN_MAX_GAP,
            "max_adjacent_centre_distance_m": mon.max_gap,
            "broken_links": C.ChainMonitor.broken(ends),
            "deepest_penetration_m": deepest,
            "link_contacts_sampled": contacts_seen,
            "lowest_link_z_m": min(e[2] for e in ends[1:]),
            "capability": "needs a convex decomposition (32 pieces per link)" if decomposed else
            "Bullet supports concave triangle meshes only on static bodies; "
            "dynamic links get no concave-concave contacts (sampled contact count above)",
        },
    )


def run_cradle(steps):
    dt = C.DT["cradle"]
    setup(dt, gravity=(0.0, 0.0, 0.0))
    p.setPhysicsEngineParameter(restitutionVelocityThreshold=0.0)
    s = p.createCollisionShape(p.GEOM_SPHERE, radius=C.CRADLE_R)
    ids = []
    for c, v in C.cradle_spheres():
        b = body(s, 1.0, c, friction=0.0, restitution=1.0)
        p.resetBaseVelocity(b, linearVelocity=v)
        ids.append(b)
    t = C.StepTimer()
    for _ in range(steps):
        t.time(p.stepSimulation)
    vels = [p.getBaseVelocity(b)[0] for b in ids]
    f = C.cradle_figures(vels, [1.0] * 6)
    f["step_time"] = t.figures()
    C.emit(
        "pybullet",
        version(),
        "cradle",
        settings(dt, steps, {"restitution_per_body": 1.0, "friction_per_body": 0.0, "restitution_combine": "product"}),
        f,
    )


def main():
    a = C.parse_args(SCENES, __doc__, extra=[("--iterations", int, "pyramid: solver iterations (default: Bullet's 50)")])
    if a.iterations is not None and a.iterations <= 0:
        sys.exit("--iterations must be positive")
    steps = a.steps or C.FULL_STEPS[a.scene]
    {"pyramid": lambda: run_pyramid(steps, a.iterations), "pile": lambda: run_pile(steps, a.n),
     "chain": lambda: run_chain(steps, a.decomposed), "cradle": lambda: run_cradle(steps)}[a.scene]()


if __name__ == "__main__":
    main()
