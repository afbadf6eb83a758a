"""Markdown table and matplotlib plots for one benchmark run (bench/run.py output).

Ratios are tumble / peer of the median time per step (or per query) from the same run on
the same machine, so they stay meaningful on a noisy machine: < 1 means tumble is faster.
"""

import os

DYN_FIGURES = {
    "pyramid": ["top_box_displacement_m", "largest_displacement_m", "deepest_penetration_m"],
    "large_pyramid": ["top_box_displacement_m", "largest_displacement_m", "deepest_penetration_m"],
    "pile": ["bodies_outside", "mean_final_height_m", "contact_points", "deepest_penetration_m",
             "final_kinetic_energy_j"],
    "chain": ["interlock_held", "broken_links", "max_adjacent_centre_distance_m", "deepest_penetration_m"],
    "cradle": ["last_sphere_vx", "momentum_error", "energy_error"],
    "bowl": ["period_error", "amplitude_kept", "amplitude_kept_facets", "deepest_penetration_m"],
    "heavy_chain": ["largest_joint_error_m", "final_joint_error_m", "weight_distance_m",
                    "simulation_unstable_at_s"],
    "concave_pile": ["bodies_escaped", "deepest_penetration_m", "kinetic_energy_at_5s_j",
                     "final_kinetic_energy_j", "most_points_in_one_pair", "contact_points"],
    "ragdoll_pile": ["largest_joint_error_m", "final_joint_error_m", "deepest_penetration_m",
                     "bodies_below_ground", "simulation_unstable_at_s"],
}
# What a tumble run with `--paired` adds (bench/run.py --paired): the same run's steps timed on one
# thread, and the one-thread steps' total time over the threaded steps'.
PAIRED_FIGURES = ["paired_speedup"]
TORI_QUERIES = [("first_contact", "first contact"), ("all_pairs", "all pairs"),
                ("all_pairs_with_contacts", "all pairs + contacts")]


def _fmt(x):
    if x is None:
        return "-"
    if isinstance(x, bool):
        return "yes" if x else "no"
    if isinstance(x, int):
        return str(x)
    if isinstance(x, float):
        if x != 0 and (abs(x) < 1e-3 or abs(x) >= 1e5):
            return f"{x:.2e}"
        return f"{x:.4g}"
    return str(x)


def _label(r):
    bv = (r.get("settings") or {}).get("bv")
    return f"{r['engine']} ({bv})" if bv else r["engine"]


def _scene_key(r):
    return r.get("scene") or "?"


def _ok(r):
    return r.get("status", "ok") == "ok" and "figures" in r


def _step_median(r):
    try:
        return r["figures"]["step_time"]["median"]
    except (KeyError, TypeError):
        return None


def _threads(r):
    return (r.get("settings") or {}).get("threads") or 1


def _is_tumble(r):
    return str(r.get("engine", "")).startswith("tumble")


def _tumble(results, scene, threads=1):
    """tumble's record of `scene` run on `threads` threads (peers compare with the same count)."""
    for r in results:
        if _is_tumble(r) and _scene_key(r) == scene and _ok(r) and _threads(r) == threads:
            return r
    return None


def _ratio(t, p):
    if t is None or p is None or p <= 0:
        return "-"
    return f"{t / p:.2f}"


def markdown(doc):
    m = doc["machine"]
    res = doc["results"]
    lines = [
        f"# Benchmark run {doc['date']} ({doc['mode']})",
        "",
        f"Machine: {m['cpu_model']}, {m['nproc']} cores, kernel {m['kernel']}, "
        f"load average at start {_fmt_load(m.get('load_average_at_start'))}, "
        f"cores' round trip at start {_fmt(m.get('core_round_trip_ns_at_start'))} ns. "
        f"Started {doc['started_utc']}.",
        "",
        "tumble built from: " + (f"commit {doc['source_commit']}" if doc.get("source_commit")
                                 else "binaries as found (--no-build)"),
        "",
        "Versions: " + ", ".join(f"{k} {v}" for k, v in sorted(doc["versions"].items())),
        "",
        "## Dynamics (ms per step: median, p10-p90; ratio = tumble / peer median, on the same thread count)",
        "",
        "| scene | engine | status | median ms | p10-p90 ms | ratio | quality | peak RSS MB |",
        "|---|---|---|---|---|---|---|---|",
    ]
    scenes = []
    for r in res:
        s = _scene_key(r)
        if s != "tori" and s not in scenes:
            scenes.append(s)
    for s in scenes:
        for r in [r for r in res if _scene_key(r) == s]:
            # Variants (pyramid-it200, chain-decomposed) are compared with tumble's base scene.
            t = _tumble(res, s.split("-")[0], _threads(r))
            tmed = _step_median(t) if t else None
            if not _ok(r):
                lines.append(f"| {s} | {_label(r)} | {r.get('status')} | - | - | - | {r.get('detail', '')[:80]} | - |")
                continue
            st = r["figures"].get("step_time", {})
            base = "pile" if s.startswith("pile") else s.split("-")[0]
            # (A figure only some engines report, such as MuJoCo's instability time, is left
            # out of the rows without it.)
            # A paired tumble run (`--paired`) also timed its one-thread steps.
            q = "; ".join(f"{k.replace('_m', '')}={_fmt(r['figures'][k])}"
                          for k in DYN_FIGURES.get(base, []) + PAIRED_FIGURES if k in r["figures"])
            # A multi-thread run's cores' round trip before and after it (run.core_round_trip).
            trip = r.get("core_round_trip_ns")
            if trip:
                trip = "cores' round trip " + "/".join(_fmt(x) for x in trip) + " ns"
                q = f"{q}; {trip}" if q else trip
            ratio = "-" if _is_tumble(r) else _ratio(tmed, st.get("median"))
            lines.append(
                f"| {s} | {_label(r)} | ok ({st.get('count')} steps) | {_fmt(st.get('median'))} | "
                f"{_fmt(st.get('p10'))}-{_fmt(st.get('p90'))} | {ratio} | {q} | "
                f"{_fmt((r.get('peak_rss_bytes') or 0) / 1e6)} |"
            )
    tori = [r for r in res if _scene_key(r) == "tori"]
    if tori:
        lines += [
            "",
            "## Tori collision queries (us per query, median over poses: all / colliding / separated)",
            "",
            "| engine | status | " + " | ".join(q for _, q in TORI_QUERIES)
            + " | distance (separated) | pairs / truth | colliding poses / truth | tree bytes |",
            "|---|---|" + "---|" * (len(TORI_QUERIES) + 4),
        ]
        t = next((r for r in tori if _is_tumble(r) and _ok(r)), None)
        for r in tori:
            if not _ok(r):
                lines.append(f"| {_label(r)} | {r.get('status')} | " + " | ".join("-" for _ in TORI_QUERIES)
                             + f" | - | - | - | {r.get('detail', '')[:60]} |")
                continue
            f = r["figures"]
            cells = []
            for key, _ in TORI_QUERIES:
                q = f.get(key) or {}
                cell = "/".join(_fmt((q.get(part) or {}).get("median")) for part in ("all", "colliding", "separated"))
                if t is not None and r is not t:
                    cell += f" (ratio {_ratio(((t['figures'].get(key) or {}).get('all') or {}).get('median'), (q.get('all') or {}).get('median'))})"
                cells.append(cell)
            chk = f.get("all_pairs_check") or {}
            lines.append(
                f"| {_label(r)} | ok | " + " | ".join(cells)
                + f" | {_fmt((f.get('distance_separated') or {}).get('median'))} | {_fmt(chk.get('total_pairs'))} / {_fmt(chk.get('truth_total_pairs'))} | "
                f"{_fmt(chk.get('colliding_poses'))} / {_fmt(chk.get('truth_colliding_poses'))} | {_fmt(f.get('tree_memory_bytes'))} |"
            )
    lines += ["", "Peer notes:", ""]
    for r in res:
        cap = (r.get("figures") or {}).get("capability") or (r.get("settings") or {}).get("notes")
        if cap:
            lines.append(f"- {_label(r)} / {_scene_key(r)}: {cap}")
    return "\n".join(lines) + "\n"


def _fmt_load(load):
    if not load:
        return "-"
    return "/".join(f"{x:.1f}" for x in load)


def plots(doc, out, date):
    """Writes PNG plots; returns their file names ([] without matplotlib)."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return []
    res = doc["results"]
    written = []
    title = f"{doc['machine']['cpu_model']}, {doc['machine']['nproc']} cores, {date} ({doc['mode']})"

    # 1. Median time per step per dynamics scene, with p10-p90 spread.
    scenes = [s for s in ("pyramid", "pile1000", "chain", "cradle") if any(_scene_key(r) == s for r in res)]
    engines = sorted({r["engine"] for r in res if _scene_key(r) in scenes and _ok(r)})
    if scenes and engines:
        fig, ax = plt.subplots(figsize=(8, 4.5))
        w = 0.8 / len(engines)
        for ei, e in enumerate(engines):
            xs, ys, lo, hi = [], [], [], []
            for si, s in enumerate(scenes):
                r = next((r for r in res if r["engine"] == e and _scene_key(r) == s and _ok(r)), None)
                if r is None or _step_median(r) is None:
                    continue
                st = r["figures"]["step_time"]
                xs.append(si + ei * w)
                ys.append(st["median"])
                lo.append(max(st["median"] - st["p10"], 0.0))
                hi.append(max(st["p90"] - st["median"], 0.0))
            ax.bar(xs, ys, w, yerr=[lo, hi], label=e, capsize=2)
        ax.set_xticks([i + 0.4 - w / 2 for i in range(len(scenes))], scenes)
        ax.set_yscale("log")
        ax.set_ylabel("ms per step (median, p10-p90)")
        ax.set_title(title, fontsize=9)
        ax.legend(fontsize=8)
        fig.tight_layout()
        name = f"dynamics-{date}.png"
        fig.savefig(os.path.join(out, name), dpi=110)
        plt.close(fig)
        written.append(name)

    # 2. Pile scaling: time per step against N.
    piles = [r for r in res if _scene_key(r).startswith("pile") and _ok(r)]
    if piles:
        fig, ax = plt.subplots(figsize=(6, 4.5))
        for e in sorted({r["engine"] for r in piles}):
            pts = sorted((r["settings"]["n"], _step_median(r), r["settings"].get("steps")) for r in piles if r["engine"] == e)
            ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-", label=e)
            for n, med, steps in pts:
                if steps is not None and steps < 600:  # shortened run: not comparable with a full one
                    ax.annotate(f"{steps} steps", (n, med), fontsize=7, textcoords="offset points", xytext=(4, -10))
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("bodies N")
        ax.set_ylabel("ms per step (median)")
        ax.set_title("pile scaling; " + title, fontsize=8)
        ax.legend(fontsize=8)
        fig.tight_layout()
        name = f"pile-scaling-{date}.png"
        fig.savefig(os.path.join(out, name), dpi=110)
        plt.close(fig)
        written.append(name)

    # 3. Tori queries: median us per query kind, per engine.
    tori = [r for r in res if _scene_key(r) == "tori" and _ok(r)]
    if tori:
        kinds = TORI_QUERIES + [("distance_separated", "distance")]
        fig, ax = plt.subplots(figsize=(8, 4.5))
        w = 0.8 / len(tori)
        for ti, r in enumerate(tori):
            xs, ys = [], []
            for ki, (key, _) in enumerate(kinds):
                q = r["figures"].get(key) or {}
                med = q.get("median") if key == "distance_separated" else (q.get("colliding") or {}).get("median")
                if med is not None:
                    xs.append(ki + ti * w)
                    ys.append(med)
            ax.bar(xs, ys, w, label=_label(r))
        ax.set_xticks([i + 0.4 - w / 2 for i in range(len(kinds))],
                      [k[1] + ("\n(colliding poses)" if k[0] != "distance_separated" else "\n(separated poses)") for k in kinds],
                      fontsize=8)
        ax.set_yscale("log")
        ax.set_ylabel("us per query (median)")
        ax.set_title("tori; " + title, fontsize=9)
        ax.legend(fontsize=8)
        fig.tight_layout()
        name = f"tori-{date}.png"
        fig.savefig(os.path.join(out, name), dpi=110)
        plt.close(fig)
        written.append(name)
    return written
