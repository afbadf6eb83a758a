//! Contact patches inside a joint island: a patch whose two bodies belong
//! to the same island (a chain folding onto its own weight, a ragdoll's arm
//! on its chest) closes a loop through the island's joints, and is solved
//! with the island's system instead of beside it; so is a patch between one
//! of the island's bodies and an immovable one (a ragdoll's forearm on the
//! ground, a finger pressed by its hand onto a table), whose loop closes
//! through the world.
//!
//! Why: relaxed one after the other, the island's direct solve and such a
//! contact undo each other. The heavy chain's last light link struck the
//! 10 kg weight it hangs from: the contact pushed the 0.1 kg link away
//! (25 m/s in one pass), the joints pulled it back, and what the last pass
//! left stretched the joints by 7 mm; forty passes still left 2 mm.
//!
//! How (the Schur complement of the island's system, the way Baraff's
//! "Linear-time dynamics using Lagrange multipliers", 1996, treats the
//! constraints that close loops):
//! with `K = J M^-1 J^T = L L^T` the island's factored system, `G` the
//! patch's normal rows and `W = J M^-1 G^T` (a joint row's velocity per
//! unit impulse at each contact point), an impulse `d` at the points with
//! the joint impulse change `-K^-1 W d` leaves every joint row's velocity
//! as it was and changes the points' normal velocities by `S d`,
//! `S = G M^-1 G^T - W^T K^-1 W`: the patch's block as the joints let it
//! act. Each pass the island solves its joint rows (`x = K^-1 rhs`), then
//! the patch's block LCP on `S` with the velocities that `x` will bring
//! (`W^T x`), then takes `K^-1 W d` back out of `x`. Joints and contact are
//! then solved together exactly (one patch; several are taken one after
//! the other). Friction stays a plain pass before the island's system,
//! which takes up what it disturbs.
//!
//! All of it runs in the factor's half-way space: with `V = L^-1 W` (a
//! forward substitution per point, no backward one) and `z = L^-1 rhs`,
//! `W^T x = V^T z`, taking `K^-1 W d` out of `x` is taking `V d` out of
//! `z`, and `W^T K^-1 W = V^T V`; one backward substitution after the last
//! patch turns `z` into the joints' impulses. A point's `W` is zero above
//! the first row of a joint on its bodies, and so is its `V`: the forward
//! substitution starts there (the limbs' joints come first in an island's
//! order, so a point on a ragdoll's torso skips them), and works out only
//! the rows the factor carries the point's joints to (`Profile::reach`: a
//! forearm's column never reaches the legs' rows).
//!
//! The loop through the world matters as much: a 20 mg finger hinged to a
//! 185 g hand that presses it onto a static plank (the hand's ball joint
//! to the world) opened its hinge by 26 mm with the patch relaxed beside
//! the island, and holds it within 0.06 mm owned (test
//! `joints::a_light_finger_pressed_onto_a_plank_by_its_hand_keeps_its_hinge`);
//! the ragdoll pile, whose limbs lie on the ground, went from 8.3 to 1.7 mm
//! of largest joint error and from 14 steps gaining energy (one by 122 J)
//! to none, for a third more time a step (docs/pipeline.md, 2026-12-02).
//!
//! Not owned: patches on a body lighter than [`LIGHTEST_OWNER`] of the
//! island's heaviest. There the owned solve runs away: many owned patches
//! on NAO's 2 mg fingers (a millionth of the robot's heaviest link) against
//! each other, their wrists and the ground, 200-390 points a sub-step with
//! blocks keeping 0.3-20 % of a point's own inverse mass, some near rank
//! one, opened the robot's joints by up to 0.43 m dropped with
//! self-collision (it blew apart before [`COMPLIANCE_SHARE`]), and the
//! finger above weighing 2 mg opened its hinge by 1.8 m on a hinged plank.
//! Relaxed beside the island, such a patch costs the joints millimetres to
//! centimetres instead (docs/pipeline.md, "Measured and not kept").
//!
//! Nor an island's dearest patches on immovable bodies beyond
//! `joint_island::MAX_OWNED_SUBSTITUTION` of forward substitution a
//! sub-step, less what its own patches cost (a point costs the factor's
//! entries from its first row on): a 30 x 30 net lying on a box owned
//! thousands of points, each a substitution over a profile of 167,000
//! entries.
//!
//! A patch between two of an island's bodies is always owned, however
//! many points it has (in blocks of four) and whatever it costs (one on an
//! immovable body only with four points at most: owned in blocks, a car's
//! wheels on a mesh terrain rolled 19 % slower than their motors drive
//! them). Left beside the island, such a patch pushes one link out while the island's
//! direct solve pulls it back, pass after pass, and the passes over it
//! added kinetic energy: NAO with its fingers made 1 g, whose finger meshes
//! touch each other in patches of five to eight points and, once the hands
//! close, in hundreds of patches (over the budget), blew apart in eight of
//! nine drops; with every such patch owned it held its joints within 1.7-5.8
//! mm in all five (docs/pipeline.md, 2026-12-05).

use super::coloring::Shared;
use super::constraint::{regularised_inverse, ManifoldConstraint, PatchBlock, PointConstraint, BLOCK_POINTS};
use super::island_factor::SideRow;
use std::ops::Range;
use tumble_collide::DVec3;

/// A patch's normal block as the island's joints let it act, what
/// `passes::solve_owned_normals` solves on.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct ArticulatedBlock {
    /// `S = G M^-1 G^T - V^T V` (`= G M^-1 G^T - W^T K^-1 W`).
    pub block: PatchBlock,
    /// Its regularised inverse (`constraint::regularised_inverse`).
    pub inverse: PatchBlock,
    /// Each point's `1 / S_ii` (0 for padding).
    pub mass: [f64; BLOCK_POINTS],
}

/// Share of a point's own inverse mass added to its articulated one (a
/// compliance, as constraint force mixing adds one). A loop the joints lock
/// along the normal leaves the point almost no freedom: `S_ii` near
/// rounding, and `S` itself, a difference of two near-equal matrices,
/// slightly indefinite where it should be singular. With this share added
/// to every diagonal entry, `S` is positive definite whenever its rounding
/// is smaller than the share, and an impulse is at most a thousand times
/// what the point alone would take. Raising only the diagonal entries that
/// fell below the share (the floor it replaced) left the off-diagonal
/// rounding in place: over sixteen drops of NAO with self-collision
/// (heights 0.32-0.48 m, with and without its `<mimic>` gears), six opened
/// its joints by more than 0.3 m and three blew apart, against one and none
/// with the share added; the heavy chain's joint error stayed 0.11 mm
/// (docs/pipeline.md, "Measured and not kept", 2026-12-02).
pub(super) const COMPLIANCE_SHARE: f64 = 1e-3;

/// Patches on a dynamic body lighter than this share of its island's
/// heaviest body are not owned (module docs): NAO's fingers (a millionth)
/// are not, a ragdoll's forearms (a sixteenth of its torso) and the heavy
/// chain's links (a hundredth of its weight) are. Over sixteen drops of NAO with
/// self-collision the largest joint error was 24-193 mm with this bound and
/// the ground's patches owned, 41-425 mm with neither (docs/pipeline.md,
/// 2026-12-02); owning the ground's patches without it blew NAO apart.
pub(super) const LIGHTEST_OWNER: f64 = 1e-5;

/// One island-owned patch, or a block of up to [`BLOCK_POINTS`] of its
/// points, and its coupling to the island's rows. A patch of more points (a
/// mesh patch: the faces of two finger links) is owned as consecutive
/// blocks, each solved exactly with the joints, one after the other as
/// patches are; left beside the island instead, such patches fought its
/// joints pass after pass and added energy (module docs).
#[derive(Debug, Clone, Default, PartialEq)]
pub(super) struct OwnedPatch {
    /// The patch (index into the solver's patch array).
    pub patch: u32,
    /// The block's first point within the patch (in patch order).
    block_start: u32,
    /// Points in the block (at most [`BLOCK_POINTS`]).
    block_points: u32,
    /// The lane of the island whose bodies it touches (in a unit of more
    /// islands).
    pub lane: usize,
    /// Rows of the island's system.
    rows: usize,
    /// The first row on one of the patch's two bodies: every row before it
    /// is zero in each point's column of `W` and of `V`.
    first_row: usize,
    /// The island's joints (bit `p` for joint `p`) whose rows of the
    /// points' columns of `V` can be other than zero (`Profile::reach`:
    /// those on the patch's bodies and those the factor carries them to;
    /// gear rows always): `V` is an exact zero in the others, whose forward
    /// substitution is skipped. `None`: every row from `first_row` on.
    reach: Option<u64>,
    /// Per point, `rows` entries: the island rows' velocities per unit
    /// impulse at the point (its column of `W`), replaced by `L^-1` times
    /// it (`V`) once the island's factor has solved it.
    response: Vec<f64>,
    /// `S`, its inverse and masses.
    block: ArticulatedBlock,
}

impl OwnedPatch {
    /// Points `start..start + count` (count at most [`BLOCK_POINTS`]) of
    /// the patch at index `patch`, owned as one block by the island in
    /// `lane`, whose first row of the island's system on one of the
    /// patch's bodies is `first_row` and whose points' columns of `V` can be
    /// other than zero in the rows of the joints `reach` (both found by
    /// `joint_island::own_patches`), to be coupled to it each sub-step
    /// ([`OwnedPatch::couple`], then `L^-1` applied to each
    /// [`OwnedPatch::response_mut`], then [`OwnedPatch::finish`]).
    pub fn new(
        patch: u32,
        start: u32,
        count: u32,
        lane: usize,
        first_row: usize,
        reach: Option<u64>,
    ) -> OwnedPatch {
        debug_assert!(count as usize <= BLOCK_POINTS);
        OwnedPatch {
            patch,
            block_start: start,
            block_points: count.min(BLOCK_POINTS as u32),
            lane,
            first_row,
            reach,
            ..OwnedPatch::default()
        }
    }

    /// Whether this is the patch's first block: the one that begins the
    /// patch (warm start) and solves its friction, once per patch.
    pub fn leads(&self) -> bool {
        self.block_start == 0
    }

    /// The block's points among the solver's points, given the patch's
    /// (`ManifoldConstraint::range`), never past the patch's last.
    pub fn points_in(&self, patch: Range<usize>) -> Range<usize> {
        let start = (patch.start + self.block_start as usize).min(patch.end);
        start..(start + self.block_points as usize).min(patch.end)
    }

    /// Builds `W` for this sub-step, after the island's rows are begun:
    /// the island's system has `n` rows, row `r`'s Jacobian on side `s`
    /// is `side(r, s)` (linear, angular), and `row_bodies` gives each
    /// row's two solver bodies, joint after joint from `joints` (each
    /// joint's first row, and the end of the last); a row on more than two
    /// bodies (a gear, after the joints' rows) is given by its parts
    /// instead, as (row, body, the part as side 0). Each point's response
    /// holds its column of `W` until the island solves it in place
    /// (`V = L^-1 W`).
    #[allow(clippy::too_many_arguments)] // the patch, and the island's rows as it lays them out
    pub fn couple(
        &mut self,
        m: &ManifoldConstraint,
        pts: &[PointConstraint],
        n: usize,
        side: impl Fn(usize, usize) -> (DVec3, DVec3),
        row_bodies: &[[u32; 2]],
        joints: &[usize],
        gear_parts: &[(usize, u32, SideRow<f64>)],
    ) {
        self.rows = n;
        self.first_row = self.first_row.min(n);
        self.response.clear();
        self.response.resize(n * pts.len(), 0.0);
        // Only the rows of joints on the patch's two bodies are not zero
        // (a ragdoll's patch is on two or three of its ten joints).
        let (a, b) = (m.a, m.b);
        for joint in joints.windows(2) {
            if joint[0] == joint[1] {
                continue;
            }
            let pair = row_bodies[joint[0]];
            if pair[0] != a && pair[0] != b && pair[1] != a && pair[1] != b {
                continue;
            }
            for r in joint[0]..joint[1] {
                for (s, &body) in pair.iter().enumerate() {
                    if body == a || body == b {
                        self.add_side(m, pts, r, body == a, side(r, s));
                    }
                }
            }
        }
        for (r, body, part) in gear_parts {
            if *body == a || *body == b {
                self.add_side(m, pts, *r, *body == a, part.side(0));
            }
        }
    }

    /// Adds a side of row `r` (on the patch's body A if `on_a`, else B),
    /// of Jacobian `(lin, ang)` on that body, to each point's column of
    /// `W`.
    #[inline(always)]
    fn add_side(
        &mut self,
        m: &ManifoldConstraint,
        pts: &[PointConstraint],
        r: usize,
        on_a: bool,
        side: (DVec3, DVec3),
    ) {
        let n = self.rows;
        let [ima, imb] = m.inv_mass;
        let (sign, im) = if on_a { (1.0, ima) } else { (-1.0, imb) };
        let (lin, ang) = side;
        debug_assert!(r >= self.first_row, "row {r} before the patch's first row");
        for (i, p) in pts.iter().enumerate() {
            // The contact's unit impulse: +n on A, -n on B.
            let dw = if on_a { p.row.ia_ra_x_d } else { p.row.ib_rb_x_d };
            self.response[i * n + r] += sign * (lin.dot(p.normal * im) + ang.dot(dw));
        }
    }

    /// The patch's points, as last coupled.
    pub fn points(&self) -> usize {
        self.response.len() / self.rows.max(1)
    }

    /// The first row of the island's system on one of the patch's bodies
    /// (the rows of `W` and `V` before it are zero).
    pub fn first_row(&self) -> usize {
        self.first_row
    }

    /// The joints whose rows of the points' columns of `V` can be other
    /// than zero (bit `p` for joint `p`; gear rows always), or `None` for
    /// every row from [`OwnedPatch::first_row`] on.
    pub fn reach(&self) -> Option<u64> {
        self.reach
    }

    /// Point `i`'s column of `W` (or of `V`, once solved).
    pub fn response(&self, i: usize) -> &[f64] {
        let n = self.rows;
        &self.response[i * n..(i + 1) * n]
    }

    /// Point `i`'s column of `W`, to be replaced by `L^-1` times it.
    pub fn response_mut(&mut self, i: usize) -> &mut [f64] {
        let n = self.rows;
        &mut self.response[i * n..(i + 1) * n]
    }

    /// `S`, its inverse and the points' masses, once `V` is in place.
    #[allow(clippy::needless_range_loop)] // a symmetric matrix reads best indexed
    pub fn finish(&mut self, m: &ManifoldConstraint, pts: &[PointConstraint]) {
        let (n, from) = (self.rows, self.first_row);
        let [ima, imb] = m.inv_mass;
        let mut s = [[0.0; BLOCK_POINTS]; BLOCK_POINTS];
        for (i, pi) in pts.iter().enumerate() {
            for (j, pj) in pts.iter().enumerate().take(i + 1) {
                let plain = pi.normal.dot(pj.normal) * (ima + imb)
                    + pi.row.ra_x_d.dot(pj.row.ia_ra_x_d)
                    + pi.row.rb_x_d.dot(pj.row.ib_rb_x_d);
                let (vi, vj) = (self.response(i), self.response(j));
                let mut through_joints = 0.0;
                for (a, b) in vi[from..n].iter().zip(&vj[from..n]) {
                    through_joints += a * b;
                }
                s[i][j] = plain - through_joints;
                s[j][i] = s[i][j];
            }
        }
        // Each diagonal softened by its share of the point's own inverse
        // mass.
        for i in 0..pts.len() {
            let own = pts[i].row.inverse_mass(pts[i].normal, ima, imb);
            s[i][i] += COMPLIANCE_SHARE * own;
        }
        let mass = std::array::from_fn(|i| {
            if i < pts.len() && s[i][i] > 0.0 {
                1.0 / s[i][i]
            } else {
                0.0
            }
        });
        self.block = ArticulatedBlock {
            block: s,
            inverse: regularised_inverse(&s),
            mass,
        };
    }

    /// `S`, its inverse and the points' masses, for
    /// `passes::solve_owned_normals`.
    pub fn block(&self) -> &ArticulatedBlock {
        &self.block
    }

    /// The normal velocity each point gains from the island's row impulses
    /// `x = L^-T z`, given `z` (row `r` of this patch's lane at
    /// `z[r * stride + lane]`): `V^T z`.
    pub fn coupled(&self, z: &[f64], stride: usize) -> [f64; BLOCK_POINTS] {
        let mut v = [0.0; BLOCK_POINTS];
        let (from, lane) = (self.first_row, self.lane);
        let z = &z[(from * stride).min(z.len())..];
        for (i, u) in self.response.chunks_exact(self.rows.max(1)).enumerate() {
            let u = &u[from..];
            // The same sums either way, row after row: one lane read
            // straight, or this lane of each row's set.
            if stride == 1 {
                for (u, z) in u.iter().zip(z) {
                    v[i] += u * z;
                }
            } else {
                for (u, z) in u.iter().zip(z.chunks_exact(stride)) {
                    v[i] += u * z[lane];
                }
            }
        }
        v
    }

    /// Takes the joints' share of the points' impulses `d` out of the
    /// island's row impulses, given as `z` (laid out as for
    /// [`OwnedPatch::coupled`]): `z -= V d`.
    pub fn take_back(&self, d: &[f64; BLOCK_POINTS], z: &mut [f64], stride: usize) {
        let (from, lane) = (self.first_row, self.lane);
        let start = (from * stride).min(z.len());
        let z = &mut z[start..];
        for (u, &di) in self.response.chunks_exact(self.rows.max(1)).zip(d) {
            if di == 0.0 {
                continue;
            }
            let u = &u[from..];
            if stride == 1 {
                for (u, z) in u.iter().zip(z.iter_mut()) {
                    *z -= u * di;
                }
            } else {
                for (u, z) in u.iter().zip(z.chunks_exact_mut(stride)) {
                    z[lane] -= u * di;
                }
            }
        }
    }
}

/// The contact arrays an island reads its owned patches from.
pub(super) struct PatchArrays<'s, 'a> {
    pub manifolds: &'s Shared<'a, ManifoldConstraint>,
    pub points: &'s Shared<'a, PointConstraint>,
}
