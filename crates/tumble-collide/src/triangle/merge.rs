//! Removal of duplicate contacts produced by triangle-pair contact generation.
//!
//! The thesis (5.4) notes that per-triangle-pair contacts repeat: a mesh vertex
//! shared by six triangles is reported six times against the same face, a
//! vertex above the shared edge of two faces twice, an edge shared by two
//! triangles twice. Two passes, both deterministic:
//! 1. identity: contacts that name the same mesh vertex (vertex/face, or the
//!    vertex side of a penetrating contact) or the same pair of mesh edges
//!    (edge/edge), found through the caller's per-triangle vertex index
//!    triples, are duplicates when their normals also agree;
//! 2. geometry: any two contacts whose points are within `point_tolerance`
//!    and whose normals agree are duplicates.
//!
//! Of each duplicate group the deepest contact (smallest `distance`) is kept:
//! contacts are visited deepest first (ties by original position) and a contact
//! is dropped when it duplicates one already kept. Survivors keep their
//! original relative order.

use crate::contact::{Contact, Feature, SubFeature};
use crate::math::DVec3;
// Fx hashing: the keys are small integers and vertex ids made here, never
// an attacker's, and SipHash was a tenth of a settled mesh pile's step.
use rustc_hash::FxHashMap as HashMap;

/// Tolerances for [`merge_contacts`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MergeParams {
    /// Points closer than this are the same contact (m). Default 1e-6 m; raise
    /// it to thin out contacts that are merely close (a coarser manifold).
    pub point_tolerance: f64,
    /// Normals within this angle agree (radians, in [0, pi]). Default 0.05 rad
    /// (about 3 degrees); contacts with the same feature but normals further
    /// apart (a vertex in a concave corner touching two faces) are both kept.
    pub normal_angle: f64,
}

impl Default for MergeParams {
    fn default() -> Self {
        MergeParams {
            point_tolerance: 1e-6,
            normal_angle: 0.05,
        }
    }
}

/// Invalid merge parameters.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum MergeError {
    /// `point_tolerance` negative or not finite.
    #[error("merge point_tolerance must be finite and >= 0 (m), got {0}")]
    PointTolerance(f64),
    /// `normal_angle` outside [0, pi] or NaN.
    #[error("merge normal_angle must be in [0, pi] (rad), got {0}")]
    NormalAngle(f64),
}

/// A feature named by mesh-global vertex ids (faces carry no identity here:
/// a vertex touching two coplanar faces is one contact).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
enum GlobalFeature {
    Vertex(u32),
    Edge(u32, u32),
}

/// Up to this many contacts, duplicates are found by scanning the kept
/// ones; beyond, among the contacts that have a possible twin at all, by
/// scanning or through maps (the same survivors every way).
const SCAN_UP_TO: usize = 48;

/// The global identities of a contact's two sides.
type FeatureKey = (Option<GlobalFeature>, Option<GlobalFeature>);

/// Global identity of one side of a contact, if the triangle is known.
fn global(f: Feature, tris: &[[u32; 3]]) -> Option<GlobalFeature> {
    let t = tris.get(f.index as usize)?;
    match f.sub {
        SubFeature::Vertex(k) => t.get(k as usize).map(|&v| GlobalFeature::Vertex(v)),
        SubFeature::Edge(k) if k < 3 => {
            let (u, v) = (t[k as usize], t[(k as usize + 1) % 3]);
            Some(GlobalFeature::Edge(u.min(v), u.max(v)))
        }
        _ => None,
    }
}

/// Removes duplicate contacts from `contacts` in place and returns how many
/// were removed.
///
/// `tris_a` / `tris_b` are the vertex index triples of the meshes of shape A
/// and B (`TriMesh::triangles()`), indexed by the triangle ids in the contacts'
/// features; pass `&[]` for a shape without mesh identity (then only the
/// geometric pass applies to it). Out-of-range ids are treated as unknown, not
/// as errors. Deterministic: the result depends only on the input order and
/// values.
pub fn merge_contacts(
    contacts: &mut Vec<Contact>,
    tris_a: &[[u32; 3]],
    tris_b: &[[u32; 3]],
    params: &MergeParams,
) -> Result<usize, MergeError> {
    let tol = params.point_tolerance;
    if !(tol >= 0.0 && tol.is_finite()) {
        return Err(MergeError::PointTolerance(tol));
    }
    let angle = params.normal_angle;
    if !(0.0..=std::f64::consts::PI).contains(&angle) {
        return Err(MergeError::NormalAngle(angle));
    }
    let n = contacts.len();
    let keys: Vec<FeatureKey> = contacts
        .iter()
        .map(|c| (global(c.feature_a, tris_a), global(c.feature_b, tris_b)))
        .collect();
    let rule = Rule {
        min_cos: angle.cos(),
        tol,
    };
    let keep = if n <= SCAN_UP_TO {
        survivors_by_scan(contacts, &keys, &rule)
    } else {
        survivors_of_twinned(contacts, &keys, &rule)
    };
    let mut idx = 0;
    contacts.retain(|_| {
        idx += 1;
        keep[idx - 1]
    });
    Ok(n - contacts.len())
}

/// When two contacts are duplicates: agreeing normals (cosine at least
/// `min_cos`), and the same named feature or points within `tol`.
struct Rule {
    min_cos: f64,
    tol: f64,
}

impl Rule {
    fn duplicates(&self, c: &Contact, d: &Contact, key_c: &FeatureKey, key_d: &FeatureKey) -> bool {
        // (Not `x >= min`: a NaN normal agrees, as it always has.)
        c.normal.dot(d.normal).partial_cmp(&self.min_cos) != Some(std::cmp::Ordering::Less)
            && ((key_c == key_d && named(key_c))
                || (c.point - d.point).length_squared() <= self.tol * self.tol)
    }
}

/// `true` when a key names a mesh feature on some side.
fn named(key: &FeatureKey) -> bool {
    key.0.is_some() || key.1.is_some()
}

/// Deepest first (ties by position): the order contacts are kept in.
fn deepest_first(contacts: &[Contact]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..contacts.len()).collect();
    order.sort_by(|&i, &j| {
        contacts[i]
            .distance
            .total_cmp(&contacts[j].distance)
            .then(i.cmp(&j))
    });
    order
}

/// Which contacts survive, each visited deepest first against every one
/// already kept (quadratic; fastest for the few contacts of most pairs).
fn survivors_by_scan(contacts: &[Contact], keys: &[FeatureKey], rule: &Rule) -> Vec<bool> {
    let mut kept: Vec<usize> = Vec::new();
    let mut keep = vec![false; contacts.len()];
    for i in deepest_first(contacts) {
        if !kept
            .iter()
            .any(|&k| rule.duplicates(&contacts[i], &contacts[k], &keys[i], &keys[k]))
        {
            kept.push(i);
            keep[i] = true;
        }
    }
    keep
}

/// [`survivors_by_scan`]'s survivors, found among the contacts that have
/// a possible twin: one with the same named feature, or a point within
/// the tolerance (normals aside). A contact with none is kept whatever
/// else is kept, and is nobody's duplicate, so the greedy pass over the
/// others alone, in the same order, drops what the whole pass would. Most
/// contacts of two meshes whose shared features are tested once have no
/// twin; finding the rest takes two sorts instead of 27 cell lookups per
/// contact.
fn survivors_of_twinned(contacts: &[Contact], keys: &[FeatureKey], rule: &Rule) -> Vec<bool> {
    let n = contacts.len();
    let mut twinned = vec![false; n];
    let mut mark_runs = |order: &[usize], same: &dyn Fn(usize, usize) -> bool| {
        for (w, &i) in order.iter().enumerate() {
            for &j in &order[w + 1..] {
                if !same(i, j) {
                    break;
                }
                twinned[i] = true;
                twinned[j] = true;
            }
        }
    };
    let mut by_name: Vec<usize> = (0..n).filter(|&i| named(&keys[i])).collect();
    by_name.sort_unstable_by_key(|&i| (keys[i], i));
    mark_runs(&by_name, &|i, j| keys[i] == keys[j]);
    // Points within `tol` are within `tol` in x: a run in x order holds
    // every pair, and the full distance picks them (a NaN point has none;
    // the run ends by the rule's own squared test, which `tol = 0` and
    // underflow keep exact). Many points sharing one x (a tessellated face
    // square to the x axis) would make the runs quadratic: past 32 checks
    // per contact, the maps take the whole set.
    let mut by_x: Vec<usize> = (0..n).collect();
    by_x.sort_unstable_by(|&i, &j| {
        contacts[i]
            .point
            .x
            .total_cmp(&contacts[j].point.x)
            .then(i.cmp(&j))
    });
    let tol2 = rule.tol * rule.tol;
    let mut checks = 0usize;
    for (w, &i) in by_x.iter().enumerate() {
        for &j in &by_x[w + 1..] {
            let dx = contacts[j].point.x - contacts[i].point.x;
            if dx.is_nan() || dx * dx > tol2 {
                break;
            }
            checks += 1;
            if checks > 32 * n {
                return survivors_by_lookup(contacts, keys, rule);
            }
            if (contacts[i].point - contacts[j].point).length_squared() <= tol2 {
                twinned[i] = true;
                twinned[j] = true;
            }
        }
    }
    let subset: Vec<usize> = (0..n).filter(|&i| twinned[i]).collect();
    let mut keep = vec![true; n];
    if subset.is_empty() {
        return keep;
    }
    let (some, some_keys): (Vec<Contact>, Vec<FeatureKey>) =
        subset.iter().map(|&i| (contacts[i], keys[i])).unzip();
    let kept = if subset.len() <= SCAN_UP_TO {
        survivors_by_scan(&some, &some_keys, rule)
    } else {
        survivors_by_lookup(&some, &some_keys, rule)
    };
    for (&i, k) in subset.iter().zip(kept) {
        keep[i] = k;
    }
    keep
}

/// [`survivors_by_scan`]'s survivors, found through maps: whether *some*
/// kept contact duplicates a new one is all that counts, so the kept ones
/// are looked up by named feature and in a grid of cells `tol` wide (two
/// points within `tol` lie in the same or neighbouring cells). Linear in
/// the contacts, not quadratic (a lumpy mesh lying on another made
/// thousands of contacts per pair). The maps are only looked up, never
/// iterated.
fn survivors_by_lookup(contacts: &[Contact], keys: &[FeatureKey], rule: &Rule) -> Vec<bool> {
    let cell = if rule.tol > 0.0 { rule.tol } else { 1e-9 };
    let cell_of = |p: DVec3| {
        [
            (p.x / cell).floor() as i64,
            (p.y / cell).floor() as i64,
            (p.z / cell).floor() as i64,
        ]
    };
    let mut by_feature: HashMap<FeatureKey, Vec<usize>> = HashMap::default();
    let mut by_cell: HashMap<[i64; 3], Vec<usize>> = HashMap::default();
    let mut keep = vec![false; contacts.len()];
    for i in deepest_first(contacts) {
        let dup = |k: &usize| rule.duplicates(&contacts[i], &contacts[*k], &keys[i], &keys[*k]);
        let home = cell_of(contacts[i].point);
        let duplicate = (named(&keys[i]) && by_feature.get(&keys[i]).is_some_and(|ks| ks.iter().any(dup)))
            || (-1..=1).any(|dx| {
                (-1..=1).any(|dy| {
                    (-1..=1).any(|dz| {
                        let near = [
                            home[0].wrapping_add(dx),
                            home[1].wrapping_add(dy),
                            home[2].wrapping_add(dz),
                        ];
                        by_cell.get(&near).is_some_and(|ks| ks.iter().any(dup))
                    })
                })
            });
        if !duplicate {
            keep[i] = true;
            if named(&keys[i]) {
                by_feature.entry(keys[i]).or_default().push(i);
            }
            by_cell.entry(home).or_default().push(i);
        }
    }
    keep
}

#[cfg(test)]
mod tests {
    use super::super::tri_contact::triangle_contacts;
    use super::*;
    use crate::contact::ContactKind;
    use crate::math::DVec3;
    use crate::mesh::{box_mesh, TriMesh};

    /// A 20 m x 20 m ground of two triangles in z = 0, normal +z, with its
    /// diagonal far from the cube placed below.
    #[test]
    fn looked_up_duplicates_are_the_scanned_ones() {
        // Random contacts crowded into a few clusters (points a fraction of
        // the tolerance apart, and some exactly on cell borders), a few
        // normals, a few shared features: the same survivors, in the same
        // order, as the quadratic scan.
        let mut rng = tumble_testkit::splitmix_f64(41);
        let tris: Vec<[u32; 3]> = (0..20).map(|t| [t, t + 1, t + 2]).collect();
        let params = MergeParams::default();
        let tol = params.point_tolerance;
        let (mut seen, mut removed, mut twinless) = (0, 0, 0);
        for round in 0..200 {
            // Every other round spreads its contacts over many clusters and
            // names mostly out of range (unknown), so that many have no twin.
            let (clusters, names) = if round % 2 == 0 {
                (4.0, 20.0)
            } else {
                (60.0, 400.0)
            };
            let mut contacts = Vec::new();
            for _ in 0..(5 + round % 60) {
                let cluster = (rng() * clusters).floor();
                let jitter = if rng() < 0.3 {
                    0.0
                } else {
                    (rng() - 0.5) * 3.0 * tol
                };
                let point = DVec3::new(
                    cluster * 7.0 * tol + jitter,
                    2.0 * tol * (rng() * 3.0).floor(),
                    -tol,
                );
                let normal =
                    [DVec3::Z, DVec3::new(0.0, 0.04, 1.0).normalize(), DVec3::X][(rng() * 3.0) as usize];
                let sub = |x: f64| match (x * 3.0) as u8 {
                    0 => SubFeature::Vertex((x * 7.0) as u8 % 3),
                    1 => SubFeature::Edge((x * 11.0) as u8 % 3),
                    _ => SubFeature::Face,
                };
                contacts.push(Contact {
                    point,
                    normal,
                    distance: (rng() * 4.0).floor() * 1e-4,
                    kind: ContactKind::VertexFace,
                    feature_a: Feature {
                        index: (rng() * names) as u32,
                        sub: sub(rng()),
                    },
                    feature_b: Feature {
                        index: (rng() * names) as u32,
                        sub: sub(rng()),
                    },
                });
            }
            let keys: Vec<FeatureKey> = contacts
                .iter()
                .map(|c| (global(c.feature_a, &tris), global(c.feature_b, &tris)))
                .collect();
            let rule = Rule {
                min_cos: params.normal_angle.cos(),
                tol,
            };
            let want = survivors_by_scan(&contacts, &keys, &rule);
            assert_eq!(
                survivors_by_lookup(&contacts, &keys, &rule),
                want,
                "round {round}"
            );
            assert_eq!(
                survivors_of_twinned(&contacts, &keys, &rule),
                want,
                "round {round}, twinned only"
            );
            twinless += (0..contacts.len())
                .filter(|&i| {
                    !(0..contacts.len()).any(|j| {
                        j != i
                            && ((keys[i] == keys[j] && named(&keys[i]))
                                || (contacts[i].point - contacts[j].point).length() <= tol)
                    })
                })
                .count();
            removed += want.iter().filter(|&&k| !k).count();
            seen += contacts.len();
        }
        // A grid of points in one plane square to x (a tessellated face),
        // with a few pairs of twins: the x runs would be quadratic and the
        // maps take over, with the same survivors.
        let mut grid: Vec<Contact> = (0..400)
            .map(|k| Contact {
                point: DVec3::new(0.25, (k % 20) as f64 * 0.01, (k / 20) as f64 * 0.01),
                normal: DVec3::X,
                distance: (k % 7) as f64 * 1e-4,
                kind: ContactKind::VertexFace,
                feature_a: Feature::face(1000),
                feature_b: Feature::face(1000),
            })
            .collect();
        for k in 0..10 {
            let twin = Contact {
                point: grid[k * 37].point + DVec3::new(0.0, 0.3 * tol, 0.0),
                ..grid[k * 37]
            };
            grid.push(twin);
        }
        let keys = vec![(None, None); grid.len()];
        let rule = Rule {
            min_cos: params.normal_angle.cos(),
            tol,
        };
        let want = survivors_by_scan(&grid, &keys, &rule);
        assert_eq!(want.iter().filter(|&&k| !k).count(), 10);
        assert_eq!(survivors_of_twinned(&grid, &keys, &rule), want);
        // The rounds do merge, and keep: both outcomes are exercised, and
        // many contacts have no twin at all.
        assert!(
            removed > seen / 8 && removed < seen * 3 / 4 && twinless > seen / 8,
            "{removed} of {seen} merged, {twinless} without a twin"
        );
    }

    fn ground() -> TriMesh {
        let v = vec![
            DVec3::new(-10.0, -10.0, 0.0),
            DVec3::new(10.0, -10.0, 0.0),
            DVec3::new(10.0, 10.0, 0.0),
            DVec3::new(-10.0, 10.0, 0.0),
        ];
        TriMesh::new(v, vec![[0, 1, 2], [0, 2, 3]]).unwrap()
    }

    /// All triangle-pair contacts of a unit cube at height `gap` above the ground.
    fn cube_on_ground(gap: f64, margin: f64) -> (TriMesh, TriMesh, Vec<Contact>) {
        let centre = DVec3::new(3.0, -3.0, 0.5 + gap);
        let cube = box_mesh(DVec3::splat(0.5))
            .unwrap()
            .map_vertices(|p| p + centre)
            .unwrap();
        let g = ground();
        let mut out = Vec::new();
        for ta in 0..cube.triangles().len() {
            for tb in 0..g.triangles().len() {
                let (a, b) = (cube.triangle(ta), g.triangle(tb));
                triangle_contacts(&a, ta as u32, &b, tb as u32, margin, &mut out).unwrap();
            }
        }
        (cube, g, out)
    }

    fn assert_four_corners(contacts: &[Contact], gap: f64) {
        assert_eq!(contacts.len(), 4, "{contacts:?}");
        let mut corners: Vec<(i64, i64)> = contacts
            .iter()
            .map(|c| {
                assert!((c.normal - DVec3::Z).length() < 1e-12);
                assert!((c.distance - gap).abs() < 1e-12);
                assert!((c.point.z - gap / 2.0).abs() < 1e-12);
                ((c.point.x * 2.0).round() as i64, (c.point.y * 2.0).round() as i64)
            })
            .collect();
        corners.sort();
        assert_eq!(corners, vec![(5, -7), (5, -5), (7, -7), (7, -5)]);
    }

    #[test]
    fn cube_resting_on_a_plane_mesh_merges_to_its_four_corners() {
        let gap = 1e-3;
        let (cube, g, mut c) = cube_on_ground(gap, 0.01);
        // Each bottom corner is in 4 to 6 cube triangles: many duplicates.
        assert!(c.len() >= 16, "{}", c.len());
        assert!(c.iter().all(|x| x.kind == ContactKind::VertexFace));
        let removed =
            merge_contacts(&mut c, cube.triangles(), g.triangles(), &MergeParams::default()).unwrap();
        assert!(removed >= 12);
        assert_four_corners(&c, gap);
    }

    #[test]
    fn cube_touching_a_plane_mesh_merges_to_its_four_corners() {
        // Exactly touching: every pair that meets is an intersecting pair.
        let (cube, g, mut c) = cube_on_ground(0.0, 0.01);
        assert!(c.iter().all(|x| x.kind == ContactKind::Penetrating));
        merge_contacts(&mut c, cube.triangles(), g.triangles(), &MergeParams::default()).unwrap();
        assert_four_corners(&c, 0.0);
    }

    #[test]
    fn geometric_merge_works_without_mesh_identity() {
        let gap = 1e-3;
        let (_, _, mut c) = cube_on_ground(gap, 0.01);
        merge_contacts(&mut c, &[], &[], &MergeParams::default()).unwrap();
        assert_four_corners(&c, gap);
    }

    fn contact(point: DVec3, normal: DVec3, distance: f64, fa: Feature) -> Contact {
        Contact {
            point,
            normal,
            distance,
            kind: ContactKind::VertexFace,
            feature_a: fa,
            feature_b: Feature::face(0),
        }
    }

    #[test]
    fn deepest_of_a_group_is_kept_and_distinct_normals_survive() {
        let tris = [[0, 1, 2], [2, 1, 3]];
        // Vertex 2 is corner 2 of triangle 0 and corner 0 of triangle 1.
        let mut c = vec![
            contact(DVec3::ZERO, DVec3::Z, 0.02, Feature::vertex(0, 2)),
            contact(DVec3::new(0.0, 0.0, 0.001), DVec3::Z, 0.01, Feature::vertex(1, 0)),
            // Same vertex against a perpendicular face: kept.
            contact(DVec3::ZERO, DVec3::X, 0.03, Feature::vertex(1, 0)),
            // Another vertex: kept.
            contact(DVec3::ONE, DVec3::Z, 0.05, Feature::vertex(1, 2)),
        ];
        let removed = merge_contacts(&mut c, &tris, &[], &MergeParams::default()).unwrap();
        assert_eq!(removed, 1);
        assert_eq!(c.len(), 3);
        // Survivors in original order; of the duplicate pair the deeper one.
        assert_eq!(c[0].distance, 0.01);
        assert_eq!(c[1].normal, DVec3::X);
        assert_eq!(c[2].point, DVec3::ONE);
    }

    /// All contacts between two small meshes given as (vertices, triangles).
    fn mesh_contacts(
        va: &[DVec3],
        ta: &[[u32; 3]],
        vb: &[DVec3],
        tb: &[[u32; 3]],
        margin: f64,
    ) -> Vec<Contact> {
        let tri = |v: &[DVec3], t: [u32; 3]| t.map(|k| v[k as usize]);
        let mut out = Vec::new();
        for (i, &x) in ta.iter().enumerate() {
            for (j, &y) in tb.iter().enumerate() {
                triangle_contacts(&tri(va, x), i as u32, &tri(vb, y), j as u32, margin, &mut out).unwrap();
            }
        }
        out
    }

    #[test]
    fn vertex_above_a_shared_edge_is_reported_twice_and_merged_once() {
        // B: a square of two faces sharing the diagonal from (0,0) to (2,2).
        let vb = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(2.0, 2.0, 0.0),
            DVec3::new(0.0, 2.0, 0.0),
        ];
        let tb = [[0, 1, 2], [0, 2, 3]];
        // A: one triangle with a corner hovering exactly above the diagonal.
        let va = [
            DVec3::new(1.0, 1.0, 0.01),
            DVec3::new(1.5, 1.0, 1.0),
            DVec3::new(1.0, 1.5, 1.0),
        ];
        let ta = [[0, 1, 2]];
        let mut c = mesh_contacts(&va, &ta, &vb, &tb, 0.05);
        assert_eq!(c.len(), 2, "{c:?}");
        assert!(c.iter().all(|x| x.kind == ContactKind::VertexFace));
        merge_contacts(&mut c, &ta, &tb, &MergeParams::default()).unwrap();
        assert_eq!(c.len(), 1);
        assert!((c[0].distance - 0.01).abs() < 1e-15);
    }

    // Crossed wedges, as in tri_contact.rs's edge/edge test but doubled so
    // that each ridge is shared by two triangles: spelled out, since the
    // duplicated edge is what this test is about.
    #[test]
    fn edge_shared_by_two_triangles_on_each_side_is_merged_once() {
        let h = 0.1;
        // A: a downward wedge whose ridge runs along x at height h.
        let va = [
            DVec3::new(-1.0, 0.0, h),
            DVec3::new(1.0, 0.0, h),
            DVec3::new(0.0, 1.0, h + 1.0),
            DVec3::new(0.0, -1.0, h + 1.0),
        ];
        let ta = [[0, 1, 2], [1, 0, 3]];
        // B: an upward wedge whose ridge runs along y at height 0.
        let vb = [
            DVec3::new(0.0, -1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(-1.0, 0.0, -1.0),
            DVec3::new(1.0, 0.0, -1.0),
        ];
        let tb = [[0, 1, 2], [1, 0, 3]];
        let mut c = mesh_contacts(&va, &ta, &vb, &tb, 0.5);
        let ridge = |x: &Contact| {
            x.kind == ContactKind::EdgeEdge && x.point.distance(DVec3::new(0.0, 0.0, h / 2.0)) < 1e-12
        };
        assert_eq!(c.iter().filter(|x| ridge(x)).count(), 4, "{c:?}");
        // Geometric tolerance zero: only the edge identity can merge them.
        let params = MergeParams {
            point_tolerance: 0.0,
            ..MergeParams::default()
        };
        merge_contacts(&mut c, &ta, &tb, &params).unwrap();
        assert_eq!(c.iter().filter(|x| ridge(x)).count(), 1, "{c:?}");
        let r = c.iter().find(|x| ridge(x)).unwrap();
        assert!((r.normal - DVec3::Z).length() < 1e-15 && (r.distance - h).abs() < 1e-15);
    }

    #[test]
    fn bad_parameters_are_errors_and_unknown_ids_are_not() {
        let mut c = vec![contact(DVec3::ZERO, DVec3::Z, 0.0, Feature::vertex(99, 2))];
        let bad = MergeParams {
            point_tolerance: -1.0,
            ..MergeParams::default()
        };
        assert_eq!(
            merge_contacts(&mut c, &[], &[], &bad),
            Err(MergeError::PointTolerance(-1.0))
        );
        let bad = MergeParams {
            normal_angle: f64::NAN,
            ..MergeParams::default()
        };
        assert!(matches!(
            merge_contacts(&mut c, &[], &[], &bad),
            Err(MergeError::NormalAngle(_))
        ));
        assert_eq!(
            merge_contacts(&mut c, &[[0, 1, 2]], &[], &MergeParams::default()),
            Ok(0)
        );
    }
}
