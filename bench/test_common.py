"""Fast checks of the scenes the peers receive and of the harness
(python3 -m unittest bench/test_common.py;
stdlib only; needs target/release/tumble, which bench-quick builds first)."""

import json
import math
import os
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "peers"))
import common as C  # noqa: E402


class SceneData(unittest.TestCase):
    """The scenes as the peers receive them from `tumble bench --export-scene` (built by bench-quick
    before these tests run): layouts as scenes.md states them, the solids' mass properties."""

    def test_pyramid_layout_and_unit_cubes(self):
        s = C.load_scene("pyramid")
        boxes = [s["bodies"][i] for i in C.dynamic_indices(s)]
        self.assertEqual(len(boxes), 210)
        self.assertEqual(boxes[-1]["position"], [0.0, 0.0, 19.5])
        self.assertAlmostEqual(boxes[1]["position"][0] - boxes[0]["position"][0], 1.05)
        for b in boxes:
            self.assertAlmostEqual(b["mass"], 1.0)
            for i in b["principal_inertia"]:
                self.assertAlmostEqual(i, 1.0 / 6.0)  # m (1^2 + 1^2) / 12
        self.assertEqual((s["dt"], s["steps"], s["gravity"]), (1.0 / 60.0, 600, [0.0, 0.0, -9.81]))

    def test_pile_inside_container_for_every_size(self):
        for n in (100, 1000, 10000):
            s = C.load_scene("pile", n)
            bodies = [s["bodies"][i] for i in C.dynamic_indices(s)]
            self.assertEqual(len(bodies), n)
            self.assertEqual(C.pile_outside(s, [b["position"] for b in bodies]), 0)
            kinds = {}
            for b in bodies:
                c, shape = b["position"], b["shapes"][0]
                # scenes.md as written: the odd layers' offset o = 0.1 puts the i = 9 / j = 9
                # bodies 0.05 m into the +x / +y walls (inner faces at 3.0 m).
                self.assertLessEqual(abs(c[0]) + 0.25, 3.05 + 1e-9)
                self.assertLessEqual(abs(c[1]) + 0.25, 3.05 + 1e-9)
                kinds[shape["type"]] = b["mass"]
            # density 1: sphere 4/3 pi r^3, cube (2h)^3
            self.assertAlmostEqual(kinds["sphere"], 4 / 3 * math.pi * 0.25**3)
            self.assertAlmostEqual(kinds["box"], 0.125)
        self.assertEqual(
            C.pile_outside(s, [(3.2, 0.0, 1.0), (0.0, 0.0, -0.1), (math.nan, 0, 0), (1, 1, 1)]), 3
        )

    def test_chain_links_start_interlocked_within_the_bound(self):
        s = C.load_scene("chain")
        self.assertEqual(len(s["bodies"]), 21)
        self.assertEqual(len(s["meshes"]), 1)
        self.assertEqual(len(s["meshes"][0]["triangles"]), 768)
        mon = C.ChainMonitor(s)
        mon.sample([b["position"] for b in s["bodies"]])
        self.assertAlmostEqual(mon.max_gap, 1.5)
        self.assertEqual(mon.limit, 1.8)
        self.assertAlmostEqual(s["bodies"][1]["mass"], 2 * math.pi**2 * 1.0 * 0.2**2)
        cut = C.load_scene("chain_decomposed")
        self.assertEqual([len(b["shapes"]) for b in cut["bodies"]], [32] * 21)
        self.assertTrue(all(p["type"] == "convex_hull" for p in cut["bodies"][1]["shapes"]))

    def test_concave_pile_starts_in_its_bin_and_its_meshes_become_convex_pieces(self):
        s = C.load_scene("concave_pile")
        self.assertEqual(s["limits"]["inside_half_width"], 0.8)
        dyn = [s["bodies"][i] for i in C.dynamic_indices(s)]
        self.assertEqual(len(dyn), 200)
        self.assertEqual(C.pile_outside(s, [b["position"] for b in dyn]), 0)
        # Each mesh shape becomes its pieces at the mesh's pose (here one box per mesh, so that
        # the test needs no CoACD), and the meshes are no longer named.
        poses = [(b["shapes"][0]["mesh"], b["shapes"][0]["position"]) for b in s["bodies"]]

        def corners(mesh):
            lo = [min(v[k] for v in mesh["vertices"]) for k in range(3)]
            hi = [max(v[k] for v in mesh["vertices"]) for k in range(3)]
            return [[[(lo, hi)[(c >> k) & 1][k] for k in range(3)] for c in range(8)]]

        real = C.convex_pieces
        C.convex_pieces = corners
        try:
            cut, pieces = C.decomposed(s)
        finally:
            C.convex_pieces = real
        self.assertEqual(cut["meshes"], [])
        self.assertEqual(sorted(pieces), list(range(6)))
        for b, (mesh, at) in zip(cut["bodies"], poses):
            self.assertEqual([p["type"] for p in b["shapes"]], ["convex_hull"])
            self.assertEqual(b["shapes"][0]["vertices"], pieces[mesh][0])
            self.assertEqual(b["shapes"][0]["position"], at)
        # A body beside the bin or below its floor has escaped.
        ends = [b["position"] for b in dyn]
        ends[0], ends[1] = [0.9, 0.0, 0.5], [0.0, 0.0, -0.1]
        figures = C.concave_pile_figures(s, ends, 1.0, [([0.0] * 3, [0.0] * 3, [0, 0, 0, 1])] * 200)
        self.assertEqual(figures["bodies_escaped"], 2)
        self.assertEqual(figures["final_kinetic_energy_j"], 0.0)

    def test_ideal_cradle_has_no_errors(self):
        s = C.load_scene("cradle")
        self.assertEqual(s["gravity"], [0.0, 0.0, 0.0])
        # The striker's momentum handed on whole to the last sphere of the row.
        v = [(0.0, 0.0, 0.0)] * 4 + [(1.0, 0.0, 0.0), (0.0, 0.0, 0.0)]
        f = C.cradle_figures(s, v)
        self.assertAlmostEqual(f["momentum_error"], 0.0)
        self.assertAlmostEqual(f["energy_error"], 0.0)

    def test_tori_poses_run_along_x_through_the_hole(self):
        t = C.load_scene("tori", poses=5)
        self.assertEqual([p["index"] for p in t["poses"]], [0, 50, 100, 149, 199])
        self.assertEqual(t["poses"][0]["position"], [-3.0, 0.05, 0.02])
        self.assertAlmostEqual(t["poses"][-1]["position"][0], 3.0)
        self.assertEqual((len(t["mesh"]["vertices"]), len(t["mesh"]["triangles"])), (2500, 5000))

    def test_bowl_swing_meter_reads_a_cosine_and_the_scene_s_rolling_period(self):
        # A swing phi0 cos(2 pi t / T) sampled at the scene's dt: the meter's period is T and its
        # amplitude after two oscillations phi0, to the sampling; with the bowl's start, the
        # rolling period of a solid ball (2 pi sqrt(7 (R - r) / 5 g) = 1.59 s, stretched by
        # the 25 degree amplitude).
        s = C.load_scene("bowl")
        phi0, period = math.radians(25), 1.6
        m = C.SwingMeter(s["dt"], phi0)
        for k in range(1, 1000):
            m.observe(phi0 * math.cos(2 * math.pi * k * s["dt"] / period))
        self.assertAlmostEqual(m.period(), period, delta=1e-4)
        self.assertAlmostEqual(m.amplitude_after_two(), phi0, delta=1e-4)
        want = C.bowl_figures(s, m)["rolling_period_s"]
        # K(m) / (pi / 2) by its series 1 + m / 4 + 9 m^2 / 64 + 25 m^3 / 256 (m = sin^2 12.5 deg).
        m = math.sin(phi0 / 2) ** 2
        stretch = 1 + m / 4 + 9 * m * m / 64 + 25 * m**3 / 256
        small = 2 * math.pi * math.sqrt(1.4 * 0.45 / 9.81)
        self.assertAlmostEqual(want, small * stretch, delta=1e-5)

    def test_a_missing_binary_is_an_error_that_names_it(self):
        old = os.environ.get("TUMBLE_BIN")
        os.environ["TUMBLE_BIN"] = "/nonexistent/tumble"
        try:
            with self.assertRaisesRegex(RuntimeError, "/nonexistent/tumble"):
                C.load_scene("pyramid")
        finally:
            if old is None:
                del os.environ["TUMBLE_BIN"]
            else:
                os.environ["TUMBLE_BIN"] = old

    def test_gears_and_pairs_kept_apart_are_refused_not_left_out(self):
        # A stand-in for the CLI that exports a scene with one of them (no standard scene has
        # either): a peer without a twin for them would run other work than tumble's.
        old = os.environ.get("TUMBLE_BIN")
        with tempfile.TemporaryDirectory() as d:
            exe = os.path.join(d, "tumble")
            for key, entry, what in [
                (
                    "gears",
                    {"follower": 1, "leader": 0, "ratio": 2.0, "offset": 0.0},
                    "joints held at a ratio of another's coordinate",
                ),
                ("no_contact", [0, 1], "pairs of bodies kept apart"),
            ]:
                scene = {"format": C.PLAIN_SCENE_FORMAT, "bodies": [], "joints": [], key: [entry]}
                with open(exe, "w") as f:
                    f.write("#!/bin/sh\ncat <<'EOF'\n" + json.dumps(scene) + "\nEOF\n")
                os.chmod(exe, 0o755)
                os.environ["TUMBLE_BIN"] = exe
                try:
                    with self.assertRaisesRegex(RuntimeError, f"{what} \\({key}\\)"):
                        C.load_scene("pyramid")
                    # Empty lists are no such parts.
                    scene[key] = []
                    with open(exe, "w") as f:
                        f.write("#!/bin/sh\ncat <<'EOF'\n" + json.dumps(scene) + "\nEOF\n")
                    self.assertEqual(C.load_scene("pyramid")[key], [])
                finally:
                    if old is None:
                        del os.environ["TUMBLE_BIN"]
                    else:
                        os.environ["TUMBLE_BIN"] = old

    def test_timing_stats(self):
        s = C.timing_stats([k * 1e-3 for k in (7, 1, 11, 3, 9, 5, 2, 10, 4, 8, 6)])
        self.assertAlmostEqual(s["median"], 6.0)
        self.assertAlmostEqual(s["p10"], 2.0)
        self.assertAlmostEqual(s["p90"], 10.0)


class Joints(unittest.TestCase):
    """What the peers build jointed scenes from: trees, anchors, URDF angles."""

    def test_ragdoll_pile_is_a_hundred_trees_rooted_at_the_pelvis(self):
        s = C.load_scene("ragdoll_pile")
        trees = C.joint_trees(s)
        self.assertEqual(len(trees), 100)
        for k, (root, order) in enumerate(trees):
            first = 1 + 11 * k
            self.assertEqual(root, first)  # the pelvis: the spine and both hips hang from it
            self.assertEqual(
                sorted(child for _, child, _ in order), list(range(first + 1, first + 11))
            )
            placed = {root}
            for parent, child, joint in order:  # breadth-first: a parent before its children
                self.assertIn(parent, placed)
                self.assertEqual(
                    {s["joints"][joint]["body_a"], s["joints"][joint]["body_b"]}, {parent, child}
                )
                placed.add(child)

    def test_heavy_chain_hangs_from_the_world(self):
        s = C.load_scene("heavy_chain")
        [(root, order)] = C.joint_trees(s)
        self.assertIsNone(root)
        self.assertEqual([c for _, c, _ in order], list(range(21)))
        self.assertEqual(order[0][0], None)

    def test_loops_and_two_world_joints_are_refused(self):
        ball = {"kind": "ball", "anchor_b": None}
        bodies = [{}] * 3
        loop = [dict(ball, body_a=a, body_b=b) for a, b in [(0, 1), (1, 2), (2, 0)]]
        with self.assertRaises(ValueError):
            C.joint_trees({"bodies": bodies, "joints": loop})
        twice = [
            dict(ball, body_a=0, body_b=None),
            dict(ball, body_a=1, body_b=0),
            dict(ball, body_a=1, body_b=None),
        ]
        with self.assertRaises(ValueError):
            C.joint_trees({"bodies": bodies, "joints": twice})

    def test_anchor_gap_is_zero_at_the_start_and_sees_a_moved_body(self):
        for name in ("heavy_chain", "ragdoll_pile"):
            s = C.load_scene(name)
            poses = [(b["position"], b["rotation"]) for b in s["bodies"]]
            anchors = C.JointAnchors(s)
            self.assertLess(anchors.largest_error(poses), 1e-12)
            moved = list(poses)
            pos, rot = moved[5]
            moved[5] = ((pos[0], pos[1], pos[2] + 0.01), rot)
            self.assertAlmostEqual(anchors.largest_error(moved), 0.01, places=12)
            # Turning a body about its own centre by 180 degrees about z moves its anchors by
            # twice their horizontal lever.
            j = next(j for j in s["joints"] if j["body_a"] == 5)
            r = [j["anchor"][k] - pos[k] for k in range(3)]
            half_turn = C.quat_mul((0.0, 0.0, 1.0, 0.0), rot)
            moved[5] = (pos, half_turn)
            self.assertGreaterEqual(
                anchors.largest_error(moved) + 1e-12, 2 * math.hypot(r[0], r[1])
            )

    def test_rpy_rebuilds_the_rotation_also_at_gimbal_lock(self):
        def about(axis, angle):
            v = [0.0, 0.0, 0.0]
            v[axis] = math.sin(angle / 2)
            return (v[0], v[1], v[2], math.cos(angle / 2))

        quarter = math.pi / 2
        turns = [
            (-0.5, -0.5, -0.5, -0.5),
            about(1, quarter),
            about(1, -quarter),
            (0.0, 0.0, 0.0, 1.0),
        ]
        turns += [
            C.quat_mul(about(2, 0.3 * k), C.quat_mul(about(1, 0.7 - 0.2 * k), about(0, 1.1 * k)))
            for k in range(9)
        ]
        for q in turns:
            roll, pitch, yaw = C.rpy(q)
            again = C.quat_mul(about(2, yaw), C.quat_mul(about(1, pitch), about(0, roll)))
            for e in ((1, 0, 0), (0, 1, 0), (0, 0, 1)):
                self.assertLess(C.dist(C.quat_rotate(q, e), C.quat_rotate(again, e)), 1e-12)


class Energy(unittest.TestCase):
    def test_kinetic_energy_counts_motion_and_spin_about_each_principal_axis(self):
        # One body with principal moments (1, 2, 3) turned a quarter about z: its body x axis
        # points along world y, so a world spin about y is a spin about its x (moment 1).
        s = math.sqrt(0.5)
        scene = {
            "bodies": [
                {"kind": "fixed", "mass": 0.0, "principal_inertia": [0, 0, 0]},
                {"kind": "dynamic", "mass": 2.0, "principal_inertia": [1.0, 2.0, 3.0]},
            ]
        }
        quarter_z = (0.0, 0.0, s, s)
        motion = [((1.0, 2.0, 2.0), (0.0, 3.0, 0.0), quarter_z)]
        self.assertAlmostEqual(C.kinetic_energy(scene, motion), 0.5 * 2 * 9 + 0.5 * 1 * 9)
        spin_x = [((0.0, 0.0, 0.0), (3.0, 0.0, 0.0), quarter_z)]  # world x = body -y: moment 2
        self.assertAlmostEqual(C.kinetic_energy(scene, spin_x), 0.5 * 2 * 9)


class Harness(unittest.TestCase):
    def test_merge_replaces_rerun_records_and_status_placeholders(self):
        sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
        import run

        old = [
            {"engine": "parry3d", "scene": "tori", "status": "not built"},
            {"engine": "coal", "scene": "tori", "status": "ok", "settings": {"bv": "OBB"}},
            {"engine": "coal", "scene": "tori", "status": "ok", "settings": {"bv": "OBBRSS"}},
        ]
        new = [
            {"engine": "parry3d", "scene": "tori", "status": "ok", "settings": {"bv": "AABB"}},
            {"engine": "coal", "scene": "tori", "status": "ok", "settings": {"bv": "OBB"}},
        ]
        got = [(r["engine"], (r.get("settings") or {}).get("bv")) for r in run.merge(old, new)]
        self.assertEqual(got, [("coal", "OBBRSS"), ("parry3d", "AABB"), ("coal", "OBB")])


class CoreRoundTrip(unittest.TestCase):
    """The cores' round trip recorded next to each multi-thread run (bench/run.py) and shown in
    the report; the probe itself (target/release/core-round-trip, built by run.py --quick)."""

    def setUp(self):
        sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
        import report
        import run

        self.run, self.report = run, report

    def test_the_probe_measures_a_round_trip(self):
        self.assertTrue(os.path.exists(os.path.join(self.run.RELEASE, "core-round-trip")),
                        "build it: cargo build --release -p tumble-bench")
        ns = self.run.core_round_trip()
        # A line to another core and back: more than a nanosecond, far less than a millisecond.
        self.assertTrue(ns is not None and 1.0 < ns < 1e6, ns)

    def test_multi_thread_runs_carry_the_round_trips_around_them_into_the_report(self):
        trips = iter([100.0, 400.0])
        real = self.run.core_round_trip
        self.run.core_round_trip = lambda: next(trips)
        try:
            def records():
                return [{"engine": "tumble (2 threads)", "scene": "pile1000", "status": "ok",
                         "figures": {"step_time": {"median": 3.0, "count": 5}}}]

            one = self.run.with_round_trips(records, 1)
            two = self.run.with_round_trips(records, 2)
        finally:
            self.run.core_round_trip = real
        self.assertNotIn("core_round_trip_ns", one[0])
        self.assertEqual(two[0]["core_round_trip_ns"], [100.0, 400.0])
        machine = {"cpu_model": "cpu", "nproc": 2, "kernel": "k"}
        machine["core_round_trip_ns_at_start"] = 80.0
        doc = {"date": "d", "mode": "full", "started_utc": "t", "versions": {},
               "source_commit": "c", "machine": machine, "results": one + two}
        table = self.report.markdown(doc)
        self.assertIn("cores' round trip at start 80 ns", table)
        self.assertIn("cores' round trip 100/400 ns", table)
        self.assertEqual(table.count("cores' round trip 100/400 ns"), 1)


class AnswerCheck(unittest.TestCase):
    """bench/run.py's check of tumble's answers: wrong answers are caught,
    right ones and peers pass."""

    def setUp(self):
        sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
        import run

        self.wrong = run.tumble_answers_wrong

    def record(self, scene, **figures):
        return {"engine": "tumble", "scene": scene, "status": "ok", "figures": figures}

    def test_right_answers_pass(self):
        check = {
            "truth_total_pairs": 10,
            "total_pairs": 11,
            "max_abs_pose_difference": 1,
            "within_two_pairs": True,
        }
        ok = [
            self.record("tori", all_pairs_check=check, all_pairs_with_contacts_check=check),
            self.record("pyramid", top_box_displacement_m=0.004),
            self.record("large_pyramid", top_box_displacement_m=0.04),
            self.record("pile1000", bodies_outside=0),
            {
                "engine": "rapier3d",
                "scene": "pile1000",
                "status": "ok",
                "figures": {"bodies_outside": 12},
            },
            {"engine": "mujoco", "scene": "pyramid", "status": "not installed"},
        ]
        self.assertEqual(self.wrong(ok), [])

    def test_wrong_answers_are_caught(self):
        bad_pairs = {
            "truth_total_pairs": 10,
            "total_pairs": 30,
            "max_abs_pose_difference": 20,
            "within_two_pairs": False,
        }
        no_truth = {"truth_total_pairs": None, "total_pairs": 30}
        cases = [
            self.record("tori", all_pairs_check=bad_pairs, all_pairs_with_contacts_check=bad_pairs),
            self.record("tori", all_pairs_check=no_truth, all_pairs_with_contacts_check=no_truth),
            self.record("pyramid", top_box_displacement_m=0.5),
            self.record("pyramid"),
            self.record("large_pyramid", top_box_displacement_m=3.0),
            self.record("pile100", bodies_outside=2),
            {"engine": "tumble", "scene": "chain", "status": "failed", "detail": "panic"},
        ]
        for r in cases:
            self.assertTrue(self.wrong([r]), r)


if __name__ == "__main__":
    unittest.main()
