//! Keeps the user manual (`docs/manual`) from rotting.
//!
//! - Every chapter is included below as a doc comment under `cfg(doctest)`,
//!   so `cargo test -p tumble-manual --doc` compiles and runs each of its
//!   ```` ```rust ```` blocks (the Python, TOML, JSON and shell blocks are run by
//!   `scripts/manual_blocks.py`); `tests/chapters.rs` checks that no chapter
//!   is missing here or from `SUMMARY.md`.
//! - [`scene_reference`] writes the scene file reference chapter from the
//!   JSON Schema of scene files; `tests/scene_reference.rs` checks the
//!   committed chapter against it.

#![warn(missing_docs)]

pub mod scene_reference;

/// Makes the repository root the working directory, so that the manual's
/// examples name files (`examples/scenes/first.toml`) as a reader at the root
/// would. Doc-tests otherwise run in this crate's directory.
pub fn at_repo_root() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    // The crate lives two levels below the root: a missing root is a broken checkout.
    std::env::set_current_dir(root).expect("the repository root exists");
}

/// The chapters, one module each: rustdoc runs their Rust blocks.
#[cfg(doctest)]
mod chapters {
    #[doc = include_str!("../../../docs/manual/src/introduction.md")]
    mod introduction {}
    #[doc = include_str!("../../../docs/manual/src/installation.md")]
    mod installation {}
    #[doc = include_str!("../../../docs/manual/src/first-simulation.md")]
    mod first_simulation {}
    #[doc = include_str!("../../../docs/manual/src/concepts/bodies.md")]
    mod concepts_bodies {}
    #[doc = include_str!("../../../docs/manual/src/concepts/materials.md")]
    mod concepts_materials {}
    #[doc = include_str!("../../../docs/manual/src/concepts/step.md")]
    mod concepts_step {}
    #[doc = include_str!("../../../docs/manual/src/concepts/solvers.md")]
    mod concepts_solvers {}
    #[doc = include_str!("../../../docs/manual/src/concepts/joints.md")]
    mod concepts_joints {}
    #[doc = include_str!("../../../docs/manual/src/concepts/integrators.md")]
    mod concepts_integrators {}
    #[doc = include_str!("../../../docs/manual/src/collision.md")]
    mod collision {}
    #[doc = include_str!("../../../docs/manual/src/scene-files.md")]
    mod scene_files {}
    #[doc = include_str!("../../../docs/manual/src/performance.md")]
    mod performance {}
    #[doc = include_str!("../../../docs/manual/src/troubleshooting.md")]
    mod troubleshooting {}
    #[doc = include_str!("../../../docs/manual/src/demos.md")]
    mod demos {}
    #[doc = include_str!("../../../docs/manual/src/reference/api.md")]
    mod reference_api {}
}
