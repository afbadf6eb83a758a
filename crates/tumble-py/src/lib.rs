//! # tumble-py
//!
//! Python bindings of tumble (PyO3 + numpy), built by maturin into the native
//! module `tumble._tumble`; the package `tumble` (crates/tumble-py/python)
//! re-exports it with the records of `_records.py` and the stubs `_tumble.pyi`.
//! The bindings only translate (shared/DESIGN.md): every check and every
//! error message is the Rust API's.
//!
//! - [`errors`]: the exception tree, the Rust-error mapping, panic guards.
//! - [`convert`]: vectors, quaternions and (N, 3) arrays in and out.
//! - [`shapes`], [`trimesh`]: shape classes and mesh input.
//! - [`world`], [`body`]: the world and body handles.
//! - [`report`]: step reports, contact events and the contacts array.
//! - [`record`]: recording and glTF / CSV export.
//! - [`mass`]: the `mass_properties` function.
//! - [`query`], [`pose_arg`], [`query_out`]: `collide`, `distance`,
//!   `within_tolerance` over `tumble_collide::query`, their pose arguments
//!   and their results.
//! - [`scene`]: `load_scene` and `SceneError`.

#![warn(missing_docs)]
// Doc comments here are the Python docstrings (pyo3 passes them to __doc__):
// their indented examples are Python, not Rust code blocks.
#![allow(rustdoc::invalid_rust_codeblocks)]

pub mod body;
pub mod convert;
pub mod errors;
pub mod joint;
pub mod mass;
pub mod pose_arg;
pub mod query;
pub mod query_out;
pub mod record;
pub mod records;
pub mod report;
pub mod rollout;
pub mod scene;
pub mod settings;
pub mod shapes;
pub mod sweep;
pub mod trimesh;
pub mod world;

use pyo3::prelude::*;

/// Panics inside the guard every entry point uses; for the test that checks
/// that a panic arrives as `tumble.InternalError` and the process survives.
#[pyfunction]
fn _panic_for_tests(message: String) -> PyResult<()> {
    errors::guard(|| panic!("{message}"))
}

/// The native module `tumble._tumble`.
#[pymodule]
fn _tumble(m: &Bound<'_, PyModule>) -> PyResult<()> {
    // One line per class and function: pyo3 registers each by its own type,
    // and the list reads as the module's contents.
    errors::register(m)?;
    m.add_class::<world::World>()?;
    m.add_class::<body::Body>()?;
    m.add_class::<joint::Joint>()?;
    m.add_class::<joint::Robot>()?;
    m.add_class::<report::PyStepReport>()?;
    m.add_class::<shapes::PyBox>()?;
    m.add_class::<shapes::PySphere>()?;
    m.add_class::<shapes::PyCapsule>()?;
    m.add_class::<shapes::PyConvexHull>()?;
    m.add_class::<shapes::PyHalfSpace>()?;
    m.add_class::<shapes::Placed>()?;
    m.add_class::<trimesh::TriMesh>()?;
    m.add_class::<sweep::SweepPlan>()?;
    m.add_function(wrap_pyfunction!(mass::mass_properties, m)?)?;
    m.add_function(wrap_pyfunction!(query::collide, m)?)?;
    m.add_function(wrap_pyfunction!(query::distance, m)?)?;
    m.add_function(wrap_pyfunction!(query::within_tolerance, m)?)?;
    m.add_function(wrap_pyfunction!(scene::load_scene, m)?)?;
    m.add_function(wrap_pyfunction!(joint::load_urdf, m)?)?;
    m.add_function(wrap_pyfunction!(rollout::_rollout, m)?)?;
    m.add_function(wrap_pyfunction!(_panic_for_tests, m)?)?;
    m.add("CONTACT_DTYPE_SPEC", report::CONTACT_FIELDS)?;
    m.add("QUERY_CONTACT_DTYPE_SPEC", query_out::QUERY_CONTACT_FIELDS)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
