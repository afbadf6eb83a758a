//! The bodies of a unit of joint islands of one shape (`joint_island`: a
//! pile of ragdolls, four at a time), one lane set per body, so that the
//! unit's passes over its equality rows (each row's velocity `J v`, then
//! each impulse applied to its two bodies) run four islands at once.
//!
//! Islands share a unit only when their systems have the same profile, and
//! the profile records which joints meet on which side at a dynamic body:
//! the joints of every lane then link the same limbs in the same way, and a
//! body of lane 0's island has the same place in every lane's. The unit's
//! bodies are gathered into one slot each (an immovable side: a slot per
//! joint side, read and never written), the rows relaxed on the slots, and
//! the dynamic slots written back, each lane with the operations of the
//! joint-by-joint pass (`Pair`) in its order: the same bits.

use super::body::SolverBody;
use super::coloring::Shared;
use super::island_factor::SideRow;
use super::joint::Pair;
use super::lanes::{Lane, LANES, V3};
use tumble_collide::DVec3;

/// A unit's bodies as lane sets (see the module header).
#[derive(Debug, Clone, Default, PartialEq)]
pub(super) struct UnitBodies {
    /// Per joint of the shape: the slots of its sides A and B.
    sides: Vec<[u32; 2]>,
    /// Per slot: the solver body of each lane (lanes beyond the unit's
    /// islands repeat the last island's, read and never written).
    bodies: Vec<[u32; LANES]>,
    /// Per slot: whether its bodies are dynamic (written back).
    dynamic: Vec<bool>,
    /// Per slot: the bodies' inverse masses.
    inv_mass: Vec<Lane>,
    /// Per slot: the bodies' linear velocities (or push-out velocities).
    v: Vec<V3>,
    /// Per slot: the angular ones.
    w: Vec<V3>,
    /// Islands in the unit (lanes written back).
    islands: usize,
}

impl UnitBodies {
    /// The slots of a unit whose lane `l` holds the island of joints
    /// `lanes[l]` (in the shape's order), given each joint's solver bodies
    /// A and B (`ends`) and each body's dynamic flag and inverse mass
    /// (`body`). `false` (and the slots cleared) if the lanes do not link
    /// their bodies in the same way, which a shared profile should rule
    /// out: the unit is then relaxed lane by lane.
    pub fn build(
        &mut self,
        lanes: &[Vec<u32>],
        ends: impl Fn(u32) -> [u32; 2],
        body: impl Fn(u32) -> (bool, f64),
    ) -> bool {
        self.sides.clear();
        self.bodies.clear();
        self.dynamic.clear();
        self.inv_mass.clear();
        self.islands = lanes.len();
        let last = lanes.len() - 1;
        for (k, _) in lanes[0].iter().enumerate() {
            let ends: [[u32; 2]; LANES] = std::array::from_fn(|l| ends(lanes[l.min(last)][k]));
            let mut slots = [0u32; 2];
            for (s, slot) in slots.iter_mut().enumerate() {
                let of_lane: [u32; LANES] = ends.map(|e| e[s]);
                let dynamic: [bool; LANES] = of_lane.map(|b| body(b).0);
                if dynamic.iter().any(|&d| d != dynamic[0]) {
                    self.sides.clear();
                    return false;
                }
                // (An immovable side gets a slot of its own: never written.)
                let found = (self.bodies.iter().zip(&self.dynamic))
                    .position(|(b, &d)| d && dynamic[0] && *b == of_lane);
                *slot = match found {
                    Some(i) => i as u32,
                    None => {
                        self.bodies.push(of_lane);
                        self.dynamic.push(dynamic[0]);
                        self.inv_mass.push(Lane::new(of_lane.map(|b| body(b).1)));
                        (self.bodies.len() - 1) as u32
                    }
                };
            }
            self.sides.push(slots);
        }
        // Each lane's dynamic body in one slot only (else the lanes link
        // their bodies differently).
        for l in 0..self.islands {
            let mut seen: Vec<u32> = (self.bodies.iter().zip(&self.dynamic))
                .filter(|(_, &d)| d)
                .map(|(b, _)| b[l])
                .collect();
            let count = seen.len();
            seen.sort_unstable();
            seen.dedup();
            if seen.len() != count {
                self.sides.clear();
                return false;
            }
        }
        self.v.resize(self.bodies.len(), V3::ZERO);
        self.w.resize(self.bodies.len(), V3::ZERO);
        true
    }

    /// Whether the slots are built (the last [`UnitBodies::build`] held).
    pub fn is_built(&self) -> bool {
        !self.sides.is_empty()
    }

    /// Reads the bodies' velocities (`push`: push-out velocities) into the
    /// slots.
    ///
    /// # Safety
    /// No other thread writes the unit's bodies meanwhile.
    pub unsafe fn gather(&mut self, bodies: &Shared<SolverBody>, push: bool) {
        for ((of_lane, v), w) in self.bodies.iter().zip(&mut self.v).zip(&mut self.w) {
            for (l, &b) in of_lane.iter().enumerate() {
                // SAFETY: the caller's promise.
                let body = unsafe { bodies.get(b as usize) };
                let (bv, bw) = if push {
                    (body.push_v, body.push_w)
                } else {
                    (body.v, body.w)
                };
                v.set_lane(l, bv);
                w.set_lane(l, bw);
            }
        }
    }

    /// Writes the dynamic slots' velocities back to the bodies of the
    /// unit's islands.
    ///
    /// # Safety
    /// As [`UnitBodies::gather`], and no other reference to the bodies lives.
    pub unsafe fn scatter(&self, bodies: &Shared<SolverBody>, push: bool) {
        for (i, of_lane) in self.bodies.iter().enumerate() {
            if !self.dynamic[i] {
                continue;
            }
            let (v, w) = (self.v[i].to_lanes(), self.w[i].to_lanes());
            for l in 0..self.islands {
                // SAFETY: the caller's promise.
                let body = unsafe { bodies.get_mut(of_lane[l] as usize) };
                if push {
                    body.push_v = v[l];
                    body.push_w = w[l];
                } else {
                    body.v = v[l];
                    body.w = w[l];
                }
            }
        }
    }

    /// Joint `k`'s pair of lane `l`, as `Pair::load` reads it from the
    /// bodies.
    pub fn pair(&self, k: usize, l: usize) -> Pair {
        let [a, b] = self.sides[k].map(|s| s as usize);
        let pick = |v: &V3| DVec3::new(v.x.as_array()[l], v.y.as_array()[l], v.z.as_array()[l]);
        Pair::new(
            [
                pick(&self.v[a]),
                pick(&self.w[a]),
                pick(&self.v[b]),
                pick(&self.w[b]),
            ],
            [self.inv_mass[a].as_array()[l], self.inv_mass[b].as_array()[l]],
        )
    }

    /// Row `row` of joint `k` in every lane: its velocity `J v`, as
    /// `JointRow::velocity` computes it.
    #[inline]
    pub fn velocity(&self, k: usize, row: &SideRow<Lane>) -> Lane {
        let [a, b] = self.sides[k].map(|s| s as usize);
        let (lin, ang_a, ang_b) = row.jacobian_lanes();
        lin.dot(self.v[a] - self.v[b]) + ang_a.dot(self.w[a]) + ang_b.dot(self.w[b])
    }

    /// Impulse `dl` (one per lane) on row `row` of joint `k`, applied to
    /// its two slots as `Pair::apply` applies it.
    #[inline]
    pub fn apply(&mut self, k: usize, row: &SideRow<Lane>, dl: Lane) {
        let [a, b] = self.sides[k].map(|s| s as usize);
        let (lin, _, _) = row.jacobian_lanes();
        let (ia, ib) = row.inertia_lanes();
        self.v[a] += lin.scale(dl * self.inv_mass[a]);
        self.w[a] += ia.scale(dl);
        self.v[b] -= lin.scale(dl * self.inv_mass[b]);
        self.w[b] += ib.scale(dl);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Lanes whose joints link their bodies alike share a slot per dynamic
    /// body (a side on the world, body 0, gets one of its own); lanes that
    /// link them otherwise are refused.
    #[test]
    fn lanes_linking_their_bodies_alike_share_slots_and_others_are_refused() {
        let body = |b: u32| (b != 0, if b == 0 { 0.0 } else { 1.0 / b as f64 });
        // Lane 0: 0 - 1 - 2 - 3 (joint 0 on the world); lane 1: 0 - 4 - 5 - 6.
        let alike = |k: u32| [[0, 1], [1, 2], [2, 3], [0, 4], [4, 5], [5, 6]][k as usize];
        let lanes = vec![vec![0, 1, 2], vec![3, 4, 5]];
        let mut unit = UnitBodies::default();
        assert!(unit.build(&lanes, alike, body));
        assert!(unit.is_built());
        // The world side, then bodies 1 (4), 2 (5) and 3 (6): four slots.
        assert_eq!(unit.sides, vec![[0, 1], [1, 2], [2, 3]]);
        assert_eq!(unit.bodies[1], [1, 4, 4, 4]);
        assert_eq!(unit.dynamic, vec![false, true, true, true]);
        assert_eq!(
            unit.inv_mass[3].to_array(),
            [1.0 / 3.0, 1.0 / 6.0, 1.0 / 6.0, 1.0 / 6.0]
        );
        // Lane 1's last joint on its first body instead (a fork, not a chain).
        let forked = |k: u32| [[0, 1], [1, 2], [2, 3], [0, 4], [4, 5], [4, 6]][k as usize];
        assert!(!unit.build(&lanes, forked, body));
        assert!(!unit.is_built());
        // Lane 1's first joint on a dynamic body where lane 0's is on the world.
        let moved = |k: u32| [[0, 1], [1, 2], [2, 3], [7, 4], [4, 5], [5, 6]][k as usize];
        assert!(!unit.build(&lanes, moved, body));
    }
}
