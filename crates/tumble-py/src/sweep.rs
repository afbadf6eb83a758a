//! `tumble.sweep`'s engine: a `_SweepPlan` wraps `tumble::sweep::Sweep`
//! (the scene, parameters, length and metrics, checked) with the rows run
//! so far and the journal of finished runs. The Python wrapper
//! (`tumble/_sweep.py`) decides where runs go (here on every core, or Ray
//! tasks that build the same plan from the scene's text) and turns the
//! table into a pyarrow Table; the plan is the one home of the rows, the
//! journal and the table layout, shared with `tumble sweep`.

use crate::errors::{guard, invalid, OrRaise};
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;
use std::time::Duration;
use tumble::export::table::Column;
use tumble::scene::{Format, SceneDocument};
use tumble::sweep::{Journal, RunLength, RunRow, RunStatus, Sweep, SweepError};

/// How often a running sweep looks at Python's signal handlers.
const SIGNAL_PERIOD: Duration = Duration::from_millis(50);

fn sweep_error(e: SweepError) -> PyErr {
    match e {
        SweepError::Scene(s) => crate::errors::ToPyErr::to_py(&s),
        other => invalid(other.to_string()),
    }
}

/// A row as a plain tuple (index, status, error, steps, metrics,
/// trajectory), for Ray.
type RowTuple = (usize, String, Option<String>, u64, Vec<f64>, Option<String>);

fn to_tuple(r: &RunRow) -> RowTuple {
    let (status, error) = match &r.status {
        RunStatus::Ok => ("ok", None),
        RunStatus::Failed(m) => ("failed", Some(m.clone())),
        RunStatus::Cancelled => ("cancelled", None),
    };
    (
        r.index,
        status.to_string(),
        error,
        r.steps,
        r.metrics.clone(),
        r.trajectory.clone(),
    )
}

fn from_tuple(t: RowTuple) -> PyResult<RunRow> {
    let status = match (t.1.as_str(), t.2) {
        ("ok", _) => RunStatus::Ok,
        ("failed", Some(m)) => RunStatus::Failed(m),
        ("cancelled", _) => RunStatus::Cancelled,
        (s, _) => return Err(invalid(format!("rows: unknown status {s:?}"))),
    };
    Ok(RunRow {
        index: t.0,
        status,
        steps: t.3,
        metrics: t.4,
        trajectory: t.5,
    })
}

/// A checked sweep and its rows (internal: use `tumble.sweep`).
#[pyclass(module = "tumble", name = "_SweepPlan")]
pub struct SweepPlan {
    sweep: Sweep,
    rows: Vec<RunRow>,
    journal: Option<Journal>,
}

#[pymethods]
impl SweepPlan {
    /// `params`: (path, JSON list of values) pairs; `text`: the scene
    /// file's text if it is to be read from there rather than from `scene`
    /// (Ray workers get the text).
    #[new]
    #[pyo3(signature = (scene, params, steps=None, duration=None, metrics=Vec::new(), text=None, trajectories=None))]
    #[allow(clippy::too_many_arguments)] // the Python signature
    fn new(
        py: Python<'_>,
        scene: PathBuf,
        params: Vec<(String, String)>,
        steps: Option<u64>,
        duration: Option<f64>,
        metrics: Vec<String>,
        text: Option<String>,
        trajectories: Option<PathBuf>,
    ) -> PyResult<SweepPlan> {
        guard(|| {
            let params = params
                .into_iter()
                .map(|(path, values)| {
                    let v: Vec<serde_json::Value> = serde_json::from_str(&values)
                        .map_err(|e| invalid(format!("params[{path:?}]: values must be a JSON list: {e}")))?;
                    Ok((path, v))
                })
                .collect::<PyResult<Vec<_>>>()?;
            let length = match (steps, duration) {
                (Some(n), _) => RunLength::Steps(n),
                (None, Some(t)) => RunLength::Duration(t),
                (None, None) => RunLength::Scene,
            };
            let doc = py
                .detach(|| match &text {
                    None => SceneDocument::load(&scene),
                    Some(t) => {
                        let format = Format::from_path(&scene).unwrap_or(Format::Toml);
                        SceneDocument::parse(t, format, &scene)
                    }
                })
                .or_raise()?;
            let mut sweep = Sweep::new(doc, params, length, &metrics).map_err(sweep_error)?;
            if let Some(dir) = trajectories {
                sweep = sweep.with_trajectories(dir).map_err(sweep_error)?;
            }
            Ok(SweepPlan {
                sweep,
                rows: Vec::new(),
                journal: None,
            })
        })
    }

    fn __len__(&self) -> usize {
        self.sweep.len()
    }

    /// Opens the journal of finished runs at `path` (with `resume`, keeps
    /// its rows) and returns the indices of the runs already finished.
    fn open_journal(&mut self, path: PathBuf, resume: bool) -> PyResult<Vec<usize>> {
        let (journal, rows) = self.sweep.open_journal(&path, resume).map_err(sweep_error)?;
        self.journal = Some(journal);
        let done = rows.iter().map(|r| r.index).collect();
        self.rows.extend(rows);
        Ok(done)
    }

    /// Runs the runs of `indices` on up to `threads` threads with the GIL
    /// released; keeps their rows (and journals the finished ones). Ctrl-C
    /// cancels the running runs and raises KeyboardInterrupt (the finished
    /// rows are kept). Returns the rows as tuples.
    #[pyo3(signature = (indices, threads=0))]
    fn run(&mut self, py: Python<'_>, indices: Vec<usize>, threads: u32) -> PyResult<Vec<RowTuple>> {
        let cancel = AtomicBool::new(false);
        let SweepPlan { sweep, journal, .. } = self;
        let journal = Mutex::new(journal.as_mut());
        let journal_error: Mutex<Option<String>> = Mutex::new(None);
        let mut interrupted: Option<PyErr> = None;
        let rows = std::thread::scope(|s| {
            let (sender, receiver) = std::sync::mpsc::channel();
            // A Receiver is not Sync; the lock lets the detached wait borrow it.
            let receiver = Mutex::new(receiver);
            let (sweep, indices, cancel, journal, journal_error) =
                (&*sweep, &indices, &cancel, &journal, &journal_error);
            s.spawn(move || {
                let rows = sweep.run(indices, threads, cancel, &|row| {
                    let mut j = journal.lock().unwrap_or_else(|e| e.into_inner());
                    if let Some(j) = j.as_mut() {
                        if let Err(e) = j.append(std::slice::from_ref(row)) {
                            *journal_error.lock().unwrap_or_else(|e| e.into_inner()) = Some(e.to_string());
                        }
                    }
                });
                let _ = sender.send(rows);
            });
            loop {
                let waited = py.detach(|| {
                    receiver
                        .lock()
                        .unwrap_or_else(|e| e.into_inner())
                        .recv_timeout(SIGNAL_PERIOD)
                });
                match waited {
                    Ok(rows) => return Some(rows),
                    Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => return None,
                    Err(std::sync::mpsc::RecvTimeoutError::Timeout) => {}
                }
                if interrupted.is_none() {
                    if let Err(e) = py.check_signals() {
                        cancel.store(true, Ordering::Relaxed);
                        interrupted = Some(e);
                    }
                }
            }
        });
        let Some(rows) = rows else {
            return Err(crate::errors::error(
                crate::errors::Kind::Internal,
                "a sweep worker stopped without its rows",
            ));
        };
        if let Some(e) = journal_error.into_inner().unwrap_or_else(|e| e.into_inner()) {
            return Err(invalid(e));
        }
        let tuples = rows.iter().map(to_tuple).collect();
        self.rows.extend(rows);
        match interrupted {
            Some(e) => Err(e),
            None => Ok(tuples),
        }
    }

    /// Keeps rows run elsewhere (Ray tasks) and journals the finished ones.
    fn add_rows(&mut self, rows: Vec<RowTuple>) -> PyResult<()> {
        let rows = rows.into_iter().map(from_tuple).collect::<PyResult<Vec<_>>>()?;
        if let Some(j) = self.journal.as_mut() {
            j.append(&rows).map_err(sweep_error)?;
        }
        self.rows.extend(rows);
        Ok(())
    }

    /// Indices of the runs without a finished row.
    fn pending(&self) -> Vec<usize> {
        let done: std::collections::BTreeSet<usize> = self
            .rows
            .iter()
            .filter(|r| r.status != RunStatus::Cancelled)
            .map(|r| r.index)
            .collect();
        (0..self.sweep.len()).filter(|i| !done.contains(i)).collect()
    }

    /// The results table as a dict of columns in order (numpy arrays for
    /// numbers, lists for text); runs without a row are cancelled rows.
    fn table<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let out = PyDict::new(py);
        for (name, column) in self.full_table().columns {
            match column {
                Column::Int(v) => out.set_item(name, v.into_pyarray(py))?,
                Column::Float(v) => out.set_item(name, v.into_pyarray(py))?,
                Column::Text(v) => out.set_item(name, v)?,
            }
        }
        Ok(out)
    }

    /// Writes the results table (.parquet, .csv or .json) as `tumble sweep` does.
    fn write(&self, path: PathBuf) -> PyResult<()> {
        self.full_table().write(&path).or_raise()
    }

    /// Removes the journal (the whole table is written).
    fn close_journal(&mut self) -> PyResult<()> {
        if let Some(j) = self.journal.take() {
            let _ = std::fs::remove_file(j.path());
        }
        Ok(())
    }
}

impl SweepPlan {
    /// The table of every run: its last finished row, or a cancelled one.
    fn full_table(&self) -> tumble::export::table::Table {
        let mut by_run: Vec<Option<&RunRow>> = vec![None; self.sweep.len()];
        for r in &self.rows {
            if let Some(slot) = by_run.get_mut(r.index) {
                if slot.is_none_or(|old| old.status == RunStatus::Cancelled) {
                    *slot = Some(r);
                }
            }
        }
        let metrics = self.sweep.metric_count();
        let rows: Vec<RunRow> = by_run
            .iter()
            .enumerate()
            .map(|(i, r)| {
                r.cloned().unwrap_or(RunRow {
                    index: i,
                    status: RunStatus::Cancelled,
                    steps: 0,
                    metrics: vec![f64::NAN; metrics],
                    trajectory: None,
                })
            })
            .collect();
        self.sweep.table(&rows)
    }
}
