//! The tori query scene of shared/scenes.md ("tori"): the thesis' two tori
//! (`torus_mesh(1, 0.3, 50, 50)`, 5,000 triangles each), A at the origin and
//! B at 200 poses along a path through A's hole. Defined once here for
//! `tumble bench --scene tori`, the Rust peers (`peer-parry`, the criterion
//! benchmark) and the tests; the ground truth is shared/data/tori_pairs.json.

use tumble_collide::mesh::{torus_mesh, GeneratorError, TriMesh};
use tumble_collide::{DQuat, DVec3, Pose};

/// Poses along the path.
pub const TORI_POSES: usize = 200;

/// The torus of both bodies: `torus_mesh(1, 0.3, 50, 50)`.
pub fn tori_torus() -> Result<TriMesh, GeneratorError> {
    torus_mesh(1.0, 0.3, 50, 50)
}

/// Pose of torus B at pose `k` (0..200): `Rz(0.1) * Rx(pi/2)` at
/// `(-3 + 6 k / 199, 0.05, 0.02)`; torus A stays at the identity.
pub fn tori_pose(k: usize) -> Pose {
    let q = DQuat::from_rotation_z(0.1) * DQuat::from_rotation_x(std::f64::consts::FRAC_PI_2);
    Pose {
        position: DVec3::new(-3.0 + 6.0 * k as f64 / 199.0, 0.05, 0.02),
        rotation: q,
    }
}

/// `count` pose indices spread evenly over 0..200,
/// `k = floor(i 199 / (count - 1) + 0.5)` (all of them for 200).
pub fn tori_pose_indices(count: usize) -> Vec<usize> {
    let count = count.clamp(1, TORI_POSES);
    if count == 1 {
        return vec![0];
    }
    let mut ks: Vec<usize> = (0..count)
        .map(|i| (i as f64 * 199.0 / (count - 1) as f64 + 0.5).floor() as usize)
        .collect();
    ks.dedup();
    ks
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_path_runs_from_minus_three_to_three_through_every_pose() {
        assert_eq!(tori_pose(0).position.x, -3.0);
        assert_eq!(tori_pose(199).position.x, 3.0);
        assert_eq!(tori_pose_indices(200), (0..200).collect::<Vec<_>>());
        assert_eq!(tori_pose_indices(3), vec![0, 100, 199]);
        assert_eq!(tori_pose_indices(5), vec![0, 50, 100, 149, 199]);
        // Ring axis of B: Rx(pi/2) maps z to -y, Rz(0.1) turns it.
        let axis = tori_pose(0).transform_vector(DVec3::Z);
        assert!((axis - DVec3::new(0.1f64.sin(), -(0.1f64.cos()), 0.0)).length() < 1e-12);
        assert_eq!(tori_pose_indices(1), vec![0]);
        assert_eq!(tori_torus().unwrap().triangles().len(), 5000);
    }
}
