//! From one collider pair's narrow-phase contacts to the solver's patches:
//! the contacts are grouped by normal (a box on the ground is one patch; a
//! mesh pair touching in two places gives two), a patch of more than
//! `PATCH_MAX_POINTS` is reduced to that many (`tumble_collide::narrow::
//! reduce_patch`: the deepest point and the ones that span the patch; two
//! lumpy meshes can touch at thousands of points), each point inherits its
//! normal impulse from the previous step by features (`manifold::lookup`)
//! and each patch its friction by normal (`manifold::lookup_patch`), and
//! with it, for a pair with a triangle mesh, the anchor where it stuck
//! (docs/pipeline.md, "Anchors").

use super::handles::BodyId;
use super::manifold::{self, CachedContact, CachedPatch, PairKey, PATCH_COS};
use crate::solver::contact_solver::PointConstraint;
use tumble_collide::contact::SubFeature;
use tumble_collide::narrow::{reduce_patch, PATCH_MAX_POINTS};
use tumble_collide::shape::MeshShape;
use tumble_collide::{Contact, DMat3, DVec3, Pose};

/// A contact point on its way to the solver, with what is needed to report
/// and cache it (its bodies and collider pair are its patch's).
pub(crate) struct PreparedPoint {
    pub contact: Contact,
    /// The contact point in A's body frame at the step start (m).
    pub local_a: DVec3,
    /// Lever arms from A's and B's centres of mass to the point (m).
    pub r_a: DVec3,
    pub r_b: DVec3,
    /// The row's separation (the contact's distance less the pair's skin, m).
    pub separation: f64,
    /// The normal impulse remembered from the last step (N s).
    pub normal_impulse: f64,
}

impl PreparedPoint {
    /// The point's solver record, laid out in `dst`
    /// (`PointConstraint::renew`: its row is left to the prepare).
    pub fn renew_constraint(&self, dst: &mut PointConstraint) {
        dst.renew(
            self.contact.normal,
            self.r_a,
            self.r_b,
            self.separation,
            self.normal_impulse,
            0.5 * self.contact.distance,
        );
    }
}

/// A contact patch on its way to the solver: a run of prepared points.
pub(crate) struct PreparedPatch {
    pub ids: (BodyId, BodyId),
    pub key: PairKey,
    /// The run of the step's points that holds the patch's
    /// ([`ContactPoints`]), and where in it they are.
    pub run: u32,
    pub first: u32,
    pub count: u32,
    /// Unit patch normal (mean of the points' normals), B to A.
    pub normal: DVec3,
    pub friction: f64,
    pub restitution: f64,
    /// Radii of the round surfaces of A and B (`Shape::rolling_radius`).
    pub rolling: [f64; 2],
    /// Warm-start friction: tangential (world vector, N s) and twist (N m s).
    pub warm_tangent: DVec3,
    pub warm_twist: f64,
    /// The patch's [`PatchExtras`] in the step's list of them, or
    /// [`NO_EXTRAS`].
    pub extras: u32,
    /// Whether the patch may hold an anchor (`PairInfo::anchors`, not round).
    pub holds: bool,
}

/// What only some patches carry, kept beside the patches (a patch record
/// is copied by the narrow phase's join, the solver's layout and the
/// write-back, and these would be two thirds of its bytes): patches of a
/// pair with a triangle mesh that stuck in the last step, and round bodies
/// on a smooth mesh.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PatchExtras {
    /// How the patch turns under a round body on a smooth mesh
    /// (`ManifoldConstraint::curvature`; zero otherwise).
    pub curvature: DMat3,
    /// The patch's anchor from the last step, if it stuck and has not
    /// drifted beyond [`ANCHOR_REACH`].
    pub anchor: Option<PatchAnchor>,
}

/// [`PreparedPatch::extras`] of a patch without [`PatchExtras`].
pub(crate) const NO_EXTRAS: u32 = u32::MAX;

/// A sticking patch's anchor at the step start.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PatchAnchor {
    /// `CachedPatch::anchor`: A's and B's points from their centres of mass,
    /// in their body axes (m).
    pub local: [DVec3; 2],
    /// Their lever arms from A's and B's centres of mass (world, m).
    pub r: [DVec3; 2],
    /// A's point less B's (world, m): how far the patch has crept.
    pub offset: DVec3,
}

/// The step's contact points, in runs: one per chunk of candidate pairs
/// that the narrow stage ran, in pair order. A patch's points are a slice
/// of one run ([`ContactPoints::of`]).
///
/// Why not one list: the chunks' points, joined into one, were copied once
/// more than they are read, about 180 bytes a point (the large pyramid's
/// 40,000 points and their patches took 0.74 ms of its step's join on two
/// threads, `profile_stages large_pyramid 60 2`).
#[derive(Default)]
pub(crate) struct ContactPoints {
    runs: Vec<Vec<PreparedPoint>>,
}

impl ContactPoints {
    /// The points held in `runs`, run `r` that of patches with `run == r`.
    pub fn from_runs(runs: Vec<Vec<PreparedPoint>>) -> ContactPoints {
        ContactPoints { runs }
    }

    /// The points of `patch`.
    pub fn of(&self, patch: &PreparedPatch) -> &[PreparedPoint] {
        &self.runs[patch.run as usize][patch.range()]
    }

    /// Points in all runs.
    pub fn len(&self) -> usize {
        self.runs.iter().map(Vec::len).sum()
    }

    /// Empties every run, keeping its buffer.
    pub fn clear(&mut self) {
        self.runs.iter_mut().for_each(Vec::clear);
    }

    /// The runs (emptied, their buffers kept), for the next step's chunks.
    pub fn take_runs(&mut self) -> Vec<Vec<PreparedPoint>> {
        self.clear();
        std::mem::take(&mut self.runs)
    }
}

impl PreparedPatch {
    /// The patch's points in its run of the step's points.
    pub fn range(&self) -> std::ops::Range<usize> {
        self.first as usize..(self.first + self.count) as usize
    }

    /// The patch's extras in the step's list of them (`extras`), if it has any.
    pub fn extras<'a>(&self, extras: &'a [PatchExtras]) -> Option<&'a PatchExtras> {
        (self.extras != NO_EXTRAS).then(|| &extras[self.extras as usize])
    }

    /// The patch's anchor from the last step (see [`PatchExtras::anchor`]).
    pub fn anchor<'a>(&self, extras: &'a [PatchExtras]) -> Option<&'a PatchAnchor> {
        self.extras(extras).and_then(|x| x.anchor.as_ref())
    }
}

/// Where [`add_pair`] appends: the points, the patches (runs of them) and
/// the patches' extras.
pub(crate) struct PatchSink<'a> {
    pub points: &'a mut Vec<PreparedPoint>,
    pub patches: &'a mut Vec<PreparedPatch>,
    pub extras: &'a mut Vec<PatchExtras>,
}

/// The per-pair inputs of [`add_pair`].
pub(crate) struct PairInfo<'a> {
    pub ids: (BodyId, BodyId),
    pub key: PairKey,
    /// Poses of the bodies' centres of mass at the step start.
    pub pose_a: &'a Pose,
    pub pose_b: &'a Pose,
    pub friction: f64,
    pub restitution: f64,
    /// Subtracted from every contact distance (m): the gap the solver keeps.
    pub skin: f64,
    /// Radii of the round surfaces of A's and B's colliders
    /// (`Shape::rolling_radius`, 0 when not round).
    pub rolling: [f64; 2],
    /// Whether the pair's sticking patches hold anchors
    /// (`CachedPatch::anchor`): pairs with a triangle mesh (a resting pile
    /// of concave bodies crept without anchors); a flat patch (a box's
    /// face, block-solved, its points sharing one normal) held still where
    /// measured (five slabs stacked on a slope of 0.4 rad did not move by
    /// a tenth of a micron from 8 s to 10 s), and anchors on the box stacks of the 20-layer
    /// pyramid let its wall sway further out of its plane (top box 17 mm
    /// away after 10 s instead of 3.7).
    pub anchors: bool,
    /// A round collider against a mesh with a smooth surface: the mesh,
    /// its world pose, and whether it is A.
    pub smooth: Option<(&'a MeshShape, Pose, bool)>,
    /// Linear and angular velocity of A and of B at the step start (m/s, rad/s).
    pub velocity_a: (DVec3, DVec3),
    pub velocity_b: (DVec3, DVec3),
    /// The step (s): how far ahead a patch looks when it chooses its points.
    pub dt: f64,
}

impl PairInfo<'_> {
    /// `ManifoldConstraint::curvature` for a patch whose first contact is
    /// `c`: the smooth mesh's path curvature at the round side's centre of
    /// curvature (a radius beyond its surface point along the normal), in
    /// the world; zero for other pairs and for contacts at a crease.
    fn curvature(&self, c: &Contact) -> DMat3 {
        match &self.smooth {
            Some(smooth) => smooth_curvature(smooth, self.rolling, c),
            None => DMat3::ZERO,
        }
    }

    /// The gap of contact `c` at the end of the step if the bodies kept
    /// their velocities (m): its distance plus the normal relative velocity
    /// at its point times the step.
    fn gap_at_step_end(&self, c: &Contact) -> f64 {
        let at = |(v, w): (DVec3, DVec3), pose: &Pose| v + w.cross(c.point - pose.position);
        let closing = (at(self.velocity_a, self.pose_a) - at(self.velocity_b, self.pose_b)).dot(c.normal);
        c.distance + closing * self.dt
    }
}

/// Scratch of [`add_pair`], reused across pairs.
#[derive(Default)]
pub(crate) struct PatchScratch {
    seeds: Vec<DVec3>,
    patch_of: Vec<usize>,
    /// The contacts of the patch being prepared, and the ones it keeps.
    members: Vec<usize>,
    kept: Vec<usize>,
    /// Where the last search of the point cache ended (see `manifold::points_of`).
    point_cursor: usize,
    /// The same for the narrow phase's re-evaluation of kept points.
    pub feature_cursor: usize,
    /// Where the last search of the patch cache ended.
    patch_cursor: usize,
}

/// [`PairInfo::curvature`] of a pair with a smooth mesh (`smooth`: the
/// mesh, its collider's pose, whether it is body A's), the round side's
/// radius in `rolling`.
///
/// Not inlined, on purpose: inlined, the compiler began the pose's
/// arithmetic before it had looked whether the pair has a smooth mesh at
/// all, on the bytes of an empty `Option` (pointers, read as f64, are
/// subnormal), and every subnormal operand costs a microcode assist of
/// some 150 cycles on Intel cores: every box pair of the pyramid paid
/// them at every step (a trap on subnormal operands stopped there).
#[inline(never)]
fn smooth_curvature(
    &(mesh, pose, mesh_is_a): &(&MeshShape, Pose, bool),
    rolling: [f64; 2],
    c: &Contact,
) -> DMat3 {
    let (feature, radius, away) = if mesh_is_a {
        (c.feature_a, rolling[1], -c.normal)
    } else {
        (c.feature_b, rolling[0], c.normal)
    };
    let surface = mesh.smooth_surface();
    if feature.sub != SubFeature::Face || surface.is_none() {
        return DMat3::ZERO;
    }
    let centre = c.point + away * (radius + 0.5 * c.distance);
    let local = pose.inverse_transform_point(centre);
    surface
        .and_then(|s| s.path_curvature(mesh.mesh(), feature.index, local))
        .map_or(DMat3::ZERO, |k| {
            let turn = DMat3::from_quat(pose.rotation);
            turn * k * turn.transpose()
        })
}

/// Appends the points and patches of one collider pair's `contacts`; points
/// of a patch are contiguous. Returns how many points were warm started.
pub(crate) fn add_pair(
    contacts: &[Contact],
    pair: &PairInfo,
    point_cache: &[CachedContact],
    patch_cache: &[CachedPatch],
    scratch: &mut PatchScratch,
    out: PatchSink,
) -> usize {
    let PatchSink {
        points,
        patches,
        extras,
    } = out;
    if contacts.is_empty() {
        return 0;
    }
    // Greedy grouping in narrow-phase order (deterministic): a contact joins
    // the first patch whose seed normal is within PATCH_COS of its own.
    scratch.seeds.clear();
    scratch.patch_of.clear();
    for c in contacts {
        let found = scratch.seeds.iter().position(|s| s.dot(c.normal) >= PATCH_COS);
        let patch = found.unwrap_or_else(|| {
            scratch.seeds.push(c.normal);
            scratch.seeds.len() - 1
        });
        scratch.patch_of.push(patch);
    }
    let mut warm = 0;
    let cached = manifold::points_of(point_cache, pair.key, &mut scratch.point_cursor);
    let to_a = pair.pose_a.rotation.inverse();
    for (patch, &seed) in scratch.seeds.iter().enumerate() {
        let first = points.len() as u32;
        let mut sum = DVec3::ZERO;
        scratch.members.clear();
        scratch
            .members
            .extend((0..contacts.len()).filter(|&i| scratch.patch_of[i] == patch));
        if scratch.members.len() > PATCH_MAX_POINTS {
            let members = &scratch.members;
            reduce_patch(
                members.len(),
                seed,
                PATCH_MAX_POINTS,
                |k| {
                    let c = &contacts[members[k]];
                    (c.point, pair.gap_at_step_end(c))
                },
                |k| {
                    let c = &contacts[members[k]];
                    manifold::was_kept(
                        cached,
                        c.feature_a,
                        c.feature_b,
                        to_a * (c.point - pair.pose_a.position),
                    )
                },
                &mut scratch.kept,
            );
            for k in 0..scratch.kept.len() {
                scratch.kept[k] = scratch.members[scratch.kept[k]];
            }
            std::mem::swap(&mut scratch.members, &mut scratch.kept);
        }
        for c in scratch.members.iter().map(|&i| &contacts[i]) {
            let r_a = c.point - pair.pose_a.position;
            let r_b = c.point - pair.pose_b.position;
            let local_a = to_a * r_a;
            let normal_impulse = match manifold::lookup(cached, c.feature_a, c.feature_b, local_a) {
                Some(old) => {
                    warm += 1;
                    old.normal_impulse
                }
                None => 0.0,
            };
            sum += c.normal;
            points.push(PreparedPoint {
                contact: *c,
                local_a,
                r_a,
                r_b,
                separation: c.distance - pair.skin,
                normal_impulse,
            });
        }
        let normal = sum.try_normalize().unwrap_or(seed);
        let curvature = pair.curvature(&contacts[scratch.members[0]]);
        let cached_patch = manifold::lookup_patch(patch_cache, pair.key, normal, &mut scratch.patch_cursor);
        let (warm_tangent, warm_twist) =
            cached_patch.map_or((DVec3::ZERO, 0.0), |p| (p.tangent_impulse, p.twist_impulse));
        let holds = pair.anchors && pair.rolling == [0.0; 2] && curvature == DMat3::ZERO;
        let anchor = cached_patch
            .and_then(|p| p.anchor)
            .filter(|_| holds)
            .and_then(|local| {
                let r = [pair.pose_a.rotation * local[0], pair.pose_b.rotation * local[1]];
                let offset = (pair.pose_a.position + r[0]) - (pair.pose_b.position + r[1]);
                let across = offset - normal * normal.dot(offset);
                (across.length() <= ANCHOR_REACH).then_some(PatchAnchor { local, r, offset })
            });
        let extras_at = if curvature != DMat3::ZERO || anchor.is_some() {
            extras.push(PatchExtras { curvature, anchor });
            extras.len() as u32 - 1
        } else {
            NO_EXTRAS
        };
        patches.push(PreparedPatch {
            ids: pair.ids,
            key: pair.key,
            // The sink's run (set when the narrow stage's chunks are joined).
            run: 0,
            first,
            count: points.len() as u32 - first,
            normal,
            friction: pair.friction,
            restitution: pair.restitution,
            rolling: pair.rolling,
            warm_tangent,
            warm_twist,
            extras: extras_at,
            holds,
        });
    }
    warm
}

/// Farthest a patch's anchor points may have drifted apart across its normal
/// for the patch to hold them (m); farther, it slid, and starts again.
pub(crate) const ANCHOR_REACH: f64 = 5e-4;
