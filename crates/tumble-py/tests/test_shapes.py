"""Shapes, meshes and mass properties: analytic values, cross-checks with
trimesh's own (independent) mass properties, files, compound bodies and
pickling."""

from __future__ import annotations

import math
import pickle

import numpy as np
import pytest

import tumble

trimesh = pytest.importorskip("trimesh")


def test_box_mass_properties_are_analytic() -> None:
    a, b, c = 0.5, 0.25, 0.1
    p = tumble.mass_properties(tumble.TriMesh.box((a, b, c)), density=7850.0)
    volume = 8 * a * b * c
    m = 7850.0 * volume
    assert p.volume == pytest.approx(volume)
    assert p.mass == pytest.approx(m)
    np.testing.assert_allclose(p.com, 0.0, atol=1e-12)
    expected = m / 3 * np.array([b * b + c * c, a * a + c * c, a * a + b * b])
    np.testing.assert_allclose(p.inertia, np.diag(expected), rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(p.principal_moments, np.sort(expected), rtol=1e-12)
    assert p.method == "solid"


def test_principal_frame_diagonalises_a_rotated_offset_box() -> None:
    box = tumble.TriMesh.box((0.3, 0.2, 0.1))
    angle = 0.7
    rot = np.array(
        [[math.cos(angle), -math.sin(angle), 0], [math.sin(angle), math.cos(angle), 0], [0, 0, 1]]
    )
    vertices = box.vertices @ rot.T + [1.0, -2.0, 0.5]
    p = tumble.mass_properties(vertices, box.faces, mass=3.0)
    assert p.mass == pytest.approx(3.0)
    np.testing.assert_allclose(p.com, [1.0, -2.0, 0.5], atol=1e-12)
    axes = p.principal_axes
    np.testing.assert_allclose(axes.T @ axes, np.eye(3), atol=1e-12)
    assert np.linalg.det(axes) == pytest.approx(1.0)
    np.testing.assert_allclose(axes @ np.diag(p.principal_moments) @ axes.T, p.inertia, atol=1e-12)
    # The same moments as the unrotated box.
    ref = tumble.mass_properties(box, mass=3.0)
    np.testing.assert_allclose(p.principal_moments, ref.principal_moments, rtol=1e-10)


def test_mass_properties_agree_with_trimesh() -> None:
    # Two independent implementations of the polyhedral integrals.
    mesh = trimesh.creation.annulus(r_min=0.3, r_max=0.6, height=0.4, sections=40)
    mesh.apply_translation([0.2, 0.1, -0.3])
    mesh.density = 2.5
    ours = tumble.mass_properties(mesh, density=2.5)  # duck-typed .vertices / .faces
    theirs = mesh.mass_properties
    assert ours.volume == pytest.approx(theirs["volume"], rel=1e-9)
    assert ours.mass == pytest.approx(theirs["mass"], rel=1e-9)
    np.testing.assert_allclose(ours.com, theirs["center_mass"], rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(ours.inertia, theirs["inertia"], rtol=1e-8, atol=1e-12)


def test_torus_volume_converges_to_pappus() -> None:
    R, r = 1.0, 0.25
    exact = 2 * math.pi**2 * R * r * r
    coarse = tumble.TriMesh.torus(R, r, 24, 12).volume
    fine = tumble.TriMesh.torus(R, r, 96, 48).volume
    assert abs(fine - exact) < abs(coarse - exact) / 10
    assert fine == pytest.approx(exact, rel=1e-2)


def test_fallbacks_for_open_meshes() -> None:
    box = tumble.TriMesh.box((0.5, 0.5, 0.5))
    open_box = tumble.TriMesh(box.vertices, box.faces[:10])
    hull = tumble.mass_properties(open_box, density=1.0, fallback="convex_hull")
    assert hull.method == "convex_hull" and hull.volume == pytest.approx(1.0)
    shell = tumble.mass_properties(open_box, density=1.0, fallback="shell", shell_thickness=0.01)
    assert shell.method == "shell" and shell.volume == pytest.approx(5.0)  # area of 5 faces
    with pytest.raises(tumble.InvalidArgument):
        tumble.mass_properties(open_box, fallback="shell")
    with pytest.raises(tumble.InvalidArgument):
        tumble.mass_properties(open_box, fallback="glue")


def test_generators_are_closed_solids_with_the_right_volume() -> None:
    cases = [
        (tumble.TriMesh.box((1, 2, 3)), 48.0, 1e-12),
        (tumble.TriMesh.sphere(1.0, 4), 4 / 3 * math.pi, 2e-2),
        (tumble.TriMesh.uv_sphere(1.0, 64, 32), 4 / 3 * math.pi, 2e-2),
        (tumble.TriMesh.cylinder(0.5, 1.0, 64), math.pi * 0.25 * 2, 2e-2),
        (tumble.TriMesh.capsule(0.5, 1.0, 48, 12), math.pi * 0.25 * 2 + 4 / 3 * math.pi / 8, 2e-2),
        (tumble.TriMesh.cone(0.5, 1.0, 64), math.pi * 0.25 / 3, 2e-2),
        (tumble.TriMesh.torus(1.0, 0.25), 2 * math.pi**2 * 0.0625, 2e-2),
    ]
    for mesh, volume, rel in cases:
        assert mesh.is_solid, mesh
        assert mesh.volume == pytest.approx(volume, rel=rel), mesh


def test_files_round_trip_through_trimesh(tmp_path) -> None:
    source = trimesh.creation.icosphere(subdivisions=2, radius=0.5)
    for ext in ["obj", "stl"]:
        path = tmp_path / f"ball.{ext}"
        source.export(path)
        mesh = tumble.TriMesh.from_file(str(path))
        assert mesh.is_solid
        assert mesh.volume == pytest.approx(source.volume, rel=1e-6)
        assert mesh.face_count == len(source.faces)
    back = tumble.TriMesh.from_file(tmp_path / "ball.obj").to_trimesh()
    assert isinstance(back, trimesh.Trimesh) and back.volume == pytest.approx(source.volume)


def test_trimesh_objects_are_bodies() -> None:
    world = tumble.World(sleeping=False)
    world.add_body(tumble.HalfSpace(), kind="static")
    mesh = trimesh.creation.box(extents=(0.4, 0.4, 0.4))
    body = world.add_body(mesh, density=1000.0, position=(0, 0, 1))
    assert body.mass == pytest.approx(64.0)
    np.testing.assert_allclose(body.principal_inertia, 64.0 * 0.32 / 12)
    world.step(120)
    assert body.position[2] == pytest.approx(0.2, abs=2e-3)  # resting on its face
    hull = tumble.ConvexHull(trimesh.creation.icosphere(subdivisions=1))
    assert hull.vertices.shape == (42, 3)
    assert tumble.TriMesh.from_trimesh(mesh).face_count == 12


def test_convex_hull_of_points() -> None:
    rng = np.random.default_rng(1)
    inside = rng.uniform(-0.5, 0.5, (200, 3))
    corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float)
    hull = tumble.ConvexHull(np.vstack([inside, corners]))
    assert sorted(map(tuple, hull.vertices)) == sorted(map(tuple, corners))
    assert hull.face_count == 6
    world = tumble.World()
    body = world.add_body(hull, density=1.0)
    assert body.mass == pytest.approx(8.0)


def test_compound_body_mass_and_centre() -> None:
    world = tumble.World()
    body = world.add_body(
        [
            tumble.Box((0.5, 0.5, 0.5)),
            tumble.Box((0.5, 0.5, 0.5)).at(position=(3, 0, 0)),
            tumble.Placed(tumble.Sphere(0.5), position=(0, 3, 0)),
        ],
        density=2.0,
        position=(10, 0, 0),
    )
    v_box, v_ball = 1.0, 4 / 3 * math.pi * 0.125
    assert body.mass == pytest.approx(2.0 * (2 * v_box + v_ball))
    com = (
        v_box * np.array([0, 0, 0]) + v_box * np.array([3, 0, 0]) + v_ball * np.array([0, 3, 0])
    ) / (2 * v_box + v_ball)
    np.testing.assert_allclose(body.center_of_mass, com + [10, 0, 0], atol=1e-9)
    np.testing.assert_allclose(body.position, [10, 0, 0], atol=1e-12)  # model frame, not com


@pytest.mark.parametrize(
    "shape",
    [
        tumble.Box((1, 2, 3)),
        tumble.Sphere(0.5),
        tumble.Capsule(0.1, 0.3),
        tumble.HalfSpace((0, 1, 0), 2.0),
        tumble.TriMesh.torus(1.0, 0.3, 12, 6),
        tumble.ConvexHull(tumble.TriMesh.box((1, 1, 1)).vertices),
    ],
)
def test_shapes_pickle(shape) -> None:
    copy = pickle.loads(pickle.dumps(shape))
    assert type(copy) is type(shape)
    assert repr(copy) == repr(shape)
    for attr in ["vertices", "faces", "half_extents", "normal", "radius"]:
        if hasattr(shape, attr):
            np.testing.assert_array_equal(getattr(copy, attr), getattr(shape, attr))


def test_records_pickle_and_unpack() -> None:
    p = tumble.mass_properties(tumble.TriMesh.box((1, 1, 1)))
    volume, mass, *_ = p
    assert (volume, mass) == (8.0, 8000.0)
    q = pickle.loads(pickle.dumps(p))
    assert q.mass == p.mass and np.array_equal(q.inertia, p.inertia)
