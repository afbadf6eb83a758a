//! [`Stage::Narrow`](crate::world::Stage::Narrow): contact generation for
//! every candidate pair within its margin (the speculative margin plus a
//! bound on the pair's motion over the step), then the points grouped into
//! patches and matched to the previous step's for warm starting.
//!
//! Two phases, so that the expensive one can run on many threads without
//! changing a bit: (1) every pair's contacts are generated on its own,
//! reading the world only; (2) the results are assembled into points and
//! patches serially, in pair order (warm starting reads the sorted cache).

use super::margins::{is_active, relative_motion_bound, velocity_change_bounds};
use super::StepFrame;
use crate::body::BodyKind;
use crate::world::patches::{add_pair, PairInfo, PatchScratch};
use crate::world::{Collider, MaterialDesc, World};
use tumble_collide::narrow::contact_shapes;
use tumble_collide::{Contact, Shape};

/// One candidate pair's narrow-phase result: its collider pairs' contacts
/// (a run of `contacts` each) and the first error met.
#[derive(Default)]
pub(super) struct PairContacts {
    /// (collider index in A, in B, end of its run in `contacts`).
    runs: Vec<(u16, u16, usize)>,
    contacts: Vec<Contact>,
    error: Option<String>,
}

impl World {
    pub(super) fn narrow_stage(&mut self, f: &mut StepFrame) {
        // Sized from the last step's contacts: no growth in a steady scene.
        f.points.reserve(self.cache.len() + self.cache.len() / 4 + 16);
        f.patches
            .reserve(self.patch_cache.len() + self.patch_cache.len() / 4 + 16);
        let shock = velocity_change_bounds(&self.bodies, &f.pairs, f.n_slots);
        let results: Vec<PairContacts> = f
            .pairs
            .iter()
            .map(|&pair| self.pair_contacts(f, &shock, pair))
            .collect();

        let mut scratch = PatchScratch::default();
        let mut warned_unsupported = false;
        let skin_mesh = 2.0 * f.settings.allowed_penetration;
        for (&(a, b), result) in f.pairs.iter().zip(&results) {
            if let Some(err) = &result.error {
                if !warned_unsupported {
                    f.report.warnings.push(format!("bodies {a} and {b}: {err}"));
                    warned_unsupported = true;
                }
            }
            if result.runs.is_empty() {
                continue;
            }
            let (ea, eb) = (self.bodies.at(a).expect("live"), self.bodies.at(b).expect("live"));
            let (pa, pb) = (ea.body.pose(), eb.body.pose());
            let ids = (
                self.bodies.id_at(a).expect("live"),
                self.bodies.id_at(b).expect("live"),
            );
            let friction =
                MaterialDesc::combine_friction(ea.body.material().friction(), eb.body.material().friction());
            let restitution = MaterialDesc::combine_restitution(
                ea.body.material().restitution(),
                eb.body.material().restitution(),
            );
            let mut start = 0;
            for &(ia, ib, end) in &result.runs {
                let contacts = &result.contacts[start..end];
                start = end;
                // Meshes rest a hair apart (see WorldSettings::allowed_penetration).
                let (ca, cb) = (&ea.colliders[ia as usize], &eb.colliders[ib as usize]);
                let skin = if is_mesh(ca) || is_mesh(cb) {
                    skin_mesh
                } else {
                    0.0
                };
                let pair = PairInfo {
                    ids,
                    key: (a, b, ia, ib),
                    pose_a: &pa,
                    pose_b: &pb,
                    friction,
                    restitution,
                    skin,
                };
                f.report.warm_started += add_pair(
                    contacts,
                    &pair,
                    &self.cache,
                    &self.patch_cache,
                    &mut scratch,
                    &mut f.points,
                    &mut f.patches,
                );
                for contact in contacts {
                    f.report.max_penetration = f.report.max_penetration.max(-contact.distance);
                }
            }
        }
        f.report.contacts = f.points.len();
    }

    /// Contacts of one candidate pair of body slots within the pair's
    /// margin; reads the world only (safe to run for many pairs at once).
    fn pair_contacts(&self, f: &StepFrame, shock: &[f64], (a, b): (u32, u32)) -> PairContacts {
        let mut out = PairContacts::default();
        let (ea, eb) = (self.bodies.at(a).expect("live"), self.bodies.at(b).expect("live"));
        if !is_active(ea) && !is_active(eb) {
            return out;
        }
        if ea.body.kind() != BodyKind::Dynamic && eb.body.kind() != BodyKind::Dynamic {
            return out;
        }
        let now = relative_motion_bound(ea, eb, f.swept[a as usize], f.swept[b as usize]);
        let motion = (now + shock[a as usize] + shock[b as usize]) * f.settings.dt;
        let margin = f.settings.contact_margin + motion;
        let (pa, pb) = (ea.body.pose(), eb.body.pose());
        for (ia, ca) in ea.colliders.iter().enumerate() {
            for (ib, cb) in eb.colliders.iter().enumerate() {
                let start = out.contacts.len();
                let (wpa, wpb) = (pa.mul_pose(&ca.local), pb.mul_pose(&cb.local));
                if let Err(err) = contact_shapes(&ca.shape, &wpa, &cb.shape, &wpb, margin, &mut out.contacts)
                {
                    out.contacts.truncate(start);
                    out.error.get_or_insert_with(|| err.to_string());
                    continue;
                }
                out.runs.push((ia as u16, ib as u16, out.contacts.len()));
            }
        }
        out
    }
}

fn is_mesh(c: &Collider) -> bool {
    matches!(c.shape, Shape::Mesh(_))
}
