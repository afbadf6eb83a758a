//! Parameter sweeps: one world per combination of scene parameters (paths
//! of [`crate::scene::params`]), each run for a number of steps or a
//! simulated time, measured by named metrics, the runs spread over the
//! threads of one pool (each run serial on its thread, as
//! [`crate::batch`]). A run that fails (a bad value, a non-finite state) is
//! a row with its error; the others go on. A run's row depends on its
//! parameters only: not on the thread count, the other runs, or the
//! machine's process that ran it (the Python side sends chunks of runs to
//! Ray and gets the same rows).

use std::sync::atomic::{AtomicBool, Ordering};

use serde_json::Value;

use crate::pool::WorkerPool;
use crate::scene::{ParamPath, SceneDocument, SceneError};
use crate::world::{BodyId, World};

/// How long each run is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RunLength {
    /// This many steps.
    Steps(u64),
    /// This much simulated time (s): `round(t / dt)` steps of the run's own dt.
    Duration(f64),
    /// The scene file's `steps` or `duration`.
    Scene,
}

/// What a body metric measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum BodyQuantity {
    X,
    Y,
    Z,
    MaxZ,
    MinZ,
    Speed,
    ReboundZ,
}

/// A named measure of a run (see [`Metric::parse`] for the names).
#[derive(Debug, Clone, PartialEq)]
pub struct Metric {
    name: String,
    kind: MetricKind,
}

#[derive(Debug, Clone, PartialEq)]
enum MetricKind {
    MaxPenetration,
    EnergyStart,
    EnergyEnd,
    EnergyDrift,
    KineticEnergyEnd,
    MaxJointError,
    Time,
    /// Dynamic bodies whose orientation is more than 45 degrees from the
    /// one they started with (dominoes down, a tower fallen).
    Toppled,
    Body(String, BodyQuantity),
}

/// The metrics a sweep knows, for messages and docs.
pub const METRIC_NAMES: &str = "max_penetration (m), energy_start, energy_end, energy_drift \
(kinetic + potential, J), kinetic_energy_end (J), max_joint_error (m), time (s), toppled \
(dynamic bodies turned more than 45 degrees from their start), and per body \
NAME.x, NAME.y, NAME.z (final centre of mass, m), NAME.max_z, NAME.min_z, NAME.speed (final, \
m/s), NAME.rebound_z (highest z after the body first turned from falling to rising, m)";

impl Metric {
    /// Parses a metric name: `max_penetration`, `energy_start`,
    /// `energy_end`, `energy_drift`, `kinetic_energy_end`,
    /// `max_joint_error`, `time`, `toppled`, or
    /// `BODY.x|y|z|max_z|min_z|speed|rebound_z`.
    pub fn parse(name: &str) -> Result<Metric, String> {
        let kind = match name {
            "max_penetration" => MetricKind::MaxPenetration,
            "energy_start" => MetricKind::EnergyStart,
            "energy_end" => MetricKind::EnergyEnd,
            "energy_drift" => MetricKind::EnergyDrift,
            "kinetic_energy_end" => MetricKind::KineticEnergyEnd,
            "max_joint_error" => MetricKind::MaxJointError,
            "time" => MetricKind::Time,
            "toppled" => MetricKind::Toppled,
            _ => {
                let (body, what) = name
                    .rsplit_once('.')
                    .ok_or_else(|| format!("unknown metric {name:?}; known: {METRIC_NAMES}"))?;
                let q = match what {
                    "x" => BodyQuantity::X,
                    "y" => BodyQuantity::Y,
                    "z" => BodyQuantity::Z,
                    "max_z" => BodyQuantity::MaxZ,
                    "min_z" => BodyQuantity::MinZ,
                    "speed" => BodyQuantity::Speed,
                    "rebound_z" => BodyQuantity::ReboundZ,
                    _ => return Err(format!("unknown metric {name:?}; known: {METRIC_NAMES}")),
                };
                MetricKind::Body(body.to_string(), q)
            }
        };
        Ok(Metric {
            name: name.to_string(),
            kind,
        })
    }

    /// The metric's name (a column of the results).
    pub fn name(&self) -> &str {
        &self.name
    }
}

/// How a run ended.
#[derive(Debug, Clone, PartialEq)]
pub enum RunStatus {
    /// All its steps ran.
    Ok,
    /// It could not be built or stepped; the message says why.
    Failed(String),
    /// The sweep was cancelled before or while it ran.
    Cancelled,
}

/// One run's row of the results.
#[derive(Debug, Clone, PartialEq)]
pub struct RunRow {
    /// Index of the run in the sweep.
    pub index: usize,
    /// How it ended.
    pub status: RunStatus,
    /// Steps taken.
    pub steps: u64,
    /// The metrics in the order asked for (NaN where the run failed).
    pub metrics: Vec<f64>,
    /// The trajectory file written for the run, if trajectories were asked for.
    pub trajectory: Option<String>,
}

/// Tracks one metric over a run.
struct Tracker<'a> {
    metric: &'a Metric,
    body: Option<BodyId>,
    /// For toppled: each dynamic body and its orientation at the start.
    start: Vec<(BodyId, crate::collide::DQuat)>,
    value: f64,
    /// For rebound_z: the body has fallen (vz < 0) and then risen.
    fell: bool,
    rose: bool,
}

fn energy(w: &World) -> f64 {
    w.kinetic_energy() + w.potential_energy()
}

impl<'a> Tracker<'a> {
    fn new(metric: &'a Metric, world: &World, ids: &[BodyId]) -> Result<Tracker<'a>, String> {
        let body = match &metric.kind {
            MetricKind::Body(name, _) => Some(
                ids.iter()
                    .copied()
                    .find(|&id| world.name(id).is_ok_and(|n| n == name))
                    .ok_or_else(|| format!("metric {:?}: no body named {name:?}", metric.name))?,
            ),
            _ => None,
        };
        let start = match metric.kind {
            MetricKind::Toppled => ids
                .iter()
                .filter(|&&id| world.body(id).is_ok_and(|b| b.kind() == crate::BodyKind::Dynamic))
                .filter_map(|&id| world.orientation(id).ok().map(|q| (id, q)))
                .collect(),
            _ => Vec::new(),
        };
        let mut t = Tracker {
            metric,
            body,
            start,
            value: match metric.kind {
                MetricKind::EnergyStart | MetricKind::EnergyDrift => energy(world),
                MetricKind::Body(_, BodyQuantity::MaxZ | BodyQuantity::ReboundZ) => f64::NEG_INFINITY,
                MetricKind::Body(_, BodyQuantity::MinZ) => f64::INFINITY,
                _ => 0.0,
            },
            fell: false,
            rose: false,
        };
        t.observe(world, 0.0);
        Ok(t)
    }

    /// After each step (and at the start, with penetration 0).
    fn observe(&mut self, world: &World, penetration: f64) {
        let com = |id| world.center_of_mass(id).unwrap_or(crate::collide::DVec3::NAN);
        match &self.metric.kind {
            MetricKind::MaxPenetration => self.value = self.value.max(penetration),
            MetricKind::MaxJointError => self.value = self.value.max(world.max_joint_error().0),
            MetricKind::Body(_, q) => {
                let id = self.body.expect("body metrics have a body");
                let z = com(id).z;
                match q {
                    BodyQuantity::MaxZ => self.value = self.value.max(z),
                    BodyQuantity::MinZ => self.value = self.value.min(z),
                    BodyQuantity::ReboundZ => {
                        let vz = world.linear_velocity(id).map_or(f64::NAN, |v| v.z);
                        if vz < 0.0 && !self.rose {
                            self.fell = true;
                        } else if vz > 0.0 && self.fell {
                            self.rose = true;
                        }
                        if self.rose {
                            self.value = self.value.max(z);
                        }
                    }
                    _ => {}
                }
            }
            _ => {}
        }
    }

    fn finish(&self, world: &World) -> f64 {
        let com = |id| world.center_of_mass(id).unwrap_or(crate::collide::DVec3::NAN);
        match &self.metric.kind {
            MetricKind::EnergyEnd => energy(world),
            MetricKind::EnergyDrift => energy(world) - self.value,
            MetricKind::KineticEnergyEnd => world.kinetic_energy(),
            MetricKind::Time => world.time(),
            MetricKind::Toppled => self
                .start
                .iter()
                .filter(|(id, q0)| {
                    world
                        .orientation(*id)
                        .is_ok_and(|q| q0.angle_between(q) > std::f64::consts::FRAC_PI_4)
                })
                .count() as f64,
            MetricKind::Body(_, q) => {
                let id = self.body.expect("body metrics have a body");
                match q {
                    BodyQuantity::X => com(id).x,
                    BodyQuantity::Y => com(id).y,
                    BodyQuantity::Z => com(id).z,
                    BodyQuantity::Speed => world.linear_velocity(id).map_or(f64::NAN, |v| v.length()),
                    BodyQuantity::ReboundZ if !self.rose => f64::NAN,
                    _ => self.value,
                }
            }
            _ => self.value,
        }
    }
}

/// What every run of a sweep does: its length, its metrics, and where its
/// trajectory goes (`DIR/run_00007.csv` for run 7), if anywhere.
#[derive(Debug, Clone, Copy)]
pub struct RunSpec<'a> {
    /// How long each run is.
    pub length: RunLength,
    /// The metrics, in column order.
    pub metrics: &'a [Metric],
    /// The directory of the trajectory files (CSV, as `tumble run
    /// --trajectory`), or `None` for none.
    pub trajectories: Option<&'a std::path::Path>,
}

/// Runs one combination; `cancel` is looked at between steps.
pub fn run_one(
    doc: &SceneDocument,
    index: usize,
    assignments: &[(ParamPath, Value)],
    spec: &RunSpec<'_>,
    cancel: &AtomicBool,
) -> RunRow {
    let metrics = spec.metrics;
    let failed = |message: String, steps: u64| RunRow {
        index,
        status: RunStatus::Failed(message),
        steps,
        metrics: vec![f64::NAN; metrics.len()],
        trajectory: None,
    };
    if cancel.load(Ordering::Relaxed) {
        return RunRow {
            index,
            status: RunStatus::Cancelled,
            steps: 0,
            metrics: vec![f64::NAN; metrics.len()],
            trajectory: None,
        };
    }
    let mut loaded = match doc.with(assignments) {
        Ok(l) => l,
        Err(e) => return failed(e.to_string(), 0),
    };
    // The run is serial on its thread; the result does not depend on it.
    loaded.scene.settings.threads = 1;
    let (mut world, ids) = match loaded.build() {
        Ok(w) => w,
        Err(e) => return failed(e.to_string(), 0),
    };
    let steps = match spec.length {
        RunLength::Steps(n) => n,
        RunLength::Duration(t) => (t / world.settings().dt).round().max(1.0) as u64,
        RunLength::Scene => loaded.scene.steps as u64,
    };
    let mut trackers = Vec::with_capacity(metrics.len());
    for m in metrics {
        match Tracker::new(m, &world, &ids) {
            Ok(t) => trackers.push(t),
            Err(e) => return failed(e, 0),
        }
    }
    let mut recorder = match spec.trajectories {
        Some(_) => match crate::export::WorldRecorder::new(&world) {
            Ok(r) => Some(r),
            Err(e) => return failed(format!("trajectory: {e}"), 0),
        },
        None => None,
    };
    let stepped = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        for k in 0..steps {
            if cancel.load(Ordering::Relaxed) {
                return Err((RunStatus::Cancelled, k));
            }
            let report = world.step();
            if !report.quarantined.is_empty() {
                return Err((
                    RunStatus::Failed(format!(
                        "step {}: {} bodies got a non-finite state (quarantined)",
                        k + 1,
                        report.quarantined.len()
                    )),
                    k + 1,
                ));
            }
            for t in trackers.iter_mut() {
                t.observe(&world, report.max_penetration);
            }
            if let Some(r) = recorder.as_mut() {
                r.record(&world);
            }
        }
        Ok(())
    }));
    match stepped {
        Ok(Ok(())) => {
            let trajectory = match (spec.trajectories, recorder) {
                (Some(dir), Some(r)) => {
                    let path = dir.join(format!("run_{index:05}.csv"));
                    if let Err(e) = crate::export::write_trajectory_csv(&r.finish(), &path) {
                        return failed(format!("trajectory: {e}"), steps);
                    }
                    Some(path.display().to_string())
                }
                _ => None,
            };
            RunRow {
                index,
                status: RunStatus::Ok,
                steps,
                metrics: trackers.iter().map(|t| t.finish(&world)).collect(),
                trajectory,
            }
        }
        Ok(Err((status, k))) => RunRow {
            index,
            status,
            steps: k,
            metrics: vec![f64::NAN; metrics.len()],
            trajectory: None,
        },
        Err(payload) => {
            let message = payload
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_else(|| "panic".into());
            failed(format!("internal error: {message}"), 0)
        }
    }
}

/// The combinations of `params` (each a path and its values), the first
/// parameter varying slowest, as assignment lists.
pub fn combinations(params: &[(ParamPath, Vec<Value>)]) -> Vec<Vec<(ParamPath, Value)>> {
    let mut runs: Vec<Vec<(ParamPath, Value)>> = vec![Vec::new()];
    for (path, values) in params {
        runs = runs
            .into_iter()
            .flat_map(|run| {
                values.iter().map(move |v| {
                    let mut r = run.clone();
                    r.push((path.clone(), v.clone()));
                    r
                })
            })
            .collect();
    }
    runs
}

/// Checks every assignment of every run against the document before any
/// runs (a path that does not exist is an error for the whole sweep,
/// naming the path and the scene file; a bad value fails its row only).
pub fn check_paths(doc: &SceneDocument, params: &[(ParamPath, Vec<Value>)]) -> Result<(), SceneError> {
    for (path, values) in params {
        if let Some(v) = values.first() {
            doc.document_with(&[(path.clone(), v.clone())])?;
        }
    }
    Ok(())
}

/// Runs `runs` (given with their sweep indices) on up to `threads` threads;
/// `done` is called after each run (for a progress bar), from its thread.
/// Rows come back in the order of `runs`.
pub fn run_many(
    doc: &SceneDocument,
    runs: &[(usize, Vec<(ParamPath, Value)>)],
    spec: &RunSpec<'_>,
    threads: u32,
    cancel: &AtomicBool,
    done: &(dyn Fn(&RunRow) + Sync),
) -> Vec<RunRow> {
    let mut rows: Vec<Option<RunRow>> = vec![None; runs.len()];
    WorkerPool::new(threads).for_each_mut(&mut rows, |k, row| {
        let (index, assignments) = &runs[k];
        let r = run_one(doc, *index, assignments, spec, cancel);
        done(&r);
        *row = Some(r);
    });
    rows.into_iter().map(|r| r.expect("every run ran")).collect()
}

/// A sweep: the scene, its parameters and values, the run length and the
/// metrics, checked; [`Sweep::run`] runs any subset of its runs.
#[derive(Debug, Clone)]
pub struct Sweep {
    doc: SceneDocument,
    params: Vec<(ParamPath, Vec<Value>)>,
    runs: Vec<Vec<(ParamPath, Value)>>,
    length: RunLength,
    metrics: Vec<Metric>,
    trajectories: Option<std::path::PathBuf>,
}

/// A sweep that cannot start: which part is wrong and why.
#[derive(Debug, Clone, thiserror::Error)]
pub enum SweepError {
    /// The scene file, or a parameter path in it.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// A parameter, metric or length that is not well formed.
    #[error("{0}")]
    Bad(String),
    /// The journal of finished runs cannot be read or written.
    #[error("{path}: {message}")]
    Journal {
        /// The journal file.
        path: std::path::PathBuf,
        /// What went wrong.
        message: String,
    },
}

impl Sweep {
    /// Checks everything a sweep can check before it runs: the scene file,
    /// every parameter path (against the file), each parameter given at
    /// least one value, the metric names, the length.
    pub fn new(
        doc: SceneDocument,
        params: Vec<(String, Vec<Value>)>,
        length: RunLength,
        metrics: &[String],
    ) -> Result<Sweep, SweepError> {
        let mut parsed = Vec::with_capacity(params.len());
        for (path, values) in params {
            let p: ParamPath = path.parse().map_err(SweepError::Bad)?;
            if values.is_empty() {
                return Err(SweepError::Bad(format!("parameter {p}: no values given")));
            }
            parsed.push((p, values));
        }
        check_paths(&doc, &parsed)?;
        match length {
            RunLength::Duration(t) if !(t.is_finite() && t > 0.0) => {
                return Err(SweepError::Bad(format!(
                    "duration must be finite and > 0 s, got {t}"
                )))
            }
            RunLength::Steps(0) => return Err(SweepError::Bad("steps must be >= 1".into())),
            _ => {}
        }
        let metrics = metrics
            .iter()
            .map(|m| Metric::parse(m).map_err(SweepError::Bad))
            .collect::<Result<Vec<_>, _>>()?;
        let runs = combinations(&parsed);
        Ok(Sweep {
            doc,
            params: parsed,
            runs,
            length,
            metrics,
            trajectories: None,
        })
    }

    /// Writes each finished run's trajectory to `dir/run_00007.csv` (run 7;
    /// the CSV of `tumble run --trajectory`) and adds a `trajectory` column.
    /// The directory is created.
    pub fn with_trajectories(mut self, dir: impl Into<std::path::PathBuf>) -> Result<Sweep, SweepError> {
        let dir = dir.into();
        std::fs::create_dir_all(&dir).map_err(|e| SweepError::Journal {
            path: dir.clone(),
            message: format!("cannot create the trajectory directory: {e}"),
        })?;
        self.trajectories = Some(dir);
        Ok(self)
    }

    /// Number of runs (the product of the value counts).
    pub fn len(&self) -> usize {
        self.runs.len()
    }

    /// Opens the journal of this sweep's finished runs at `path` (see
    /// [`Journal::open`]); each run is labelled by its assignments, its
    /// length and the metric names, so that `resume` keeps only rows of
    /// the very same runs.
    pub fn open_journal(
        &self,
        path: impl AsRef<std::path::Path>,
        resume: bool,
    ) -> Result<(Journal, Vec<RunRow>), SweepError> {
        let metrics: Vec<&str> = self.metrics.iter().map(Metric::name).collect();
        let labels = self
            .runs
            .iter()
            .map(|run| {
                format!(
                    "{} | {:?} | {}",
                    crate::scene::params::describe(run),
                    self.length,
                    metrics.join(",")
                )
            })
            .collect();
        Journal::open(path, resume, labels)
    }

    /// Number of metrics (columns after `steps`).
    pub fn metric_count(&self) -> usize {
        self.metrics.len()
    }

    /// Whether the sweep has no runs (never: every parameter has a value).
    pub fn is_empty(&self) -> bool {
        self.runs.is_empty()
    }

    /// Runs the runs of `indices` (out of range ones are skipped) on up to
    /// `threads` threads, rows in the order of `indices`.
    pub fn run(
        &self,
        indices: &[usize],
        threads: u32,
        cancel: &AtomicBool,
        done: &(dyn Fn(&RunRow) + Sync),
    ) -> Vec<RunRow> {
        let runs: Vec<(usize, Vec<(ParamPath, Value)>)> = indices
            .iter()
            .filter_map(|&i| self.runs.get(i).map(|r| (i, r.clone())))
            .collect();
        let spec = RunSpec {
            length: self.length,
            metrics: &self.metrics,
            trajectories: self.trajectories.as_deref(),
        };
        run_many(&self.doc, &runs, &spec, threads, cancel, done)
    }

    /// The results table of `rows` (any order; sorted by run): `run`, one
    /// column per parameter (numbers as floats where every value is a
    /// number, JSON text otherwise), `status` (ok, failed, cancelled),
    /// `error`, `steps`, then the metrics.
    pub fn table(&self, rows: &[RunRow]) -> crate::export::table::Table {
        use crate::export::table::{Column, Table};
        let mut rows: Vec<&RunRow> = rows.iter().collect();
        rows.sort_by_key(|r| r.index);
        let mut columns = vec![(
            "run".to_string(),
            Column::Int(rows.iter().map(|r| r.index as i64).collect()),
        )];
        for (k, (path, values)) in self.params.iter().enumerate() {
            let value = |r: &RunRow| &self.runs[r.index][k].1;
            let column = if values.iter().all(Value::is_number) {
                Column::Float(
                    rows.iter()
                        .map(|r| value(r).as_f64().unwrap_or(f64::NAN))
                        .collect(),
                )
            } else {
                Column::Text(
                    rows.iter()
                        .map(|r| {
                            Some(
                                value(r)
                                    .as_str()
                                    .map_or_else(|| value(r).to_string(), str::to_string),
                            )
                        })
                        .collect(),
                )
            };
            columns.push((path.to_string(), column));
        }
        columns.push((
            "status".into(),
            Column::Text(
                rows.iter()
                    .map(|r| {
                        Some(match r.status {
                            RunStatus::Ok => "ok".to_string(),
                            RunStatus::Failed(_) => "failed".to_string(),
                            RunStatus::Cancelled => "cancelled".to_string(),
                        })
                    })
                    .collect(),
            ),
        ));
        columns.push((
            "error".into(),
            Column::Text(
                rows.iter()
                    .map(|r| match &r.status {
                        RunStatus::Failed(m) => Some(m.clone()),
                        _ => None,
                    })
                    .collect(),
            ),
        ));
        columns.push((
            "steps".into(),
            Column::Int(rows.iter().map(|r| r.steps as i64).collect()),
        ));
        for (k, m) in self.metrics.iter().enumerate() {
            columns.push((
                m.name().to_string(),
                Column::Float(rows.iter().map(|r| r.metrics[k]).collect()),
            ));
        }
        if self.trajectories.is_some() {
            columns.push((
                "trajectory".into(),
                Column::Text(rows.iter().map(|r| r.trajectory.clone()).collect()),
            ));
        }
        Table { columns }
    }
}

/// Finished runs of a sweep, one JSON line per run appended (and flushed)
/// as each chunk ends, so an interrupted or killed sweep keeps its rows and
/// a resumed one runs only the rest. Cancelled runs are not kept.
#[derive(Debug)]
pub struct Journal {
    path: std::path::PathBuf,
    file: std::fs::File,
    /// What each run of the sweep is (its assignments, length and metrics),
    /// stored with its row: a resumed sweep keeps only rows of the same runs.
    labels: Vec<String>,
}

impl Journal {
    /// Opens `path` for a sweep whose run `i` is described by `labels[i]`:
    /// with `resume`, reads the rows already there (a torn last line is
    /// dropped; a row of another sweep, by its label, is an error) and
    /// appends after them; without, starts empty.
    pub fn open(
        path: impl AsRef<std::path::Path>,
        resume: bool,
        labels: Vec<String>,
    ) -> Result<(Journal, Vec<RunRow>), SweepError> {
        let path = path.as_ref().to_path_buf();
        let err = |message: String| SweepError::Journal {
            path: path.clone(),
            message,
        };
        let mut rows = Vec::new();
        if resume {
            if let Ok(text) = std::fs::read_to_string(&path) {
                for (k, line) in text.lines().enumerate() {
                    match row_from_json(line) {
                        Some((r, label)) => {
                            if labels.get(r.index) != Some(&label) {
                                return Err(err(format!(
                                    "line {}: run {} of another sweep ({label}); resume the same \
                                     sweep, or start afresh without --resume",
                                    k + 1,
                                    r.index
                                )));
                            }
                            rows.push(r)
                        }
                        None if k + 1 == text.lines().count() => {} // torn by a kill
                        None => return Err(err(format!("line {}: not a sweep row", k + 1))),
                    }
                }
            }
            // Rewrite without a torn line, so appends start on a new line.
            let text: String = rows
                .iter()
                .map(|r| row_to_json(r, &labels[r.index]) + "\n")
                .collect();
            std::fs::write(&path, text).map_err(|e| err(e.to_string()))?;
        } else {
            std::fs::write(&path, "").map_err(|e| err(e.to_string()))?;
        }
        let file = std::fs::OpenOptions::new()
            .append(true)
            .open(&path)
            .map_err(|e| err(e.to_string()))?;
        Ok((Journal { path, file, labels }, rows))
    }

    /// Appends finished rows (cancelled ones are left to run again).
    pub fn append(&mut self, rows: &[RunRow]) -> Result<(), SweepError> {
        use std::io::Write;
        let text: String = rows
            .iter()
            .filter(|r| r.status != RunStatus::Cancelled)
            .map(|r| row_to_json(r, self.labels.get(r.index).map_or("", String::as_str)) + "\n")
            .collect();
        self.file
            .write_all(text.as_bytes())
            .and_then(|_| self.file.flush())
            .map_err(|e| SweepError::Journal {
                path: self.path.clone(),
                message: e.to_string(),
            })
    }

    /// The journal file.
    pub fn path(&self) -> &std::path::Path {
        &self.path
    }
}

/// A row as one JSON line with its run's label; floats as their bits, so
/// that a resumed sweep's table equals an uninterrupted one's exactly (NaN
/// included).
pub fn row_to_json(r: &RunRow, label: &str) -> String {
    let (status, error) = match &r.status {
        RunStatus::Ok => ("ok", None),
        RunStatus::Failed(m) => ("failed", Some(m.clone())),
        RunStatus::Cancelled => ("cancelled", None),
    };
    serde_json::json!({
        "run": r.index,
        "status": status,
        "error": error,
        "steps": r.steps,
        "metric_bits": r.metrics.iter().map(|x| x.to_bits()).collect::<Vec<u64>>(),
        "trajectory": r.trajectory,
        "label": label,
    })
    .to_string()
}

/// The row and label of a [`row_to_json`] line.
pub fn row_from_json(line: &str) -> Option<(RunRow, String)> {
    let v: Value = serde_json::from_str(line).ok()?;
    let status = match v.get("status")?.as_str()? {
        "ok" => RunStatus::Ok,
        "failed" => RunStatus::Failed(v.get("error")?.as_str()?.to_string()),
        "cancelled" => RunStatus::Cancelled,
        _ => return None,
    };
    let label = v.get("label")?.as_str()?.to_string();
    let row = RunRow {
        index: v.get("run")?.as_u64()? as usize,
        status,
        steps: v.get("steps")?.as_u64()?,
        metrics: v
            .get("metric_bits")?
            .as_array()?
            .iter()
            .map(|b| b.as_u64().map(f64::from_bits))
            .collect::<Option<Vec<f64>>>()?,
        trajectory: v.get("trajectory").and_then(Value::as_str).map(str::to_string),
    };
    Some((row, label))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `run_many` of `runs` for `length` on `threads` threads, measuring
    /// `metrics`, with no progress callback.
    fn run(
        doc: &SceneDocument,
        runs: &[(usize, Vec<(ParamPath, Value)>)],
        length: RunLength,
        metrics: &[Metric],
        threads: u32,
        cancel: &AtomicBool,
    ) -> Vec<RunRow> {
        let spec = RunSpec {
            length,
            metrics,
            trajectories: None,
        };
        run_many(doc, runs, &spec, threads, cancel, &|_| {})
    }

    /// examples/scenes/bounce.toml: a ball dropped from 1 m, 2 s.
    fn ball_drop_doc() -> SceneDocument {
        SceneDocument::load(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../examples/scenes/bounce.toml"
        ))
        .unwrap()
    }

    #[test]
    fn a_bounce_rises_to_e_squared_of_its_drop_and_rows_do_not_depend_on_threads() {
        let doc = ball_drop_doc();
        let e: Vec<Value> = [0.3, 0.5, 0.7, 0.9].iter().map(|&x| x.into()).collect();
        let params = vec![("bodies[ball].restitution".parse().unwrap(), e)];
        check_paths(&doc, &params).unwrap();
        let runs: Vec<_> = combinations(&params).into_iter().enumerate().collect();
        let metrics: Vec<Metric> = ["ball.rebound_z", "max_penetration", "time"]
            .iter()
            .map(|m| Metric::parse(m).unwrap())
            .collect();
        let cancel = AtomicBool::new(false);
        let rows = run(&doc, &runs, RunLength::Scene, &metrics, 1, &cancel);
        for (row, e) in rows.iter().zip([0.3, 0.5, 0.7, 0.9]) {
            assert_eq!(row.status, RunStatus::Ok);
            assert_eq!(row.steps, 500);
            // Drop height 1 m (centre 1.1 m, radius 0.1 m): the rebound
            // rises e^2 of it, to the solver's restitution accuracy.
            let rebound = row.metrics[0] - 0.1;
            assert!(
                (rebound - e * e).abs() < 0.03 * e * e + 0.005,
                "e = {e}: rebound {rebound}"
            );
            assert!((row.metrics[2] - 2.0).abs() < 1e-9);
        }
        let on_two = run(&doc, &runs, RunLength::Steps(500), &metrics, 2, &cancel);
        for (a, b) in rows.iter().zip(&on_two) {
            assert_eq!(
                a.metrics.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                b.metrics.iter().map(|x| x.to_bits()).collect::<Vec<_>>()
            );
        }
    }

    #[test]
    fn a_bad_value_fails_its_row_and_a_bad_path_the_sweep() {
        let doc = ball_drop_doc();
        let params = vec![(
            "bodies[ball].mass".parse().unwrap(),
            vec![Value::from(2.0), Value::from(-1.0)],
        )];
        let runs: Vec<_> = combinations(&params).into_iter().enumerate().collect();
        let metrics = vec![Metric::parse("ball.z").unwrap()];
        let cancel = AtomicBool::new(false);
        let rows = run(&doc, &runs, RunLength::Steps(10), &metrics, 2, &cancel);
        assert_eq!(rows[0].status, RunStatus::Ok);
        match &rows[1].status {
            RunStatus::Failed(m) => assert!(
                m.contains("bounce.toml") && m.contains("bodies[ball].mass=-1") && m.contains("mass"),
                "{m}"
            ),
            s => panic!("{s:?}"),
        }
        assert!(rows[1].metrics[0].is_nan());
        let bad = vec![("bodies[rock].mass".parse().unwrap(), vec![Value::from(1.0)])];
        let err = check_paths(&doc, &bad).unwrap_err().to_string();
        assert!(
            err.contains("bounce.toml")
                && err.contains("bodies[rock].mass")
                && err.contains("no element named"),
            "{err}"
        );
        assert!(Metric::parse("ball.colour").is_err());
        let rock = [Metric::parse("rock.z").unwrap()];
        let missing = run(&doc, &runs[..1], RunLength::Steps(1), &rock, 1, &cancel);
        assert!(matches!(&missing[0].status, RunStatus::Failed(m) if m.contains("no body named")));
        cancel.store(true, Ordering::Relaxed);
        let cancelled = run(&doc, &runs, RunLength::Steps(10), &metrics, 1, &cancel);
        assert!(cancelled.iter().all(|r| r.status == RunStatus::Cancelled));
    }
}
