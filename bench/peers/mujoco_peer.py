"""MuJoCo peer for the dynamics scenes of scenes.md, with MJCF built as strings in code.

MuJoCo combines friction by max, so every geom gets sliding friction 0.5 (condim 3, i.e.
no torsional/rolling friction). Its contacts are soft (solref/solimp defaults), with no
restitution parameter: the cradle uses the documented direct form solref = (-stiffness, 0)
(zero damping = elastic). Default Euler integrator; pyramid, chain, cradle use the default
Newton solver, the pile CG (Newton's dense factorisation does not scale to 6000+ dofs).
Sleeping (mjENBL_SLEEP) is off. Mesh geoms collide as their convex hull.
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common as C  # noqa: E402

import mujoco  # noqa: E402

SCENES = ["pyramid", "pile", "chain", "cradle"]


def fmt(v):
    return " ".join(repr(float(x)) for x in v)


def wxyz(q):
    return (q[3], q[0], q[1], q[2])


def model(name, dt, body_xml, static_xml, gravity=C.G, solver="Newton", asset="", default=""):
    return f"""<mujoco model="{name}">
  <option timestep="{dt!r}" gravity="{fmt(gravity)}" solver="{solver}"/>
  <size memory="1G"/>
  <default><geom friction="0.5 0 0" condim="3" {default}/></default>
  <asset>{asset}</asset>
  <worldbody>
{static_xml}
{body_xml}
  </worldbody>
</mujoco>"""


def build(xml):
    m = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    return m, d


def settings(m, dt, steps, extra=None):
    s = {
        "dt": dt,
        "steps": steps,
        "solver": mujoco.mjtSolver(m.opt.solver).name,
        "iterations": int(m.opt.iterations),
        "integrator": mujoco.mjtIntegrator(m.opt.integrator).name,
        "substeps": 0,
        "friction_per_geom": 0.5,
        "friction_combine": "max",
        "sleeping": "off",
        "contacts": "soft (default solref/solimp)",
    }
    if extra:
        s.update(extra)
    return s


def positions(d, ids):
    return [tuple(d.xpos[i]) for i in ids]


def deepest(d, geoms=None):
    x = 0.0
    for i in range(d.ncon):
        c = d.contact[i]
        if geoms is not None and not (c.geom1 in geoms and c.geom2 in geoms):
            continue
        x = min(x, c.dist)
    return 0.0 - x


def box_static(half, centre):
    return f'    <geom type="box" size="{fmt(half)}" pos="{fmt(centre)}"/>'


def run_pyramid(steps):
    dt = C.DT["pyramid"]
    starts = C.pyramid_boxes()
    bodies = "\n".join(
        f'    <body name="b{i}" pos="{fmt(c)}"><freejoint/>'
        f'<geom type="box" size="0.5 0.5 0.5" mass="{C.PYRAMID_MASS}"/></body>'
        for i, c in enumerate(starts)
    )
    g = C.PYRAMID_GROUND
    m, d = build(model("pyramid", dt, bodies, box_static(g["half"], g["centre"])))
    ids = [mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, f"b{i}") for i in range(len(starts))]
    t = C.StepTimer()
    pen = 0.0
    for s in range(steps):
        t.time(mujoco.mj_step, m, d)
        if s % 10 == 9 or s == steps - 1:
            pen = max(pen, deepest(d))
    disp = [C.dist(a, b) for a, b in zip(starts, positions(d, ids))]
    C.emit("mujoco", mujoco.__version__, "pyramid", settings(m, dt, steps), {
        "step_time": t.figures(),
        "top_box_displacement_m": disp[-1],
        "largest_displacement_m": max(disp),
        "deepest_penetration_m": pen,
    })


def run_pile(steps, n):
    dt = C.DT["pile"]
    out = []
    for i, (kind, c, size, mass) in enumerate(C.pile_bodies(n)):
        geom = (f'<geom type="sphere" size="{size}" mass="{mass!r}"/>' if kind == "sphere"
                else f'<geom type="box" size="{size} {size} {size}" mass="{mass!r}"/>')
        out.append(f'    <body name="b{i}" pos="{fmt(c)}"><freejoint/>{geom}</body>')
    static = "\n".join(box_static(h, c) for h, c in C.pile_container(n))
    m, d = build(model(f"pile{n}", dt, "\n".join(out), static, solver="CG"))
    ids = [mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, f"b{i}") for i in range(n)]
    t = C.StepTimer()
    for _ in range(steps):
        t.time(mujoco.mj_step, m, d)
    ends = positions(d, ids)
    C.emit("mujoco", mujoco.__version__, f"pile{n}", settings(m, dt, steps, {"n": n}), {
        "step_time": t.figures(),
        "bodies_outside": C.pile_outside(ends),
        "mean_final_height_m": sum(e[2] for e in ends) / len(ends),
        "contact_points": int(d.ncon),
        "deepest_penetration_m": deepest(d),
    })


def run_chain(steps, decomposed):
    dt = C.DT["chain"]
    if decomposed:
        pieces = C.chain_link_pieces()
        asset = "".join(f'<mesh name="p{i}" vertex="{fmt([x for v in pv for x in v])}"/>' for i, (pv, _) in enumerate(pieces))
        geoms = "".join(f'<geom type="mesh" mesh="p{i}"/>' for i in range(len(pieces)))
    else:
        verts, tris = C.torus_mesh(C.CHAIN_R, C.CHAIN_r, 32, 12)
        asset = (f'<mesh name="torus" vertex="{fmt([x for v in verts for x in v])}" '
                 f'face="{" ".join(str(i) for t in tris for i in t)}"/>')
        geoms = '<geom type="mesh" mesh="torus"/>'
    links = C.chain_links()
    c0, q0 = links[0]
    static = f'    <body name="l0" pos="{fmt(c0)}" quat="{fmt(wxyz(q0))}">{geoms}</body>'
    inertial = f'<inertial pos="0 0 0" mass="{C.CHAIN_MASS!r}" diaginertia="{fmt(C.CHAIN_INERTIA)}"/>'
    bodies = "\n".join(
        f'    <body name="l{k}" pos="{fmt(c)}" quat="{fmt(wxyz(q))}"><freejoint/>{inertial}{geoms}</body>'
        for k, (c, q) in enumerate(links) if k > 0
    )
    m, d = build(model("chain", dt, bodies, static, asset=asset))
    ids = [mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, f"l{k}") for k in range(21)]
    gids = set(range(m.ngeom))
    initial_overlap = deepest(d, gids)
    mon = C.ChainMonitor()
    t = C.StepTimer()
    pen = 0.0
    blew_up_at = None
    for s in range(steps):
        t.time(mujoco.mj_step, m, d)
        if blew_up_at is None and (d.warning[mujoco.mjtWarning.mjWARN_BADQACC].number > 0):
            blew_up_at = (s + 1) * dt
        if s % 10 == 9 or s == steps - 1:
            mon.sample(positions(d, ids))
            pen = max(pen, deepest(d, gids))
    ends = positions(d, ids)
    collision = ("32 convex pieces per link (hulls of consecutive rings), not the plain mesh" if decomposed
                 else "mesh geom = convex hull of the 768-triangle link (MuJoCo has no concave mesh collision)")
    C.emit("mujoco", mujoco.__version__, "chain-decomposed" if decomposed else "chain",
           settings(m, dt, steps, {"collision": collision}), {
        "step_time": t.figures(),
        "interlock_held": mon.max_gap <= C.CHAIN_MAX_GAP,
        "max_adjacent_centre_distance_m": mon.max_gap,
        "broken_links": C.ChainMonitor.broken(ends),
        "deepest_penetration_m": pen,
        "initial_hull_overlap_m": initial_overlap,
        "simulation_unstable_at_s": blew_up_at,
        "capability": ("needs a convex decomposition (32 pieces per link)" if decomposed
                       else "links collide as convex hulls: interlocked links overlap from the start"),
    })


def run_cradle(steps):
    dt = C.DT["cradle"]
    spheres = C.cradle_spheres()
    bodies = "\n".join(
        f'    <body name="s{i}" pos="{fmt(c)}"><freejoint/>'
        f'<geom type="sphere" size="{C.CRADLE_R}" mass="1" condim="1" solref="-10000 0"/></body>'
        for i, (c, _) in enumerate(spheres)
    )
    m, d = build(model("cradle", dt, bodies, "", gravity=(0.0, 0.0, 0.0)))
    for i, (_, v) in enumerate(spheres):
        adr = m.jnt_dofadr[m.body_jntadr[mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, f"s{i}")]]
        d.qvel[adr:adr + 3] = v
    t = C.StepTimer()
    for _ in range(steps):
        t.time(mujoco.mj_step, m, d)
    vels = []
    for i in range(6):
        adr = m.jnt_dofadr[m.body_jntadr[mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, f"s{i}")]]
        vels.append(tuple(d.qvel[adr:adr + 3]))
    f = C.cradle_figures(vels, [1.0] * 6)
    f["step_time"] = t.figures()
    C.emit("mujoco", mujoco.__version__, "cradle", settings(m, dt, steps, {
        "restitution": "solref=(-1e4, 0): undamped contact spring (elastic)", "friction": "none (condim 1)"}), f)


def main():
    a = C.parse_args(SCENES, __doc__)
    steps = a.steps or C.FULL_STEPS[a.scene]
    {"pyramid": lambda: run_pyramid(steps), "pile": lambda: run_pile(steps, a.n),
     "chain": lambda: run_chain(steps, a.decomposed), "cradle": lambda: run_cradle(steps)}[a.scene]()


if __name__ == "__main__":
    main()
