//! The standard scenes of shared/scenes.md, defined once in code and shared by
//! tests, benchmarks, the CLI and the examples. Each function returns a
//! [`Scene`]: world settings plus body descriptions in insertion order.

mod mesh_scenes;
mod primitives_scenes;

pub use mesh_scenes::{chain, tori_pass, torus_on_ground};
pub use primitives_scenes::{
    ball_drop, cradle, domino, incline, large_pyramid, pile, pyramid, pyramid_of_base, tower,
};

use crate::world::{BodyDesc, BodyId, World, WorldError, WorldSettings};

/// A scene: settings and bodies, in the order they are added.
#[derive(Debug, Clone)]
pub struct Scene {
    /// Name (as in shared/scenes.md).
    pub name: String,
    /// World settings.
    pub settings: WorldSettings,
    /// Bodies in insertion order.
    pub bodies: Vec<BodyDesc>,
    /// Suggested number of steps.
    pub steps: usize,
}

impl Scene {
    /// Builds the world; returns it with the body handles in insertion order.
    pub fn build(&self) -> Result<(World, Vec<BodyId>), WorldError> {
        let mut world = World::new(self.settings.clone())?;
        let ids = self
            .bodies
            .iter()
            .map(|b| world.add_body(b))
            .collect::<Result<Vec<_>, _>>()?;
        Ok((world, ids))
    }
}
