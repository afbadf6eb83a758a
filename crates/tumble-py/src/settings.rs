//! World settings as Python keywords: one keyword per `WorldSettings` field,
//! same name, same unit, same default (the Rust `Default`); enums as
//! strings ("semi_implicit", "pgs", ...). Unknown keywords are errors.

use crate::convert::{describe, vec3, vec_out};
use crate::errors::invalid;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};
use tumble::world::{SolverKind, WorldSettings};
use tumble::Integrator;

/// Every keyword accepted, in the order of `WorldSettings`.
pub const NAMES: [&str; 21] = [
    "gravity",
    "dt",
    "substeps",
    "integrator",
    "solver",
    "iterations",
    "push_out_iterations",
    "contact_margin",
    "mesh_contact_margin",
    "resting_motion",
    "allowed_penetration",
    "push_out_fraction",
    "max_push_out_speed",
    "restitution_threshold",
    "continuous",
    "sleeping",
    "sleep_linear_speed",
    "sleep_angular_speed",
    "time_to_sleep",
    "threads",
    "adaptive_threads",
];

/// Integrator names, as in shared/DESIGN.md.
pub fn integrator_name(i: Integrator) -> &'static str {
    match i {
        Integrator::Euler => "euler",
        Integrator::Midpoint => "midpoint",
        Integrator::Rk4 => "rk4",
        Integrator::SemiImplicitEuler => "semi_implicit",
        Integrator::SemiImplicitSplitting => "semi_implicit_splitting",
    }
}

fn parse_integrator(s: &str) -> PyResult<Integrator> {
    Integrator::ALL
        .into_iter()
        .find(|&i| integrator_name(i) == s)
        .ok_or_else(|| {
            invalid(format!(
                "integrator: expected one of \"euler\", \"midpoint\", \"rk4\", \"semi_implicit\", \
                 \"semi_implicit_splitting\", got {s:?}"
            ))
        })
}

fn solver_name(s: SolverKind) -> &'static str {
    match s {
        SolverKind::Pgs => "pgs",
        SolverKind::Lemke => "lemke",
    }
}

fn parse_solver(s: &str) -> PyResult<SolverKind> {
    match s {
        "pgs" => Ok(SolverKind::Pgs),
        "lemke" => Ok(SolverKind::Lemke),
        _ => Err(invalid(format!(
            "solver: expected \"pgs\" or \"lemke\", got {s:?}"
        ))),
    }
}

fn float(v: &Bound<'_, PyAny>, name: &str) -> PyResult<f64> {
    if v.is_instance_of::<PyString>() {
        return Err(invalid(format!("{name}: expected a number, got {}", describe(v))));
    }
    v.extract()
        .map_err(|_| invalid(format!("{name}: expected a number, got {}", describe(v))))
}

fn count(v: &Bound<'_, PyAny>, name: &str) -> PyResult<u32> {
    v.extract().map_err(|_| {
        invalid(format!(
            "{name}: expected a non-negative integer, got {}",
            describe(v)
        ))
    })
}

fn text(v: &Bound<'_, PyAny>, name: &str) -> PyResult<String> {
    v.extract()
        .map_err(|_| invalid(format!("{name}: expected a string, got {}", describe(v))))
}

/// Applies keyword settings on top of `s`. Validation of ranges is the
/// world's (`World::new` / `set_settings`), so the messages are the Rust ones.
pub fn apply(s: &mut WorldSettings, kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<()> {
    let Some(kwargs) = kwargs else { return Ok(()) };
    for (k, v) in kwargs.iter() {
        let key: String = k.extract()?;
        let name = key.as_str();
        if v.is_none() {
            continue; // None means "keep the default / current value".
        }
        match name {
            "gravity" => s.gravity = vec3(&v, name)?,
            "dt" => s.dt = float(&v, name)?,
            "substeps" => s.substeps = count(&v, name)?,
            "integrator" => s.integrator = parse_integrator(&text(&v, name)?)?,
            "solver" => s.solver = parse_solver(&text(&v, name)?)?,
            "iterations" => s.iterations = count(&v, name)?,
            "push_out_iterations" => s.push_out_iterations = count(&v, name)?,
            "contact_margin" => s.contact_margin = float(&v, name)?,
            "mesh_contact_margin" => s.mesh_contact_margin = float(&v, name)?,
            "resting_motion" => s.resting_motion = float(&v, name)?,
            "allowed_penetration" => s.allowed_penetration = float(&v, name)?,
            "push_out_fraction" => s.push_out_fraction = float(&v, name)?,
            "max_push_out_speed" => s.max_push_out_speed = float(&v, name)?,
            "restitution_threshold" => s.restitution_threshold = float(&v, name)?,
            "continuous" => {
                s.continuous = v.extract().map_err(|_| {
                    invalid(format!(
                        "continuous: expected True or False, got {}",
                        describe(&v)
                    ))
                })?
            }
            "sleeping" => {
                s.sleeping = v
                    .extract()
                    .map_err(|_| invalid(format!("sleeping: expected True or False, got {}", describe(&v))))?
            }
            "sleep_linear_speed" => s.sleep_linear_speed = float(&v, name)?,
            "sleep_angular_speed" => s.sleep_angular_speed = float(&v, name)?,
            "time_to_sleep" => s.time_to_sleep = float(&v, name)?,
            "threads" => s.threads = count(&v, name)?,
            "adaptive_threads" => {
                s.adaptive_threads = v.extract().map_err(|_| {
                    invalid(format!(
                        "adaptive_threads: expected True or False, got {}",
                        describe(&v)
                    ))
                })?
            }
            other => {
                return Err(invalid(format!(
                    "unknown world setting {other:?}; the settings are: {}",
                    NAMES.join(", ")
                )))
            }
        }
    }
    Ok(())
}

/// The settings as a dict of keyword -> value (vectors as numpy arrays).
pub fn to_dict<'py>(py: Python<'py>, s: &WorldSettings) -> PyResult<Bound<'py, PyDict>> {
    // One line per setting, the Python name beside the Rust field: alike by
    // design (the names and units are the API; `apply` reads the same keys).
    let d = PyDict::new(py);
    d.set_item("gravity", vec_out(py, s.gravity))?;
    d.set_item("dt", s.dt)?;
    d.set_item("substeps", s.substeps)?;
    d.set_item("integrator", integrator_name(s.integrator))?;
    d.set_item("solver", solver_name(s.solver))?;
    d.set_item("iterations", s.iterations)?;
    d.set_item("push_out_iterations", s.push_out_iterations)?;
    d.set_item("contact_margin", s.contact_margin)?;
    d.set_item("mesh_contact_margin", s.mesh_contact_margin)?;
    d.set_item("resting_motion", s.resting_motion)?;
    d.set_item("allowed_penetration", s.allowed_penetration)?;
    d.set_item("push_out_fraction", s.push_out_fraction)?;
    d.set_item("max_push_out_speed", s.max_push_out_speed)?;
    d.set_item("restitution_threshold", s.restitution_threshold)?;
    d.set_item("continuous", s.continuous)?;
    d.set_item("sleeping", s.sleeping)?;
    d.set_item("sleep_linear_speed", s.sleep_linear_speed)?;
    d.set_item("sleep_angular_speed", s.sleep_angular_speed)?;
    d.set_item("time_to_sleep", s.time_to_sleep)?;
    d.set_item("threads", s.threads)?;
    d.set_item("adaptive_threads", s.adaptive_threads)?;
    Ok(d)
}
