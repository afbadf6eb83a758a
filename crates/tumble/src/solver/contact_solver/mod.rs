//! Sub-stepped contact solver: non-penetration, Coulomb friction and
//! restitution by sequential impulses (projected Gauss-Seidel on the contact
//! LCP of thesis 7.2), sub-stepped as in E. Catto's "soft step" (Solver2D
//! 2024, Box2D v3), with position correction by split impulses (Catto 2006;
//! Bullet's split-impulse mode) and friction per contact patch.
//!
//! One step of `dt` is split into `n` sub-steps of `h = dt / n`. The contact
//! points, normals and effective masses are computed once per step; within
//! each sub-step the separation of every point is updated from the bodies'
//! motion since the start of the step (`s = s0 + n . (dA - dB)` with `d` the
//! displacement of each anchor), so the narrow phase runs once per step while
//! the solver sees the contact close and open. Per sub-step:
//!
//! 1. integrate velocities (gravity, forces),
//! 2. separations, and warm start: apply the impulses accumulated so far
//!    ([`begin_substep`]),
//! 3. velocity passes ([`solve`]): each patch's friction in its Coulomb
//!    disc, then `v_n >= 0` on touching points and `v_n >= -s/h` on points
//!    with a gap `s` (speculative: the gap may close, never go negative),
//! 4. push-out ([`push_out`]): overlap beyond the allowance is removed by
//!    pseudo-velocities that move the bodies but are then discarded (in
//!    the first pass, sticking patches of meshes also pull their anchor
//!    points back together: static friction at the position level),
//! 5. integrate positions with the velocities plus the pseudo-velocities
//!    ([`integrate_positions`]).
//!
//! Before the sub-steps, colliding contacts get Newton's restitution law
//! `v_n+ = -e v_n-` (thesis 7.1) by [`resolve_collisions`]; the sub-steps then
//! treat every contact as resting (the LCP of thesis 7.2, `e = 0`). Normals
//! point from B to A; an impulse `lambda n` acts on A and `-lambda n` on B.
//!
//! Data layout: patches ([`ManifoldConstraint`]: body pair, friction rows)
//! index runs of points ([`PointConstraint`]: normal rows) in one flat array;
//! every pass keeps the pair's velocities in registers across the patch's
//! rows. In the world, patches are coloured ([`color_patches`]: no two
//! patches of a colour share a dynamic body; a problem of fewer than 128
//! patches keeps its patch order, cut into levels that share no body) and
//! sorted by colour, and each pass walks the colours in order, the patches
//! of a colour split over the world's threads: the same bits for any thread
//! count. Within a colour the
//! patches of up to four points travel four at a time, one per SIMD lane
//! (`wide`, over the portable lane type of `lanes`), grouped by point count
//! (lone points, edges, faces); each lane computes the scalar kernel's bits.

mod batches;
mod body;
mod collisions;
mod coloring;
mod constraint;
mod exact;
mod gear;
mod island_contacts;
mod island_factor;
mod island_lanes;
mod joint;
mod joint_island;
mod lanes;
mod passes;
mod prefetch;
mod rolling;
mod solved;
mod wide;

#[cfg(test)]
mod tests;

pub(crate) use batches::{RecordSource, SolverArrays, ThreadFlow, VelocityPass, BODIES_PER_BLOCK};
pub use body::{integrate_positions, SolverBody};
pub use collisions::{resolve_collisions, MAX_COLLISION_SWEEPS};
pub(crate) use coloring::Shared;
pub use coloring::{color_joints, color_patches, color_patches_except, Coloring, MAX_COLORS};
pub use constraint::{
    inverse_effective_mass, prepare, refresh_masses, tangent_basis, ManifoldConstraint, PointConstraint,
    RowJacobian, SolverParams, BLOCK_POINTS, BLOCK_REFRESH,
};
pub use exact::{solve_normals_exactly, ExactSolveError, EXACT_MAX_CONTACTS};
pub use gear::GearConstraint;
pub(crate) use gear::{begin_gears, push_gears, solve_gears};
pub use joint::{
    begin_joints, push_joints, solve_joints, JointConstraint, JointLaw, JointRow, JOINT_PUSH_FRACTION,
    JOINT_ROWS,
};
pub use joint_island::{
    joint_islands, keep_joint_islands, JointIsland, OwnableContact, MAX_OWNED_SUBSTITUTION, MAX_PROFILE,
};
pub use passes::{begin_substep, push_out, residual, solve, solve_friction};
pub(crate) use prefetch::prefetch;
pub use solved::{SolvedPatch, SolvedPatches, SolvedPoint, STICKING};
pub(crate) use wide::{BundleKind, WideBatches};
