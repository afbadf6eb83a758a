//! Mesh generators for the standard solids (thesis 6.2, `BodyCreatorUtil`).
//!
//! Every generator but the ground sheet [`grid_mesh`] returns a closed mesh
//! wound counter-clockwise seen from outside. The standard solids are
//! centred on their bounding box, with the symmetry axis along z; the bowl
//! and the half-pipe are placed by the centre (axis) of the surface a body
//! rolls on, and a revolved profile stays where its points are.
//! Curved solids are inscribed polyhedra: their volume converges to the
//! analytic one from below as the resolution rises. Resolutions below the
//! smallest sensible value are rejected with a [`GeneratorError`].

use super::{MeshError, TriMesh};
use crate::math::DVec3;
use std::collections::HashMap;
use std::f64::consts::{PI, TAU};

/// Why a generator refused its parameters.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GeneratorError {
    /// A dimension is not finite and positive.
    #[error("{shape}: {name} must be finite and > 0, got {value}")]
    BadDimension {
        /// Which generator.
        shape: &'static str,
        /// Which parameter.
        name: &'static str,
        /// The value given.
        value: f64,
    },
    /// A resolution is below the minimum.
    #[error("{shape}: {name} must be >= {min}, got {value}")]
    BadResolution {
        /// Which generator.
        shape: &'static str,
        /// Which parameter.
        name: &'static str,
        /// Smallest accepted value.
        min: usize,
        /// The value given.
        value: usize,
    },
    /// The resolutions ask for more triangles than [`MAX_GENERATED_TRIANGLES`]
    /// (each resolution may be fine alone; their product is what is stored).
    #[error("{shape}: {triangles} triangles requested, at most {max} are generated")]
    TooLarge {
        /// Which generator.
        shape: &'static str,
        /// Triangles the resolutions would give.
        triangles: u128,
        /// [`MAX_GENERATED_TRIANGLES`].
        max: usize,
    },
    /// Geometric constraint between dimensions violated (e.g. torus r >= R).
    #[error("{shape}: {0}", shape = .1)]
    Constraint(String, &'static str),
    /// The produced mesh failed validation (should not happen for valid input).
    #[error(transparent)]
    Mesh(#[from] MeshError),
}

fn dim(shape: &'static str, name: &'static str, value: f64) -> Result<(), GeneratorError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(GeneratorError::BadDimension { shape, name, value })
    }
}

/// Largest mesh a generator makes (16.7 million triangles, about 600 MB with
/// its vertices). Without it two resolutions of 2^20 each ask for 2^41
/// triangles: an allocation that aborts the process (found by fuzzing the
/// scene format).
pub const MAX_GENERATED_TRIANGLES: usize = 1 << 24;

/// Refuses resolutions whose mesh would exceed [`MAX_GENERATED_TRIANGLES`].
fn budget(shape: &'static str, triangles: u128) -> Result<(), GeneratorError> {
    if triangles <= MAX_GENERATED_TRIANGLES as u128 {
        Ok(())
    } else {
        Err(GeneratorError::TooLarge {
            shape,
            triangles,
            max: MAX_GENERATED_TRIANGLES,
        })
    }
}

fn res(shape: &'static str, name: &'static str, value: usize, min: usize) -> Result<(), GeneratorError> {
    if value >= min && value <= 1 << 20 {
        Ok(())
    } else {
        Err(GeneratorError::BadResolution {
            shape,
            name,
            min,
            value,
        })
    }
}

/// Box with the given half extents (m): 8 vertices, 12 triangles.
pub fn box_mesh(half_extents: DVec3) -> Result<TriMesh, GeneratorError> {
    dim("box", "half_extents.x", half_extents.x)?;
    dim("box", "half_extents.y", half_extents.y)?;
    dim("box", "half_extents.z", half_extents.z)?;
    // Corner i has x = +hx when bit 0 is set, y when bit 1, z when bit 2.
    let vertices = (0..8)
        .map(|i| {
            DVec3::new(
                if i & 1 != 0 { 1.0 } else { -1.0 },
                if i & 2 != 0 { 1.0 } else { -1.0 },
                if i & 4 != 0 { 1.0 } else { -1.0 },
            ) * half_extents
        })
        .collect();
    let quads: [[u32; 4]; 6] = [
        [0, 2, 3, 1], // -z
        [4, 5, 7, 6], // +z
        [0, 1, 5, 4], // -y
        [2, 6, 7, 3], // +y
        [0, 4, 6, 2], // -x
        [1, 3, 7, 5], // +x
    ];
    let triangles = quads
        .iter()
        .flat_map(|&[a, b, c, d]| [[a, b, c], [a, c, d]])
        .collect();
    Ok(TriMesh::new(vertices, triangles)?)
}

/// Flat ground sheet in the plane z = 0 over `[-half_x, half_x] x [-half_y,
/// half_y]`, split into `nx` by `ny` cells of two triangles each, facing +z.
/// The one generator whose mesh is open: terrain for static bodies (it has
/// no volume, so no mass). The cell diagonals alternate direction in a
/// checkerboard, so sliding across it meets internal edges at every angle.
pub fn grid_mesh(half_x: f64, half_y: f64, nx: usize, ny: usize) -> Result<TriMesh, GeneratorError> {
    dim("grid", "half_x", half_x)?;
    dim("grid", "half_y", half_y)?;
    res("grid", "nx", nx, 1)?;
    res("grid", "ny", ny, 1)?;
    budget("grid", 2 * nx as u128 * ny as u128)?;
    let mut vertices = Vec::with_capacity((nx + 1) * (ny + 1));
    for j in 0..=ny {
        for i in 0..=nx {
            vertices.push(DVec3::new(
                -half_x + 2.0 * half_x * i as f64 / nx as f64,
                -half_y + 2.0 * half_y * j as f64 / ny as f64,
                0.0,
            ));
        }
    }
    let index = |i: usize, j: usize| (j * (nx + 1) + i) as u32;
    let mut triangles = Vec::with_capacity(2 * nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let (a, b, c, d) = (index(i, j), index(i + 1, j), index(i + 1, j + 1), index(i, j + 1));
            if (i + j) % 2 == 0 {
                triangles.extend([[a, b, c], [a, c, d]]);
            } else {
                triangles.extend([[a, b, d], [b, c, d]]);
            }
        }
    }
    Ok(TriMesh::new(vertices, triangles)?)
}

/// Surface of revolution about z: `rings` are (radius, z) from bottom to top,
/// closed by optional pole vertices below the first and above the last ring.
fn revolve(
    rings: &[(f64, f64)],
    segments: usize,
    bottom_pole: Option<f64>,
    top_pole: Option<f64>,
) -> Result<TriMesh, MeshError> {
    let n = segments as u32;
    let mut vertices = Vec::with_capacity(rings.len() * segments + 2);
    for &(r, z) in rings {
        for s in 0..segments {
            let u = TAU * s as f64 / segments as f64;
            vertices.push(DVec3::new(r * u.cos(), r * u.sin(), z));
        }
    }
    let ring = |k: usize, s: u32| k as u32 * n + (s % n);
    let mut triangles = Vec::new();
    for k in 0..rings.len().saturating_sub(1) {
        for s in 0..n {
            let (a, b, c, d) = (ring(k, s), ring(k, s + 1), ring(k + 1, s + 1), ring(k + 1, s));
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    if let Some(z) = bottom_pole {
        let p = vertices.len() as u32;
        vertices.push(DVec3::new(0.0, 0.0, z));
        for s in 0..n {
            triangles.push([p, ring(0, s + 1), ring(0, s)]);
        }
    }
    if let Some(z) = top_pole {
        let p = vertices.len() as u32;
        let last = rings.len() - 1;
        vertices.push(DVec3::new(0.0, 0.0, z));
        for s in 0..n {
            triangles.push([p, ring(last, s), ring(last, s + 1)]);
        }
    }
    TriMesh::new(vertices, triangles)
}

/// UV sphere: `segments` around z (>= 3), `rings` from pole to pole (>= 2).
pub fn uv_sphere_mesh(radius: f64, segments: usize, rings: usize) -> Result<TriMesh, GeneratorError> {
    dim("uv_sphere", "radius", radius)?;
    res("uv_sphere", "segments", segments, 3)?;
    res("uv_sphere", "rings", rings, 2)?;
    budget("uv_sphere", 2 * segments as u128 * rings as u128)?;
    let profile: Vec<(f64, f64)> = (1..rings)
        .map(|k| {
            let phi = -PI / 2.0 + PI * k as f64 / rings as f64;
            (radius * phi.cos(), radius * phi.sin())
        })
        .collect();
    Ok(revolve(&profile, segments, Some(-radius), Some(radius))?)
}

/// Geodesic sphere: an icosahedron subdivided `subdivisions` times
/// (20 * 4^s triangles), vertices projected onto the sphere.
pub fn icosphere_mesh(radius: f64, subdivisions: usize) -> Result<TriMesh, GeneratorError> {
    dim("icosphere", "radius", radius)?;
    if subdivisions > 8 {
        return Err(GeneratorError::BadResolution {
            shape: "icosphere",
            name: "subdivisions (at most 8)",
            min: 0,
            value: subdivisions,
        });
    }
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut vertices: Vec<DVec3> = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| DVec3::new(x, y, z).normalize())
    .collect();
    let mut triangles: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions {
        // Lookup only (never iterated), so the HashMap keeps output deterministic.
        let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
        let mut mid = |a: u32, b: u32, vertices: &mut Vec<DVec3>| -> u32 {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                vertices.push(((vertices[a as usize] + vertices[b as usize]) * 0.5).normalize());
                vertices.len() as u32 - 1
            })
        };
        let mut next = Vec::with_capacity(triangles.len() * 4);
        for &[a, b, c] in &triangles {
            let ab = mid(a, b, &mut vertices);
            let bc = mid(b, c, &mut vertices);
            let ca = mid(c, a, &mut vertices);
            next.extend_from_slice(&[[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        triangles = next;
    }
    for v in &mut vertices {
        *v *= radius;
    }
    Ok(TriMesh::new(vertices, triangles)?)
}

/// Cylinder of `radius` from z = -half_height to +half_height, capped.
pub fn cylinder_mesh(radius: f64, half_height: f64, segments: usize) -> Result<TriMesh, GeneratorError> {
    dim("cylinder", "radius", radius)?;
    dim("cylinder", "half_height", half_height)?;
    res("cylinder", "segments", segments, 3)?;
    Ok(revolve(
        &[(radius, -half_height), (radius, half_height)],
        segments,
        Some(-half_height),
        Some(half_height),
    )?)
}

/// Capsule: a cylinder of `radius` and `half_height` with hemispherical caps;
/// `rings` latitude bands per hemisphere (>= 1).
pub fn capsule_mesh(
    radius: f64,
    half_height: f64,
    segments: usize,
    rings: usize,
) -> Result<TriMesh, GeneratorError> {
    dim("capsule", "radius", radius)?;
    if !(half_height.is_finite() && half_height >= 0.0) {
        return Err(GeneratorError::BadDimension {
            shape: "capsule",
            name: "half_height",
            value: half_height,
        });
    }
    res("capsule", "segments", segments, 3)?;
    res("capsule", "rings", rings, 1)?;
    budget("capsule", 2 * segments as u128 * (2 * rings as u128 + 1))?;
    let mut profile = Vec::new();
    for k in 1..=rings {
        let phi = -PI / 2.0 + PI / 2.0 * k as f64 / rings as f64;
        profile.push((radius * phi.cos(), -half_height + radius * phi.sin()));
    }
    let start = if half_height > 0.0 { 0 } else { 1 };
    for k in start..rings {
        let phi = PI / 2.0 * k as f64 / rings as f64;
        profile.push((radius * phi.cos(), half_height + radius * phi.sin()));
    }
    Ok(revolve(
        &profile,
        segments,
        Some(-half_height - radius),
        Some(half_height + radius),
    )?)
}

/// Cone of base `radius` and `height`; base at z = -height/2, apex at +height/2.
pub fn cone_mesh(radius: f64, height: f64, segments: usize) -> Result<TriMesh, GeneratorError> {
    dim("cone", "radius", radius)?;
    dim("cone", "height", height)?;
    res("cone", "segments", segments, 3)?;
    Ok(revolve(
        &[(radius, -height / 2.0)],
        segments,
        Some(-height / 2.0),
        Some(height / 2.0),
    )?)
}

/// The solid swept by turning `profile` about z in `segments` steps (>= 3).
/// `profile` lists `(radius, z)` points counter-clockwise around the solid's
/// cross-section in the (r, z) half-plane, the first and the last on the axis
/// (r = 0) and every other one off it (r > 0): a cup is
/// `[(0, 0), (R, 0), (R, h), (R - t, h), (R - t, t), (0, t)]`.
pub fn revolved_mesh(profile: &[(f64, f64)], segments: usize) -> Result<TriMesh, GeneratorError> {
    let shape = "revolved";
    res(shape, "segments", segments, 3)?;
    if profile.len() < 3 {
        return Err(GeneratorError::Constraint(
            format!(
                "the profile needs at least 3 points (two on the axis), got {}",
                profile.len()
            ),
            shape,
        ));
    }
    let last = profile.len() - 1;
    for (i, &(r, z)) in profile.iter().enumerate() {
        let on_axis = i == 0 || i == last;
        let fine = r.is_finite() && z.is_finite() && if on_axis { r == 0.0 } else { r > 0.0 };
        if !fine {
            let want = if on_axis {
                "on the axis (r = 0)"
            } else {
                "off the axis (r > 0)"
            };
            return Err(GeneratorError::Constraint(
                format!("profile point {i} = ({r}, {z}) must be finite and {want}"),
                shape,
            ));
        }
    }
    budget(shape, 2 * segments as u128 * profile.len() as u128)?;
    Ok(revolve(
        &profile[1..last],
        segments,
        Some(profile[0].1),
        Some(profile[last].1),
    )?)
}

/// A hemispherical bowl: a shell of `thickness` whose inside is the lower
/// half of the sphere of `inner_radius` about the origin, open at the top
/// (rim at z = 0), with `segments` facets around z (>= 3) and `rings` from
/// the rim to the bottom (>= 1) on each of its two curved surfaces.
/// Unlike the other solids it is placed by its sphere's centre, not centred
/// on its box: a ball of radius r rests in it at z = -(inner_radius - r).
pub fn bowl_mesh(
    inner_radius: f64,
    thickness: f64,
    segments: usize,
    rings: usize,
) -> Result<TriMesh, GeneratorError> {
    dim("bowl", "inner_radius", inner_radius)?;
    dim("bowl", "thickness", thickness)?;
    res("bowl", "segments", segments, 3)?;
    res("bowl", "rings", rings, 1)?;
    budget("bowl", 4 * segments as u128 * rings as u128)?;
    let outer = inner_radius + thickness;
    // Polar angle from the bottom, ring k of `rings`.
    let at = |radius: f64, k: usize| {
        let phi = PI / 2.0 * k as f64 / rings as f64;
        (radius * phi.sin(), -radius * phi.cos())
    };
    // Up the outside, across the rim, down the inside: counter-clockwise.
    let mut profile = vec![(0.0, -outer)];
    profile.extend((1..=rings).map(|k| at(outer, k)));
    profile.extend((1..=rings).rev().map(|k| at(inner_radius, k)));
    profile.push((0.0, -inner_radius));
    revolved_mesh(&profile, segments)
}

/// A half-pipe: a trough along x of `length`, whose inside is the lower half
/// of the cylinder of `inner_radius` about the x axis, `thickness` thick,
/// open at the top (rims at z = 0), with `segments` facets across the
/// trough (>= 2), closed by flat ends at x = +-length / 2. Like
/// [`bowl_mesh`], placed by its cylinder's axis.
pub fn half_pipe_mesh(
    inner_radius: f64,
    thickness: f64,
    length: f64,
    segments: usize,
) -> Result<TriMesh, GeneratorError> {
    dim("half_pipe", "inner_radius", inner_radius)?;
    dim("half_pipe", "thickness", thickness)?;
    dim("half_pipe", "length", length)?;
    res("half_pipe", "segments", segments, 2)?;
    budget("half_pipe", 8 * segments as u128 + 4)?;
    let n = segments + 1;
    // Vertex (end e, surface s, j): end 0 at -x, 1 at +x; surface 0 the
    // inside, 1 the outside; j from the -y rim under the axis to the +y rim.
    let index = |e: usize, s: usize, j: usize| ((e * 2 + s) * n + j) as u32;
    let mut vertices = Vec::with_capacity(4 * n);
    for e in 0..2 {
        let x = if e == 0 { -0.5 * length } else { 0.5 * length };
        for radius in [inner_radius, inner_radius + thickness] {
            for j in 0..n {
                let theta = PI + PI * j as f64 / segments as f64;
                vertices.push(DVec3::new(x, radius * theta.cos(), radius * theta.sin()));
            }
        }
    }
    // Each quad wound so that its first triangle faces `outward`.
    let mut triangles = Vec::with_capacity(8 * segments + 4);
    let mut quad = |q: [u32; 4], outward: DVec3| {
        let [a, b, c, d] = q;
        let p = |i: u32| vertices[i as usize];
        let facing = (p(b) - p(a)).cross(p(c) - p(a)).dot(outward);
        if facing >= 0.0 {
            triangles.extend([[a, b, c], [a, c, d]]);
        } else {
            triangles.extend([[a, d, c], [a, c, b]]);
        }
    };
    for j in 0..segments {
        let mid = PI + PI * (j as f64 + 0.5) / segments as f64;
        let radial = DVec3::new(0.0, mid.cos(), mid.sin());
        // The inside faces the axis, the outside away from it.
        quad(
            [
                index(0, 0, j),
                index(1, 0, j),
                index(1, 0, j + 1),
                index(0, 0, j + 1),
            ],
            -radial,
        );
        quad(
            [
                index(0, 1, j),
                index(1, 1, j),
                index(1, 1, j + 1),
                index(0, 1, j + 1),
            ],
            radial,
        );
        for (e, outward) in [(0, -DVec3::X), (1, DVec3::X)] {
            quad(
                [
                    index(e, 0, j),
                    index(e, 0, j + 1),
                    index(e, 1, j + 1),
                    index(e, 1, j),
                ],
                outward,
            );
        }
    }
    for j in [0, segments] {
        quad(
            [index(0, 0, j), index(1, 0, j), index(1, 1, j), index(0, 1, j)],
            DVec3::Z,
        );
    }
    Ok(TriMesh::new(vertices, triangles)?)
}

/// Torus around z with major radius `major` (R) and tube radius `minor` (r),
/// laid out exactly as `torus_mesh` in shared/scenes.md: vertex (i, j) has index
/// `i * n_minor + j`; triangles `2 (i n_minor + j)` = [a, b, c] and `+1` = [a, c, d].
/// At 50 x 50 it has the thesis' 2,500 vertices and 5,000 triangles.
pub fn torus_mesh(major: f64, minor: f64, n_major: usize, n_minor: usize) -> Result<TriMesh, GeneratorError> {
    // The check sequence of `grid_mesh` (two dimensions, two resolutions,
    // the triangle budget) through the same helpers; only names and minimum
    // resolutions differ (3 per ring here), plus the torus's own R > r rule.
    dim("torus", "major radius R", major)?;
    dim("torus", "minor radius r", minor)?;
    res("torus", "n_major", n_major, 3)?;
    res("torus", "n_minor", n_minor, 3)?;
    budget("torus", 2 * n_major as u128 * n_minor as u128)?;
    if minor >= major {
        return Err(GeneratorError::Constraint(
            format!(
                "minor radius r = {minor} must be < major radius R = {major} (self-intersecting otherwise)"
            ),
            "torus",
        ));
    }
    let mut vertices = Vec::with_capacity(n_major * n_minor);
    for i in 0..n_major {
        let u = TAU * i as f64 / n_major as f64;
        for j in 0..n_minor {
            let v = TAU * j as f64 / n_minor as f64;
            let rho = major + minor * v.cos();
            vertices.push(DVec3::new(rho * u.cos(), rho * u.sin(), minor * v.sin()));
        }
    }
    let mut triangles = Vec::with_capacity(2 * n_major * n_minor);
    for i in 0..n_major {
        let i1 = (i + 1) % n_major;
        for j in 0..n_minor {
            let j1 = (j + 1) % n_minor;
            let a = (i * n_minor + j) as u32;
            let b = (i1 * n_minor + j) as u32;
            let c = (i1 * n_minor + j1) as u32;
            let d = (i * n_minor + j1) as u32;
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    Ok(TriMesh::new(vertices, triangles)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all() -> Vec<(&'static str, TriMesh)> {
        vec![
            ("box", box_mesh(DVec3::new(1.0, 2.0, 3.0)).unwrap()),
            ("uv_sphere", uv_sphere_mesh(1.0, 16, 8).unwrap()),
            ("icosphere", icosphere_mesh(1.0, 2).unwrap()),
            ("cylinder", cylinder_mesh(0.5, 1.0, 12).unwrap()),
            ("capsule", capsule_mesh(0.5, 1.0, 12, 4).unwrap()),
            ("capsule0", capsule_mesh(0.5, 0.0, 12, 4).unwrap()),
            ("cone", cone_mesh(0.5, 2.0, 12).unwrap()),
            ("torus", torus_mesh(1.0, 0.3, 50, 50).unwrap()),
            ("bowl", bowl_mesh(0.5, 0.05, 24, 6).unwrap()),
            ("half_pipe", half_pipe_mesh(0.5, 0.05, 2.0, 12).unwrap()),
            (
                "cup",
                revolved_mesh(
                    &[
                        (0.0, 0.0),
                        (1.0, 0.0),
                        (1.0, 2.0),
                        (0.9, 2.0),
                        (0.9, 0.1),
                        (0.0, 0.1),
                    ],
                    16,
                )
                .unwrap(),
            ),
        ]
    }

    #[test]
    fn every_generator_makes_a_closed_outward_solid() {
        for (name, m) in all() {
            m.check_solid().unwrap_or_else(|e| panic!("{name}: {e}"));
            assert!(
                m.degenerate_triangles(1e-9).is_empty(),
                "{name} has degenerate triangles"
            );
        }
    }

    #[test]
    fn torus_matches_thesis_size_and_layout() {
        let m = torus_mesh(1.0, 0.3, 50, 50).unwrap();
        assert_eq!(m.vertices().len(), 2500);
        assert_eq!(m.triangles().len(), 5000);
        // Vertex (i=1, j=0) sits at u = 2 pi / 50, v = 0.
        let u = TAU / 50.0;
        assert!((m.vertices()[50] - DVec3::new(1.3 * u.cos(), 1.3 * u.sin(), 0.0)).length() < 1e-15);
        assert_eq!(m.triangles()[0], [0, 50, 51]);
        assert_eq!(m.triangles()[1], [0, 51, 1]);
    }

    #[test]
    fn bad_parameters_are_rejected() {
        assert!(box_mesh(DVec3::new(1.0, -1.0, 1.0)).is_err());
        assert!(uv_sphere_mesh(f64::NAN, 8, 8).is_err());
        assert!(cylinder_mesh(1.0, 1.0, 2).is_err());
        assert!(torus_mesh(1.0, 1.5, 8, 8).is_err());
        assert!(icosphere_mesh(1.0, 30).is_err());
        assert!(grid_mesh(1.0, 0.0, 4, 4).is_err());
        assert!(grid_mesh(1.0, 1.0, 0, 4).is_err());
    }

    /// The shells hold the volume of their analytic solids, from below (the
    /// facets are inscribed) and within the chord error of their resolution.
    #[test]
    fn bowl_and_half_pipe_enclose_their_shells() {
        let (r, t): (f64, f64) = (0.5, 0.05);
        let shell = 2.0 / 3.0 * PI * ((r + t).powi(3) - r * r * r);
        let bowl = bowl_mesh(r, t, 96, 48).unwrap().signed_volume();
        assert!(
            bowl < shell && bowl > shell * (1.0 - 2e-3),
            "bowl {bowl} vs {shell}"
        );
        let trough = 0.5 * PI * ((r + t).powi(2) - r * r) * 2.0;
        let pipe = half_pipe_mesh(r, t, 2.0, 64).unwrap().signed_volume();
        assert!(
            pipe < trough && pipe > trough * (1.0 - 1e-3),
            "half-pipe {pipe} vs {trough}"
        );
        // The bowl's inside vertices lie on its sphere: a ball resting at
        // the bottom sits at z = -(r - radius).
        let inside = bowl_mesh(r, t, 96, 48).unwrap();
        let on_inner = inside
            .vertices()
            .iter()
            .filter(|v| (v.length() - r).abs() < 1e-12)
            .count();
        assert_eq!(on_inner, 96 * 48 + 1);
    }

    #[test]
    fn revolved_profiles_off_the_axis_or_open_are_refused() {
        assert!(revolved_mesh(&[(0.0, 0.0), (1.0, 0.0)], 8).is_err());
        assert!(revolved_mesh(&[(0.1, 0.0), (1.0, 0.0), (0.0, 1.0)], 8).is_err());
        assert!(revolved_mesh(&[(0.0, 0.0), (0.0, 0.5), (0.0, 1.0)], 8).is_err());
        assert!(revolved_mesh(&[(0.0, 0.0), (f64::NAN, 0.5), (0.0, 1.0)], 8).is_err());
        assert!(revolved_mesh(&[(0.0, 0.0), (1.0, 0.5), (0.0, 1.0)], 2).is_err());
        assert!(bowl_mesh(0.5, 0.0, 8, 4).is_err());
        assert!(half_pipe_mesh(0.5, 0.1, 1.0, 1).is_err());
    }

    #[test]
    fn grid_covers_its_rectangle_facing_up() {
        let m = grid_mesh(2.0, 1.5, 8, 6).unwrap();
        assert_eq!(m.vertices().len(), 9 * 7);
        assert_eq!(m.triangles().len(), 2 * 8 * 6);
        assert!((m.surface_area() - 4.0 * 3.0).abs() < 1e-12);
        for t in 0..m.triangles().len() {
            let n = m.triangle_normal_scaled(t);
            assert!(n.x == 0.0 && n.y == 0.0 && n.z > 0.0, "triangle {t} faces {n:?}");
        }
        let (lo, hi) = m.bounds();
        assert_eq!((lo, hi), (DVec3::new(-2.0, -1.5, 0.0), DVec3::new(2.0, 1.5, 0.0)));
    }
}
