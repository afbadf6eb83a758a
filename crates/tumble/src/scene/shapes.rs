//! Shapes of scene files: [`ShapeSpec`] to the collision crate's [`Shape`],
//! with meshes from the generators of `tumble_collide::mesh` or from OBJ/STL
//! files found relative to the scene file.

use std::path::Path;

use super::error::{FieldError, FieldPath};
use super::schema::{MeshSource, ShapeSpec};
use super::values::{non_negative, pose, positive, positive3, vec3};
use crate::world::ShapeDesc;
use tumble_collide::mesh::{self, GeneratorError, TriMesh};
use tumble_collide::shape::{Capsule, ConvexHull, Cuboid, HalfSpace, MeshShape, Shape, Sphere};
use tumble_collide::DVec3;

/// The triangle mesh of a [`MeshSource`] at `path`.
pub fn mesh_from_source(src: &MeshSource, path: &FieldPath, base_dir: &Path) -> Result<TriMesh, FieldError> {
    super::values::exactly_one(
        path,
        &[
            src.file.is_some(),
            src.box_.is_some(),
            src.sphere.is_some(),
            src.icosphere.is_some(),
            src.cylinder.is_some(),
            src.capsule.is_some(),
            src.cone.is_some(),
            src.torus.is_some(),
            src.bowl.is_some(),
            src.half_pipe.is_some(),
        ],
        "file, box, sphere, icosphere, cylinder, capsule, cone, torus, bowl, half_pipe",
    )?;
    let generated = |key: &str, r: Result<TriMesh, GeneratorError>| {
        r.map_err(|e| FieldError::new(&path.key(key), e.to_string()))
    };
    if let Some(file) = &src.file {
        let full = base_dir.join(file);
        return mesh::load_mesh(&full).map_err(|e| FieldError::new(&path.key("file"), e.to_string()));
    }
    if let Some(g) = &src.box_ {
        let h = positive3(&path.key("box").key("half_extents"), g.half_extents, "m")?;
        return generated("box", mesh::box_mesh(h));
    }
    if let Some(g) = &src.sphere {
        let n = g.segments.unwrap_or(32);
        return generated(
            "sphere",
            mesh::uv_sphere_mesh(g.radius, n, g.rings.unwrap_or(n / 2)),
        );
    }
    if let Some(g) = &src.icosphere {
        return generated(
            "icosphere",
            mesh::icosphere_mesh(g.radius, g.subdivisions.unwrap_or(3)),
        );
    }
    if let Some(g) = &src.cylinder {
        return generated(
            "cylinder",
            mesh::cylinder_mesh(g.radius, g.half_height, g.segments.unwrap_or(32)),
        );
    }
    if let Some(g) = &src.capsule {
        let n = g.segments.unwrap_or(32);
        return generated(
            "capsule",
            mesh::capsule_mesh(g.radius, g.half_height, n, g.rings.unwrap_or((n / 4).max(1))),
        );
    }
    if let Some(g) = &src.cone {
        return generated(
            "cone",
            mesh::cone_mesh(g.radius, g.height, g.segments.unwrap_or(32)),
        );
    }
    if let Some(g) = &src.bowl {
        let n = g.segments.unwrap_or(96);
        return generated(
            "bowl",
            mesh::bowl_mesh(g.inner_radius, g.thickness, n, g.rings.unwrap_or((n / 2).max(1))),
        );
    }
    if let Some(g) = &src.half_pipe {
        return generated(
            "half_pipe",
            mesh::half_pipe_mesh(g.inner_radius, g.thickness, g.length, g.segments.unwrap_or(64)),
        );
    }
    match &src.torus {
        Some(g) => generated(
            "torus",
            mesh::torus_mesh(
                g.major_radius,
                g.minor_radius,
                g.n_major.unwrap_or(50),
                g.n_minor.unwrap_or(50),
            ),
        ),
        None => Err(FieldError::new(path, "no mesh source given")),
    }
}

/// The shape and its local pose described by `spec` at `path`.
pub fn build_shape(spec: &ShapeSpec, path: &FieldPath, base_dir: &Path) -> Result<ShapeDesc, FieldError> {
    let bad = |e: &dyn std::fmt::Display| FieldError::new(path, e.to_string());
    let local = |lp: &super::schema::PoseSpec| {
        pose(
            &path.key("local_pose"),
            lp.position,
            lp.orientation,
            lp.rotation.as_deref(),
        )
    };
    let (shape, local_pose) = match spec {
        ShapeSpec::Sphere { radius, local_pose } => {
            let r = positive(&path.key("radius"), *radius, "m")?;
            (
                Shape::Sphere(Sphere::new(r).map_err(|e| bad(&e))?),
                local(local_pose)?,
            )
        }
        // One arm per shape, as Sphere above: each checks its own fields, with
        // their paths and units, before its constructor.
        ShapeSpec::Box {
            half_extents,
            local_pose,
        } => {
            let h = positive3(&path.key("half_extents"), *half_extents, "m")?;
            (
                Shape::Cuboid(Cuboid::new(h).map_err(|e| bad(&e))?),
                local(local_pose)?,
            )
        }
        ShapeSpec::Capsule {
            radius,
            half_height,
            local_pose,
        } => {
            let r = positive(&path.key("radius"), *radius, "m")?;
            let h = non_negative(&path.key("half_height"), *half_height, "m")?;
            (
                Shape::Capsule(Capsule::new(r, h).map_err(|e| bad(&e))?),
                local(local_pose)?,
            )
        }
        ShapeSpec::ConvexHull {
            points,
            mesh,
            local_pose,
        } => {
            let hull = match (points, mesh) {
                (Some(points), None) => {
                    let pts = points
                        .iter()
                        .enumerate()
                        .map(|(i, p)| vec3(&path.key("points").index(i), *p))
                        .collect::<Result<Vec<DVec3>, _>>()?;
                    ConvexHull::from_points(&pts)
                        .map_err(|e| FieldError::new(&path.key("points"), e.to_string()))?
                }
                (None, Some(src)) => {
                    let m = mesh_from_source(src, &path.key("mesh"), base_dir)?;
                    ConvexHull::from_mesh(&m)
                        .map_err(|e| FieldError::new(&path.key("mesh"), e.to_string()))?
                }
                _ => return Err(FieldError::new(path, "give exactly one of points or mesh")),
            };
            (Shape::ConvexHull(hull), local(local_pose)?)
        }
        ShapeSpec::HalfSpace {
            normal,
            offset,
            local_pose,
        } => {
            let n = vec3(&path.key("normal"), normal.unwrap_or([0.0, 0.0, 1.0]))?;
            let n = n
                .try_normalize()
                .ok_or_else(|| FieldError::new(&path.key("normal"), "must have a length > 0"))?;
            let d = offset.unwrap_or(0.0);
            if !d.is_finite() {
                return Err(FieldError::new(
                    &path.key("offset"),
                    format!("must be finite, got {d}"),
                ));
            }
            (
                Shape::HalfSpace(HalfSpace::new(n, d).map_err(|e| bad(&e))?),
                local(local_pose)?,
            )
        }
        ShapeSpec::Mesh {
            mesh,
            crease_angle_deg,
            local_pose,
        } => {
            let m = mesh_from_source(mesh, &path.key("mesh"), base_dir)?;
            let mut shape =
                MeshShape::new(m).map_err(|e| FieldError::new(&path.key("mesh"), e.to_string()))?;
            if let Some(degrees) = *crease_angle_deg {
                let at = path.key("crease_angle_deg");
                if !(degrees.is_finite() && degrees > 0.0 && degrees < 180.0) {
                    return Err(FieldError::new(
                        &at,
                        format!("must be an angle in (0, 180) degrees, got {degrees}"),
                    ));
                }
                shape = shape
                    .with_smooth_surface(degrees.to_radians())
                    .map_err(|e| FieldError::new(&at, e.to_string()))?;
            }
            (Shape::Mesh(shape), local(local_pose)?)
        }
    };
    Ok(ShapeDesc { shape, local_pose })
}
