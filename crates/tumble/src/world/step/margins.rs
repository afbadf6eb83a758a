//! Margins and motion bounds of the step: how far bodies can move within it
//! (swept boxes, pair margins, the neighbour-stop bound), which bodies are
//! active, and the runaway test of quarantine.

use crate::body::BodyKind;
use crate::world::handles::Arena;
use crate::world::{BodyEntry, Collider, MaterialDesc};
use tumble_collide::broad::Aabb;
use tumble_collide::{DVec3, Pose};

/// Fattened world AABB of a body: the union of its colliders' boxes, grown
/// by `fatten` (m) on every side.
pub(crate) fn body_aabb(e: &BodyEntry, fatten: f64) -> Aabb {
    let pose = e.body.pose();
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for c in &e.colliders {
        let b = c.shape.aabb(&pose.mul_pose(&c.local));
        lo = lo.min(b.min);
        hi = hi.max(b.max);
    }
    Aabb::new(lo - DVec3::splat(fatten), hi + DVec3::splat(fatten))
        .unwrap_or_else(|_| Aabb::new(DVec3::ZERO, DVec3::ZERO).expect("zero box is valid"))
}

/// Largest distance of a collider point from the centre of mass (m): bounds
/// how far rotation can move a surface point. Computed once when the body is
/// added (the colliders are fixed in the body frame).
pub(crate) fn bounding_radius(colliders: &[Collider]) -> f64 {
    colliders
        .iter()
        .map(|c| {
            let b = c.shape.aabb(&c.local);
            b.min.abs().max(b.max.abs()).length()
        })
        .filter(|r| r.is_finite())
        .fold(0.0, f64::max)
}

/// Smallest half extent of the body's colliders, each in its own frame
/// (m): how far the body's centre lies inside its surface at least, the
/// scale against which continuous collision calls a motion fast. Infinite
/// for a body of half-spaces only.
pub(crate) fn thickness(colliders: &[Collider]) -> f64 {
    colliders
        .iter()
        .map(|c| {
            let b = c.shape.aabb(&tumble_collide::Pose::IDENTITY);
            ((b.max - b.min) * 0.5).min_element()
        })
        .fold(f64::INFINITY, f64::min)
}

/// Radius of the body's core (m): the largest ball about the centre of mass
/// inside one of its colliders (for a closed mesh, the distance from the
/// centre to its triangles when the centre is inside). Continuous collision
/// keeps the core from crossing a surface where the body itself started in
/// contact. Zero when the centre is outside the material (a ring's centre,
/// in its hole) or on a surface.
pub(crate) fn core_radius(colliders: &[Collider]) -> f64 {
    use tumble_collide::query::{distance_primitive, DistanceOptions};
    use tumble_collide::shape::Polytope;
    use tumble_collide::{Shape, Sphere};
    let inside = |c: &Collider| -> f64 {
        // The centre of mass in the collider's frame.
        let p = c.local.inverse_transform_point(DVec3::ZERO);
        let depth = match &c.shape {
            Shape::Sphere(s) => s.radius() - p.length(),
            Shape::Capsule(s) => {
                let z = p.z.clamp(-s.half_height(), s.half_height());
                s.radius() - (p - DVec3::new(0.0, 0.0, z)).length()
            }
            Shape::Cuboid(s) => (s.half_extents() - p.abs()).min_element(),
            Shape::ConvexHull(h) => (0..h.face_count())
                .map(|f| h.face_offset(f) - h.face_normal(f).dot(p))
                .fold(f64::INFINITY, f64::min),
            Shape::Mesh(m) => {
                let Ok(point) = Sphere::new(1e-9) else { return 0.0 };
                distance_primitive(
                    &Shape::Sphere(point),
                    &tumble_collide::Pose::from_translation(p),
                    m,
                    &tumble_collide::Pose::IDENTITY,
                    &DistanceOptions::default(),
                )
                // Inside when the centre is behind the closest triangle's
                // face (a ring's centre, in its hole, is in front).
                .map_or(0.0, |d| {
                    let face = m.mesh().triangle_normal_scaled(d.tri_b as usize);
                    if (p - d.point_b).dot(face) < 0.0 {
                        d.distance
                    } else {
                        0.0
                    }
                })
            }
            _ => 0.0,
        };
        depth.max(0.0)
    };
    colliders.iter().map(inside).fold(0.0, f64::max)
}

/// What the narrow stage's per-pair work reads of a body slot, gathered
/// once a step in slot order ([`slot_motions`]): a pile's body is in about
/// eight pairs, and each pair read these from the two bodies' entries,
/// where the pose, velocity, material, flags and collider list lie on
/// different cache lines among much else. Read from here, the 1,000-body
/// pile's narrow stage took 1.05-1.15 ms a step instead of 1.26-1.39
/// (`profile_stages pile1000 300 1`, the last third, seven alternated
/// runs). What [`velocity_change_bounds`] reads comes first.
#[derive(Debug, Clone, Copy)]
#[repr(C)]
pub(crate) struct SlotMotion<'a> {
    /// Centre of mass and orientation at the step's start.
    pub pose: Pose,
    /// Linear velocity as the step sees it ([`velocities`]).
    pub v: DVec3,
    /// Restitution of the body's material.
    pub restitution: f64,
    /// Dynamic (not static or kinematic).
    pub dynamic: bool,
    /// [`is_active`].
    pub active: bool,
    /// A collider is a triangle mesh ([`has_mesh`]).
    pub mesh: bool,
    /// Angular velocity as the step sees it.
    pub w: DVec3,
    /// How fast the body's spin moves its farthest point (m/s): the length
    /// of `w` times the body's bounding radius (once a body, not once a
    /// pair: [`relative_motion_bound`]'s cap).
    pub spin_reach: f64,
    /// Friction of the body's material.
    pub friction: f64,
    /// The body's colliders (empty for a free slot).
    pub colliders: &'a [Collider],
}

impl SlotMotion<'_> {
    /// Linear and angular velocity.
    pub fn velocity(&self) -> (DVec3, DVec3) {
        (self.v, self.w)
    }
}

/// [`SlotMotion`] of every body slot (a free slot: at rest at the origin,
/// inactive, without colliders); `meshes`: some body of the world has a
/// triangle mesh (without one, no collider list is read for `mesh`).
pub(crate) fn slot_motions(bodies: &Arena<BodyEntry>, n_slots: usize, meshes: bool) -> Vec<SlotMotion<'_>> {
    (0..n_slots as u32)
        .map(|i| match bodies.at(i) {
            Some(e) => {
                let (v, w) = velocities(e);
                let material = e.body.material();
                SlotMotion {
                    pose: e.body.pose(),
                    v,
                    restitution: material.restitution(),
                    dynamic: e.body.kind() == BodyKind::Dynamic,
                    active: is_active(e),
                    mesh: meshes && has_mesh(e),
                    w,
                    spin_reach: w.length() * e.radius,
                    friction: material.friction(),
                    colliders: &e.colliders,
                }
            }
            None => SlotMotion {
                pose: Pose::IDENTITY,
                v: DVec3::ZERO,
                restitution: 0.0,
                dynamic: false,
                active: false,
                mesh: false,
                w: DVec3::ZERO,
                spin_reach: 0.0,
                friction: 0.0,
                colliders: &[],
            },
        })
        .collect()
}

/// Bound on the speed at which a point of A approaches a point of B, for the
/// points where the two can touch during the step (m/s).
///
/// Where A and B can meet is inside both swept boxes; around the centre `p0`
/// of their intersection the relative velocity of coincident material points
/// is `v_rel(p) = v_rel(p0) + (wA - wB) x (p - p0)`, so within the
/// intersection's half diagonal `rho` it is at most
/// `|v_rel(p0)| + |wA - wB| rho`. For bodies that turn together (the links
/// of a swinging chain) this is far tighter than each body's own speed
/// bound `|vA - vB| + |wA| rA + |wB| rB`, which is kept as the cap.
pub(crate) fn relative_motion_bound(
    a: &SlotMotion,
    b: &SlotMotion,
    box_a: Option<Aabb>,
    box_b: Option<Aabb>,
) -> f64 {
    let ((va, wa), (vb, wb)) = (a.velocity(), b.velocity());
    let coarse = (va - vb).length() + a.spin_reach + b.spin_reach;
    let region = match (box_a, box_b) {
        (Some(x), Some(y)) => {
            let (lo, hi) = (x.min().max(y.min()), x.max().min(y.max()));
            // Disjoint boxes (cannot happen for a broad-phase pair): no bound.
            lo.cmple(hi).all().then_some((lo, hi))
        }
        (Some(x), None) | (None, Some(x)) => Some((x.min(), x.max())),
        (None, None) => None,
    };
    let Some((lo, hi)) = region else { return coarse };
    let p0 = (lo + hi) * 0.5;
    let rho = ((hi - lo) * 0.5).length();
    let v_rel = (va + wa.cross(p0 - a.pose.position)) - (vb + wb.cross(p0 - b.pose.position));
    (v_rel.length() + (wa - wb).length() * rho).min(coarse)
}

/// Per dynamic body slot, the largest [`relative_motion_bound`] of the
/// body's broad-phase pairs (m/s): how fast anything near it moves against
/// it, an estimate of how hard it can be struck within the step (static
/// and kinematic bodies are not moved by blows: zero, as for a body
/// without pairs).
pub(crate) fn neighbour_speeds(
    slots: &[SlotMotion],
    pairs: &[(u32, u32)],
    swept: &[Option<Aabb>],
) -> Vec<f64> {
    let mut speed = vec![0.0f64; slots.len()];
    for &(a, b) in pairs {
        let (sa, sb) = (&slots[a as usize], &slots[b as usize]);
        let s = relative_motion_bound(sa, sb, swept[a as usize], swept[b as usize]);
        for (slot, motion) in [(a, sa), (b, sb)] {
            if motion.dynamic {
                speed[slot as usize] = speed[slot as usize].max(s);
            }
        }
    }
    speed
}

/// Per body slot, an estimate of how much the body's velocity can change in
/// this step through its contacts (m/s): its largest closing speed towards
/// a broad-phase neighbour along the line of their centres, times `1 + e`
/// (stopped by that neighbour, or bounced back). Zero for static and
/// kinematic bodies, whose velocity is imposed.
///
/// Why: the margin of a pair must cover the pair's relative motion over
/// the whole step, and that motion changes when a third body stops one of
/// the two. In a falling column every pair moves together until the bottom
/// body lands; the body above then closes its 0.1 m gap at the full fall
/// speed within the same step, which the pair's own relative velocity
/// (zero) never announced. The centre line, not the full relative speed,
/// because bodies that slide or swing against each other (a chain's links)
/// do not stop each other, and a margin grown by their sliding speed would
/// only multiply the triangle pairs to test. Pairs with a concave mesh are
/// left out: interlocked rings touch where their centres move apart, so
/// the centre line says nothing about their contact normal (a column of
/// mesh bodies dropped together can still overlap by one step's fall).
pub(crate) fn velocity_change_bounds(slots: &[SlotMotion], pairs: &[(u32, u32)], meshes: bool) -> Vec<f64> {
    let mut shock = vec![0.0f64; slots.len()];
    for &(a, b) in pairs {
        let (sa, sb) = (&slots[a as usize], &slots[b as usize]);
        if !sa.active && !sb.active {
            continue;
        }
        let e = MaterialDesc::combine_restitution(sa.restitution, sb.restitution);
        // `meshes`: some body of the world has a mesh (without one, no
        // pair is left out for it).
        if meshes && (sa.mesh || sb.mesh) {
            continue;
        }
        let line = (sb.pose.position - sa.pose.position).normalize_or_zero();
        let change = (sa.v - sb.v).dot(line).max(0.0) * (1.0 + e);
        for (slot, motion) in [(a, sa), (b, sb)] {
            if motion.dynamic {
                shock[slot as usize] = shock[slot as usize].max(change);
            }
        }
    }
    shock
}

pub(crate) fn has_mesh(e: &BodyEntry) -> bool {
    e.colliders
        .iter()
        .any(|c| matches!(c.shape, tumble_collide::Shape::Mesh(_)))
}

pub(crate) fn is_active(e: &BodyEntry) -> bool {
    match e.body.kind() {
        BodyKind::Dynamic => !e.sleeping,
        BodyKind::Kinematic => {
            let (v, w) = e.body.kinematic_velocity();
            v != DVec3::ZERO || w != DVec3::ZERO
        }
        BodyKind::Static => false,
    }
}

/// A body's linear and angular velocity as the step sees it: zero for
/// static and sleeping bodies, the imposed one for kinematic bodies.
pub(crate) fn velocities(e: &BodyEntry) -> (DVec3, DVec3) {
    match e.body.kind() {
        BodyKind::Dynamic if !e.sleeping => (e.body.velocity(), e.body.angular_velocity()),
        BodyKind::Kinematic => e.body.kinematic_velocity(),
        _ => (DVec3::ZERO, DVec3::ZERO),
    }
}

#[cfg(test)]
mod tests {
    //! The motion bounds against the rigid motions they bound: sampled
    //! points of two moving bodies, and pairs closing along their centres.
    use super::*;
    use tumble_testkit::{RandomSource, SplitMix64};

    /// A body slot at `position` moving at `v`, spinning at `w`, whose
    /// points lie within `radius` of its centre.
    fn slot(position: DVec3, v: DVec3, w: DVec3, radius: f64, dynamic: bool) -> SlotMotion<'static> {
        SlotMotion {
            pose: Pose::from_translation(position),
            v,
            restitution: 0.0,
            dynamic,
            active: dynamic,
            mesh: false,
            w,
            spin_reach: w.length() * radius,
            friction: 0.5,
            colliders: &[],
        }
    }

    /// Velocity of the material point of `s` at `p`.
    fn at(s: &SlotMotion, p: DVec3) -> DVec3 {
        s.v + s.w.cross(p - s.pose.position)
    }

    #[test]
    fn the_relative_motion_bound_holds_at_every_point_both_bodies_can_reach() {
        let mut rng = SplitMix64(17);
        let mut checked = 0;
        for _ in 0..500 {
            let radius = [rng.range(0.5, 2.0), rng.range(0.5, 2.0)];
            let a = slot(rng.vec3(3.0), rng.vec3(5.0), rng.vec3(8.0), radius[0], true);
            // Near enough that their reaches mostly meet.
            let b = slot(
                a.pose.position + rng.vec3(1.0),
                rng.vec3(5.0),
                rng.vec3(8.0),
                radius[1],
                true,
            );
            // Each body's box holds the ball of its points, as a swept box
            // holds the body.
            let boxed = |s: &SlotMotion, r: f64| {
                Aabb::new(
                    s.pose.position - DVec3::splat(r),
                    s.pose.position + DVec3::splat(r),
                )
                .unwrap()
            };
            let (box_a, box_b) = (boxed(&a, radius[0]), boxed(&b, radius[1]));
            let (lo, hi) = (box_a.min().max(box_b.min()), box_a.max().min(box_b.max()));
            let bound = relative_motion_bound(&a, &b, Some(box_a), Some(box_b));
            let coarse = (a.v - b.v).length() + a.spin_reach + b.spin_reach;
            assert!(bound <= coarse, "the bound {bound} exceeds its cap {coarse}");
            if !lo.cmple(hi).all() {
                assert_eq!(bound, coarse, "apart boxes: the cap");
                continue;
            }
            for _ in 0..20 {
                let t = DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64());
                let p = lo + (hi - lo) * t;
                // Only points within both bodies' radii can be material
                // points of both (the cap holds there; the box corners lie
                // beyond a body's radius).
                if (p - a.pose.position).length() > radius[0] || (p - b.pose.position).length() > radius[1] {
                    continue;
                }
                let speed = (at(&a, p) - at(&b, p)).length();
                assert!(
                    speed <= bound * (1.0 + 1e-12) + 1e-12,
                    "relative speed {speed} at {p} above the bound {bound}"
                );
                checked += 1;
            }
        }
        assert!(checked > 3000, "only {checked} points within both bodies' reach");
    }

    #[test]
    fn the_bound_with_one_unbounded_body_covers_the_other_bodys_box() {
        let mut rng = SplitMix64(3);
        for _ in 0..200 {
            let a = slot(rng.vec3(3.0), rng.vec3(5.0), rng.vec3(8.0), 1.0, true);
            // A half-space (no box), at rest.
            let ground = slot(DVec3::ZERO, DVec3::ZERO, DVec3::ZERO, 0.0, false);
            let box_a = Aabb::new(a.pose.position - DVec3::ONE, a.pose.position + DVec3::ONE).unwrap();
            let bound = relative_motion_bound(&a, &ground, Some(box_a), None);
            for _ in 0..20 {
                // A material point of the body: within its radius (1 m).
                let p = a.pose.position + rng.vec3(1.0).clamp_length_max(1.0);
                let speed = (at(&a, p) - at(&ground, p)).length();
                assert!(speed <= bound * (1.0 + 1e-12) + 1e-12, "{speed} above {bound}");
            }
        }
    }

    #[test]
    fn a_pair_closing_along_its_centres_bounds_the_change_of_its_dynamic_bodies() {
        let e = 0.5;
        let mut a = slot(DVec3::ZERO, DVec3::new(2.0, 0.0, 0.0), DVec3::ZERO, 0.5, true);
        let mut b = slot(
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(-1.0, 0.0, 0.0),
            DVec3::ZERO,
            0.5,
            true,
        );
        a.restitution = e;
        b.restitution = 0.2;
        let ground = slot(DVec3::new(0.0, 0.0, -1.0), DVec3::ZERO, DVec3::ZERO, 0.0, false);
        let slots = [a, b, ground];
        // Closing at 3 m/s along the line of centres: stopped, or bounced
        // back with the larger restitution, each body's velocity changes
        // by at most 3 (1 + e). A body falling onto the ground at rest
        // closes along z only: a's x motion does not count there.
        let shock = velocity_change_bounds(&slots, &[(0, 1), (0, 2)], false);
        assert_eq!(shock[0], 3.0 * (1.0 + e));
        assert_eq!(shock[1], 3.0 * (1.0 + e));
        // The static ground is never struck.
        assert_eq!(shock[2], 0.0);
        // Separating: nothing to stop.
        let apart = [
            slot(DVec3::ZERO, DVec3::new(-2.0, 0.0, 0.0), DVec3::ZERO, 0.5, true),
            slot(
                DVec3::new(1.0, 0.0, 0.0),
                DVec3::new(1.0, 0.0, 0.0),
                DVec3::ZERO,
                0.5,
                true,
            ),
        ];
        assert_eq!(velocity_change_bounds(&apart, &[(0, 1)], false), vec![0.0, 0.0]);
        // Two resting (inactive) bodies are skipped whatever they hold.
        let mut idle = slots;
        idle[0].active = false;
        idle[1].active = false;
        assert_eq!(velocity_change_bounds(&idle, &[(0, 1)], false)[..2], [0.0, 0.0]);
        // A pair with a mesh is left to the mesh look-ahead.
        let mut meshy = slots;
        meshy[1].mesh = true;
        assert_eq!(velocity_change_bounds(&meshy, &[(0, 1)], true)[..2], [0.0, 0.0]);
    }

    #[test]
    fn neighbour_speeds_are_the_largest_bound_of_each_dynamic_bodys_pairs() {
        let mut rng = SplitMix64(5);
        let slots: Vec<SlotMotion> = (0..6)
            .map(|i| slot(rng.vec3(2.0), rng.vec3(3.0), rng.vec3(3.0), 0.5, i != 5))
            .collect();
        let pairs = [(0, 1), (0, 2), (1, 3), (2, 5), (3, 4)];
        let swept: Vec<Option<Aabb>> = vec![None; slots.len()];
        let speed = neighbour_speeds(&slots, &pairs, &swept);
        for (k, s) in slots.iter().enumerate() {
            let expected = pairs
                .iter()
                .filter(|&&(a, b)| s.dynamic && (a == k as u32 || b == k as u32))
                .map(|&(a, b)| relative_motion_bound(&slots[a as usize], &slots[b as usize], None, None))
                .fold(0.0, f64::max);
            assert_eq!(speed[k], expected, "slot {k}");
        }
        assert_eq!(speed[5], 0.0, "a static body is not struck");
    }
}
