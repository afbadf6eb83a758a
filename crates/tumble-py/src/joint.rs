//! `tumble.Joint` and `World.add_joint`: Python arguments translated into a
//! Rust `JointDesc` (no physics here), and a handle that reads a joint's
//! state. A handle of a removed joint (or of a joint whose body was
//! removed) raises `StaleBodyError`. `tumble.load_urdf` and its `Robot`.
//! The getters of `Joint` are one line each over `Joint::state` (its
//! `JointState`) or `Joint::desc` (its `JointDesc`, what it was made with):
//! pyo3 wants a method per attribute, so they are alike by design.

use crate::body::Body;
use crate::convert::{self, vec3, vec_out};
use crate::errors::{guard, invalid, OrRaise};
use crate::world::World;
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use tumble::joint::{Gear, JointDesc, JointKind, JointState, Motor, Spring};
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

/// A motor target: a number (hinge, slider) or three (a ball joint's
/// vector), named for errors.
enum Target {
    Scalar(f64),
    Vector([f64; 3]),
}

/// The target under `key` of `d`, if given.
fn target(d: &Bound<'_, PyDict>, key: &str) -> PyResult<Option<Target>> {
    match d.get_item(key)? {
        None => Ok(None),
        Some(v) => {
            if let Ok(x) = v.extract::<f64>() {
                return Ok(Some(Target::Scalar(x)));
            }
            convert::numbers::<3>(
                &v,
                &format!("motor[{key:?}]"),
                "a number or 3 numbers (ball joint)",
            )
            .map(|t| Some(Target::Vector(t)))
        }
    }
}

/// `{"target_velocity": v, "max_force": f}` or `{"target_position": x,
/// "stiffness": k, "damping": c, "max_force": f}`; on a ball joint the
/// targets are 3-vectors (`Motor::AngularVelocity`, `Motor::Orientation`).
fn motor_from(obj: &Bound<'_, PyAny>) -> PyResult<Motor> {
    let d = obj.cast::<PyDict>().map_err(|_| {
        invalid(format!(
            "motor: expected a dict such as {{\"target_velocity\": 1.0, \"max_force\": 10.0}}, got {}",
            convert::describe(obj)
        ))
    })?;
    let max_force = number(d, "max_force", "motor")?.unwrap_or(f64::INFINITY);
    match (target(d, "target_velocity")?, target(d, "target_position")?) {
        (Some(target), None) => {
            only_keys(d, &["target_velocity", "max_force"], "motor")?;
            Ok(match target {
                Target::Scalar(target) => Motor::Velocity { target, max_force },
                Target::Vector(target) => Motor::AngularVelocity { target, max_force },
            })
        }
        (None, Some(target)) => {
            only_keys(d, &["target_position", "stiffness", "damping", "max_force"], "motor")?;
            let stiffness = number(d, "stiffness", "motor")?.unwrap_or(0.0);
            let damping = number(d, "damping", "motor")?.unwrap_or(0.0);
            Ok(match target {
                Target::Scalar(target) => Motor::Position {
                    target,
                    stiffness,
                    damping,
                    max_force,
                },
                Target::Vector(target) => Motor::Orientation {
                    target,
                    stiffness,
                    damping,
                    max_force,
                },
            })
        }
        _ => Err(invalid(
            "motor: give exactly one of \"target_velocity\" (rad/s or m/s; a ball joint's: 3 numbers, rad/s) \
             and \"target_position\" (rad or m; a ball joint's: a rotation vector, 3 numbers, rad)",
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

/// A motor as the dict `motor_from` reads.
fn motor_dict<'py>(py: Python<'py>, m: &Motor) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    match *m {
        Motor::Velocity { target, max_force } => {
            d.set_item("target_velocity", target)?;
            d.set_item("max_force", max_force)?;
        }
        Motor::Position {
            target,
            stiffness,
            damping,
            max_force,
        } => {
            d.set_item("target_position", target)?;
            d.set_item("stiffness", stiffness)?;
            d.set_item("damping", damping)?;
            d.set_item("max_force", max_force)?;
        }
        Motor::AngularVelocity { target, max_force } => {
            d.set_item("target_velocity", target.to_vec())?;
            d.set_item("max_force", max_force)?;
        }
        Motor::Orientation {
            target,
            stiffness,
            damping,
            max_force,
        } => {
            d.set_item("target_position", target.to_vec())?;
            d.set_item("stiffness", stiffness)?;
            d.set_item("damping", damping)?;
            d.set_item("max_force", max_force)?;
        }
    }
    Ok(d)
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
    pub friction: Option<f64>,
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
    desc.friction = args.friction;
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
    out.set_item("rotation", rows(&|s| s.rotation)?)?;
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
    /// A gear from its dict {"leader": Joint of this world, "ratio": r,
    /// "offset": o (optional)}.
    fn gear_from(&self, v: &Bound<'_, PyAny>) -> PyResult<Gear> {
        let d = v.cast::<PyDict>().map_err(|_| {
            invalid(format!(
                "gear: expected a dict such as {{\"leader\": joint, \"ratio\": 2.0}}, got {}",
                convert::describe(v)
            ))
        })?;
        only_keys(d, &["leader", "ratio", "offset"], "gear")?;
        let leader = d
            .get_item("leader")?
            .ok_or_else(|| invalid("gear: \"leader\" (the Joint it follows) is missing"))?;
        let leader = leader.cast::<Joint>().map_err(|_| {
            invalid(format!(
                "gear[\"leader\"]: expected a Joint, got {}",
                convert::describe(&leader)
            ))
        })?;
        let leader = leader.get();
        if leader.world.as_ptr() != self.world.as_ptr() {
            return Err(invalid("gear[\"leader\"]: a joint of another world"));
        }
        let ratio = number(d, "ratio", "gear")?.ok_or_else(|| invalid("gear: \"ratio\" is missing"))?;
        let offset = number(d, "offset", "gear")?.unwrap_or(0.0);
        Ok(Gear::new(leader.id, ratio).with_offset(offset))
    }

    fn state(&self, py: Python<'_>) -> PyResult<JointState> {
        let w = self.world.bind(py).borrow();
        w.check_usable()?;
        guard(|| w.inner.joint_state(self.id).or_raise())
    }

    /// `f` of the joint's description (what it was made with).
    fn desc<T>(&self, py: Python<'_>, f: impl FnOnce(&JointDesc) -> T) -> PyResult<T> {
        let w = self.world.bind(py).borrow();
        Ok(f(w.inner.joint(self.id).or_raise()?))
    }
}

#[pymethods]
impl Joint {
    /// "fixed", "ball", "hinge", "slider" or "distance".
    #[getter]
    fn kind(&self, py: Python<'_>) -> PyResult<&'static str> {
        self.desc(py, |d| d.kind.name())
    }

    /// The name given at creation.
    #[getter]
    fn name(&self, py: Python<'_>) -> PyResult<String> {
        self.desc(py, |d| d.name.clone())
    }

    /// The first body.
    #[getter]
    fn body_a(&self, py: Python<'_>) -> PyResult<Body> {
        let id = self.desc(py, |d| d.body_a)?;
        Ok(Body {
            world: self.world.clone_ref(py),
            id,
        })
    }

    /// The second body, or None for the world.
    #[getter]
    fn body_b(&self, py: Python<'_>) -> PyResult<Option<Body>> {
        let id = self.desc(py, |d| d.body_b)?;
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

    /// The rotation of body A relative to body B since the joint was made:
    /// a rotation vector (rad) in the world's axes at creation carried with
    /// B, shape (3,); what a ball joint's `target_position` motor drives to
    /// its target.
    #[getter]
    fn rotation<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(vec_out(py, self.state(py)?.rotation))
    }

    /// The motor as a dict (see `World.add_joint`), or None. Settable: a
    /// new dict (e.g. a servo's next target) or None to switch it off.
    #[getter]
    fn motor<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let motor = self.desc(py, |d| d.motor)?;
        motor.map(|m| motor_dict(py, &m)).transpose()
    }

    #[setter]
    fn set_motor(&self, py: Python<'_>, value: Option<&Bound<'_, PyAny>>) -> PyResult<()> {
        let motor = value.filter(|v| !v.is_none()).map(motor_from).transpose()?;
        let mut w = self.world.bind(py).borrow_mut();
        w.check_usable()?;
        w.inner.set_joint_motor(self.id, motor).or_raise()
    }

    /// The spring-damper as {"stiffness": k, "damping": c}, or None.
    /// Settable: (k, c), a dict, or None to take it off (e.g. a robot's
    /// joint damping varied between rollouts).
    #[getter]
    fn spring<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let spring = self.desc(py, |d| d.spring)?;
        spring
            .map(|s| {
                let d = PyDict::new(py);
                d.set_item("stiffness", s.stiffness)?;
                d.set_item("damping", s.damping)?;
                Ok(d)
            })
            .transpose()
    }

    #[setter]
    fn set_spring(&self, py: Python<'_>, value: Option<&Bound<'_, PyAny>>) -> PyResult<()> {
        let spring = value.filter(|v| !v.is_none()).map(spring_from).transpose()?;
        let mut w = self.world.bind(py).borrow_mut();
        w.check_usable()?;
        w.inner.set_joint_spring(self.id, spring).or_raise()
    }

    /// Coulomb friction on the joint's coordinate (N m or N; whichever way
    /// a ball joint turns), or None. Settable: a number >= 0, or
    /// None to take it off (e.g. a robot's joint friction varied between
    /// rollouts).
    #[getter]
    fn friction(&self, py: Python<'_>) -> PyResult<Option<f64>> {
        self.desc(py, |d| d.friction)
    }

    #[setter]
    fn set_friction(&self, py: Python<'_>, value: Option<f64>) -> PyResult<()> {
        let mut w = self.world.bind(py).borrow_mut();
        w.check_usable()?;
        w.inner.set_joint_friction(self.id, value).or_raise()
    }

    /// The gear that holds this joint's coordinate at a ratio of another
    /// joint's, as {"leader": Joint, "ratio": r, "offset": o}, or None:
    /// `position = ratio * leader.position + offset` (a gear pair, a rack
    /// and pinion, a URDF mimic joint; hinges and sliders). Settable: such
    /// a dict ("offset" optional, default 0) or None to let the joint go.
    #[getter]
    fn gear<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let gear = {
            let w = self.world.bind(py).borrow();
            w.check_usable()?;
            w.inner.joint_gear(self.id).or_raise()?
        };
        gear.map(|g| {
            let d = PyDict::new(py);
            let leader = Joint {
                world: self.world.clone_ref(py),
                id: g.leader,
            };
            d.set_item("leader", Py::new(py, leader)?)?;
            d.set_item("ratio", g.ratio)?;
            d.set_item("offset", g.offset)?;
            Ok(d)
        })
        .transpose()
    }

    #[setter]
    fn set_gear(&self, py: Python<'_>, value: Option<&Bound<'_, PyAny>>) -> PyResult<()> {
        let gear = match value.filter(|v| !v.is_none()) {
            None => None,
            Some(v) => Some(self.gear_from(v)?),
        };
        let mut w = self.world.bind(py).borrow_mut();
        w.check_usable()?;
        w.inner.set_joint_gear(self.id, gear).or_raise()
    }

    /// How far the coordinate is from where its gear holds it (rad or m;
    /// 0 without a gear).
    #[getter]
    fn gear_error(&self, py: Python<'_>) -> PyResult<f64> {
        let w = self.world.bind(py).borrow();
        w.check_usable()?;
        w.inner.gear_error(self.id).or_raise()
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

/// A robot loaded from a URDF file by `tumble.load_urdf`.
#[pyclass(module = "tumble", name = "Robot", frozen)]
pub struct Robot {
    /// The world the robot is in.
    #[pyo3(get)]
    world: Py<World>,
    /// The robot's name.
    #[pyo3(get)]
    name: String,
    /// The root link's name.
    #[pyo3(get)]
    root: String,
    /// Link name -> Body (links merged by fixed joints share one body).
    #[pyo3(get)]
    links: Py<PyDict>,
    /// Joint name -> Joint, for every non-fixed joint.
    #[pyo3(get)]
    joints: Py<PyDict>,
    /// Joint name -> largest motor torque or force of the URDF `<limit effort>`.
    #[pyo3(get)]
    efforts: Py<PyDict>,
    /// What was read but not used.
    #[pyo3(get)]
    warnings: Vec<String>,
    /// With ``self_collision``: the (Body, Body) pairs of links that
    /// overlap in the file's pose and so never touch (as loaded; later
    /// ``World.set_contacts_between`` calls do not change this list).
    #[pyo3(get)]
    no_contact: Py<PyList>,
}

#[pymethods]
impl Robot {
    fn __repr__(&self, py: Python<'_>) -> String {
        format!(
            "Robot({:?}, {} links, {} joints)",
            self.name,
            self.links.bind(py).len(),
            self.joints.bind(py).len()
        )
    }
}

/// Loads a URDF robot (links with inertial, collision geometry: box,
/// cylinder, sphere, mesh STL/OBJ relative to the file or in a ROS
/// package://; revolute,
/// continuous, prismatic and fixed joints with limits) into `world` (a new
/// World with default settings when None). Joint angles are 0 at the file's
/// zero configuration; links joined by fixed joints become one body.
///
/// Args:
///     path: the .urdf file.
///     world: the World to add the robot to.
///     position: where the root link's frame goes (m).
///     orientation: its orientation (x, y, z, w).
///     fixed_base: weld the root link to the world.
///     self_collision: let the robot's links touch each other (off by
///         default, as in PyBullet). Links that overlap in the file's pose
///         still never touch (``Robot.no_contact``): files written for other
///         engines overlap links beyond their joints, and contacts between
///         them would fight the joints.
///     balance_inertia: replace an inertia no body could have by the
///         isotropic one of the same trace (as MuJoCo's balanceinertia),
///         with a warning, instead of refusing the file.
///     convex_meshes: give each ``<mesh>`` link shape as its convex hull, as
///         PyBullet and MuJoCo read them (concave links such as hands touch
///         with a few points a pair, their hollows filled), instead of the
///         exact triangle mesh.
///
/// Returns:
///     Robot with ``world``, ``links`` and ``joints`` (dicts by name),
///     ``efforts``, ``root``, ``warnings``, ``no_contact``.
///
/// Raises:
///     InvalidArgument: a bad file, with file:line:column and element; the
///         world is unchanged.
///     FileError: the file cannot be read.
#[pyfunction]
#[pyo3(signature = (path, *, world=None, position=None, orientation=None, fixed_base=false,
    self_collision=false, balance_inertia=false, convex_meshes=false))]
#[allow(clippy::too_many_arguments)] // the Python signature
pub fn load_urdf(
    py: Python<'_>,
    path: std::path::PathBuf,
    world: Option<Bound<'_, World>>,
    position: Option<&Bound<'_, PyAny>>,
    orientation: Option<&Bound<'_, PyAny>>,
    fixed_base: bool,
    self_collision: bool,
    balance_inertia: bool,
    convex_meshes: bool,
) -> PyResult<Robot> {
    let options = tumble::joint::urdf::UrdfOptions {
        position: convert::vec3_or(position, "position", DVec3::ZERO)?,
        orientation: convert::quat_or_identity(orientation, "orientation")?,
        fixed_base,
        self_collision,
        balance_inertia,
        convex_meshes,
    };
    let world = match world {
        Some(w) => w,
        None => Bound::new(
            py,
            World::from_parts(RWorld::new(Default::default()).or_raise()?, Vec::new()),
        )?,
    };
    let robot = guard(|| {
        let mut w = world.borrow_mut();
        w.check_usable()?;
        let robot = tumble::joint::urdf::load_urdf(&mut w.inner, &path, options).or_raise()?;
        w.push_bodies(&robot.bodies);
        Ok(robot)
    })?;
    let links = PyDict::new(py);
    for (name, &id) in &robot.links {
        links.set_item(
            name,
            Body {
                world: world.clone().unbind(),
                id,
            },
        )?;
    }
    let joints = PyDict::new(py);
    let efforts = PyDict::new(py);
    for (name, j) in &robot.joints {
        joints.set_item(
            name,
            Joint {
                world: world.clone().unbind(),
                id: j.id,
            },
        )?;
        efforts.set_item(name, j.effort)?;
    }
    let body = |id| Body {
        world: world.clone().unbind(),
        id,
    };
    let no_contact = PyList::empty(py);
    for &(a, b) in &robot.no_contact {
        no_contact.append((body(a), body(b)))?;
    }
    let no_contact = no_contact.unbind();
    Ok(Robot {
        no_contact,
        world: world.unbind(),
        name: robot.name,
        root: robot.root,
        links: links.unbind(),
        joints: joints.unbind(),
        efforts: efforts.unbind(),
        warnings: robot.warnings,
    })
}
