//! Plain records (named tuples) defined in Python, in `tumble/_records.py`,
//! and built here: they pickle, compare and unpack like any tuple.

use pyo3::call::PyCallArgs;
use pyo3::prelude::*;

/// `tumble._records.<name>(*args)`.
pub fn record<'py, A>(py: Python<'py>, name: &str, args: A) -> PyResult<Bound<'py, PyAny>>
where
    A: PyCallArgs<'py>,
{
    py.import("tumble._records")?.getattr(name)?.call1(args)
}
