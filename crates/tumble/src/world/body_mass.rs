//! Mass properties of a body from its shapes (thesis 3.1, 6.2): each shape's
//! analytic or polyhedral properties placed by its local pose, combined, then
//! diagonalised so that the body frame is the centre of mass with principal
//! axes (the frame the momentum state lives in).

use super::desc::{MassDesc, ShapeDesc};
use super::error::WorldError;
use tumble_collide::mass::{self, MassProperties, MassSpec, PrincipalFrame};
use tumble_collide::shape::Shape;

/// Mass properties of one shape in its own frame for a mass spec.
fn shape_properties(shape: &Shape, spec: MassSpec, index: usize) -> Result<MassProperties, WorldError> {
    let bad = |e: &dyn std::fmt::Display| WorldError::BadShape {
        index,
        message: e.to_string(),
    };
    match shape {
        Shape::Sphere(s) => mass::solid_sphere(s.radius(), spec).map_err(|e| bad(&e)),
        Shape::Cuboid(c) => mass::solid_box(c.half_extents(), spec).map_err(|e| bad(&e)),
        Shape::Capsule(c) => mass::solid_capsule(c.radius(), c.half_height(), spec).map_err(|e| bad(&e)),
        Shape::ConvexHull(h) => {
            let mesh = h.surface_mesh().map_err(|e| bad(&e))?;
            mass::solid_mass_properties(&mesh, spec)
                .map(|(p, _volume)| p)
                .map_err(|e| bad(&e))
        }
        Shape::Mesh(m) => mass::solid_mass_properties(m.mesh(), spec)
            .map(|(p, _volume)| p)
            .map_err(|e| bad(&e)),
        Shape::HalfSpace(_) => Err(WorldError::BadShape {
            index,
            message: "a half-space has infinite volume: it can only belong to a static body".into(),
        }),
        other => Err(WorldError::BadShape {
            index,
            message: format!("mass of a {} shape is not supported", other.kind_name()),
        }),
    }
}

/// Combined mass properties of the shapes in the model frame, and their
/// principal frame.
pub(crate) fn body_mass(shapes: &[ShapeDesc], mass: MassDesc) -> Result<PrincipalFrame, WorldError> {
    let per_shape_spec = match mass {
        MassDesc::Inertial(p) => {
            // Checked as the geometry's own would be: finite, mass > 0,
            // inertia symmetric and physical (triangle inequality).
            let p = MassProperties::new(p.mass, p.com, p.inertia).map_err(|e| WorldError::BadValue {
                field: "mass.inertial",
                message: e.to_string(),
            })?;
            return Ok(p.principal());
        }
        MassDesc::Density(d) => {
            if !(d.is_finite() && d > 0.0) {
                return Err(WorldError::BadValue {
                    field: "mass.density",
                    message: format!("must be finite and > 0 kg/m^3, got {d}"),
                });
            }
            MassSpec::Density(d)
        }
        MassDesc::Mass(m) => {
            if !(m.is_finite() && m > 0.0) {
                return Err(WorldError::BadValue {
                    field: "mass.mass",
                    message: format!("must be finite and > 0 kg, got {m}"),
                });
            }
            // Unit density first; the total is rescaled below.
            MassSpec::Density(1.0)
        }
    };
    let mut parts = Vec::with_capacity(shapes.len());
    for (i, s) in shapes.iter().enumerate() {
        parts.push(shape_properties(&s.shape, per_shape_spec, i)?.transformed(&s.local_pose));
    }
    let mut total = MassProperties::combine(&parts).map_err(|e| WorldError::BadShape {
        index: 0,
        message: e.to_string(),
    })?;
    if let MassDesc::Mass(m) = mass {
        let scale = m / total.mass;
        total =
            MassProperties::new(m, total.com, total.inertia * scale).map_err(|e| WorldError::BadShape {
                index: 0,
                message: e.to_string(),
            })?;
    }
    Ok(total.principal())
}
