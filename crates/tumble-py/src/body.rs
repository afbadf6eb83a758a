//! `tumble.Body`: a handle (world + generational `BodyId`) with properties
//! that read and write one body. A handle of a removed body raises
//! `StaleBodyError` on every use; it never addresses the body that reused
//! the slot.

use crate::convert::{self, quat_out, vec3, vec_out};
use crate::errors::{busy, error, guard, invalid, Kind, OrRaise};
use crate::world::World;
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use tumble::world::BodyId;
use tumble::BodyKind;
use tumble_collide::Pose;

/// "dynamic" / "static" / "kinematic".
pub fn kind_from(s: &str) -> PyResult<BodyKind> {
    match s {
        "dynamic" => Ok(BodyKind::Dynamic),
        "static" => Ok(BodyKind::Static),
        "kinematic" => Ok(BodyKind::Kinematic),
        _ => Err(invalid(format!(
            "kind: expected \"dynamic\", \"static\" or \"kinematic\", got {s:?}"
        ))),
    }
}

/// The name of a body kind.
pub fn kind_name(k: BodyKind) -> &'static str {
    match k {
        BodyKind::Dynamic => "dynamic",
        BodyKind::Static => "static",
        BodyKind::Kinematic => "kinematic",
    }
}

/// Force at the centre of mass, or at a world point.
pub fn apply_force(
    w: &mut World,
    id: BodyId,
    force: &Bound<'_, PyAny>,
    point: Option<&Bound<'_, PyAny>>,
) -> PyResult<()> {
    w.check_usable()?;
    let f = vec3(force, "force")?;
    let p = match point {
        Some(p) if !p.is_none() => Some(vec3(p, "point")?),
        _ => None,
    };
    guard(|| match p {
        None => w.inner.apply_force(id, f).or_raise(),
        Some(p) => w.inner.apply_force_at_point(id, f, p).or_raise(),
    })
}

/// Handle of a body in a World, returned by `World.add_body`. Equal handles
/// refer to the same body; a handle of a removed body raises StaleBodyError.
#[pyclass(module = "tumble", name = "Body", frozen)]
pub struct Body {
    pub(crate) world: Py<World>,
    pub(crate) id: BodyId,
}

impl Body {
    /// The id, checked to belong to `world` (the Rust world checks that it
    /// is live).
    pub(crate) fn id_in(&self, world: &Bound<'_, World>) -> PyResult<BodyId> {
        if self.world.as_ptr() != world.as_ptr() {
            return Err(invalid(format!("body {:?} belongs to another world", self.id)));
        }
        Ok(self.id)
    }

    fn read<T>(&self, py: Python<'_>, f: impl FnOnce(&World, BodyId) -> PyResult<T>) -> PyResult<T> {
        let w = self.world.bind(py).try_borrow().map_err(|_| busy())?;
        w.check_usable()?;
        guard(|| f(&w, self.id))
    }

    fn write<T>(&self, py: Python<'_>, f: impl FnOnce(&mut World, BodyId) -> PyResult<T>) -> PyResult<T> {
        let mut w = self.world.bind(py).try_borrow_mut().map_err(|_| busy())?;
        w.check_usable()?;
        guard(|| f(&mut w, self.id))
    }
}

#[pymethods]
impl Body {
    // `position` and `orientation` are mirror property pairs, like `velocity`
    // and `angular_velocity` below: pyo3 wants a getter and a setter per
    // attribute, and each setter keeps the other half of the pose it sets.
    /// Position of the model-frame origin (m), shape (3,). Settable (teleport).
    #[getter]
    fn position<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let p = self.read(py, |w, id| w.inner.pose(id).or_raise())?;
        Ok(vec_out(py, p.position))
    }

    #[setter]
    fn set_position(&self, py: Python<'_>, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let p = vec3(value, "position")?;
        self.write(py, |w, id| {
            let pose = w.inner.pose(id).or_raise()?;
            w.inner.set_pose(id, Pose { position: p, ..pose }).or_raise()
        })
    }

    /// Orientation of the model frame (x, y, z, w), shape (4,). Settable.
    #[getter]
    fn orientation<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let p = self.read(py, |w, id| w.inner.pose(id).or_raise())?;
        Ok(quat_out(py, p.rotation))
    }

    #[setter]
    fn set_orientation(&self, py: Python<'_>, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let q = convert::quat(value, "orientation")?;
        self.write(py, |w, id| {
            let pose = w.inner.pose(id).or_raise()?;
            w.inner.set_pose(id, Pose { rotation: q, ..pose }).or_raise()
        })
    }

    /// (position, orientation) of the model frame. Settable with a pair.
    #[getter]
    fn pose<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        let p = self.read(py, |w, id| w.inner.pose(id).or_raise())?;
        PyTuple::new(py, [vec_out(py, p.position), quat_out(py, p.rotation)])
    }

    #[setter]
    fn set_pose(&self, py: Python<'_>, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let pair: Vec<Bound<'_, PyAny>> = value
            .extract()
            .ok()
            .filter(|v: &Vec<_>| v.len() == 2)
            .ok_or_else(|| {
                invalid(format!(
                    "pose: expected (position, orientation), got {}",
                    convert::describe(value)
                ))
            })?;
        let pose = Pose {
            position: vec3(&pair[0], "position")?,
            rotation: convert::quat(&pair[1], "orientation")?,
        };
        self.write(py, |w, id| w.inner.set_pose(id, pose).or_raise())
    }

    // `velocity` and `angular_velocity` are mirror property pairs (pyo3 wants a
    // getter and a setter per attribute); each setter keeps the other half,
    // since the world sets both velocities at once.
    /// Linear velocity of the centre of mass (m/s), shape (3,). Settable
    /// (dynamic and kinematic bodies).
    #[getter]
    fn velocity<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let v = self.read(py, |w, id| w.inner.linear_velocity(id).or_raise())?;
        Ok(vec_out(py, v))
    }

    #[setter]
    fn set_velocity(&self, py: Python<'_>, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let v = vec3(value, "velocity")?;
        self.write(py, |w, id| {
            let omega = w.inner.angular_velocity(id).or_raise()?;
            w.inner.set_velocity(id, v, omega).or_raise()
        })
    }

    /// Angular velocity, world frame (rad/s), shape (3,). Settable.
    #[getter]
    fn angular_velocity<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let v = self.read(py, |w, id| w.inner.angular_velocity(id).or_raise())?;
        Ok(vec_out(py, v))
    }

    #[setter]
    fn set_angular_velocity(&self, py: Python<'_>, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let omega = vec3(value, "angular_velocity")?;
        self.write(py, |w, id| {
            let v = w.inner.linear_velocity(id).or_raise()?;
            w.inner.set_velocity(id, v, omega).or_raise()
        })
    }

    /// Centre of mass in the world (m), shape (3,).
    #[getter]
    fn center_of_mass<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let c = self.read(py, |w, id| w.inner.center_of_mass(id).or_raise())?;
        Ok(vec_out(py, c))
    }

    /// Mass (kg); inf for static and kinematic bodies.
    #[getter]
    fn mass(&self, py: Python<'_>) -> PyResult<f64> {
        self.read(py, |w, id| Ok(w.inner.body(id).or_raise()?.mass()))
    }

    /// Principal moments of inertia (kg m^2), shape (3,); inf for static and
    /// kinematic bodies.
    #[getter]
    fn principal_inertia<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let i = self.read(py, |w, id| Ok(w.inner.body(id).or_raise()?.principal_inertia()))?;
        Ok(vec_out(py, i))
    }

    /// Kinetic energy (J); 0 for static and kinematic bodies.
    #[getter]
    fn kinetic_energy(&self, py: Python<'_>) -> PyResult<f64> {
        self.read(py, |w, id| {
            let b = w.inner.body(id).or_raise()?;
            Ok(if b.kind() == BodyKind::Dynamic {
                b.kinetic_energy()
            } else {
                0.0
            })
        })
    }

    /// "dynamic", "static" or "kinematic".
    #[getter]
    fn kind(&self, py: Python<'_>) -> PyResult<&'static str> {
        self.read(py, |w, id| Ok(kind_name(w.inner.body(id).or_raise()?.kind())))
    }

    /// The name given to add_body ("" if none).
    #[getter]
    fn name(&self, py: Python<'_>) -> PyResult<String> {
        self.read(py, |w, id| Ok(w.inner.name(id).or_raise()?.to_string()))
    }

    /// Row of this body in the world's arrays (positions, contacts, ...).
    #[getter]
    fn index(&self, py: Python<'_>) -> PyResult<usize> {
        self.read(py, |w, id| {
            w.row(id).ok_or_else(|| {
                error(
                    Kind::Stale,
                    format!("body {id:?} does not exist (removed, or never added)"),
                )
            })
        })
    }

    /// `True` while the body is in its world (False after remove()).
    #[getter]
    fn is_alive(&self, py: Python<'_>) -> PyResult<bool> {
        let w = self.world.bind(py).try_borrow().map_err(|_| busy())?;
        Ok(w.row(self.id).is_some())
    }

    /// `True` when the body is asleep (skipped until touched or woken).
    #[getter]
    fn is_sleeping(&self, py: Python<'_>) -> PyResult<bool> {
        self.read(py, |w, id| w.inner.is_sleeping(id).or_raise())
    }

    /// The world this body belongs to.
    #[getter]
    fn world(&self, py: Python<'_>) -> Py<World> {
        self.world.clone_ref(py)
    }

    /// Adds a force (N) for the next step, at the centre of mass or at the
    /// world `point` (adding the torque (point - com) x force). Dynamic bodies.
    #[pyo3(signature = (force, point=None))]
    fn apply_force(
        &self,
        py: Python<'_>,
        force: &Bound<'_, PyAny>,
        point: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let mut w = self.world.bind(py).try_borrow_mut().map_err(|_| busy())?;
        apply_force(&mut w, self.id, force, point)
    }

    /// Adds a torque (N m, world frame) for the next step. Dynamic bodies.
    fn apply_torque(&self, py: Python<'_>, torque: &Bound<'_, PyAny>) -> PyResult<()> {
        let t = vec3(torque, "torque")?;
        self.write(py, |w, id| w.inner.apply_torque(id, t).or_raise())
    }

    // The (vector, point=None) arguments of `apply_force` above, but a method of
    // its own: an impulse changes the velocities now, a force waits for the step.
    /// Applies an impulse (N s) now, at the centre of mass or at the world
    /// `point`: the velocities change immediately. Dynamic bodies.
    #[pyo3(signature = (impulse, point=None))]
    fn apply_impulse(
        &self,
        py: Python<'_>,
        impulse: &Bound<'_, PyAny>,
        point: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let j = vec3(impulse, "impulse")?;
        let p = match point {
            Some(p) if !p.is_none() => Some(vec3(p, "point")?),
            _ => None,
        };
        self.write(py, |w, id| {
            let at = match p {
                Some(p) => p,
                None => w.inner.center_of_mass(id).or_raise()?,
            };
            w.inner.apply_impulse_at_point(id, j, at).or_raise()
        })
    }

    /// Wakes the body (and its island at the next step).
    fn wake(&self, py: Python<'_>) -> PyResult<()> {
        self.write(py, |w, id| w.inner.wake(id).or_raise())
    }

    /// Removes the body from its world; this handle becomes stale.
    fn remove(&self, py: Python<'_>) -> PyResult<()> {
        self.write(py, |w, id| w.remove(id))
    }

    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        match other.cast::<Body>() {
            Ok(o) => {
                let o = o.get();
                o.id == self.id && o.world.as_ptr() == self.world.as_ptr()
            }
            Err(_) => false,
        }
    }

    fn __hash__(&self) -> u64 {
        let w = self.world.as_ptr() as usize as u64;
        w ^ ((self.id.index as u64) << 32 | self.id.generation as u64).rotate_left(17)
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        let Ok(w) = self.world.bind(py).try_borrow() else {
            return format!(
                "tumble.Body(slot={}, generation={})",
                self.id.index, self.id.generation
            );
        };
        match (w.row(self.id), w.inner.body(self.id)) {
            (Some(row), Ok(b)) => {
                let name = w.inner.name(self.id).unwrap_or("");
                let name = if name.is_empty() {
                    String::new()
                } else {
                    format!(", name={name:?}")
                };
                format!("tumble.Body(index={row}, kind={:?}{name})", kind_name(b.kind()))
            }
            _ => format!(
                "tumble.Body(<removed: slot {}, generation {}>)",
                self.id.index, self.id.generation
            ),
        }
    }
}
