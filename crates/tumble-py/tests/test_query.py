"""tumble.collide / distance / within_tolerance against brute-force numpy
oracles (tests/oracle.py), analytic distances, the tori ground truth, and the
checks of poses, options and shapes."""

from __future__ import annotations

import dataclasses
import importlib.util
import math
import pickle
from pathlib import Path

import numpy as np
import oracle
import pytest

import tumble

ROOT = Path(__file__).resolve().parents[3]


def random_soup(rng: np.random.Generator, n: int, size: float = 0.35) -> tumble.TriMesh:
    """n random triangles (separate vertices) around the origin."""
    centres = rng.uniform(-0.5, 0.5, size=(n, 1, 3))
    vertices = (centres + rng.uniform(-size, size, size=(n, 3, 3))).reshape(-1, 3)
    return tumble.TriMesh(vertices, np.arange(3 * n).reshape(n, 3))


def placed(mesh: tumble.TriMesh, position, q) -> np.ndarray:
    return oracle.world_triangles(mesh.vertices, mesh.faces, position, q)


# --- collide -----------------------------------------------------------------------------


@pytest.mark.parametrize("seed", range(6))
def test_pairs_equal_the_separating_axis_oracle(seed: int) -> None:
    rng = np.random.default_rng(seed)
    a, b = random_soup(rng, 30), random_soup(rng, 30)
    pa = (rng.uniform(-0.2, 0.2, 3), oracle.random_quaternion(rng))
    pb = (rng.uniform(-0.2, 0.2, 3), oracle.random_quaternion(rng))
    sep = oracle.triangle_separation(placed(a, *pa), placed(b, *pb))
    clear = np.abs(sep) > oracle.AMBIGUOUS
    assert clear.mean() > 0.999  # the oracle decides (almost) every pair
    expected = {tuple(p) for p in np.argwhere((sep <= 0) & clear)}
    assert 10 < len(expected) < 0.5 * sep.size  # both answers occur

    result = tumble.collide(a, pa, b, pb)
    got = {tuple(p) for p in result.pairs}
    undecided = {tuple(p) for p in np.argwhere(~clear)}
    assert got - undecided == expected
    assert result.intersect and bool(result)
    assert result.pairs.dtype == np.int64 and result.pairs.shape == (len(got), 2)
    assert [tuple(p) for p in result.pairs] == sorted(got)

    first = tumble.collide(a, pa, b, pb, stop_at_first=True)
    assert len(first.pairs) == 1 and tuple(first.pairs[0]) in got
    assert first.stats.stopped_early
    boolean = tumble.collide(a, pa, b, pb, report="bool")
    assert boolean.intersect and boolean.pairs.shape == (0, 2) and boolean.contacts is None

    contacts = tumble.collide(a, pa, b, pb, report="contacts")
    assert {tuple(p) for p in contacts.pairs} == got
    assert contacts.contacts.dtype == tumble.QUERY_CONTACT_DTYPE
    c = contacts.contacts
    assert len(c) > 0
    np.testing.assert_allclose(np.linalg.norm(c["normal"], axis=1), 1.0, atol=1e-9)
    np.testing.assert_array_equal(c["depth"], -c["distance"])
    # Every contact belongs to a candidate pair of triangles of A and B.
    assert c["feature_a"]["index"].max() < a.face_count
    assert c["feature_b"]["index"].max() < b.face_count
    assert set(c["feature_a"]["part"]) <= {"vertex", "edge", "face"}
    assert set(c["kind"]) <= {"vertex_face", "face_vertex", "edge_edge", "penetrating"}


def test_separated_soups_do_not_collide() -> None:
    rng = np.random.default_rng(11)
    a, b = random_soup(rng, 20), random_soup(rng, 20)
    far = ((3.0, 0.0, 0.0), (0, 0, 0, 1))
    result = tumble.collide(a, None, b, far, report="contacts")
    assert not result and result.pairs.shape == (0, 2) and len(result.contacts) == 0
    assert oracle.triangle_separation(placed(a, (0, 0, 0), (0, 0, 0, 1)), placed(b, *far)).min() > 0


def test_sphere_primitive_against_the_point_triangle_oracle() -> None:
    rng = np.random.default_rng(5)
    soup = random_soup(rng, 40)
    tris = placed(soup, (0, 0, 0), (0, 0, 0, 1))
    for _ in range(5):
        centre, radius = rng.uniform(-0.5, 0.5, 3), rng.uniform(0.1, 0.4)
        d = oracle.point_triangle_distance(centre[None], tris)[0]
        clear = np.abs(d - radius) > oracle.AMBIGUOUS
        expected = set(np.flatnonzero((d <= radius) & clear))
        # Both orders: the primitive's index in a pair is 0.
        ab = tumble.collide(tumble.Sphere(radius), (centre, (0, 0, 0, 1)), soup, None)
        ba = tumble.collide(soup, None, tumble.Sphere(radius), (centre, (0, 0, 0, 1)))
        assert set(ab.pairs[:, 1]) - set(np.flatnonzero(~clear)) == expected
        assert set(ab.pairs[:, 0]) <= {0}
        np.testing.assert_array_equal(ba.pairs, ab.pairs[:, ::-1])
        dist = tumble.distance(tumble.Sphere(radius), (centre, (0, 0, 0, 1)), soup, None)
        assert dist.distance == pytest.approx(max(d.min() - radius, 0.0), abs=1e-12)


def test_boxes_overlapping_by_a_known_depth() -> None:
    cube = tumble.TriMesh.box((0.5, 0.5, 0.5))
    above = ((0.3, 0.2, 0.9), (0, 0, 0, 1))  # B overlaps A by 0.1 m along z
    r = tumble.collide(cube, None, cube, above, report="contacts")
    deepest = r.contacts[np.argmax(r.contacts["depth"])]
    assert deepest["depth"] == pytest.approx(0.1, abs=1e-12)
    np.testing.assert_allclose(deepest["normal"], (0, 0, -1), atol=1e-12)  # from B to A

    # A solid box primitive gives the same depth; swapping A and B flips the normal.
    prim = tumble.Box((0.5, 0.5, 0.5))
    pm = tumble.collide(prim, above, cube, None, report="contacts").contacts
    mp = tumble.collide(cube, None, prim, above, report="contacts").contacts
    assert pm["depth"].max() == pytest.approx(0.1, abs=1e-9)
    np.testing.assert_allclose(pm["normal"][np.argmax(pm["depth"])], (0, 0, 1), atol=1e-9)
    np.testing.assert_allclose(mp["normal"], -pm["normal"])
    np.testing.assert_array_equal(mp["feature_a"], pm["feature_b"])

    lifted = ((0.3, 0.2, 1.5), (0, 0, 0, 1))
    d = tumble.distance(cube, None, cube, lifted)
    assert d.distance == pytest.approx(0.5, abs=1e-12)
    assert d.point_b[2] - d.point_a[2] == pytest.approx(0.5, abs=1e-12)
    assert float(d) == d.distance


def test_a_corner_pointing_at_a_corner_within_the_margin_is_a_vertex_vertex_contact() -> None:
    # B's lowest corner 4 mm from A's highest along each axis: the meshes are
    # 4 sqrt(3) mm apart, and the closest features are two corners, which no
    # vertex/face or edge/edge contact sees. The contact lies between them,
    # along a face normal of either box (from B to A), at the gap along it.
    cube = tumble.TriMesh.box((0.5, 0.5, 0.5))
    diagonal = ((1.004, 1.004, 1.004), (0, 0, 0, 1))
    gap = 0.004 * math.sqrt(3.0)
    assert tumble.distance(cube, None, cube, diagonal).distance == pytest.approx(gap, abs=1e-12)
    for a in (cube, tumble.Box((0.5, 0.5, 0.5))):
        contacts = tumble.collide(
            a, None, cube, diagonal, report="contacts", contact_margin=0.01
        ).contacts
        corner = contacts[contacts["kind"] == "vertex_vertex"]
        assert len(corner) == 1, contacts
        assert corner["distance"][0] == pytest.approx(0.004, abs=1e-12)
        np.testing.assert_allclose(corner["point"][0], (0.502, 0.502, 0.502), atol=1e-12)
        assert sorted(np.round(corner["normal"][0], 12)) == [-1.0, 0.0, 0.0]
        # Without a margin the query reports the contacts of touching
        # triangles only: none here.
        assert len(tumble.collide(a, None, cube, diagonal, report="contacts").contacts) == 0


def test_half_space_against_a_box_mesh() -> None:
    cube = tumble.TriMesh.box((0.5, 0.5, 0.5))
    ground = tumble.HalfSpace()
    for z in (0.4, 0.6):
        r = tumble.collide(ground, None, cube, ((0, 0, z), (0, 0, 0, 1)))
        tris = placed(cube, (0, 0, z), (0, 0, 0, 1))
        expected = np.flatnonzero(tris[:, :, 2].min(axis=1) <= 0)  # a corner on or below z = 0
        np.testing.assert_array_equal(r.pairs[:, 1], expected)
        assert r.intersect == (z < 0.5)
    d = tumble.distance(cube, ((0, 0, 0.6), (0, 0, 0, 1)), ground, None)
    assert d.distance == pytest.approx(0.1, abs=1e-12)
    assert d.point_a[2] == pytest.approx(0.1) and d.point_b[2] == pytest.approx(0.0)
    assert d.tri_b == 0


# --- distance ----------------------------------------------------------------------------


@pytest.mark.parametrize("seed", range(8))
def test_distance_equals_the_brute_force_minimum(seed: int) -> None:
    rng = np.random.default_rng(100 + seed)
    a, b = random_soup(rng, 15, 0.2), random_soup(rng, 15, 0.2)
    pa = (np.zeros(3), oracle.random_quaternion(rng))
    qb, direction = oracle.random_quaternion(rng), oracle.random_quaternion(rng)[:3]
    # B moved out along a random direction until the soups just stop intersecting.
    for shift in np.arange(0.05, 3.0, 0.05):
        pb = (shift * direction / np.linalg.norm(direction), qb)
        ta, tb = placed(a, *pa), placed(b, *pb)
        if oracle.triangle_separation(ta, tb).min() > oracle.AMBIGUOUS:
            break
    expected = oracle.soup_distance(ta, tb)
    assert 0 < expected < 0.2

    d = tumble.distance(a, pa, b, pb)
    assert d.distance == pytest.approx(expected, rel=1e-12, abs=1e-14)
    assert np.linalg.norm(d.point_b - d.point_a) == pytest.approx(d.distance, rel=1e-12)
    # The closest points lie on the triangles named.
    assert oracle.point_triangle_distance(d.point_a[None], ta[[d.tri_a]])[0, 0] < 1e-12
    assert oracle.point_triangle_distance(d.point_b[None], tb[[d.tri_b]])[0, 0] < 1e-12

    approx = tumble.distance(a, pa, b, pb, rel_err=0.5, abs_err=0.0)
    assert expected - 1e-12 <= approx.distance <= 1.5 * expected + 1e-12
    approx = tumble.distance(a, pa, b, pb, abs_err=0.05)
    assert expected - 1e-12 <= approx.distance <= expected + 0.05 + 1e-12

    assert tumble.within_tolerance(a, pa, b, pb, d.distance)
    assert not tumble.within_tolerance(a, pa, b, pb, d.distance * (1 - 1e-9))
    assert tumble.within_tolerance(a, pa, b, pb, d.distance * 1.01)


def test_distance_of_intersecting_soups_is_zero_at_an_intersecting_pair() -> None:
    rng = np.random.default_rng(3)
    a, b = random_soup(rng, 20), random_soup(rng, 20)
    d = tumble.distance(a, None, b, None)
    assert d.distance == 0.0
    np.testing.assert_allclose(d.point_a, d.point_b, atol=1e-12)
    pairs = {tuple(p) for p in tumble.collide(a, None, b, None).pairs}
    assert (d.tri_a, d.tri_b) in pairs
    assert tumble.within_tolerance(a, None, b, None, 0.0)


def inradius(mesh: tumble.TriMesh) -> float:
    """Distance from the origin to the nearest face plane of a mesh around it."""
    t = mesh.vertices[mesh.faces]
    n = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    return float(np.abs(np.einsum("md,md->m", n, t[:, 0])).min())


@pytest.mark.parametrize("mesh", [tumble.TriMesh.sphere(0.5, 2), tumble.TriMesh.uv_sphere(0.5)])
def test_sphere_meshes_are_as_far_apart_as_the_balls_up_to_faceting(mesh) -> None:
    # Vertices lie on the sphere of radius 0.5 and the faces around an inner ball
    # of radius r_in, so the meshes are between D - 2 * 0.5 and D - 2 * r_in apart.
    r_in = inradius(mesh)
    assert 0.45 < r_in < 0.5
    rng = np.random.default_rng(8)
    for _ in range(4):
        direction = oracle.random_quaternion(rng)[:3]
        centre = direction / np.linalg.norm(direction) * rng.uniform(1.2, 2.0)
        pb = (centre, oracle.random_quaternion(rng))
        d = tumble.distance(mesh, None, mesh, pb).distance
        gap = np.linalg.norm(centre)
        assert gap - 1.0 <= d <= gap - 2 * r_in
        # A solid ball of radius 0.3 against the mesh.
        ball = tumble.distance(tumble.Sphere(0.3), pb, mesh, None).distance
        assert gap - 0.3 - 0.5 <= ball <= gap - 0.3 - r_in


# --- poses -------------------------------------------------------------------------------


def test_every_pose_form_gives_the_same_answer() -> None:
    rng = np.random.default_rng(21)
    a, b = random_soup(rng, 25), random_soup(rng, 25)
    q = oracle.random_quaternion(rng)
    p = np.array([0.1, -0.05, 0.2])
    reference = tumble.collide(a, None, b, (p, q)).pairs
    assert len(reference) > 0
    forms = [
        (tuple(p), tuple(q)),
        [list(p), list(q)],
        np.concatenate([p, q]),
        list(np.concatenate([p, q])),
        np.concatenate([p, q]).astype(np.float32).astype(np.float64),
        oracle.matrix(p, q),
        oracle.matrix(p, q).tolist(),
    ]
    for form in forms[:4] + forms[5:]:
        np.testing.assert_array_equal(tumble.collide(a, np.eye(4), b, form).pairs, reference)
        np.testing.assert_array_equal(
            tumble.collide(a, (0, 0, 0, 0, 0, 0, 1), b, form).pairs, reference
        )
    # A float32 rotation matrix and an integer identity matrix are accepted.
    tumble.collide(a, np.eye(4, dtype=np.int32), b, oracle.matrix(p, q).astype(np.float32))
    # q and -q are the same rotation.
    np.testing.assert_array_equal(tumble.collide(a, None, b, (p, -q)).pairs, reference)


@pytest.mark.parametrize(
    "pose, message",
    [
        (
            ((0, 0, 0), (0, 0, 0, 2)),
            "pose_b: pose orientation must be a unit quaternion (x, y, z, w), got length 2",
        ),
        (((0, 0, math.nan), (0, 0, 0, 1)), "pose_b: pose position must be finite"),
        (((0, 0), (0, 0, 0, 1)), "pose_b position: expected 3 numbers"),
        (((0, 0, 0), (0, 0, 1)), "pose_b orientation: expected a quaternion of 4 numbers"),
        ((0, 0, 0, 0, 0), "pose_b: expected a pose: (position, orientation)"),
        (np.eye(3), "pose_b: expected a pose"),
        ("identity", "pose_b: expected a pose"),
        (np.diag([2.0, 2.0, 2.0, 1.0]), "R^T R differs from the identity by 3.000e0"),
        (np.diag([1.0, 1.0, -1.0, 1.0]), "is a reflection (determinant -1"),
        (
            np.array([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0.5, 1]]),
            "the last row of a 4x4 pose matrix must be (0, 0, 0, 1)",
        ),
        (np.full((4, 4), np.inf), "the 4x4 pose matrix must be finite"),
    ],
)
def test_bad_poses_are_refused(pose, message: str) -> None:
    mesh = tumble.TriMesh.box((0.5, 0.5, 0.5))
    for fn in (tumble.collide, tumble.distance):
        with pytest.raises(tumble.InvalidArgument) as info:
            fn(mesh, None, mesh, pose)
        assert message in str(info.value)
    # The name is the Python argument's, also when A and B are swapped inside.
    with pytest.raises(tumble.InvalidArgument, match="pose_b"):
        tumble.within_tolerance(mesh, None, tumble.Sphere(1.0), pose, 0.1)


def test_slightly_scaled_matrices_within_tolerance_pass() -> None:
    mesh = tumble.TriMesh.box((0.5, 0.5, 0.5))
    m = oracle.matrix((0, 0, 0.5), (0, 0, math.sin(0.3), math.cos(0.3)))
    m[:3, :3] *= 1 + 1e-8
    assert tumble.collide(mesh, None, mesh, m)
    m[:3, :3] *= 1 + 1e-3
    with pytest.raises(tumble.InvalidArgument, match="scale or shear"):
        tumble.collide(mesh, None, mesh, m)


# --- options, shapes, results ------------------------------------------------------------


def test_bad_options_and_shapes() -> None:
    mesh = tumble.TriMesh.box((0.5, 0.5, 0.5))
    cases = [
        (
            lambda: tumble.collide(mesh, None, mesh, None, report="all"),
            'report: expected "bool", "pairs" or "contacts", got "all"',
        ),
        (
            lambda: tumble.collide(mesh, None, mesh, None, report="contacts", contact_margin=-1),
            "CollideOptions::contact_margin must be finite and >= 0, got -1",
        ),
        (
            lambda: tumble.distance(mesh, None, mesh, None, rel_err=-0.1),
            "DistanceOptions::rel_err must be finite and >= 0, got -0.1",
        ),
        (
            lambda: tumble.distance(mesh, None, mesh, None, abs_err=math.inf),
            "DistanceOptions::abs_err must be finite and >= 0, got inf",
        ),
        (
            lambda: tumble.within_tolerance(mesh, None, mesh, None, math.nan),
            "within_tolerance tol must be finite and >= 0, got NaN",
        ),
        (
            lambda: tumble.collide(tumble.Sphere(1), None, tumble.Box((1, 1, 1)), None),
            "a query needs at least one mesh; got two primitives (sphere and cuboid)",
        ),
        (
            lambda: tumble.collide(mesh, None, tumble.ConvexHull(mesh.vertices), None),
            "b: the queries take a TriMesh",
        ),
        (lambda: tumble.collide("box", None, mesh, None), "a: expected a TriMesh"),
        (
            lambda: tumble.collide(mesh, None, tumble.Sphere(1).at((0, 0, 1)), None),
            "b: the queries take a TriMesh",
        ),
    ]
    for call, message in cases:
        with pytest.raises(tumble.InvalidArgument) as info:
            call()
        assert message in str(info.value)


def test_trimesh_like_objects_are_accepted() -> None:
    class Soup:
        def __init__(self, mesh: tumble.TriMesh) -> None:
            self.vertices, self.faces = mesh.vertices, mesh.faces

    rng = np.random.default_rng(2)
    a, b = random_soup(rng, 20), random_soup(rng, 20)
    expected = tumble.collide(a, None, b, None).pairs
    np.testing.assert_array_equal(tumble.collide(Soup(a), None, Soup(b), None).pairs, expected)
    trimesh = pytest.importorskip("trimesh")
    tm = trimesh.Trimesh(b.vertices, b.faces, process=False)
    np.testing.assert_array_equal(tumble.collide(a, None, tm, None).pairs, expected)
    assert tumble.distance(tm, None, a, ((3, 0, 0), (0, 0, 0, 1))).distance > 0


def test_results_are_frozen_dataclasses() -> None:
    cube = tumble.TriMesh.box((0.5, 0.5, 0.5))
    r = tumble.collide(cube, None, cube, ((0.3, 0.2, 0.9), (0, 0, 0, 1)))
    d = tumble.distance(cube, None, cube, ((0.3, 0.2, 1.5), (0, 0, 0, 1)))
    for result in (r, d, r.stats):
        assert dataclasses.is_dataclass(result)
        with pytest.raises(dataclasses.FrozenInstanceError):
            result.stats = None  # type: ignore[misc]
        # Made without __init__ (see query_out.rs): the same as made with it.
        fields = {f.name: getattr(result, f.name) for f in dataclasses.fields(result)}
        again = type(result)(**fields)
        assert vars(again).keys() == vars(result).keys()
        assert repr(again) == repr(result)
    assert r.stats == tumble.QueryStats(r.stats.bv_tests, r.stats.triangle_tests, False)
    back = pickle.loads(pickle.dumps(r))
    assert back.intersect and back.stats == r.stats
    np.testing.assert_array_equal(back.pairs, r.pairs)
    assert pickle.loads(pickle.dumps(d)).distance == d.distance
    assert repr(r).startswith("CollisionResult(intersect=True, pairs=<")
    assert repr(d).startswith("DistanceResult(distance=0.5")
    for fn in (
        tumble.collide,
        tumble.distance,
        tumble.within_tolerance,
        tumble.CollisionResult,
        tumble.DistanceResult,
        tumble.QueryStats,
    ):
        assert fn.__doc__ and len(fn.__doc__) > 100, fn
    assert "report=" in tumble.collide.__text_signature__


# --- the tori (shared/scenes.md) ----------------------------------------------------------


def load_example():
    path = ROOT / "examples" / "python" / "collision_query.py"
    spec = importlib.util.spec_from_file_location("collision_query", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_tori_pairs_equal_the_ground_truth() -> None:
    example = load_example()
    torus = example.torus()
    counts, first = [], []
    for pose in example.tori_poses():
        counts.append(len(tumble.collide(torus, None, torus, pose).pairs))
        first.append(tumble.collide(torus, None, torus, pose, report="bool").intersect)
    assert sum(counts) == example.TOTAL_PAIRS == 36_782
    assert sum(first) == example.COLLIDING_POSES == 122
    assert first == [n > 0 for n in counts]
    truth = example.truth_pairs_per_pose()
    if truth is not None:
        assert counts == truth
