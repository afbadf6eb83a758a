"""PyBullet peer (DIRECT mode) for the dynamics scenes of scenes.md, built from tumble's plain
scene export (common.load_scene): the same bodies, poses, velocities, masses and principal
inertias (each body's base frame is its centre of mass and principal axes).

Bullet combines friction and restitution by product, so each body gets the square root of its
friction (a pair of equal bodies then has tumble's geometric mean) and its restitution as is
(the standard scenes use 0, or 1 throughout the cradle). Default solver (sequential impulses,
50 iterations), no substeps, sleeping disabled per body, damping set to 0 (Bullet's default 0.04
would otherwise bleed energy that the other engines keep). Concave meshes are
GEOM_FORCE_CONCAVE_TRIMESH shapes (Bullet collides them on static bodies only); a body made of
several convex hulls is one compound shape (an OBJ file with one `o` object per hull, the
format of Bullet's own V-HACD output); the concave pile's meshes are CoACD's convex pieces
(common.decomposed), its bodies such compounds.

Jointed scenes (heavy_chain, ragdoll_pile) become one URDF per kinematic tree
(common.joint_trees), loaded as Featherstone multibodies (reduced coordinates: a joint cannot
open): spherical and revolute joints with the scene's limits, the inertia from the file, the
default joint motors switched off, self-collision on except between parent and child (tumble's
"no contacts across a joint"). Each body's start pose is checked after loading.
"""

import math
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common as C  # noqa: E402
import pybullet as p  # noqa: E402

SCENES = [
    "pyramid",
    "pile",
    "chain",
    "cradle",
    "bowl",
    "heavy_chain",
    "ragdoll_pile",
    "concave_pile",
]


def version():
    try:
        from importlib.metadata import version as v

        return v("pybullet")
    except Exception:
        return "unknown"


def settings(scene, steps, extra=None):
    s = {
        "dt": scene["dt"],
        "steps": steps,
        "mode": "DIRECT",
        "solver_iterations": p.getPhysicsEngineParameters()["numSolverIterations"],
        "substeps": 0,
        "friction_per_body": "sqrt of tumble's",
        "friction_combine": "product",
        "restitution_combine": "product",
        "damping": 0.0,
        "sleeping": "disabled",
    }
    if extra:
        s.update(extra)
    return s


def hull_compound(hulls):
    """One compound of convex hulls: an OBJ file with one `o` object per hull (vertices only
    matter: Bullet takes each object's convex hull)."""
    lines, base = [], 1
    for i, (verts, pose) in enumerate(hulls):
        lines.append(f"o piece{i}")
        lines += [f"v {x!r} {y!r} {z!r}" for x, y, z in (C.to_world(*pose, v) for v in verts)]
        # A fan over the vertices so that the object is not empty; the hull ignores faces.
        lines += [f"f {base} {base + k} {base + k + 1}" for k in range(1, len(verts) - 1)]
        base += len(verts)
    fd, path = tempfile.mkstemp(suffix=".obj", prefix="tumble-compound-")
    with os.fdopen(fd, "w") as f:
        f.write("\n".join(lines) + "\n")
    try:
        return p.createCollisionShape(p.GEOM_MESH, fileName=path)
    finally:
        os.unlink(path)


def collision_shape(scene, body):
    """The Bullet collision shape of a body's shapes (in its body frame)."""
    shapes = body["shapes"]
    if len(shapes) > 1:
        if any(s["type"] != "convex_hull" for s in shapes):
            raise ValueError(
                f"{body['name']}: several shapes other than convex hulls have no translation here"
            )
        return hull_compound([(s["vertices"], (s["position"], s["rotation"])) for s in shapes])
    s = shapes[0]
    frame = {"collisionFramePosition": s["position"], "collisionFrameOrientation": s["rotation"]}
    t = s["type"]
    if t == "sphere":
        return p.createCollisionShape(p.GEOM_SPHERE, radius=s["radius"], **frame)
    if t == "box":
        return p.createCollisionShape(p.GEOM_BOX, halfExtents=s["half_extents"], **frame)
    if t == "capsule":
        return p.createCollisionShape(
            p.GEOM_CAPSULE, radius=s["radius"], height=2 * s["half_height"], **frame
        )
    if t == "convex_hull":
        return p.createCollisionShape(p.GEOM_MESH, vertices=s["vertices"], **frame)
    if t == "mesh":
        m = scene["meshes"][s["mesh"]]
        return p.createCollisionShape(
            p.GEOM_MESH,
            vertices=m["vertices"],
            indices=[i for t3 in m["triangles"] for i in t3],
            flags=p.GEOM_FORCE_CONCAVE_TRIMESH,
            **frame,
        )
    if t == "half_space":
        n, d = s["normal"], s["offset"]
        return p.createCollisionShape(
            p.GEOM_PLANE, planeNormal=n, collisionFramePosition=[d * x for x in n]
        )
    raise ValueError(f"{body['name']}: shape type {t!r} has no translation here")


def vec(v):
    return " ".join(repr(float(x)) for x in v)


def urdf_collisions(body, offset):
    """<collision> elements of a body's shapes in a link frame whose origin is `offset` from the
    body's centre of mass (body axes)."""
    out = []
    for s in body["shapes"]:
        t = s["type"]
        if t == "sphere":
            g = f'<sphere radius="{s["radius"]!r}"/>'
        elif t == "box":
            g = f'<box size="{vec([2 * h for h in s["half_extents"]])}"/>'
        elif t == "capsule":
            g = f'<capsule radius="{s["radius"]!r}" length="{2 * s["half_height"]!r}"/>'
        else:
            raise ValueError(f"{body['name']}: shape type {t!r} has no URDF translation here")
        at = [offset[k] + s["position"][k] for k in range(3)]
        out.append(
            f'<collision><origin xyz="{vec(at)}" rpy="{vec(C.rpy(s["rotation"]))}"/>'
            f"<geometry>{g}</geometry></collision>"
        )
    return "".join(out)


def urdf_link(name, body, offset):
    """A link carrying `body`, its centre of mass `offset` from the link frame (body axes)."""
    i = body["principal_inertia"]
    inertial = (
        f'<inertial><origin xyz="{vec(offset)}" rpy="0 0 0"/><mass value="{body["mass"]!r}"/>'
        f'<inertia ixx="{i[0]!r}" iyy="{i[1]!r}" izz="{i[2]!r}" ixy="0" ixz="0" iyz="0"/>'
        "</inertial>"
    )
    return f'<link name="{name}">{inertial}{urdf_collisions(body, offset)}</link>'


URDF_JOINT = {"ball": "spherical", "hinge": "revolute", "slider": "prismatic", "fixed": "fixed"}


def tree_urdf(scene, root, order):
    """One kinematic tree (C.joint_trees) as URDF. Each link's frame has its body's axes and sits
    at the anchor of the joint to its parent (the root's at its centre of mass; a tree hung from
    the world has a massless fixed base at the world origin)."""
    bodies = scene["bodies"]
    frame = {}  # body -> (origin, rotation) of its link frame in the world
    links, joints = [], []
    if root is None:
        # (PyBullet refuses a tree whose base link has no <inertial>.)
        links.append(
            '<link name="world_anchor"><inertial><mass value="0"/>'
            '<inertia ixx="0" iyy="0" izz="0" ixy="0" ixz="0" iyz="0"/></inertial></link>'
        )
    else:
        b = bodies[root]
        frame[root] = (b["position"], b["rotation"])
        links.append(urdf_link(f"l{root}", b, (0.0, 0.0, 0.0)))
    for up, child, k in order:
        j, b = scene["joints"][k], bodies[child]
        kind = j["kind"]
        if kind not in URDF_JOINT or j["anchor_b"] is not None or j["motor"] or j["spring"]:
            raise ValueError(f"joint {k}: {kind} as given has no URDF translation here")
        if kind == "ball" and (j["limits"] or j["swing_limit"]):
            raise ValueError(f"joint {k}: ball joint limits have no URDF translation here")
        anchor = j["anchor"]
        frame[child] = (anchor, b["rotation"])
        offset = C.to_local(anchor, b["rotation"], b["position"])
        links.append(urdf_link(f"l{child}", b, offset))
        origin, rot = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0)) if up is None else frame[up]
        at = C.to_local(origin, rot, anchor)
        turn = C.rpy(C.quat_mul(C.quat_conj(rot), b["rotation"]))
        axis = C.quat_rotate(C.quat_conj(b["rotation"]), j["axis"])
        typ = URDF_JOINT[kind]
        limit = ""
        if kind in ("hinge", "slider"):
            if j["limits"] is None:
                typ = "continuous" if kind == "hinge" else typ
                limit = (
                    '<limit lower="0" upper="-1" effort="0" velocity="0"/>'
                    if kind == "slider"
                    else ""
                )
            else:
                lo, hi = j["limits"]
                limit = f'<limit lower="{lo!r}" upper="{hi!r}" effort="0" velocity="0"/>'
        parent_link = "world_anchor" if up is None else f"l{up}"
        joints.append(
            f'<joint name="j{k}" type="{typ}"><parent link="{parent_link}"/>'
            f'<child link="l{child}"/><origin xyz="{vec(at)}" rpy="{vec(turn)}"/>'
            f'<axis xyz="{vec(axis)}"/>{limit}</joint>'
        )
    # One element per line: PyBullet's URDF reader lost a joint's <origin> deep in one long line.
    return f'<robot name="tree">{"".join(links)}{"".join(joints)}</robot>'.replace("><", ">\n<")


def load_tree(scene, root, order):
    """Loads one tree as a Bullet multibody (reduced coordinates: Featherstone) with its default
    joint motors off, and returns {body index: (multibody, link index or -1 for the base)}."""
    fd, path = tempfile.mkstemp(suffix=".urdf", prefix="tumble-tree-")
    with os.fdopen(fd, "w") as f:
        f.write(tree_urdf(scene, root, order))
    try:
        flags = (
            p.URDF_USE_INERTIA_FROM_FILE
            | p.URDF_USE_SELF_COLLISION
            | p.URDF_USE_SELF_COLLISION_EXCLUDE_PARENT
        )
        if root is None:
            bid = p.loadURDF(path, useFixedBase=True, flags=flags)
        else:
            b = scene["bodies"][root]
            bid = p.loadURDF(
                path, basePosition=b["position"], baseOrientation=b["rotation"], flags=flags
            )
    finally:
        os.unlink(path)
    where = {} if root is None else {root: (bid, -1)}
    for li in range(p.getNumJoints(bid)):
        info = p.getJointInfo(bid, li)
        where[int(info[12].decode()[1:])] = (bid, li)
        if info[2] in (p.JOINT_REVOLUTE, p.JOINT_PRISMATIC):
            p.setJointMotorControl2(bid, li, p.VELOCITY_CONTROL, force=0)
        elif info[2] == p.JOINT_SPHERICAL:
            p.setJointMotorControlMultiDof(
                bid,
                li,
                p.POSITION_CONTROL,
                targetPosition=[0, 0, 0, 1],
                positionGain=0,
                velocityGain=0,
                force=[0, 0, 0],
            )
    return where


def pose_of(where):
    """(centre of mass, rotation) of a body: a multibody's base or one of its links."""
    bid, link = where
    if link < 0:
        return p.getBasePositionAndOrientation(bid)
    s = p.getLinkState(bid, link, computeForwardKinematics=1)
    return s[0], s[1]


def set_material(bid, link, body, **extra):
    """A body's Bullet settings (base `link` -1, or a multibody link): the square root of its
    friction (Bullet multiplies), its restitution, no damping or rolling/spinning friction,
    never asleep; `extra` adds to them (inertia, joint damping)."""
    p.changeDynamics(
        bid,
        link,
        lateralFriction=math.sqrt(body["friction"]),
        restitution=body["restitution"],
        linearDamping=0.0,
        angularDamping=0.0,
        rollingFriction=0.0,
        spinningFriction=0.0,
        activationState=p.ACTIVATION_STATE_DISABLE_SLEEPING,
        **extra,
    )


def build(scene):
    """Connects, sets up the scene's world and returns the body ids in scene order."""
    p.connect(p.DIRECT)
    p.resetSimulation()
    p.setGravity(*scene["gravity"])
    p.setPhysicsEngineParameter(
        fixedTimeStep=scene["dt"], numSubSteps=0, deterministicOverlappingPairs=1
    )
    if any(b["restitution"] > 0 for b in scene["bodies"]):
        # Elastic scenes (the cradle): bounce at any approach speed, as tumble does.
        p.setPhysicsEngineParameter(restitutionVelocityThreshold=0.0)
    ids = []
    trees = C.joint_trees(scene) if scene.get("joints") else []
    jointed = {}
    for root, order in trees:
        jointed.update(load_tree(scene, root, order))
    for i, b in enumerate(scene["bodies"]):
        if i in jointed:
            bid, link = jointed[i]
            if any(b["linear_velocity"]) or any(b["angular_velocity"]):
                raise ValueError(f"{b['name']}: a jointed body's start velocity has no translation")
            set_material(bid, link, b, jointDamping=0.0)
            # The multibody must start where the scene's bodies are.
            at = pose_of(jointed[i])[0]
            if C.dist(at, b["position"]) > 1e-6:
                raise RuntimeError(f"{b['name']}: loaded at {at}, expected {b['position']}")
            ids.append(jointed[i])
            continue
        if b["kind"] == "kinematic":
            raise ValueError(f"{b['name']}: kinematic bodies have no translation here")
        dynamic = b["kind"] == "dynamic"
        bid = p.createMultiBody(
            baseMass=b["mass"] if dynamic else 0.0,
            baseCollisionShapeIndex=collision_shape(scene, b),
            basePosition=b["position"],
            baseOrientation=b["rotation"],
        )
        kw = {"localInertiaDiagonal": b["principal_inertia"]} if dynamic else {}
        set_material(bid, -1, b, **kw)
        if dynamic:
            p.resetBaseVelocity(
                bid, linearVelocity=b["linear_velocity"], angularVelocity=b["angular_velocity"]
            )
        ids.append(bid)
    return ids


def centres(ids):
    return [
        pose_of(b)[0] if isinstance(b, tuple) else p.getBasePositionAndOrientation(b)[0]
        for b in ids
    ]


def poses(ids):
    """(centre of mass, rotation) of every body in scene order."""
    return [pose_of(b) if isinstance(b, tuple) else p.getBasePositionAndOrientation(b) for b in ids]


def deepest_penetration(ids=None):
    d = 0.0
    for c in p.getContactPoints():
        if ids is None or (c[1] in ids and c[2] in ids):
            d = min(d, c[8])
    return 0.0 - d


def run(scene, steps, variant, iterations=None):
    ids = build(scene)
    if iterations is not None:
        p.setPhysicsEngineParameter(numSolverIterations=iterations)
    dyn = [ids[i] for i in C.dynamic_indices(scene)]
    starts = centres(dyn)
    chain = variant.startswith("chain")
    mon = C.ChainMonitor(scene) if chain else None
    joints = C.JointAnchors(scene) if scene.get("joints") else None
    worst_joint = 0.0
    t = C.StepTimer()
    deepest, contacts_seen = 0.0, 0
    ball_angle = lambda: C.swing_angle(centres([ids[1]])[0])  # noqa: E731 (the bowl's ball)
    meter = C.SwingMeter(scene["dt"], ball_angle()) if variant == "bowl" else None
    concave = variant.startswith("concave_pile")
    five_seconds, at_five = round(5.0 / scene["dt"]), None

    def motions():
        return [(*p.getBaseVelocity(b), p.getBasePositionAndOrientation(b)[1]) for b in dyn]

    for s in range(steps):
        t.time(p.stepSimulation)
        if meter:
            meter.observe(ball_angle())
        if concave and s + 1 == five_seconds:
            at_five = C.kinetic_energy(scene, motions())
        if s % 10 == 9 or s == steps - 1:
            deepest = max(deepest, deepest_penetration(ids if chain else None))
            if chain:
                mon.sample(centres(ids))
                contacts_seen += sum(1 for c in p.getContactPoints() if c[1] in ids and c[2] in ids)
            if joints:
                worst_joint = max(worst_joint, joints.largest_error(poses(ids)))
    ends = centres(dyn)
    figures = {"step_time": t.figures(), "deepest_penetration_m": deepest}
    extra = {}
    if variant.startswith("pyramid"):
        figures.update(C.pyramid_figures(starts, ends))
    elif variant.startswith("pile"):
        figures.update(C.pile_figures(scene, ends, len(p.getContactPoints()), motions()))
        extra["n"] = len(dyn)
    elif concave:
        figures.update(C.concave_pile_figures(scene, ends, at_five, motions()))
        figures["contact_points"] = len(p.getContactPoints())
        figures["capability"] = "no dynamic concave-concave collision: needs a convex decomposition"
        extra["collision"] = C.pieces_note(scene, "hulls (one compound)")
    elif chain:
        decomposed = variant == "chain-decomposed"
        all_ends = centres(ids)
        figures.update(
            interlock_held=mon.max_gap <= mon.limit,
            max_adjacent_centre_distance_m=mon.max_gap,
            broken_links=mon.broken(all_ends),
            link_contacts_sampled=contacts_seen,
            lowest_link_z_m=min(e[2] for e in all_ends[1:]),
            capability="needs a convex decomposition (32 pieces per link)"
            if decomposed
            else "Bullet supports concave triangle meshes only on static bodies; "
            "dynamic links get no concave-concave contacts (sampled contact count above)",
        )
        extra["collision"] = (
            "compound of 32 convex hulls per link (OBJ objects)"
            if decomposed
            else "plain concave mesh (GEOM_FORCE_CONCAVE_TRIMESH), 768 triangles"
        )
    elif joints:
        figures.update(C.joint_figures(scene, joints, worst_joint, poses(ids)))
        extra["joints"] = (
            "reduced coordinates (Featherstone multibodies from URDF); "
            "self-collision on, parent-child off"
        )
    elif variant == "bowl":
        figures.update(C.bowl_figures(scene, meter))
        extra["collision"] = "static concave mesh (GEOM_FORCE_CONCAVE_TRIMESH), 96 x 48 facets"
    elif variant == "cradle":
        figures.update(C.cradle_figures(scene, [p.getBaseVelocity(b)[0] for b in ids]))
        extra.update(restitution_per_body=1.0, gravity=scene["gravity"])
    C.emit("pybullet", version(), variant, settings(scene, steps, extra), figures)


def main():
    a = C.parse_args(
        SCENES,
        __doc__,
        extra=[("--iterations", int, "pyramid: solver iterations (default: Bullet's 50)")],
    )
    if a.iterations is not None and a.iterations <= 0:
        sys.exit("--iterations must be positive")
    scene = C.scene_for(a)
    if a.scene == "pile":
        variant = f"pile{a.n}"
    elif a.scene == "chain" and a.decomposed:
        variant = "chain-decomposed"
    elif a.scene == "concave_pile":
        variant = "concave_pile-coacd"
    elif a.scene == "pyramid" and a.iterations is not None:
        variant = f"pyramid-it{a.iterations}"
    else:
        variant = a.scene
    run(scene, a.steps or scene["steps"], variant, a.iterations)


if __name__ == "__main__":
    main()
