//! What a `step(n)` call leaves for Python: the `StepReport` of its last
//! step, the contact events and warnings of all its steps (so `step(100)`
//! loses none), and the contact points as a numpy structured array.

use crate::convert::matrix_out;
use crate::world::World;
use pyo3::exceptions::PyRuntimeWarning;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use tumble::world::{BodyId, ContactEvent, SolveStage, Stage, StepReport};
use tumble_collide::ContactKind;

/// At most this many distinct warnings are kept per `step(n)` call.
const MAX_WARNINGS: usize = 100;

/// The accumulated outcome of one `step(n)` call.
#[derive(Debug, Default)]
pub struct StepSummary {
    /// Report of the last step (its `events` moved into `events`).
    pub last: StepReport,
    /// Steps taken in the call.
    pub steps: u64,
    /// (begin?, body_a, body_b, time after the step).
    pub events: Vec<(bool, BodyId, BodyId, f64)>,
    /// Distinct warnings of all steps.
    pub warnings: Vec<String>,
    /// Bodies stopped because their state became non-finite.
    pub quarantined: Vec<BodyId>,
}

impl StepSummary {
    /// Forgets the previous call.
    pub fn clear(&mut self) {
        *self = StepSummary::default();
    }

    /// Adds the report of one step that ended at `time`.
    pub fn absorb(&mut self, mut r: StepReport, time: f64) {
        self.steps += 1;
        for e in r.events.drain(..) {
            self.events.push(match e {
                ContactEvent::Begin(a, b) => (true, a, b, time),
                ContactEvent::End(a, b) => (false, a, b, time),
            });
        }
        for w in r.warnings.drain(..) {
            if self.warnings.len() < MAX_WARNINGS && !self.warnings.contains(&w) {
                self.warnings.push(w);
            }
        }
        for q in r.quarantined.drain(..) {
            if !self.quarantined.contains(&q.body) {
                self.quarantined.push(q.body);
            }
        }
        self.last = r;
    }
}

/// Issues the call's warnings and quarantines as Python RuntimeWarnings.
pub fn warn_summary(py: Python<'_>, s: &StepSummary) -> PyResult<()> {
    let category = py.get_type::<PyRuntimeWarning>();
    for w in &s.warnings {
        let msg = std::ffi::CString::new(format!("tumble step: {w}")).unwrap_or_default();
        PyErr::warn(py, &category, &msg, 1)?;
    }
    for id in &s.quarantined {
        let msg = std::ffi::CString::new(format!(
            "tumble step: body {id:?} got a non-finite or runaway state; it was restored and stopped"
        ))
        .unwrap_or_default();
        PyErr::warn(py, &category, &msg, 1)?;
    }
    Ok(())
}

/// What the last `step(n)` did: counters of its last step, and the warnings
/// and quarantined bodies of all its steps.
#[pyclass(module = "tumble", name = "StepReport", frozen)]
pub struct PyStepReport {
    /// Steps taken by the last step(n) call.
    #[pyo3(get)]
    steps: u64,
    /// Bodies simulated (awake dynamic or moving kinematic) in the last step.
    #[pyo3(get)]
    awake_bodies: usize,
    /// Bodies asleep after the last step.
    #[pyo3(get)]
    sleeping_bodies: usize,
    /// Overlapping bounding-box pairs from the broad phase.
    #[pyo3(get)]
    broad_pairs: usize,
    /// Contact points handed to the solver.
    #[pyo3(get)]
    contacts: usize,
    /// Contact points warm started from the previous step.
    #[pyo3(get)]
    warm_started: usize,
    /// Mesh pairs that reused a remembered walk of their trees (resting
    /// pairs: same contacts, less work).
    #[pyo3(get)]
    recalled_mesh_pairs: usize,
    /// Mesh collider pairs that had barely moved since their last contact
    /// search and re-evaluated the points they kept (`resting_motion`).
    #[pyo3(get)]
    revalidated_mesh_pairs: usize,
    /// Islands of awake bodies.
    #[pyo3(get)]
    islands: usize,
    /// Solver sub-steps run.
    #[pyo3(get)]
    substeps: u32,
    /// Solver iterations per sub-step.
    #[pyo3(get)]
    iterations: u32,
    /// Deepest penetration at the start of the last step (m).
    #[pyo3(get)]
    max_penetration: f64,
    /// Fast bodies put back at their first time of impact by continuous
    /// collision in the last step.
    #[pyo3(get)]
    continuous: usize,
    /// Warnings of all steps of the call (also issued as RuntimeWarning).
    #[pyo3(get)]
    warnings: Vec<String>,
    /// Bodies stopped because their state became non-finite.
    #[pyo3(get)]
    quarantined: Py<PyList>,
    /// Threads the last step ran on.
    #[pyo3(get)]
    threads: usize,
    /// Colours of the last step's constraint graph (batches solved in parallel).
    #[pyo3(get)]
    colors: usize,
    /// Joints the solver handled in the last step (those with a moving body).
    #[pyo3(get)]
    joints: usize,
    stage_times: Vec<(&'static str, f64)>,
    solve_times: Vec<(&'static str, f64)>,
}

impl PyStepReport {
    /// From the summary; `quarantined` are the handles of its bodies.
    pub fn new(s: &StepSummary, quarantined: Vec<crate::body::Body>) -> PyStepReport {
        let r = &s.last;
        let quarantined = Python::attach(|py| {
            PyList::new(py, quarantined)
                .map(|l| l.unbind())
                .unwrap_or_else(|_| PyList::empty(py).unbind())
        });
        PyStepReport {
            steps: s.steps,
            awake_bodies: r.awake_bodies,
            sleeping_bodies: r.sleeping_bodies,
            broad_pairs: r.broad_pairs,
            contacts: r.contacts,
            warm_started: r.warm_started,
            recalled_mesh_pairs: r.recalled_mesh_pairs,
            revalidated_mesh_pairs: r.revalidated_mesh_pairs,
            islands: r.islands,
            substeps: r.substeps,
            iterations: r.iterations,
            max_penetration: r.max_penetration,
            continuous: r.continuous,
            warnings: s.warnings.clone(),
            quarantined,
            stage_times: Stage::ALL
                .iter()
                .map(|&st| (st.name(), r.time(st).as_secs_f64()))
                .collect(),
            solve_times: SolveStage::ALL
                .iter()
                .map(|&part| (part.name(), r.solve_time(part).as_secs_f64()))
                .collect(),
            threads: r.threads,
            colors: r.colors,
            joints: r.joints,
        }
    }
}

/// A Python dict of named times (s), in the list's order.
fn timing_dict<'py>(py: Python<'py>, times: &[(&'static str, f64)]) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (k, v) in times {
        d.set_item(k, v)?;
    }
    Ok(d)
}

#[pymethods]
impl PyStepReport {
    /// Wall time of each stage of the last step (s), in pipeline order:
    /// forces, broad, narrow, islands, solve, integrate, continuous, events.
    #[getter]
    fn stage_times<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        timing_dict(py, &self.stage_times)
    }

    /// Wall time of each part of the last step's solve stage (s), in order:
    /// prepare, restitution, integrate_velocities, warm_start, iterate,
    /// relax, integrate_positions, store_impulses (the sub-step parts summed
    /// over the sub-steps). They add up to `stage_times["solve"]`, less the
    /// clock's own cost.
    #[getter]
    fn solve_times<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        timing_dict(py, &self.solve_times)
    }

    /// Wall time of the last step (s).
    #[getter]
    fn total_time(&self) -> f64 {
        self.stage_times.iter().map(|(_, t)| t).sum()
    }

    fn __repr__(&self) -> String {
        format!(
            "tumble.StepReport(steps={}, awake_bodies={}, sleeping_bodies={}, contacts={}, \
             islands={}, max_penetration={:.3e}, warnings={}, total_time={:.3e})",
            self.steps,
            self.awake_bodies,
            self.sleeping_bodies,
            self.contacts,
            self.islands,
            self.max_penetration,
            self.warnings.len(),
            self.total_time()
        )
    }
}

/// The Python name of a contact kind (`World.contacts()`, `tumble.collide`).
pub(crate) fn contact_kind_name(k: ContactKind) -> &'static str {
    match k {
        ContactKind::VertexFace => "vertex_face",
        ContactKind::FaceVertex => "face_vertex",
        ContactKind::EdgeEdge => "edge_edge",
        ContactKind::VertexEdge => "vertex_edge",
        ContactKind::EdgeVertex => "edge_vertex",
        ContactKind::VertexVertex => "vertex_vertex",
        ContactKind::FaceFace => "face_face",
        ContactKind::Penetrating => "penetrating",
        ContactKind::Smooth => "smooth",
    }
}

/// The numpy dtype of `World.contacts()`.
pub const CONTACT_FIELDS: &str = "[('body_a', '<i8'), ('body_b', '<i8'), ('point', '<f8', (3,)), \
    ('normal', '<f8', (3,)), ('distance', '<f8'), ('depth', '<f8'), ('normal_impulse', '<f8'), \
    ('tangent_impulse', '<f8', (3,)), ('kind', '<U16')]";

/// The contacts of the last step as a structured array (see `World.contacts`).
pub fn contacts_array<'py>(py: Python<'py>, w: &World) -> PyResult<Bound<'py, PyAny>> {
    let contacts = w.inner.contacts();
    let n = contacts.len();
    let mut body_a = Vec::with_capacity(n);
    let mut body_b = Vec::with_capacity(n);
    let mut point = Vec::with_capacity(3 * n);
    let mut normal = Vec::with_capacity(3 * n);
    let mut distance = Vec::with_capacity(n);
    let mut impulse = Vec::with_capacity(n);
    let mut tangent = Vec::with_capacity(3 * n);
    let mut kind = Vec::with_capacity(n);
    let row = |id| w.row(id).map_or(-1, |r| r as i64);
    for c in contacts {
        body_a.push(row(c.body_a));
        body_b.push(row(c.body_b));
        point.extend_from_slice(&c.contact.point.to_array());
        normal.extend_from_slice(&c.contact.normal.to_array());
        distance.push(c.contact.distance);
        impulse.push(c.normal_impulse);
        tangent.extend_from_slice(&c.tangent_impulse.to_array());
        kind.push(contact_kind_name(c.contact.kind));
    }
    let np = py.import("numpy")?;
    let dtype = np.call_method1(
        "dtype",
        (py.eval(&std::ffi::CString::new(CONTACT_FIELDS)?, None, None)?,),
    )?;
    let out = np.call_method1("zeros", (n, dtype))?;
    let neg: Vec<f64> = distance.iter().map(|d| -d).collect();
    out.set_item("body_a", numpy::PyArray1::from_vec(py, body_a))?;
    out.set_item("body_b", numpy::PyArray1::from_vec(py, body_b))?;
    out.set_item("point", matrix_out(py, point, 3))?;
    out.set_item("normal", matrix_out(py, normal, 3))?;
    out.set_item("distance", numpy::PyArray1::from_vec(py, distance))?;
    out.set_item("depth", numpy::PyArray1::from_vec(py, neg))?;
    out.set_item("normal_impulse", numpy::PyArray1::from_vec(py, impulse))?;
    out.set_item("tangent_impulse", matrix_out(py, tangent, 3))?;
    out.set_item("kind", PyList::new(py, kind)?)?;
    Ok(out)
}
