//! `tumble.Joint` and `World.add_joint`: Python arguments translated into a
//! Rust `JointDesc` (no physics here), and a handle that reads a joint's
//! state. A handle of a removed joint (or of a joint whose body was
//! removed) raises `StaleBodyError`.

use crate::body::Body;
use crate::convert::{self, vec3, vec_out};
use crate::errors::{guard, invalid, OrRaise};
use crate::world::World;
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use tumble::joint::{JointDesc, JointKind, JointState, Motor, Spring};
use tumble::world::{JointId, World as RWorld};
use tumble_collide::DVec3;

/// A float from a dict entry, named for errors.
fn number(d: &Bound<'_, PyDict>, key: &str, what: &str) -> PyResult<Option<f64>> {
    match d.get_item(key)? {
        None => Ok(None),
        Some(v) => v.extract::<f64>().map(Some).map_err(|_| {
            invalid(format!(
                "{what}[{key:?}]: expected a number, got {}",
                convert::describe(&v)
            ))
        }),
    }
}

/// Refuses keys of `d` outside `allowed`.
fn only_keys(d: &Bound<'_, PyDict>, allowed: &[&str], what: &str) -> PyResult<()> {
    for k in d.keys() {
        let k: String = k
            .extract()
            .map_err(|_| invalid(format!("{what}: keys must be strings")))?;
        if !allowed.contains(&k.as_str()) {
            return Err(invalid(format!(
                "{what}: unknown key {k:?} (expected {})",
                allowed.join(", ")
            )));
        }
    }
    Ok(())
}

/// `{"target_velocity": v, "max_force": f}` or `{"target_position": x,
/// "stiffness": k, "damping": c, "max_force": f}`.
fn motor_from(obj: &Bound<'_, PyAny>) -> PyResult<Motor> {
    let d = obj.cast::<PyDict>().map_err(|_| {
        invalid(format!(
            "motor: expected a dict such as {{\"target_velocity\": 1.0, \"max_force\": 10.0}}, got {}",
            convert::describe(obj)
        ))
    })?;
    let max_force = number(d, "max_force", "motor")?.unwrap_or(f64::INFINITY);
    match (number(d, "target_velocity", "motor")?, number(d, "target_position", "motor")?) {
        (Some(target), None) => {
            only_keys(d, &["target_velocity", "max_force"], "motor")?;
            Ok(Motor::Velocity { target, max_force })
        }
        (None, Some(target)) => {
            only_keys(d, &["target_position", "stiffness", "damping", "max_force"], "motor")?;
            Ok(Motor::Position {
                target,
                stiffness: number(d, "stiffness", "motor")?.unwrap_or(0.0),
                damping: number(d, "damping", "motor")?.unwrap_or(0.0),
                max_force,
            })
        }
        _ => Err(invalid(
            "motor: give exactly one of \"target_velocity\" (rad/s or m/s) and \"target_position\" (rad or m)",
        )),
    }
}

/// `(stiffness, damping)` or `{"stiffness": k, "damping": c}`.
fn spring_from(obj: &Bound<'_, PyAny>) -> PyResult<Spring> {
    if let Ok(d) = obj.cast::<PyDict>() {
        only_keys(d, &["stiffness", "damping"], "spring")?;
        return Ok(Spring {
            stiffness: number(d, "stiffness", "spring")?.unwrap_or(0.0),
            damping: number(d, "damping", "spring")?.unwrap_or(0.0),
        });
    }
    let (stiffness, damping): (f64, f64) = obj.extract().map_err(|_| {
        invalid(format!(
            "spring: expected (stiffness, damping) or a dict, got {}",
            convert::describe(obj)
        ))
    })?;
    Ok(Spring { stiffness, damping })
}

/// The joint kind named `s`.
fn kind_from(s: &str) -> PyResult<JointKind> {
    JointKind::from_name(s).ok_or_else(|| {
        invalid(format!(
            "kind: expected one of \"fixed\", \"ball\", \"hinge\", \"slider\", \"distance\", got {s:?}"
        ))
    })
}

/// The arguments of `World.add_joint`, gathered (see its docstring for
/// their meaning and units).
#[allow(missing_docs)]
pub struct JointArgs<'a, 'py> {
    pub kind: &'a str,
    pub anchor: &'a Bound<'py, PyAny>,
    pub axis: Option<&'a Bound<'py, PyAny>>,
    pub anchor_b: Option<&'a Bound<'py, PyAny>>,
    pub limits: Option<(f64, f64)>,
    pub swing_limit: Option<f64>,
    pub motor: Option<&'a Bound<'py, PyAny>>,
    pub spring: Option<&'a Bound<'py, PyAny>>,
    pub length: Option<f64>,
    pub collide_connected: bool,
    pub name: Option<String>,
}

/// Adds a joint to `world` from Python arguments.
pub fn add_joint(
    world: &Bound<'_, World>,
    body_a: PyRef<'_, Body>,
    body_b: Option<PyRef<'_, Body>>,
    args: JointArgs<'_, '_>,
) -> PyResult<Joint> {
    let a = body_a.id_in(world)?;
    let b = body_b.map(|b| b.id_in(world)).transpose()?;
    let mut desc = JointDesc::new(
        kind_from(args.kind)?,
        a,
        b,
        vec3(args.anchor, "anchor")?,
        convert::vec3_or(args.axis, "axis", DVec3::Z)?,
    );
    desc.anchor_b = match args.anchor_b {
        Some(p) if !p.is_none() => Some(vec3(p, "anchor_b")?),
        _ => None,
    };
    desc.limits = args.limits.map(|(lo, hi)| [lo, hi]);
    desc.swing_limit = args.swing_limit;
    desc.motor = args.motor.filter(|m| !m.is_none()).map(motor_from).transpose()?;
    desc.spring = args
        .spring
        .filter(|s| !s.is_none())
        .map(spring_from)
        .transpose()?;
    desc.length = args.length;
    desc.collide_connected = args.collide_connected;
    desc.name = args.name.unwrap_or_default();
    let id = guard(|| {
        let mut w = world.borrow_mut();
        w.check_usable()?;
        w.inner.add_joint(&desc).or_raise()
    })?;
    Ok(Joint {
        world: world.clone().unbind(),
        id,
    })
}

/// Rows of the joint-state arrays: one per joint, in `World.joints()` order.
pub fn joint_arrays<'py>(py: Python<'py>, world: &RWorld) -> PyResult<Bound<'py, PyDict>> {
    let states: Vec<JointState> = world
        .joint_ids()
        .into_iter()
        .map(|id| world.joint_state(id).or_raise())
        .collect::<PyResult<_>>()?;
    let column = |f: &dyn Fn(&JointState) -> f64| PyArray1::from_vec(py, states.iter().map(f).collect());
    let rows = |f: &dyn Fn(&JointState) -> DVec3| -> PyResult<Bound<'py, PyArray2<f64>>> {
        let flat: Vec<f64> = states.iter().flat_map(|s| f(s).to_array()).collect();
        Ok(convert::matrix_out(py, flat, 3))
    };
    let out = PyDict::new(py);
    out.set_item("position", column(&|s| s.position))?;
    out.set_item("rate", column(&|s| s.rate))?;
    out.set_item("linear_error", column(&|s| s.linear_error))?;
    out.set_item("angular_error", column(&|s| s.angular_error))?;
    out.set_item("force", rows(&|s| s.force)?)?;
    out.set_item("torque", rows(&|s| s.torque)?)?;
    out.set_item("anchor_a", rows(&|s| s.anchor_a)?)?;
    out.set_item("anchor_b", rows(&|s| s.anchor_b)?)?;
    out.set_item("axis", rows(&|s| s.axis)?)?;
    Ok(out)
}

/// Handle of a joint in a World, returned by `World.add_joint`. Equal
/// handles refer to the same joint; a handle of a removed joint raises
/// StaleBodyError.
#[pyclass(module = "tumble", name = "Joint", frozen)]
pub struct Joint {
    pub(crate) world: Py<World>,
    pub(crate) id: JointId,
}

impl Joint {
    fn state(&self, py: Python<'_>) -> PyResult<JointState> {
        let w = self.world.bind(py).borrow();
        w.check_usable()?;
        guard(|| w.inner.joint_state(self.id).or_raise())
    }
}

#[pymethods]
impl Joint {
    /// "fixed", "ball", "hinge", "slider" or "distance".
    #[getter]
    fn kind(&self, py: Python<'_>) -> PyResult<&'static str> {
        let w = self.world.bind(py).borrow();
        Ok(w.inner.joint(self.id).or_raise()?.kind.name())
    }

    /// The name given at creation.
    #[getter]
    fn name(&self, py: Python<'_>) -> PyResult<String> {
        let w = self.world.bind(py).borrow();
        Ok(w.inner.joint(self.id).or_raise()?.name.clone())
    }

    /// The first body.
    #[getter]
    fn body_a(&self, py: Python<'_>) -> PyResult<Body> {
        let id = self
            .world
            .bind(py)
            .borrow()
            .inner
            .joint(self.id)
            .or_raise()?
            .body_a;
        Ok(Body {
            world: self.world.clone_ref(py),
            id,
        })
    }

    /// The second body, or None for the world.
    #[getter]
    fn body_b(&self, py: Python<'_>) -> PyResult<Option<Body>> {
        let id = self
            .world
            .bind(py)
            .borrow()
            .inner
            .joint(self.id)
            .or_raise()?
            .body_b;
        Ok(id.map(|id| Body {
            world: self.world.clone_ref(py),
            id,
        }))
    }

    /// The joint coordinate: hinge angle or ball twist (rad), slider offset
    /// (m), anchor distance (m); 0 for a weld. Zero at creation.
    #[getter]
    fn position(&self, py: Python<'_>) -> PyResult<f64> {
        Ok(self.state(py)?.position)
    }

    /// Rate of the joint coordinate (rad/s or m/s).
    #[getter]
    fn rate(&self, py: Python<'_>) -> PyResult<f64> {
        Ok(self.state(py)?.rate)
    }

    /// How far the anchors are from where the joint wants them (m).
    #[getter]
    fn linear_error(&self, py: Python<'_>) -> PyResult<f64> {
        Ok(self.state(py)?.linear_error)
    }

    /// How far the frames are turned from what the joint allows (rad).
    #[getter]
    fn angular_error(&self, py: Python<'_>) -> PyResult<f64> {
        Ok(self.state(py)?.angular_error)
    }

    /// Force the joint applied to body A in the last step (N), shape (3,).
    #[getter]
    fn force<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(vec_out(py, self.state(py)?.force))
    }

    /// Torque the joint applied to body A about its anchor (N m), shape (3,).
    #[getter]
    fn torque<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(vec_out(py, self.state(py)?.torque))
    }

    /// A's anchor now (m, world), shape (3,).
    #[getter]
    fn anchor_a<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(vec_out(py, self.state(py)?.anchor_a))
    }

    /// B's anchor now (m, world), shape (3,).
    #[getter]
    fn anchor_b<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(vec_out(py, self.state(py)?.anchor_b))
    }

    /// The joint axis as body B carries it now (world, unit), shape (3,).
    #[getter]
    fn axis<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(vec_out(py, self.state(py)?.axis))
    }

    /// Removes the joint; the handle becomes stale.
    fn remove(&self, py: Python<'_>) -> PyResult<()> {
        let mut w = self.world.bind(py).borrow_mut();
        w.check_usable()?;
        w.inner.remove_joint(self.id).or_raise()
    }

    fn __eq__(&self, other: &Joint) -> bool {
        self.world.as_ptr() == other.world.as_ptr() && self.id == other.id
    }

    fn __hash__(&self) -> u64 {
        ((self.id.index as u64) << 32) ^ self.id.generation as u64 ^ (self.world.as_ptr() as u64)
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        let w = self.world.bind(py).borrow();
        match w.inner.joint(self.id) {
            Ok(d) => format!("Joint({:?}, kind={:?})", d.name, d.kind.name()),
            Err(_) => format!("Joint(<removed {}>)", self.id.index),
        }
    }
}
