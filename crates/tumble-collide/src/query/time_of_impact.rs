//! Time of impact of two moving shapes of any pair in the narrow phase's
//! table, by conservative advancement (Mirtich 1996, "Impulse-based dynamic
//! simulation of rigid body systems", ch. 4; Zhang, Lee, Kim 2006 for the
//! rotational motion bound).
//!
//! At time `t` a lower bound `d` on the distance between the shapes is
//! taken; no point of A approaches B faster than
//! `mu = |travel_A - travel_B| + turn_A r_A + turn_B r_B` per unit of `t`
//! (travel of the rotation centres, turn angles, largest distances `r` of
//! the shapes' points from their centres), so the shapes cannot come
//! closer than `target` before `t + (d - target) / mu`, and `t` advances
//! there. Every `t` visited is therefore safe (no closer than `target`), for
//! rotation as for translation, and the walk stops within `tolerance` of
//! `target` or when the interval ends.
//!
//! The distance bound comes from three places, cheapest first: the gap
//! between the shapes' bounding boxes (far away, it lets `t` leap); for a
//! mesh, the exact OBBTree distance to the other shape (PQP's query, the
//! primitive queries, GJK for a hull); and for two convex shapes the narrow
//! phase itself, asked for contacts within a probe distance: its closest
//! contact is the distance (or, for the separating axis routines, a lower
//! bound on it) and no contact means farther than the probe.

use super::distance::distance;
use super::error::QueryError;
use super::hull_distance::polytope_mesh_distance;
use super::motion::Motion;
use super::options::DistanceOptions;
use super::primitive_query::distance_primitive;
use super::report::DistanceResult;
use crate::contact::Contact;
use crate::math::DVec3;
use crate::narrow::contact_shapes;
use crate::pose::Pose;
use crate::shape::{Aabb, MeshShape, Shape};

/// Settings of [`time_of_impact`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ToiOptions {
    /// Distance at which the shapes count as touching (m, >= 0). A
    /// simulation asks for a small positive gap, so that the contact found
    /// at the impact pose has room for its normal. Default 0.
    pub target: f64,
    /// How far above `target` the answer may stop (m, > 0). Default 1e-4.
    pub tolerance: f64,
    /// Most advancement steps (>= 1); the time reached so far is returned,
    /// still safe, when they run out. Default 256.
    pub max_iterations: u32,
}

impl Default for ToiOptions {
    fn default() -> Self {
        ToiOptions {
            target: 0.0,
            tolerance: 1e-4,
            max_iterations: 256,
        }
    }
}

impl ToiOptions {
    fn validate(&self) -> Result<(), QueryError> {
        if !(self.target.is_finite() && self.target >= 0.0) {
            return Err(QueryError::BadOption {
                option: "ToiOptions::target",
                expected: "finite and >= 0",
                value: self.target,
            });
        }
        if !(self.tolerance.is_finite() && self.tolerance > 0.0) {
            return Err(QueryError::BadOption {
                option: "ToiOptions::tolerance",
                expected: "finite and > 0",
                value: self.tolerance,
            });
        }
        if self.max_iterations == 0 {
            return Err(QueryError::BadOption {
                option: "ToiOptions::max_iterations",
                expected: ">= 1",
                value: 0.0,
            });
        }
        Ok(())
    }
}

/// Work done by one [`time_of_impact`] query.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ToiStats {
    /// Advancement steps taken.
    pub iterations: u32,
    /// Steps decided by the bounding boxes alone.
    pub box_bounds: u32,
    /// Steps that ran an exact distance or contact query.
    pub shape_queries: u32,
}

/// Where and when two moving shapes first come within the target distance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Impact {
    /// The time of impact in `[0, 1]` (fraction of the motions). 0 when the
    /// shapes are already within `target + tolerance` at the start.
    pub time: f64,
    /// Distance bound at that time (m): within `[target, target +
    /// tolerance]` when `converged`; below `target` (or negative, an
    /// overlap) only when `time` is 0.
    pub distance: f64,
    /// Unit normal from B to A at the impact (world frame); zero in the rare
    /// case that the shapes overlap at the start with no contact to give a
    /// direction.
    pub normal: DVec3,
    /// A point between the shapes where they meet (world frame).
    pub point: DVec3,
    /// `false` when the iterations ran out first: `time` is then the last
    /// safe time reached before the impact, not the impact itself.
    pub converged: bool,
    /// The work done.
    pub stats: ToiStats,
}

/// The first time at which shape A moving by `motion_a` and shape B moving
/// by `motion_b` come within `options.target` of each other (to within
/// `options.tolerance`), or `None` when they stay farther apart over the
/// whole interval.
///
/// Works for every pair of [`crate::narrow::contact_shapes`]; a half-space
/// may move but not turn.
///
/// ```
/// use tumble_collide::query::{time_of_impact, Motion, ToiOptions};
/// use tumble_collide::shape::{Cuboid, Shape, Sphere};
/// use tumble_collide::{DVec3, Pose};
///
/// // A 0.1 m ball fired at 1 cm plate 2 m away, covering 4 m in the interval.
/// let ball = Shape::Sphere(Sphere::new(0.1)?);
/// let plate = Shape::Cuboid(Cuboid::new(DVec3::new(1.0, 1.0, 0.005))?);
/// let from = Pose::from_translation(DVec3::new(0.0, 0.0, 2.0));
/// let to = Pose::from_translation(DVec3::new(0.0, 0.0, -2.0));
/// let hit = time_of_impact(
///     &ball, &Motion::between(from, to),
///     &plate, &Motion::fixed(Pose::IDENTITY),
///     &ToiOptions::default(),
/// )?.expect("the ball hits the plate");
/// // The ball's surface reaches the plate's top face (z = 0.005) when its
/// // centre is at z = 0.105: after (2 - 0.105) / 4 of the interval.
/// assert!((hit.time - (2.0 - 0.105) / 4.0).abs() < 1e-4);
/// assert!(hit.normal.z > 0.99);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// [`QueryError::BadPose`] for a pose that is not finite or not unit,
/// [`QueryError::BadOption`] for bad options, a non-finite rotation centre or
/// a turning half-space, [`QueryError::Narrow`] when the pair has no contact
/// routine or its arithmetic overflows.
pub fn time_of_impact(
    a: &Shape,
    motion_a: &Motion,
    b: &Shape,
    motion_b: &Motion,
    options: &ToiOptions,
) -> Result<Option<Impact>, QueryError> {
    options.validate()?;
    let (ma, mb) = (motion_a.checked("motion_a")?, motion_b.checked("motion_b")?);
    let (ra, rb) = (reach(a, ma.center), reach(b, mb.center));
    let turn_bound = |turn: f64, r: f64| {
        if turn == 0.0 {
            Ok(0.0)
        } else if r.is_finite() {
            Ok(turn * r)
        } else {
            Err(QueryError::BadOption {
                option: "Motion (half-space)",
                expected: "a motion without rotation",
                value: turn,
            })
        }
    };
    // The fastest approach of any two points, per unit of t.
    let speed =
        (ma.travel() - mb.travel()).length() + turn_bound(ma.turn(), ra)? + turn_bound(mb.turn(), rb)?;
    let goal = options.target + options.tolerance;
    // The probe of a contact query: far enough to leap in few steps, near
    // enough that the narrow phase reports few points.
    let probe = (0.5 * ra.min(rb)).max(4.0 * goal);
    let mut stats = ToiStats::default();
    let mut buffer = Vec::new();
    let mut t = 0.0f64;
    loop {
        let (pa, pb) = (ma.pose_at(t), mb.pose_at(t));
        // Farther than this, the rest of the motion cannot reach the target.
        let reachable = speed * (1.0 - t) + goal;
        let bound = separation_bound(
            a,
            &pa,
            b,
            &pb,
            probe.min(reachable).max(goal),
            &mut buffer,
            &mut stats,
        )?;
        stats.iterations += 1;
        let impact = |converged: bool| {
            let (normal, point) = bound.witness.unwrap_or((DVec3::ZERO, pa.position));
            Impact {
                time: t,
                distance: bound.distance,
                normal,
                point,
                converged,
                stats,
            }
        };
        if bound.distance <= goal {
            return Ok(Some(impact(true)));
        }
        if bound.distance >= reachable || speed == 0.0 {
            return Ok(None);
        }
        if stats.iterations >= options.max_iterations {
            return Ok(Some(impact(false)));
        }
        t += (bound.distance - options.target) / speed;
        if t >= 1.0 {
            return Ok(None);
        }
    }
}

/// A lower bound on the distance of two placed shapes, with the normal
/// (B to A) and point of the closest contact when one was computed.
struct SeparationBound {
    distance: f64,
    witness: Option<(DVec3, DVec3)>,
}

/// The distance of A and B if it is below `probe`, else a bound `>= probe`
/// (m).
fn separation_bound(
    a: &Shape,
    pa: &Pose,
    b: &Shape,
    pb: &Pose,
    probe: f64,
    buffer: &mut Vec<Contact>,
    stats: &mut ToiStats,
) -> Result<SeparationBound, QueryError> {
    let gap = box_gap(&a.aabb(pa), &b.aabb(pb));
    if gap >= probe {
        stats.box_bounds += 1;
        return Ok(SeparationBound {
            distance: gap,
            witness: None,
        });
    }
    stats.shape_queries += 1;
    // A mesh against anything: an exact distance. (The narrow phase's mesh
    // routines report the contacts a solver needs, not always the closest
    // pair of features: a box edge crossing a triangle edge can be missed
    // while they are apart.)
    let exact = match (a, b) {
        (Shape::Mesh(x), Shape::Mesh(y)) => Some(distance(x, pa, y, pb, &DistanceOptions::default())?),
        (_, Shape::Mesh(y)) => Some(convex_mesh_distance(a, pa, y, pb)?),
        (Shape::Mesh(x), _) => Some(convex_mesh_distance(b, pb, x, pa)?.swapped()),
        _ => None,
    };
    if let Some(d) = exact {
        // Apart: the closest points give the direction. Touching or
        // overlapping (distance 0), they coincide up to round-off, whose
        // direction is noise: a hull spinning along a mesh slab took such a
        // normal for the slab's, and continuous collision, finding the body
        // on the wrong side of it, put it back where it began, step after
        // step. The deepest contact of the narrow phase gives the direction.
        let normal = (d.point_a - d.point_b).normalize_or_zero();
        if d.distance > 0.0 && normal != DVec3::ZERO {
            return Ok(SeparationBound {
                distance: d.distance,
                witness: Some((normal, (d.point_a + d.point_b) * 0.5)),
            });
        }
        buffer.clear();
        contact_shapes(a, pa, b, pb, probe, buffer)?;
        let deepest = buffer.iter().min_by(|x, y| x.distance.total_cmp(&y.distance));
        return Ok(SeparationBound {
            distance: d.distance,
            witness: deepest.map(|c| (c.normal, c.point)),
        });
    }
    buffer.clear();
    contact_shapes(a, pa, b, pb, probe, buffer)?;
    let closest = buffer.iter().min_by(|x, y| x.distance.total_cmp(&y.distance));
    Ok(match closest {
        Some(c) => SeparationBound {
            distance: c.distance,
            witness: Some((c.normal, c.point)),
        },
        None => SeparationBound {
            distance: probe.max(gap),
            witness: None,
        },
    })
}

/// Distance of a shape that is not a mesh to mesh `m`.
fn convex_mesh_distance(
    a: &Shape,
    pa: &Pose,
    m: &MeshShape,
    pm: &Pose,
) -> Result<DistanceResult, QueryError> {
    let options = DistanceOptions::default();
    match a {
        Shape::Sphere(_) | Shape::Cuboid(_) | Shape::Capsule(_) | Shape::HalfSpace(_) => {
            distance_primitive(a, pa, m, pm, &options)
        }
        Shape::ConvexHull(h) => polytope_mesh_distance(h, pa, m, pm),
        Shape::Mesh(x) => distance(x, pa, m, pm, &options),
    }
}

/// Largest distance of a point of `shape` from `center` (shape frame, m),
/// bounded through the shape's own box; infinite for a half-space.
fn reach(shape: &Shape, center: DVec3) -> f64 {
    let b = shape.aabb(&Pose::IDENTITY);
    let far = (b.min - center).abs().max((b.max - center).abs());
    far.length()
}

/// Distance between two axis-aligned boxes (m): a lower bound on the
/// distance of anything inside them.
fn box_gap(x: &Aabb, y: &Aabb) -> f64 {
    let g = (y.min - x.max).max(x.min - y.max).max(DVec3::ZERO);
    let d = g.length();
    if d.is_nan() {
        0.0
    } else {
        d
    }
}
