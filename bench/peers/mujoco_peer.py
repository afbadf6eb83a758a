"""MuJoCo peer for the dynamics scenes of scenes.md, with MJCF built as strings in code from
tumble's plain scene export (common.load_scene): the same bodies, poses, velocities, masses and
principal inertias (each body's frame is its centre of mass and principal axes, with an
explicit <inertial>; static bodies are bodies without a joint).

MuJoCo combines friction by max, so every geom gets its body's sliding friction (condim 3, i.e.
no torsional/rolling friction; condim 1 where the friction is 0). Its contacts are soft
(solref/solimp defaults), with no restitution parameter: an elastic body (restitution 1, the
cradle) uses the documented direct form solref = (-stiffness, 0) (zero damping = elastic); other
restitutions have no translation. Default Euler integrator; the default Newton solver, CG for
the piles (Newton's dense factorisation does not scale to 6000+ dofs). Sleeping (mjENBL_SLEEP)
is off. Mesh geoms collide as their convex hull (MuJoCo has no concave mesh collision); the
concave pile's meshes are CoACD's convex pieces (common.decomposed), a hull geom each.

Jointed scenes (heavy_chain, ragdoll_pile) become kinematic trees (common.joint_trees): MuJoCo's
joints are reduced coordinates, so a joint cannot open and its error is round-off; ball and hinge
joints sit in the child body at the scene's anchor, hinge limits as ranges, and MuJoCo's own
parent-child contact filter plays tumble's "no contacts across a joint". `--substeps k` runs k
steps of dt / k per scene step (tumble sub-steps 8 times), timed together.
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common as C  # noqa: E402
import mujoco  # noqa: E402

SCENES = ["pyramid", "pile", "chain", "cradle", "heavy_chain", "ragdoll_pile", "concave_pile"]
ELASTIC = 'solref="-10000 0"'


def fmt(v):
    return " ".join(repr(float(x)) for x in v)


def wxyz(q):
    return (q[3], q[0], q[1], q[2])


def geom(body, s, assets):
    """One <geom> of a body's shape (posed in the body frame); mesh assets are added to `assets`."""
    frame = f'pos="{fmt(s["position"])}" quat="{fmt(wxyz(s["rotation"]))}"'
    mat = f'friction="{body["friction"]!r} 0 0" condim="{1 if body["friction"] == 0 else 3}"'
    if body["restitution"] == 1.0:
        mat += " " + ELASTIC
    elif body["restitution"] != 0.0:
        raise ValueError(
            f"{body['name']}: MuJoCo has no restitution coefficient ({body['restitution']})"
        )
    t = s["type"]
    if t == "sphere":
        g = f'type="sphere" size="{s["radius"]!r}"'
    elif t == "box":
        g = f'type="box" size="{fmt(s["half_extents"])}"'
    elif t == "capsule":
        g = f'type="capsule" size="{s["radius"]!r} {s["half_height"]!r}"'
    elif t == "convex_hull":
        name = f"hull{len(assets)}"
        assets.append(
            f'<mesh name="{name}" vertex="{fmt([x for v in s["vertices"] for x in v])}"/>'
        )
        g = f'type="mesh" mesh="{name}"'
    elif t == "mesh":
        g = f'type="mesh" mesh="mesh{s["mesh"]}"'
    elif t == "half_space":
        # A plane geom's solid side is below its local z:
        # turn z onto the normal, shift by the offset.
        n, d = s["normal"], s["offset"]
        at = fmt([d * x for x in n])
        return f'<geom type="plane" size="0 0 1" pos="{at}" zaxis="{fmt(n)}" {mat}/>'
    else:
        raise ValueError(f"{body['name']}: shape type {t!r} has no translation here")
    return f"<geom {g} {frame} {mat}/>"


def joint_xml(scene, k, child):
    """The <joint> of scene joint `k` in the frame of its child body `child` (MuJoCo's joints
    sit in the child; a fixed joint is no element: the child is welded to its parent)."""
    j, body = scene["joints"][k], scene["bodies"][child]
    if j["anchor_b"] is not None or j["motor"] or j["spring"]:
        raise ValueError(f"joint {k}: anchor_b, motors and springs have no translation here")
    pos = fmt(C.to_local(body["position"], body["rotation"], j["anchor"]))
    axis = fmt(C.quat_rotate(C.quat_conj(body["rotation"]), j["axis"]))
    kind = j["kind"]
    if kind == "fixed":
        return ""
    if kind == "ball":
        if j["limits"] or j["swing_limit"]:
            raise ValueError(f"joint {k}: ball joint limits have no translation here")
        return f'<joint type="ball" pos="{pos}"/>'
    if kind in ("hinge", "slider"):
        limits = j["limits"]
        lim = "" if limits is None else f' limited="true" range="{fmt(limits)}"'
        mj = "hinge" if kind == "hinge" else "slide"
        return f'<joint type="{mj}" pos="{pos}" axis="{axis}"{lim}/>'
    raise ValueError(f"joint {k}: kind {kind!r} has no translation here")


def mjcf(scene):
    """The scene as MJCF: jointed bodies nested as kinematic trees (C.joint_trees: reduced
    coordinates, MuJoCo's only kind of joint), every other dynamic body on a free joint."""
    assets = [
        f'<mesh name="mesh{k}" vertex="{fmt([x for v in m["vertices"] for x in v])}" '
        f'face="{" ".join(str(i) for t in m["triangles"] for i in t)}"/>'
        for k, m in enumerate(scene["meshes"])
    ]
    parent = {}  # child body -> (parent body or None for the world, joint)
    floating = set()
    for root, order in C.joint_trees(scene) if scene.get("joints") else []:
        if root is not None:
            floating.add(root)
        for up, child, k in order:
            parent[child] = (up, k)
    kids = {}
    for child, (up, _) in parent.items():
        kids.setdefault(up, []).append(child)

    def body_xml(i, depth):
        b = scene["bodies"][i]
        if b["kind"] == "kinematic":
            raise ValueError(f"{b['name']}: kinematic bodies have no translation here")
        geoms = "".join(geom(b, s, assets) for s in b["shapes"])
        up = parent.get(i, (None, None))[0]
        if up is None:
            pos, quat = b["position"], b["rotation"]
        else:
            pb = scene["bodies"][up]
            pos = C.to_local(pb["position"], pb["rotation"], b["position"])
            quat = C.quat_mul(C.quat_conj(pb["rotation"]), b["rotation"])
        inner = ""
        if b["kind"] == "dynamic":
            if i in parent:
                inner = joint_xml(scene, parent[i][1], i)
            else:
                inner = "<freejoint/>"
            inner += (
                f'<inertial pos="0 0 0" mass="{b["mass"]!r}" '
                f'diaginertia="{fmt(b["principal_inertia"])}"/>'
            )
        nested = "".join(body_xml(c, depth + 1) for c in sorted(kids.get(i, [])))
        return (
            f'{"  " * depth}<body name="b{i}" pos="{fmt(pos)}" quat="{fmt(wxyz(quat))}">'
            f"{inner}{geoms}{nested}</body>\n"
        )

    top = [i for i in range(len(scene["bodies"])) if parent.get(i, (None,))[0] is None]
    bodies = "".join(body_xml(i, 2) for i in top)
    piles = scene["name"].startswith("pile") or scene["name"] == "concave_pile"
    solver = "CG" if piles else "Newton"
    return f"""<mujoco model="{scene["name"]}">
  <compiler angle="radian"/>
  <option timestep="{scene["dt"]!r}" gravity="{fmt(scene["gravity"])}" solver="{solver}"/>
  <size memory="1G"/>
  <asset>{"".join(assets)}</asset>
  <worldbody>
{bodies}  </worldbody>
</mujoco>"""


def build(scene):
    m = mujoco.MjModel.from_xml_string(mjcf(scene))
    d = mujoco.MjData(m)
    ids = [
        mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, f"b{i}") for i in range(len(scene["bodies"]))
    ]
    for i, b in zip(ids, scene["bodies"]):
        if b["kind"] != "dynamic":
            continue
        moving = any(b["linear_velocity"]) or any(b["angular_velocity"])
        if m.jnt_type[m.body_jntadr[i]] != mujoco.mjtJoint.mjJNT_FREE:
            if moving:
                raise ValueError(f"{b['name']}: a jointed body's start velocity has no translation")
            continue
        adr = m.jnt_dofadr[m.body_jntadr[i]]
        # A free joint's velocity: linear (world), then angular (body frame).
        d.qvel[adr : adr + 3] = b["linear_velocity"]
        mujoco.mju_rotVecQuat(
            d.qvel[adr + 3 : adr + 6],
            b["angular_velocity"],
            [b["rotation"][3], -b["rotation"][0], -b["rotation"][1], -b["rotation"][2]],
        )
    mujoco.mj_forward(m, d)
    return m, d, ids


def settings(m, scene, steps, substeps, extra=None):
    s = {
        "dt": scene["dt"],
        "steps": steps,
        "solver": mujoco.mjtSolver(m.opt.solver).name,
        "iterations": int(m.opt.iterations),
        "integrator": mujoco.mjtIntegrator(m.opt.integrator).name,
        "substeps": substeps,
        "friction_per_geom": "tumble's per body",
        "friction_combine": "max",
        "sleeping": "off",
        "contacts": "soft (default solref/solimp)",
    }
    if extra:
        s.update(extra)
    return s


def positions(d, ids):
    return [tuple(d.xpos[i]) for i in ids]


def motions(m, d, ids):
    """(linear velocity, world angular velocity, rotation xyzw) of free bodies: a free joint's
    qvel is the linear velocity (world) and the angular one in the body frame."""
    out = []
    for i in ids:
        adr = m.jnt_dofadr[m.body_jntadr[i]]
        q = (d.xquat[i][1], d.xquat[i][2], d.xquat[i][3], d.xquat[i][0])
        w = C.quat_rotate(q, d.qvel[adr + 3 : adr + 6])
        out.append((tuple(d.qvel[adr : adr + 3]), w, q))
    return out


def poses(d, ids):
    """(position, rotation xyzw) of each body."""
    return [
        (tuple(d.xpos[i]), (d.xquat[i][1], d.xquat[i][2], d.xquat[i][3], d.xquat[i][0]))
        for i in ids
    ]


def deepest(d):
    x = 0.0
    for i in range(d.ncon):
        x = min(x, d.contact[i].dist)
    return 0.0 - x


def run(scene, steps, variant, substeps=1):
    m, d, ids = build(scene)
    dyn = [ids[i] for i in C.dynamic_indices(scene)]
    starts = positions(d, dyn)
    chain = variant.startswith("chain")
    mon = C.ChainMonitor(scene) if chain else None
    joints = C.JointAnchors(scene) if scene.get("joints") else None
    worst_joint = 0.0
    initial_overlap = deepest(d)
    t = C.StepTimer()
    pen, blew_up_at = 0.0, None
    # `substeps` MuJoCo steps of dt / substeps per step of the scene (timed together).
    m.opt.timestep = scene["dt"] / substeps

    def frame():
        for _ in range(substeps):
            mujoco.mj_step(m, d)

    concave = variant.startswith("concave_pile")
    five_seconds, at_five = round(5.0 / scene["dt"]), None
    for s in range(steps):
        t.time(frame)
        if concave and s + 1 == five_seconds:
            at_five = C.kinetic_energy(scene, motions(m, d, dyn))
        if blew_up_at is None and d.warning[mujoco.mjtWarning.mjWARN_BADQACC].number > 0:
            blew_up_at = (s + 1) * scene["dt"]
        if s % 10 == 9 or s == steps - 1:
            pen = max(pen, deepest(d))
            if chain:
                mon.sample(positions(d, ids))
            if joints:
                worst_joint = max(worst_joint, joints.largest_error(poses(d, ids)))
    ends = positions(d, dyn)
    figures = {"step_time": t.figures(), "deepest_penetration_m": pen}
    extra = {}
    if variant == "pyramid":
        figures.update(C.pyramid_figures(starts, ends))
    elif variant.startswith("pile"):
        figures.update(C.pile_figures(scene, ends, int(d.ncon), motions(m, d, dyn)))
        extra["n"] = len(dyn)
    elif concave:
        figures.update(C.concave_pile_figures(scene, ends, at_five, motions(m, d, dyn)))
        figures["contact_points"] = int(d.ncon)
        figures["simulation_unstable_at_s"] = blew_up_at
        figures["capability"] = "no concave mesh collision: needs a convex decomposition"
        extra["collision"] = C.pieces_note(scene, "hull geoms")
    elif chain:
        decomposed = variant == "chain-decomposed"
        figures.update(
            interlock_held=mon.max_gap <= mon.limit,
            max_adjacent_centre_distance_m=mon.max_gap,
            broken_links=mon.broken(positions(d, ids)),
            initial_hull_overlap_m=initial_overlap,
            simulation_unstable_at_s=blew_up_at,
            capability=(
                "needs a convex decomposition (32 pieces per link)"
                if decomposed
                else "links collide as convex hulls: interlocked links overlap from the start"
            ),
        )
        extra["collision"] = (
            "32 convex pieces per link (hulls of consecutive rings), not the plain mesh"
            if decomposed
            else "mesh geom = convex hull of the 768-triangle link "
            "(MuJoCo has no concave mesh collision)"
        )
    elif joints:
        figures.update(C.joint_figures(scene, joints, worst_joint, poses(d, ids)))
        figures["simulation_unstable_at_s"] = blew_up_at
        extra["joints"] = "reduced coordinates (kinematic trees; parent-child contacts off)"
    elif variant == "cradle":
        vels = [
            tuple(d.qvel[m.jnt_dofadr[m.body_jntadr[i]] : m.jnt_dofadr[m.body_jntadr[i]] + 3])
            for i in ids
        ]
        figures.update(C.cradle_figures(scene, vels))
        extra.update(
            restitution="solref=(-1e4, 0): undamped contact spring (elastic)",
            friction="none (condim 1)",
        )
    C.emit(
        "mujoco", mujoco.__version__, variant, settings(m, scene, steps, substeps, extra), figures
    )


def main():
    a = C.parse_args(
        SCENES,
        __doc__,
        extra=[("--substeps", int, "MuJoCo steps of dt / substeps per scene step (default 1)")],
    )
    if a.substeps is not None and a.substeps <= 0:
        sys.exit("--substeps must be positive")
    scene = C.scene_for(a)
    if a.scene == "pile":
        variant = f"pile{a.n}"
    elif a.scene == "chain" and a.decomposed:
        variant = "chain-decomposed"
    elif a.scene == "concave_pile":
        variant = "concave_pile-coacd"
    else:
        variant = a.scene
    if a.substeps is not None:
        variant += f"-substeps{a.substeps}"
    run(scene, a.steps or scene["steps"], variant, a.substeps or 1)


if __name__ == "__main__":
    main()
