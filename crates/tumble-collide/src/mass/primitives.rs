//! Closed-form mass properties of the standard solids (thesis 3.1; the
//! formulas are the classical ones, e.g. Goldstein, "Classical Mechanics",
//! and derivations are given where they are not textbook tables).
//!
//! Every frame matches the generator of the same solid in
//! [`crate::mesh`] exactly: centred on the bounding box, symmetry axis z.

use super::{MassError, MassProperties, MassSpec};
use crate::math::{DMat3, DVec3};
use std::f64::consts::PI;

// The test of `shape::check_positive` (shape/mod.rs) in `MassError`: mass
// properties come from bare dimensions, without building a shape first.
fn dim(shape: &'static str, name: &'static str, value: f64) -> Result<(), MassError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(MassError::BadDimension {
            shape,
            name,
            expected: "> 0",
            value,
        })
    }
}

/// Builds the result for a body of `volume` whose inertia per unit mass is
/// `diag(ixx, ixx, izz)` (or the given diagonal) and whose centre is at `z`.
fn finish(spec: MassSpec, volume: f64, per_kg: DVec3, com_z: f64) -> Result<MassProperties, MassError> {
    spec.validate()?;
    let mass = spec.mass_for(volume)?;
    let inertia = DMat3::from_diagonal(per_kg * mass);
    if !inertia.is_finite() || !com_z.is_finite() {
        return Err(MassError::NonFiniteResult { what: "inertia" });
    }
    Ok(MassProperties {
        mass,
        com: DVec3::new(0.0, 0.0, com_z),
        inertia,
    })
}

/// Solid box with `half_extents` (m), centred: `I_xx = m (b^2 + c^2) / 3`
/// for half extents (a, b, c).
pub fn solid_box(half_extents: DVec3, spec: MassSpec) -> Result<MassProperties, MassError> {
    dim("box", "half_extents.x", half_extents.x)?;
    dim("box", "half_extents.y", half_extents.y)?;
    dim("box", "half_extents.z", half_extents.z)?;
    let h2 = half_extents * half_extents;
    let volume = 8.0 * half_extents.x * half_extents.y * half_extents.z;
    let per_kg = DVec3::new(h2.y + h2.z, h2.x + h2.z, h2.x + h2.y) / 3.0;
    finish(spec, volume, per_kg, 0.0)
}

/// Solid sphere of `radius` (m), centred: `I = 2/5 m r^2`.
pub fn solid_sphere(radius: f64, spec: MassSpec) -> Result<MassProperties, MassError> {
    dim("sphere", "radius", radius)?;
    let volume = 4.0 / 3.0 * PI * radius.powi(3);
    finish(spec, volume, DVec3::splat(0.4 * radius * radius), 0.0)
}

/// Solid cylinder of `radius` from z = -half_height to +half_height (m):
/// `I_zz = m r^2 / 2`, `I_xx = m (r^2 / 4 + h^2 / 3)` with h the half height
/// (the usual `m (3 r^2 + L^2) / 12` with `L = 2 h`).
pub fn solid_cylinder(radius: f64, half_height: f64, spec: MassSpec) -> Result<MassProperties, MassError> {
    dim("cylinder", "radius", radius)?;
    dim("cylinder", "half_height", half_height)?;
    let (r2, h2) = (radius * radius, half_height * half_height);
    let volume = 2.0 * PI * r2 * half_height;
    finish(
        spec,
        volume,
        DVec3::new(r2 / 4.0 + h2 / 3.0, r2 / 4.0 + h2 / 3.0, r2 / 2.0),
        0.0,
    )
}

/// Capsule: a cylinder of `radius` and `half_height` (m, may be 0: a sphere)
/// capped by two hemispheres, centred.
///
/// Composed from a cylinder of mass `m_c` and two hemispheres of mass `m_h`
/// each. About its flat face a hemisphere has the sphere's `2/5 m_h r^2` about
/// every axis through the face centre (half of a sphere, by symmetry); its
/// centre of mass is `3r/8` above the face, so about its own centre
/// `I_xx = (2/5 - 9/64) m_h r^2 = 83/320 m_h r^2`, and it sits at
/// `d = h + 3r/8` from the capsule's centre (parallel axis).
pub fn solid_capsule(radius: f64, half_height: f64, spec: MassSpec) -> Result<MassProperties, MassError> {
    dim("capsule", "radius", radius)?;
    // Refuses exactly what `Capsule::new` (shape/capsule.rs) refuses, in this
    // module's error type; a zero half height (a sphere) is allowed by both.
    if !(half_height.is_finite() && half_height >= 0.0) {
        return Err(MassError::BadDimension {
            shape: "capsule",
            name: "half_height",
            expected: ">= 0",
            value: half_height,
        });
    }
    let (r, h) = (radius, half_height);
    let v_cyl = 2.0 * PI * r * r * h;
    let v_hemi = 2.0 / 3.0 * PI * r.powi(3);
    let volume = v_cyl + 2.0 * v_hemi;
    // Per unit total mass: the parts' mass fractions are their volume fractions.
    let (fc, fh) = (v_cyl / volume, v_hemi / volume);
    let d = h + 3.0 * r / 8.0;
    let ixx = fc * (r * r / 4.0 + h * h / 3.0) + 2.0 * fh * (83.0 / 320.0 * r * r + d * d);
    let izz = fc * r * r / 2.0 + 2.0 * fh * 0.4 * r * r;
    finish(spec, volume, DVec3::new(ixx, ixx, izz), 0.0)
}

/// Solid cone of base `radius` and `height` (m), base at z = -height/2, apex
/// at +height/2 (bounding-box centred, like `cone_mesh`). The centre of mass
/// is a quarter of the height above the base, z = -height/4.
///
/// About the centre of mass: `I_zz = 3/10 m r^2`,
/// `I_xx = m (3/20 r^2 + 3/80 H^2)` (the apex value `3/20 r^2 + 3/5 H^2`
/// minus `m (3H/4)^2`).
pub fn solid_cone(radius: f64, height: f64, spec: MassSpec) -> Result<MassProperties, MassError> {
    dim("cone", "radius", radius)?;
    dim("cone", "height", height)?;
    let (r2, hh) = (radius * radius, height * height);
    let volume = PI * r2 * height / 3.0;
    let ixx = 3.0 / 20.0 * r2 + 3.0 / 80.0 * hh;
    finish(spec, volume, DVec3::new(ixx, ixx, 0.3 * r2), -height / 4.0)
}

/// Solid torus about z with major radius `major` (R) and tube radius `minor`
/// (r < R), centred: `V = 2 pi^2 R r^2`, `I_zz = m (R^2 + 3/4 r^2)`,
/// `I_xx = m (R^2 / 2 + 5/8 r^2)`.
pub fn solid_torus(major: f64, minor: f64, spec: MassSpec) -> Result<MassProperties, MassError> {
    dim("torus", "major radius R", major)?;
    dim("torus", "minor radius r", minor)?;
    if minor >= major {
        return Err(MassError::Constraint {
            shape: "torus",
            message: format!("minor radius r = {minor} must be < major radius R = {major}"),
        });
    }
    let (rr, r2) = (major * major, minor * minor);
    let volume = 2.0 * PI * PI * major * r2;
    let ixx = rr / 2.0 + 5.0 / 8.0 * r2;
    finish(spec, volume, DVec3::new(ixx, ixx, rr + 0.75 * r2), 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::max_abs_diff_mat;

    #[test]
    fn capsule_with_zero_length_is_a_sphere() {
        let c = solid_capsule(0.7, 0.0, MassSpec::Density(3.0)).unwrap();
        let s = solid_sphere(0.7, MassSpec::Density(3.0)).unwrap();
        assert!((c.mass - s.mass).abs() < 1e-14 * s.mass);
        assert!(max_abs_diff_mat(&c.inertia, &s.inertia) < 1e-14 * s.inertia.x_axis.x);
    }

    /// Oracle independent of the closed forms: a solid of revolution about z
    /// sliced into annuli of outer radius `ro(z)` and inner radius `ri(z)`; an
    /// annulus of mass dm has `dI_zz = dm (ro^2 + ri^2) / 2` and
    /// `dI_xx = dm ((ro^2 + ri^2) / 4 + z^2)` about the origin. Composite
    /// Simpson rule over [z0, z1] at unit density.
    fn revolve_oracle(
        z0: f64,
        z1: f64,
        ro: impl Fn(f64) -> f64,
        ri: impl Fn(f64) -> f64,
    ) -> (f64, f64, f64, f64) {
        let n = 200_000;
        let h = (z1 - z0) / n as f64;
        let (mut m, mut mz, mut ixx, mut izz) = (0.0, 0.0, 0.0, 0.0);
        for k in 0..=n {
            let z = z0 + h * k as f64;
            let w = if k == 0 || k == n {
                1.0
            } else if k % 2 == 1 {
                4.0
            } else {
                2.0
            };
            let (o2, i2) = (ro(z).powi(2), ri(z).powi(2));
            let dm = PI * (o2 - i2) * w;
            m += dm;
            mz += dm * z;
            ixx += dm * ((o2 + i2) / 4.0 + z * z);
            izz += dm * (o2 + i2) / 2.0;
        }
        let s = h / 3.0;
        (m * s, mz * s, ixx * s, izz * s)
    }

    fn check_against_slices(p: &MassProperties, slices: (f64, f64, f64, f64), tol: f64) {
        let (m, mz, ixx0, izz) = slices;
        let zc = mz / m;
        assert!((p.mass - m).abs() < tol * m, "mass {} vs {m}", p.mass);
        assert!((p.com.z - zc).abs() < tol, "com {} vs {zc}", p.com.z);
        // Parallel axis back to the centre of mass.
        let ixx = ixx0 - m * zc * zc;
        assert!(
            (p.inertia.x_axis.x - ixx).abs() < tol * ixx,
            "ixx {} vs {ixx}",
            p.inertia.x_axis.x
        );
        assert!((p.inertia.y_axis.y - ixx).abs() < tol * ixx);
        assert!(
            (p.inertia.z_axis.z - izz).abs() < tol * izz,
            "izz {} vs {izz}",
            p.inertia.z_axis.z
        );
    }

    #[test]
    fn solids_of_revolution_match_slice_integration() {
        let d = MassSpec::Density(1.0);
        let zero = |_: f64| 0.0;
        let circ = |r: f64, c: f64| move |z: f64| (r * r - (z - c).powi(2)).max(0.0).sqrt();
        let tol = 1e-6;
        check_against_slices(
            &solid_sphere(0.8, d).unwrap(),
            revolve_oracle(-0.8, 0.8, circ(0.8, 0.0), zero),
            tol,
        );
        check_against_slices(
            &solid_cylinder(0.5, 1.2, d).unwrap(),
            revolve_oracle(-1.2, 1.2, |_| 0.5, zero),
            tol,
        );
        let (r, h) = (0.4, 0.9);
        let capsule = move |z: f64| {
            if z.abs() <= h {
                r
            } else {
                circ(r, h * z.signum())(z)
            }
        };
        check_against_slices(
            &solid_capsule(r, h, d).unwrap(),
            revolve_oracle(-h - r, h + r, capsule, zero),
            tol,
        );
        let (rb, hc) = (0.6, 1.5);
        let cone = move |z: f64| rb * (0.5 - z / hc);
        check_against_slices(
            &solid_cone(rb, hc, d).unwrap(),
            revolve_oracle(-hc / 2.0, hc / 2.0, cone, zero),
            tol,
        );
        let (big, small) = (1.0, 0.3);
        let half = move |z: f64| (small * small - z * z).max(0.0).sqrt();
        check_against_slices(
            &solid_torus(big, small, d).unwrap(),
            revolve_oracle(-small, small, move |z| big + half(z), move |z| big - half(z)),
            tol,
        );
    }

    #[test]
    fn hemisphere_about_face_is_sphere_value() {
        // Check the 83/320 constant: shifting back by 3r/8 recovers 2/5.
        let v: f64 = 83.0 / 320.0 + (3.0f64 / 8.0).powi(2);
        assert!((v - 0.4).abs() < 1e-16);
    }

    #[test]
    fn mass_spec_is_honoured() {
        let p = solid_torus(1.0, 0.25, MassSpec::Mass(4.0)).unwrap();
        assert_eq!(p.mass, 4.0);
        let q = solid_torus(1.0, 0.25, MassSpec::Density(2.0)).unwrap();
        assert!((q.mass - 2.0 * 2.0 * PI * PI * 0.0625).abs() < 1e-14);
    }

    #[test]
    fn bad_dimensions_are_rejected() {
        let d = MassSpec::Density(1.0);
        assert!(matches!(
            solid_sphere(f64::NAN, d),
            Err(MassError::BadDimension { .. })
        ));
        assert!(matches!(
            solid_box(DVec3::new(1.0, 0.0, 1.0), d),
            Err(MassError::BadDimension { .. })
        ));
        assert!(matches!(
            solid_cylinder(1.0, f64::INFINITY, d),
            Err(MassError::BadDimension { .. })
        ));
        assert!(matches!(
            solid_capsule(1.0, -0.1, d),
            Err(MassError::BadDimension { .. })
        ));
        assert!(matches!(
            solid_cone(-1.0, 1.0, d),
            Err(MassError::BadDimension { .. })
        ));
        assert!(matches!(
            solid_torus(1.0, 1.0, d),
            Err(MassError::Constraint { .. })
        ));
        assert!(matches!(
            solid_sphere(1.0, MassSpec::Mass(-2.0)),
            Err(MassError::BadSpec { .. })
        ));
    }
}
