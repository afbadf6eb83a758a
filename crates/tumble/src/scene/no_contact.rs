//! The `[[no_contact]]` pairs of a scene file: two bodies, found by name,
//! that never touch each other (`World::set_contacts_between`).

use super::error::{FieldError, FieldPath};
use super::resolve::body_named;
use super::schema::NoContactSpec;
use crate::world::BodyDesc;

/// Each `[[no_contact]]` pair of the file as indices into `bodies`, the
/// lower first.
pub(super) fn resolve_no_contact(
    specs: &[NoContactSpec],
    bodies: &[BodyDesc],
) -> Result<Vec<(usize, usize)>, FieldError> {
    specs
        .iter()
        .enumerate()
        .map(|(k, spec)| {
            let path = FieldPath::root().key("no_contact").index(k).key("bodies");
            let a = body_named(bodies, &path.index(0), &spec.bodies[0])?;
            let b = body_named(bodies, &path.index(1), &spec.bodies[1])?;
            if a == b {
                return Err(FieldError::new(
                    &path.index(1),
                    format!("`{}` twice: a body never touches itself", spec.bodies[1]),
                ));
            }
            Ok((a.min(b), a.max(b)))
        })
        .collect()
}
