"""Fast checks of the shared scene data and the harness (python3 -m unittest bench/test_common.py; stdlib only)."""

import math
import os
import sys
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "peers"))
import common as C  # noqa: E402


class SceneData(unittest.TestCase):
    def test_torus_is_outward_with_solid_torus_volume(self):
        v, t = C.torus_mesh(1.0, 0.3, 50, 50)
        self.assertEqual((len(v), len(t)), (2500, 5000))
        vol = 0.0
        for a, b, c in t:
            p, q, r = v[a], v[b], v[c]
            vol += (p[0] * (q[1] * r[2] - q[2] * r[1]) - p[1] * (q[0] * r[2] - q[2] * r[0])
                    + p[2] * (q[0] * r[1] - q[1] * r[0])) / 6.0
        exact = 2 * math.pi**2 * 1.0 * 0.3**2
        self.assertTrue(0.99 * exact < vol < exact, (vol, exact))

    def test_pyramid_layout(self):
        b = C.pyramid_boxes()
        self.assertEqual(len(b), 210)
        self.assertEqual(b[-1], (0.0, 0.0, 19.5))
        self.assertAlmostEqual(b[1][0] - b[0][0], 1.05)

    def test_pile_inside_container_for_every_size(self):
        for n in (100, 1000, 10000):
            bodies = C.pile_bodies(n)
            self.assertEqual(len(bodies), n)
            walls = C.pile_container(n)
            top = walls[1][1][2] + walls[1][0][2]
            for _, c, size, mass in bodies:
                # scenes.md as written: the odd layers' offset o = 0.1 puts the i = 9 / j = 9
                # bodies 0.05 m into the +x / +y walls (inner faces at 3.0 m).
                self.assertLessEqual(abs(c[0]) + size, 3.05 + 1e-9)
                self.assertLessEqual(abs(c[1]) + size, 3.05 + 1e-9)
                self.assertLess(c[2] + size, top)
            self.assertEqual(C.pile_outside([c for _, c, _, _ in bodies]), 0)
        # density 1: sphere 4/3 pi r^3, cube (2h)^3
        masses = {k: m for k, _, _, m in C.pile_bodies(100)}
        self.assertAlmostEqual(masses["sphere"], 4 / 3 * math.pi * 0.25**3)
        self.assertAlmostEqual(masses["box"], 0.125)

    def test_rotations_follow_the_conventions(self):
        # Rx(pi/2) maps z to -y; Ry(theta) * Rx(pi/2) applies Rx first.
        z = C.quat_rotate(C.rx(math.pi / 2), (0.0, 0.0, 1.0))
        for got, want in zip(z, (0.0, -1.0, 0.0)):
            self.assertAlmostEqual(got, want)
        q = C.quat_mul(C.ry(math.pi / 2), C.rx(math.pi / 2))
        y = C.quat_rotate(q, (0.0, 1.0, 0.0))  # Rx: y -> z, then Ry(pi/2): z -> x
        for got, want in zip(y, (1.0, 0.0, 0.0)):
            self.assertAlmostEqual(got, want)

    def test_chain_links_start_interlocked_within_the_bound(self):
        links = C.chain_links()
        self.assertEqual(len(links), 21)
        mon = C.ChainMonitor()
        mon.sample([c for c, _ in links])
        self.assertAlmostEqual(mon.max_gap, 1.5)
        self.assertLess(mon.max_gap, C.CHAIN_MAX_GAP)
        self.assertAlmostEqual(C.CHAIN_MASS, 0.78957, places=5)

    def test_ideal_cradle_has_no_errors(self):
        v = [(0.0, 0.0, 0.0)] * 4 + [(1.0, 0.0, 0.0), (0.0, 0.0, 0.0)]
        f = C.cradle_figures(v, [1.0] * 6)
        self.assertAlmostEqual(f["momentum_error"], 0.0)
        self.assertAlmostEqual(f["energy_error"], 0.0)

    def test_timing_stats(self):
        s = C.timing_stats([k * 1e-3 for k in (7, 1, 11, 3, 9, 5, 2, 10, 4, 8, 6)])
        self.assertAlmostEqual(s["median"], 6.0)
        self.assertAlmostEqual(s["p10"], 2.0)
        self.assertAlmostEqual(s["p90"], 10.0)


if __name__ == "__main__":
    unittest.main()


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


class AnswerCheck(unittest.TestCase):
    """bench/run.py's check of tumble's answers: wrong answers are caught, right ones and peers pass."""

    def setUp(self):
        sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
        import run

        self.wrong = run.tumble_answers_wrong

    def record(self, scene, **figures):
        return {"engine": "tumble", "scene": scene, "status": "ok", "figures": figures}

    def test_right_answers_pass(self):
        check = {"truth_total_pairs": 10, "total_pairs": 11, "max_abs_pose_difference": 1, "within_two_pairs": True}
        ok = [
            self.record("tori", all_pairs_check=check, all_pairs_with_contacts_check=check),
            self.record("pyramid", top_box_displacement_m=0.004),
            self.record("large_pyramid", top_box_displacement_m=0.04),
            self.record("pile1000", bodies_outside=0),
            {"engine": "rapier3d", "scene": "pile1000", "status": "ok", "figures": {"bodies_outside": 12}},
            {"engine": "mujoco", "scene": "pyramid", "status": "not installed"},
        ]
        self.assertEqual(self.wrong(ok), [])

    def test_wrong_answers_are_caught(self):
        bad_pairs = {"truth_total_pairs": 10, "total_pairs": 30, "max_abs_pose_difference": 20,
                     "within_two_pairs": False}
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
