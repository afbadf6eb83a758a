//! The tori query scene of `shared/scenes.md` in parry3d (f32), from its one
//! definition in `tumble::scenes` (`tori_torus`, `tori_pose`): shared by the
//! `peer-parry` binary and the criterion bench `tori_vs_parry`.

use parry3d::math::{Pose, Rot3, Vector};
use parry3d::shape::TriMesh;

/// The tori's torus (`tumble::scenes::tori_torus`, 5,000 triangles) as a parry `TriMesh`.
pub fn torus() -> Result<TriMesh, String> {
    let mesh = tumble::scenes::tori_torus().map_err(|e| format!("tori torus: {e}"))?;
    let v: Vec<Vector> = mesh
        .vertices()
        .iter()
        .map(|p| Vector::new(p.x as f32, p.y as f32, p.z as f32))
        .collect();
    TriMesh::new(v, mesh.triangles().to_vec()).map_err(|e| format!("torus mesh rejected by parry: {e:?}"))
}

/// A tumble pose as parry's (f32).
pub fn pose(p: &tumble::collide::Pose) -> Pose {
    let (t, q) = (p.position, p.rotation);
    Pose::from_parts(
        Vector::new(t.x as f32, t.y as f32, t.z as f32),
        Rot3::from_xyzw(q.x as f32, q.y as f32, q.z as f32, q.w as f32),
    )
}

/// Pose of torus B at tori pose `k` (0..200) in parry: `tumble::scenes::tori_pose`.
pub fn tori_pose(k: usize) -> Pose {
    pose(&tumble::scenes::tori_pose(k))
}
