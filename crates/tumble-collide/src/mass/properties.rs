//! Mass, centre of mass and inertia tensor of a rigid body, and what can be
//! done with them without the geometry: move, rotate, shift the reference
//! point (parallel-axis theorem), combine parts, and diagonalise into the
//! principal frame (thesis 2.2.3; Goldstein, "Classical Mechanics", 5.3-5.4).

use super::MassError;
use crate::math::{sym_eigen, symmetrize, DMat3, DQuat, DVec3};
use crate::mesh::TriMesh;
use crate::pose::Pose;
use serde::{Deserialize, Serialize};

/// Mass properties of a rigid body, expressed in the frame of its geometry.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MassProperties {
    /// Total mass (kg).
    pub mass: f64,
    /// Centre of mass in the geometry's frame (m).
    pub com: DVec3,
    /// Inertia tensor about the centre of mass, axes of the geometry's frame
    /// (kg m^2). Symmetric, positive definite.
    pub inertia: DMat3,
}

/// Principal frame of a body: centre of mass and principal axes.
///
/// `rotation` maps principal-frame vectors into the geometry's frame: its
/// matrix has the principal axes as columns, right-handed, in the order of
/// `moments`. So `inertia = R diag(moments) R^T` and a point `p` of the
/// geometry sits at `R^T (p - com)` in the principal frame.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PrincipalFrame {
    /// Total mass (kg).
    pub mass: f64,
    /// Centre of mass in the geometry's frame (m).
    pub com: DVec3,
    /// Principal moments of inertia, ascending (kg m^2).
    pub moments: DVec3,
    /// Unit quaternion (x, y, z, w) from principal axes to the geometry's frame.
    pub rotation: DQuat,
}

/// Inertia of a point mass `m` at offset `d` from the reference point:
/// `m (|d|^2 E - d d^T)`, the parallel-axis term.
pub(crate) fn point_inertia(m: f64, d: DVec3) -> DMat3 {
    DMat3::from_diagonal(DVec3::splat(m * d.length_squared())) - outer(d * m, d)
}

/// Outer product `a b^T`.
pub(crate) fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}

impl MassProperties {
    /// Validated mass properties (see [`MassProperties::validate`]).
    pub fn new(mass: f64, com: DVec3, inertia: DMat3) -> Result<MassProperties, MassError> {
        let p = MassProperties { mass, com, inertia };
        p.validate()?;
        Ok(p)
    }

    /// Checks that a physical body could have these properties: finite
    /// values, mass > 0, a symmetric tensor whose principal moments are
    /// non-negative and obey the triangle inequality `I1 + I2 >= I3` (true for
    /// any real mass distribution), all up to round-off.
    pub fn validate(&self) -> Result<(), MassError> {
        let bad = |reason: String| Err(MassError::Invalid { reason });
        if !(self.mass.is_finite() && self.mass > 0.0) {
            return bad(format!("mass must be finite and > 0 kg, got {}", self.mass));
        }
        if !self.com.is_finite() {
            return bad(format!("centre of mass must be finite, got {:?}", self.com));
        }
        if !self.inertia.is_finite() {
            return bad(format!("inertia must be finite, got {:?}", self.inertia));
        }
        let scale = self
            .inertia
            .to_cols_array()
            .iter()
            .fold(0.0f64, |m, x| m.max(x.abs()));
        let tol = 1e-9 * scale;
        let asym = crate::math::max_abs_diff_mat(&self.inertia, &self.inertia.transpose());
        if asym > tol {
            return bad(format!("inertia is not symmetric (|I - I^T| = {asym:e})"));
        }
        let (m, _) = sym_eigen(&self.inertia);
        if m.x < -tol {
            return bad(format!("principal moment {:e} kg m^2 is negative", m.x));
        }
        if m.x + m.y < m.z - tol {
            return bad(format!(
                "principal moments {m:?} break the triangle inequality I1 + I2 >= I3"
            ));
        }
        Ok(())
    }

    /// The same body moved by `offset` (m): the centre of mass moves, the
    /// inertia about it does not change.
    pub fn translated(&self, offset: DVec3) -> MassProperties {
        MassProperties {
            com: self.com + offset,
            ..*self
        }
    }

    /// The same body rotated by unit quaternion `q` about the frame's origin:
    /// `com -> R com`, `I -> R I R^T`.
    pub fn rotated(&self, q: DQuat) -> MassProperties {
        let r = DMat3::from_quat(q);
        MassProperties {
            mass: self.mass,
            com: q * self.com,
            inertia: symmetrize(&(r * self.inertia * r.transpose())),
        }
    }

    /// The same body carried by `pose` (rotation first, then translation).
    pub fn transformed(&self, pose: &Pose) -> MassProperties {
        self.rotated(pose.rotation).translated(pose.position)
    }

    /// Inertia tensor about `point` instead of the centre of mass (kg m^2), by
    /// the parallel-axis theorem: `I_p = I_com + m (|d|^2 E - d d^T)`,
    /// `d = com - point`.
    pub fn inertia_about(&self, point: DVec3) -> DMat3 {
        self.inertia + point_inertia(self.mass, self.com - point)
    }

    /// Properties of a rigid body made of `parts` (all in the same frame):
    /// masses add, the centre of mass is the mass-weighted mean, and each
    /// part's inertia is carried to the common centre by the parallel-axis
    /// theorem. Parts are validated; an empty slice is an error.
    pub fn combine(parts: &[MassProperties]) -> Result<MassProperties, MassError> {
        if parts.is_empty() {
            return Err(MassError::EmptyComposite);
        }
        for (index, p) in parts.iter().enumerate() {
            p.validate().map_err(|e| MassError::BadPart {
                index,
                source: Box::new(e),
            })?;
        }
        let mass: f64 = parts.iter().map(|p| p.mass).sum();
        let com = parts.iter().map(|p| p.com * p.mass).sum::<DVec3>() / mass;
        let inertia = parts.iter().fold(DMat3::ZERO, |acc, p| {
            acc + p.inertia + point_inertia(p.mass, p.com - com)
        });
        let out = MassProperties {
            mass,
            com,
            inertia: symmetrize(&inertia),
        };
        if !(mass.is_finite() && com.is_finite() && out.inertia.is_finite()) {
            return Err(MassError::NonFiniteResult { what: "composite" });
        }
        Ok(out)
    }

    /// Principal moments (ascending) and axes, from the Jacobi eigen-solver
    /// [`sym_eigen`]. For repeated moments (symmetric bodies) any orthonormal
    /// basis of the degenerate eigenspace is returned.
    pub fn principal(&self) -> PrincipalFrame {
        let (moments, axes) = sym_eigen(&self.inertia);
        PrincipalFrame {
            mass: self.mass,
            com: self.com,
            moments,
            // `axes` is orthonormal with det +1 (sym_eigen guarantees it), so it
            // is a rotation and converts exactly.
            rotation: DQuat::from_mat3(&axes).normalize(),
        }
    }
}

impl PrincipalFrame {
    /// The pose of the principal frame in the geometry's frame: maps
    /// principal-frame points to geometry points.
    pub fn pose(&self) -> Pose {
        Pose {
            position: self.com,
            rotation: self.rotation,
        }
    }

    /// The inertia tensor in the geometry's axes, `R diag(moments) R^T`
    /// (kg m^2).
    pub fn inertia_tensor(&self) -> DMat3 {
        let r = DMat3::from_quat(self.rotation);
        symmetrize(&(r * DMat3::from_diagonal(self.moments) * r.transpose()))
    }

    /// Properties in the principal frame: centre of mass at the origin and
    /// a diagonal inertia tensor.
    pub fn to_properties(&self) -> MassProperties {
        MassProperties {
            mass: self.mass,
            com: DVec3::ZERO,
            inertia: DMat3::from_diagonal(self.moments),
        }
    }
}

/// `mesh` re-expressed in the principal `frame`: every vertex `v` maps to
/// `R^T (v - com)`. The result has its centre of mass at the origin and a
/// diagonal inertia tensor (the body frame of the dynamics).
pub fn to_principal_frame(mesh: &TriMesh, frame: &PrincipalFrame) -> Result<TriMesh, MassError> {
    let inv = frame.rotation.inverse();
    mesh.map_vertices(|v| inv * (v - frame.com))
        .map_err(MassError::Mesh)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::max_abs_diff_mat;

    fn sample() -> MassProperties {
        // A rotated, shifted 1 x 2 x 3 box of 2 kg: half extents 0.5, 1, 1.5.
        let i = DMat3::from_diagonal(DVec3::new(
            2.0 / 12.0 * (4.0 + 9.0),
            2.0 / 12.0 * (1.0 + 9.0),
            2.0 / 12.0 * (1.0 + 4.0),
        ));
        MassProperties::new(2.0, DVec3::new(0.3, -0.2, 1.0), i)
            .unwrap()
            .rotated(DQuat::from_euler(glam::EulerRot::XYZ, 0.4, -0.9, 1.3))
    }

    #[test]
    fn parallel_axis_matches_point_sum() {
        // Oracle: a body of 8 point masses at cube corners; inertia about any
        // point is sum m (|r|^2 E - r r^T) computed directly.
        let pts: Vec<DVec3> = (0..8)
            .map(|i| {
                DVec3::new(
                    if i & 1 != 0 { 1.0 } else { -1.0 },
                    if i & 2 != 0 { 2.0 } else { -2.0 },
                    if i & 4 != 0 { 0.5 } else { -0.5 },
                ) + DVec3::new(3.0, -1.0, 2.0)
            })
            .collect();
        let m = 0.25;
        let direct = |p: DVec3| pts.iter().fold(DMat3::ZERO, |a, &x| a + point_inertia(m, x - p));
        let com = pts.iter().sum::<DVec3>() / 8.0;
        let props = MassProperties {
            mass: 8.0 * m,
            com,
            inertia: direct(com),
        };
        let q = DVec3::new(-1.0, 4.0, 0.5);
        assert!(max_abs_diff_mat(&props.inertia_about(q), &direct(q)) < 1e-12);
    }

    #[test]
    fn principal_reconstructs_tensor() {
        let p = sample();
        let f = p.principal();
        assert!(max_abs_diff_mat(&f.inertia_tensor(), &p.inertia) < 1e-13);
        assert!(f.moments.x <= f.moments.y && f.moments.y <= f.moments.z);
        // Moments are invariant: they equal the box's diagonal, sorted.
        let want = DVec3::new(2.0 / 12.0 * 5.0, 2.0 / 12.0 * 10.0, 2.0 / 12.0 * 13.0);
        assert!((f.moments - want).abs().max_element() < 1e-13);
    }

    #[test]
    fn rotation_then_inverse_is_identity() {
        let p = sample();
        let q = DQuat::from_euler(glam::EulerRot::ZYX, 0.7, 0.1, -2.0);
        let back = p.rotated(q).rotated(q.inverse());
        assert!(max_abs_diff_mat(&back.inertia, &p.inertia) < 1e-13);
        assert!((back.com - p.com).length() < 1e-14);
        // Trace (sum of moments) is rotation invariant.
        let tr = |m: &DMat3| m.x_axis.x + m.y_axis.y + m.z_axis.z;
        assert!((tr(&p.rotated(q).inertia) - tr(&p.inertia)).abs() < 1e-13);
    }

    #[test]
    fn validate_rejects_unphysical() {
        let mut p = sample();
        p.mass = -1.0;
        assert!(matches!(p.validate(), Err(MassError::Invalid { .. })));
        let bad = MassProperties::new(1.0, DVec3::ZERO, DMat3::from_diagonal(DVec3::new(1.0, 1.0, 3.0)));
        assert!(matches!(bad, Err(MassError::Invalid { .. })));
        let nan = MassProperties::new(1.0, DVec3::new(f64::NAN, 0.0, 0.0), DMat3::IDENTITY);
        assert!(matches!(nan, Err(MassError::Invalid { .. })));
        assert_eq!(MassProperties::combine(&[]), Err(MassError::EmptyComposite));
        assert!(matches!(
            MassProperties::combine(&[sample(), p]),
            Err(MassError::BadPart { index: 1, .. })
        ));
    }
}
