//! `tumble.rollout`'s engine: B worlds stepped T steps side by side on the
//! batch threads of `tumble::batch`, with the GIL released, forces and
//! torques applied per step from an array, and what is asked for recorded
//! into (B, T, N, k) arrays. The Python wrapper (`tumble/_batch.py`) builds
//! the worlds, broadcasts the controls and calls back between chunks.
//!
//! Each world's trajectory is the one `World.step` gives it alone, bit for
//! bit, whatever the thread count and the other worlds (tests/test_batch.py).

use crate::convert::describe;
use crate::errors::{error, invalid, panic_message, Kind};
use crate::world::{live3, state_row, World, STATE_COLUMNS};
use numpy::ndarray::{Array2, Array4};
use numpy::{IntoPyArray, PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::panic::{catch_unwind, AssertUnwindSafe};
use tumble::world::{BodyId, World as RWorld};
use tumble::BodyKind;
use tumble_collide::{DQuat, DVec3, Pose};

/// What a rollout can record, with its columns per body.
pub const RECORDABLE: [(&str, usize); 6] = [
    ("positions", 3),
    ("orientations", 4),
    ("velocities", 3),
    ("angular_velocities", 3),
    ("centers_of_mass", 3),
    ("states", STATE_COLUMNS),
];

/// Steps between two looks at Python's signal handlers (Ctrl-C).
const STEPS_PER_CHUNK: usize = 16;

/// Columns of a control row: force (N) and torque (N m), world frame, at the
/// centre of mass.
const CONTROL_COLUMNS: usize = 6;

/// An (n, 13) float array of state rows.
pub fn state_matrix(obj: &Bound<'_, PyAny>, n: usize, name: &str) -> PyResult<Vec<[f64; STATE_COLUMNS]>> {
    let bad = || {
        invalid(format!(
            "{name}: expected a float array of shape ({n}, {STATE_COLUMNS}) (one row per body: \
             position, orientation x y z w, velocity, angular velocity), got {}",
            describe(obj)
        ))
    };
    let rows: Vec<Vec<f64>> = obj.extract().map_err(|_| bad())?;
    if rows.len() != n || rows.iter().any(|r| r.len() != STATE_COLUMNS) {
        return Err(bad());
    }
    Ok(rows
        .into_iter()
        .map(|r| r.try_into().expect("length checked"))
        .collect())
}

/// Sets every body's state from its row, all rows checked first (the world
/// is unchanged on error).
pub fn set_states(world: &mut RWorld, order: &[BodyId], rows: &[[f64; STATE_COLUMNS]]) -> Result<(), String> {
    let mut poses = Vec::with_capacity(rows.len());
    for (row, (&id, r)) in order.iter().zip(rows).enumerate() {
        let position = DVec3::new(r[0], r[1], r[2]);
        let rotation = DQuat::from_xyzw(r[3], r[4], r[5], r[6]);
        let pose = Pose::new(position, rotation).map_err(|e| format!("states: row {row}: {e}"))?;
        if !r[7..].iter().all(|x| x.is_finite()) {
            return Err(format!(
                "states: row {row}: velocities must be finite, got {:?}",
                &r[7..]
            ));
        }
        let kind = world.body(id).map_err(|e| e.to_string())?.kind();
        if kind == BodyKind::Static && r[7..].iter().any(|&x| x != 0.0) {
            return Err(format!(
                "states: row {row} is a static body: its velocities must be 0, got {:?}",
                &r[7..]
            ));
        }
        poses.push((id, kind, pose));
    }
    for ((id, kind, pose), r) in poses.into_iter().zip(rows) {
        world.set_pose(id, pose).map_err(|e| e.to_string())?;
        if kind != BodyKind::Static {
            let linear = DVec3::new(r[7], r[8], r[9]);
            let angular = DVec3::new(r[10], r[11], r[12]);
            world
                .set_velocity(id, linear, angular)
                .map_err(|e| e.to_string())?;
        }
    }
    Ok(())
}

/// One world of the batch and what it writes.
struct Lane<'a> {
    world: &'a mut World,
    /// Its controls, (T, N, 6) row-major, if any.
    controls: Option<&'a [f64]>,
    /// One buffer per recorded quantity, (T, N, k) row-major.
    records: Vec<Vec<f64>>,
    times: Vec<f64>,
    /// A panic inside its step.
    failed: Option<String>,
}

fn record_into(out: &mut Vec<f64>, what: &str, w: &RWorld, order: &[BodyId]) {
    for &id in order {
        match what {
            "positions" => out.extend(live3(w.pose(id).map(|p| p.position))),
            "orientations" => out.extend(w.orientation(id).map_or([f64::NAN; 4], |q| q.to_array())),
            "velocities" => out.extend(live3(w.linear_velocity(id))),
            "angular_velocities" => out.extend(live3(w.angular_velocity(id))),
            "centers_of_mass" => out.extend(live3(w.center_of_mass(id))),
            _ => out.extend(state_row(w, id)),
        }
    }
}

/// Steps `lane` from step `from` to `to` (exclusive) of its rollout.
fn run_lane(lane: &mut Lane<'_>, record: &[(&str, usize)], from: usize, to: usize) {
    let n = lane.world.order.len();
    let World {
        inner,
        order,
        summary,
        recorder,
        ..
    } = &mut *lane.world;
    let run = catch_unwind(AssertUnwindSafe(|| {
        for t in from..to {
            if let Some(c) = lane.controls {
                let rows = &c[t * n * CONTROL_COLUMNS..(t + 1) * n * CONTROL_COLUMNS];
                for (&id, row) in order.iter().zip(rows.chunks_exact(CONTROL_COLUMNS)) {
                    let force = DVec3::new(row[0], row[1], row[2]);
                    let torque = DVec3::new(row[3], row[4], row[5]);
                    // Checked before the rollout: non-zero rows are dynamic bodies.
                    if force != DVec3::ZERO {
                        let _ = inner.apply_force(id, force);
                    }
                    if torque != DVec3::ZERO {
                        let _ = inner.apply_torque(id, torque);
                    }
                }
            }
            let report = inner.step();
            summary.absorb(report, inner.time());
            if let Some(rec) = recorder.as_mut() {
                rec.after_step(inner);
            }
            for (buffer, (what, _)) in lane.records.iter_mut().zip(record) {
                record_into(buffer, what, inner, order);
            }
            lane.times.push(inner.time());
        }
    }));
    if let Err(payload) = run {
        lane.failed = Some(panic_message(payload.as_ref()));
    }
}

/// Steps `worlds` (distinct `tumble.World`s) `steps` times side by side and
/// returns a dict: `time` (B, T) and each recorded quantity (B, T, N, k).
/// `controls`: None or a C-contiguous float64 array (B, T, N, 6) of forces
/// and torques. The Python wrapper `tumble.rollout` is the documented API.
#[pyfunction]
#[pyo3(signature = (worlds, steps, controls=None, record=Vec::new(), threads=0))]
pub fn _rollout<'py>(
    py: Python<'py>,
    worlds: Vec<Bound<'py, World>>,
    steps: usize,
    controls: Option<Bound<'py, PyArrayDyn<f64>>>,
    record: Vec<String>,
    threads: u32,
) -> PyResult<Bound<'py, PyDict>> {
    let b = worlds.len();
    let record: Vec<(&str, usize)> = record
        .iter()
        .map(|r| {
            RECORDABLE
                .iter()
                .copied()
                .find(|(name, _)| name == r)
                .ok_or_else(|| {
                    let names: Vec<&str> = RECORDABLE.iter().map(|(n, _)| *n).collect();
                    invalid(format!(
                        "record: unknown quantity {r:?}; expected some of {names:?}"
                    ))
                })
        })
        .collect::<PyResult<_>>()?;
    let mut refs = Vec::with_capacity(b);
    for (k, w) in worlds.iter().enumerate() {
        let r = w.try_borrow_mut().map_err(|_| {
            invalid(format!(
                "worlds: world {k} appears twice (or is in use); pass distinct worlds, e.g. world.copy()"
            ))
        })?;
        r.check_usable()?;
        refs.push(r);
    }
    let n = refs.first().map_or(0, |w| w.order.len());
    if let Some(k) = refs.iter().position(|w| w.order.len() != n) {
        return Err(invalid(format!(
            "worlds: world {k} has {} bodies, world 0 has {n}; a rollout's arrays need the same number in each",
            refs[k].order.len()
        )));
    }
    let control_data = match &controls {
        None => None,
        Some(c) => {
            let shape = c.shape().to_vec();
            if shape != [b, steps, n, CONTROL_COLUMNS] {
                return Err(invalid(format!(
                    "controls: expected shape ({b}, {steps}, {n}, {CONTROL_COLUMNS}) (worlds, steps, bodies, force and torque), got {shape:?}"
                )));
            }
            let ro = c
                .try_readonly()
                .map_err(|_| invalid("controls: the array is being written elsewhere"))?;
            let data = ro
                .as_slice()
                .map_err(|_| invalid("controls: expected a C-contiguous array"))?
                .to_vec();
            if let Some(i) = data.iter().position(|x| !x.is_finite()) {
                let (w, rest) = (
                    i / (steps * n * CONTROL_COLUMNS),
                    i % (steps * n * CONTROL_COLUMNS),
                );
                return Err(invalid(format!(
                    "controls: not finite at world {w}, step {}, body {}",
                    rest / (n * CONTROL_COLUMNS),
                    rest / CONTROL_COLUMNS % n
                )));
            }
            for (k, w) in refs.iter().enumerate() {
                for (row, &id) in w.order.iter().enumerate() {
                    let dynamic = w
                        .inner
                        .body(id)
                        .is_ok_and(|body| body.kind() == BodyKind::Dynamic);
                    let pushed = (0..steps).any(|t| {
                        let at = ((k * steps + t) * n + row) * CONTROL_COLUMNS;
                        data[at..at + CONTROL_COLUMNS].iter().any(|&x| x != 0.0)
                    });
                    if pushed && !dynamic {
                        return Err(invalid(format!(
                            "controls: world {k}, body {row} is not dynamic; forces and torques act on dynamic bodies only"
                        )));
                    }
                }
            }
            Some(data)
        }
    };
    let per_world = steps * n * CONTROL_COLUMNS;
    let mut lanes: Vec<Lane<'_>> = refs
        .iter_mut()
        .enumerate()
        .map(|(k, w)| {
            w.summary.clear();
            Lane {
                world: w,
                controls: control_data
                    .as_ref()
                    .map(|d| &d[k * per_world..(k + 1) * per_world]),
                records: record
                    .iter()
                    .map(|(_, cols)| Vec::with_capacity(steps * n * cols))
                    .collect(),
                times: Vec::with_capacity(steps),
                failed: None,
            }
        })
        .collect();

    let mut done = 0;
    while done < steps {
        let to = (done + STEPS_PER_CHUNK).min(steps);
        py.detach(|| {
            tumble::batch::for_each_item(
                &mut lanes,
                threads,
                |lane| &mut lane.world.inner,
                |_, lane| run_lane(lane, &record, done, to),
            );
        });
        if let Some((k, message)) = lanes
            .iter()
            .enumerate()
            .find_map(|(k, l)| l.failed.clone().map(|m| (k, m)))
        {
            lanes[k].world.poisoned = Some(message.clone());
            return Err(error(
                Kind::Internal,
                format!("internal error in tumble during the rollout of world {k}: {message}"),
            ));
        }
        done = to;
        if done < steps {
            py.check_signals()?;
        }
    }

    let out = PyDict::new(py);
    let mut time = Vec::with_capacity(b * steps);
    for lane in &lanes {
        time.extend_from_slice(&lane.times);
    }
    out.set_item(
        "time",
        Array2::from_shape_vec((b, steps), time)
            .expect("one time per world and step")
            .into_pyarray(py),
    )?;
    for (q, (name, cols)) in record.iter().enumerate() {
        let mut data = Vec::with_capacity(b * steps * n * cols);
        for lane in &lanes {
            data.extend_from_slice(&lane.records[q]);
        }
        out.set_item(
            *name,
            Array4::from_shape_vec((b, steps, n, *cols), data)
                .expect("one row per world, step and body")
                .into_pyarray(py),
        )?;
    }
    Ok(out)
}
