//! Which bodies may touch: the one home of the three filters the broad
//! phase applies to its candidate pairs. A pair never touches when its two
//! bodies share a nonzero non-colliding group (`BodyDesc::
//! non_colliding_group`), when a joint links them without
//! `collide_connected`, or when [`World::set_contacts_between`] switched
//! the pair off (Bullet's `setCollisionFilterPair`, MuJoCo's `<exclude>`):
//! the way to keep apart two links of a robot that overlap where no joint
//! links them, which their joints would otherwise fight.

use super::{BodyId, World, WorldError};

impl World {
    /// Allows (`true`) or forbids (`false`) contacts between bodies `a` and
    /// `b`, from the next step on. Forbidding them ends their contacts with
    /// that step; allowing them again undoes only this call's exclusion (a
    /// shared non-colliding group or a joint still keeps them apart: see
    /// [`World::contacts_allowed`]). Both bodies wake if it changes
    /// anything.
    ///
    /// ```
    /// use tumble::collide::{Cuboid, DVec3};
    /// use tumble::world::{BodyDesc, World, WorldSettings};
    ///
    /// let mut world = World::new(WorldSettings { gravity: DVec3::ZERO, ..WorldSettings::default() })?;
    /// let cube = BodyDesc::dynamic(Cuboid::new(DVec3::splat(0.5))?);
    /// let a = world.add_body(&cube)?;
    /// let b = world.add_body(&cube.clone().at(DVec3::new(0.5, 0.0, 0.0)))?;
    /// world.set_contacts_between(a, b, false)?;
    /// world.step();
    /// assert!(world.contacts().is_empty() && !world.contacts_allowed(a, b)?);
    /// // Overlapping by half, they do not push each other apart.
    /// assert_eq!(world.linear_velocity(a)?, DVec3::ZERO);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn set_contacts_between(&mut self, a: BodyId, b: BodyId, allowed: bool) -> Result<(), WorldError> {
        let pair = self.body_pair(a, b)?;
        match (allowed, self.contact_exclusions.binary_search(&pair)) {
            (true, Ok(i)) => {
                self.contact_exclusions.remove(i);
            }
            (false, Err(i)) => self.contact_exclusions.insert(i, pair),
            // Nothing changes: the bodies sleep on.
            _ => return Ok(()),
        }
        for id in [a, b] {
            // (Both are live: `body_pair` said so.)
            let e = self.entry_mut(id).expect("live body");
            e.sleeping = false;
            e.rest_time = 0.0;
        }
        Ok(())
    }

    /// Whether bodies `a` and `b` may touch: not in one nonzero
    /// non-colliding group, not linked by a joint without
    /// `collide_connected`, and not kept apart by
    /// [`World::set_contacts_between`].
    pub fn contacts_allowed(&self, a: BodyId, b: BodyId) -> Result<bool, WorldError> {
        let (a, b) = self.body_pair(a, b)?;
        // The broad phase's own filter, on this one pair: the rules have
        // one home.
        let mut pair = vec![(a.index, b.index)];
        self.filter_contact_pairs(&mut pair);
        Ok(!pair.is_empty())
    }

    /// The body pairs [`World::set_contacts_between`] keeps apart, each
    /// with the lower slot first, in slot order.
    pub fn excluded_contact_pairs(&self) -> &[(BodyId, BodyId)] {
        &self.contact_exclusions
    }

    /// Drops the candidate pairs (body slots, sorted, `a < b`) that may
    /// not touch (module docs).
    pub(crate) fn filter_contact_pairs(&self, pairs: &mut Vec<(u32, u32)>) {
        let mut apart = self.jointed_pairs_without_contact();
        if !self.contact_exclusions.is_empty() {
            apart.extend(self.contact_exclusions.iter().map(|(a, b)| (a.index, b.index)));
            apart.sort_unstable();
        }
        if !apart.is_empty() {
            // Both lists sorted: one walk along `apart` beside the pairs (a
            // binary search per pair cost a ragdoll pile's 3,200 pairs about
            // twelve comparisons each against its 1,000 joints).
            let mut k = 0;
            pairs.retain(|p| {
                while apart.get(k).is_some_and(|q| q < p) {
                    k += 1;
                }
                apart.get(k) != Some(p)
            });
        }
        let group = |slot: u32| self.bodies.at(slot).map_or(0, |e| e.non_colliding_group);
        if (0..self.bodies.slot_count() as u32).any(|i| group(i) != 0) {
            pairs.retain(|&(a, b)| group(a) == 0 || group(a) != group(b));
        }
    }

    /// Body slot pairs (sorted, `a < b`) whose contacts a joint switches off.
    fn jointed_pairs_without_contact(&self) -> Vec<(u32, u32)> {
        let mut pairs: Vec<(u32, u32)> = self
            .joints
            .iter()
            .filter(|(_, j)| !j.desc.collide_connected)
            .filter_map(|(_, j)| {
                let (a, b) = j.slots();
                b.map(|b| (a.min(b), a.max(b)))
            })
            .collect();
        pairs.sort_unstable();
        pairs.dedup();
        pairs
    }

    /// `a` and `b` as a pair of live, distinct bodies, the lower slot first.
    fn body_pair(&self, a: BodyId, b: BodyId) -> Result<(BodyId, BodyId), WorldError> {
        self.entry(a)?;
        self.entry(b)?;
        if a == b {
            return Err(WorldError::BadValue {
                field: "body_b",
                message: format!("is body_a ({a:?}): a body never touches itself"),
            });
        }
        Ok(if a.index < b.index { (a, b) } else { (b, a) })
    }
}
