//! `tumble.World`: the Rust `World` with Python conventions. Bodies are kept
//! in insertion order (the rows of every array the world returns), `step`
//! releases the GIL and catches panics, and the world is poisoned (refuses
//! further calls) if one ever happens mid-step.
//!
//! Snapshots: `World.save` / `World.load` (files), `to_bytes` /
//! `from_bytes` and pickling (`__reduce__`), over the Rust snapshot API; the
//! snapshot keeps the body insertion order, so the array rows of a loaded
//! world are those of the saved one. A `tumble.load_scene` builds a world
//! through [`World::from_parts`] too.

use crate::body::{kind_from, Body};
use crate::convert::{self, matrix_out};
use crate::errors::{busy, error, guard, invalid, panic_message, Kind, OrRaise};
use crate::joint::{Joint, JointArgs};
use crate::record::Recorder;
use crate::report::{self, PyStepReport, StepSummary};
use crate::settings;
use crate::shapes::shape_descs;
use numpy::PyArray2;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// How long `step(n)` runs without looking at Python's signal handlers.
const SIGNAL_CHECK_PERIOD: Duration = Duration::from_millis(50);
use pyo3::types::PyBytes;
use tumble::world::{
    BodyDesc, BodyId, MassDesc, MaterialDesc, Snapshot, SnapshotError, World as RWorld, WorldSettings,
};
use tumble::BodyKind;
use tumble_collide::mass::MassProperties;
use tumble_collide::{DMat3, DVec3, Pose};

/// A simulated world of rigid bodies (SI units, z up, quaternions (x, y, z, w),
/// angular velocity in the world frame).
///
/// Keyword arguments are the fields of the Rust `WorldSettings`, with the same
/// defaults; `None` keeps the default:
///
///     gravity=(0, 0, -9.81)      m/s^2
///     dt=1/60                    s per step()
///     substeps=8                 solver sub-steps per step
///     integrator="semi_implicit" or "euler", "midpoint", "rk4",
///                                "semi_implicit_splitting"
///     solver="pgs"               or "lemke" (exact normal LCP, small systems)
///     iterations=2               velocity iterations per sub-step
///     push_out_iterations=1      position iterations per sub-step (a step
///                                deeper than 5 mm gets up to 3 more)
///     contact_margin=0.005       m, speculative contact distance
///     mesh_contact_margin=0.002  m, the same between two triangle meshes
///     resting_motion=5e-7        m, a mesh pair that moved less since its
///                                last search re-evaluates its kept points
///     allowed_penetration=0.0005 m, overlap left uncorrected
///     push_out_fraction=0.2      overlap removed per sub-step, in (0, 1]
///     max_push_out_speed=3       m/s
///     restitution_threshold=0.5  m/s, slower impacts do not bounce
///     continuous=True            fast bodies stop at the first surface in
///                                their path (continuous collision)
///     sleeping=True              resting islands fall asleep
///     sleep_linear_speed=0.05    m/s
///     sleep_angular_speed=0.05   rad/s
///     time_to_sleep=0.5          s
///     threads=0                  worker threads of step(); 0 = every core,
///                                1 = serial; results are bit-identical
///                                for any count
///     adaptive_threads=True      a step runs on one thread while the
///                                threads are measured slower (a busy or
///                                shared machine); same results
///
/// Arrays returned by the world (positions, contacts, ...) have one row per
/// live body in the order the bodies were added.
#[pyclass(module = "tumble", name = "World")]
pub struct World {
    pub(crate) inner: RWorld,
    /// Live bodies in insertion order: the rows of every array.
    pub(crate) order: Vec<BodyId>,
    /// Slot index -> row in `order` (`u32::MAX` for an empty slot).
    rows: Vec<u32>,
    pub(crate) summary: StepSummary,
    pub(crate) recorder: Option<Recorder>,
    /// Set when a panic escaped `step`; the world's state may be torn.
    pub(crate) poisoned: Option<String>,
}

impl World {
    /// Wraps a Rust world whose bodies were added in the order `ids`
    /// (for scene loading and snapshots).
    pub fn from_parts(inner: RWorld, ids: Vec<BodyId>) -> World {
        let mut w = World {
            inner,
            order: ids,
            rows: Vec::new(),
            summary: StepSummary::default(),
            recorder: None,
            poisoned: None,
        };
        w.reindex();
        w
    }

    fn reindex(&mut self) {
        let slots = self
            .order
            .iter()
            .map(|id| id.index as usize + 1)
            .max()
            .unwrap_or(0);
        self.rows = vec![u32::MAX; slots];
        for (row, id) in self.order.iter().enumerate() {
            self.rows[id.index as usize] = row as u32;
        }
    }

    /// Row of a live body in the arrays.
    pub(crate) fn row(&self, id: BodyId) -> Option<usize> {
        let row = *self.rows.get(id.index as usize)?;
        (row != u32::MAX && self.order[row as usize] == id).then_some(row as usize)
    }

    pub(crate) fn check_usable(&self) -> PyResult<()> {
        match &self.poisoned {
            Some(m) => Err(error(
                Kind::Internal,
                format!("this world is unusable after an internal error during step(): {m}"),
            )),
            None => Ok(()),
        }
    }

    /// Bodies added to the Rust world behind this wrapper's back (a URDF
    /// robot), appended to the rows in the order given.
    pub(crate) fn push_bodies(&mut self, ids: &[BodyId]) {
        self.order.extend_from_slice(ids);
        self.reindex();
    }

    pub(crate) fn remove(&mut self, id: BodyId) -> PyResult<()> {
        self.check_usable()?;
        self.inner.remove_body(id).or_raise()?;
        self.order.retain(|&b| b != id);
        self.reindex();
        Ok(())
    }

    /// The state rows of [`STATE_COLUMNS`] for every body.
    pub(crate) fn state_rows(&self) -> Vec<f64> {
        let mut out = Vec::with_capacity(self.order.len() * STATE_COLUMNS);
        for &id in &self.order {
            out.extend_from_slice(&state_row(&self.inner, id));
        }
        out
    }

    /// An (N, 3) float64 array of `f` for every body, in row order: the
    /// per-body vector getters (`positions`, `velocities`, ...).
    fn rows_of<'py>(
        &self,
        py: Python<'py>,
        f: impl Fn(&RWorld, BodyId) -> [f64; 3],
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.check_usable()?;
        let mut out = Vec::with_capacity(self.order.len() * 3);
        for &id in &self.order {
            out.extend_from_slice(&f(&self.inner, id));
        }
        Ok(matrix_out(py, out, 3))
    }

    fn body_handle(slf: &Bound<'_, Self>, id: BodyId) -> Body {
        Body {
            world: slf.clone().unbind(),
            id,
        }
    }
}

/// A snapshot error as a Python exception: files that cannot be read or
/// written are `FileError`, anything wrong with the content (another format
/// version, corrupt or inconsistent data) `InvalidArgument`.
fn snapshot_error(e: SnapshotError) -> PyErr {
    match e {
        SnapshotError::Io { .. } => error(Kind::File, e.to_string()),
        _ => invalid(e.to_string()),
    }
}

impl World {
    /// The snapshot of the world with the Python row order in it.
    fn snapshot(&self) -> PyResult<Snapshot> {
        self.check_usable()?;
        let mut snap = self.inner.snapshot();
        snap.set_body_order(self.order.clone()).map_err(snapshot_error)?;
        Ok(snap)
    }

    /// A world continuing from `snap`, rows in its saved order.
    fn from_snapshot(snap: &Snapshot) -> PyResult<World> {
        let inner = RWorld::from_snapshot(snap).map_err(snapshot_error)?;
        Ok(World::from_parts(inner, snap.body_order().to_vec()))
    }
}

/// A 3-vector of a live body (ids come from `order`, so they are live).
/// Columns of a body's state row: position of the model frame (3),
/// orientation (x, y, z, w) (4), velocity of the centre of mass (3),
/// angular velocity (3), all in the world frame.
pub const STATE_COLUMNS: usize = 13;

/// One body's state row (NaN for a removed body).
pub(crate) fn state_row(w: &RWorld, id: BodyId) -> [f64; STATE_COLUMNS] {
    let mut row = [f64::NAN; STATE_COLUMNS];
    if let Ok(p) = w.pose(id) {
        row[..3].copy_from_slice(&p.position.to_array());
        row[3..7].copy_from_slice(&p.rotation.to_array());
    }
    row[7..10].copy_from_slice(&live3(w.linear_velocity(id)));
    row[10..].copy_from_slice(&live3(w.angular_velocity(id)));
    row
}

pub(crate) fn live3(r: Result<DVec3, tumble::world::WorldError>) -> [f64; 3] {
    r.map(|v| v.to_array()).unwrap_or([f64::NAN; 3])
}

#[pymethods]
impl World {
    #[new]
    #[pyo3(
        signature = (**settings),
        text_signature = "(*, gravity=(0, 0, -9.81), dt=0.016666666666666666, substeps=8, integrator='semi_implicit', \
            solver='pgs', iterations=2, push_out_iterations=1, contact_margin=0.005, \
            mesh_contact_margin=0.002, resting_motion=5e-07, allowed_penetration=0.0005, push_out_fraction=0.2, max_push_out_speed=3.0, \
            restitution_threshold=0.5, continuous=True, sleeping=True, sleep_linear_speed=0.05, \
            sleep_angular_speed=0.05, time_to_sleep=0.5, threads=0, adaptive_threads=True)"
    )]
    fn new(settings: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        guard(|| {
            let mut s = WorldSettings::default();
            settings::apply(&mut s, settings)?;
            let inner = RWorld::new(s).or_raise()?;
            Ok(World::from_parts(inner, Vec::new()))
        })
    }

    /// Adds a body and returns its handle.
    ///
    /// Args:
    ///     shape: a shape (Box, Sphere, Capsule, ConvexHull, TriMesh, HalfSpace),
    ///         a trimesh.Trimesh-like object, a Placed shape, or a list of
    ///         those for a compound body; None (or []) for a body without
    ///         shapes, which touches nothing: a kinematic one, or a dynamic
    ///         one given `mass` and `inertia`.
    ///     mass: total mass (kg), spread by volume. Dynamic bodies only.
    ///     density: uniform density (kg/m^3); default 1000 when neither is given.
    ///     inertia: the inertia about the centre of mass in the model frame
    ///         (kg m^2): 3 numbers (a diagonal) or a symmetric 3x3 matrix,
    ///         with `mass`; the shapes then only collide.
    ///     center_of_mass: with `inertia`, the centre of mass in the model
    ///         frame (m), default (0, 0, 0).
    ///     position: model-frame origin in the world (m), default (0, 0, 0).
    ///     orientation: (x, y, z, w) unit quaternion, default identity.
    ///     velocity: linear velocity of the centre of mass (m/s).
    ///     angular_velocity: world frame (rad/s).
    ///     kind: "dynamic" (default), "static" or "kinematic".
    ///     restitution: coefficient of restitution in [0, 1], default 0.
    ///     friction: Coulomb coefficient >= 0, default 0.5.
    ///     linear_damping: 1/s, default 0.
    ///     angular_damping: 1/s, default 0.
    ///     ccd: a bullet: always swept by continuous collision, against
    ///         dynamic bodies too (bodies that move more than half their
    ///         thickness in a step are swept against static and kinematic
    ///         ones anyway), default False.
    ///     non_colliding_group: bodies that share a nonzero group never
    ///         touch each other (they still touch every other body),
    ///         default 0 (none).
    ///     name: optional name (exports, find()).
    ///
    /// Raises:
    ///     InvalidArgument: a bad value or shape; the world is unchanged.
    #[pyo3(signature = (shape, *, mass=None, density=None, inertia=None, center_of_mass=None,
        position=None, orientation=None, velocity=None, angular_velocity=None, kind="dynamic",
        restitution=None, friction=None, linear_damping=0.0, angular_damping=0.0, ccd=false,
        non_colliding_group=0, name=None))]
    #[allow(clippy::too_many_arguments)]
    fn add_body(
        slf: &Bound<'_, Self>,
        shape: &Bound<'_, PyAny>,
        mass: Option<f64>,
        density: Option<f64>,
        inertia: Option<&Bound<'_, PyAny>>,
        center_of_mass: Option<&Bound<'_, PyAny>>,
        position: Option<&Bound<'_, PyAny>>,
        orientation: Option<&Bound<'_, PyAny>>,
        velocity: Option<&Bound<'_, PyAny>>,
        angular_velocity: Option<&Bound<'_, PyAny>>,
        kind: &str,
        restitution: Option<f64>,
        friction: Option<f64>,
        linear_damping: f64,
        angular_damping: f64,
        ccd: bool,
        non_colliding_group: u32,
        name: Option<String>,
    ) -> PyResult<Body> {
        guard(|| {
            slf.borrow().check_usable()?;
            let kind = kind_from(kind)?;
            if kind != BodyKind::Dynamic && (mass.is_some() || density.is_some()) {
                return Err(invalid("mass and density apply to dynamic bodies only"));
            }
            let inertia = inertia.filter(|i| !i.is_none());
            let center_of_mass = center_of_mass.filter(|c| !c.is_none());
            if kind != BodyKind::Dynamic && inertia.is_some() {
                return Err(invalid("inertia applies to dynamic bodies only"));
            }
            if center_of_mass.is_some() && inertia.is_none() {
                return Err(invalid(
                    "center_of_mass is given with inertia (else it follows from the shapes)",
                ));
            }
            let mass = match (mass, density, inertia) {
                (_, Some(_), Some(_)) => return Err(invalid("give inertia with mass, not density")),
                (None, None, Some(_)) => return Err(invalid("inertia needs mass (kg)")),
                (Some(m), None, Some(i)) => {
                    let com = convert::vec3_or(center_of_mass, "center_of_mass", DVec3::ZERO)?;
                    let p = MassProperties::new(m, com, inertia_matrix(i)?)
                        .map_err(|e| invalid(format!("mass, center_of_mass, inertia: {e}")))?;
                    MassDesc::Inertial(p)
                }
                (Some(_), Some(_), None) => return Err(invalid("give mass or density, not both")),
                (Some(m), None, None) => MassDesc::Mass(m),
                (None, Some(d), None) => MassDesc::Density(d),
                (None, None, None) => MassDesc::default(),
            };
            let pose = Pose {
                position: convert::vec3_or(position, "position", DVec3::ZERO)?,
                rotation: convert::quat_or_identity(orientation, "orientation")?,
            };
            let defaults = MaterialDesc::default();
            let desc = BodyDesc {
                kind,
                shapes: shape_descs(shape)?,
                mass,
                pose,
                linear_velocity: convert::vec3_or(velocity, "velocity", DVec3::ZERO)?,
                angular_velocity: convert::vec3_or(angular_velocity, "angular_velocity", DVec3::ZERO)?,
                material: MaterialDesc {
                    friction: friction.unwrap_or(defaults.friction),
                    restitution: restitution.unwrap_or(defaults.restitution),
                },
                linear_damping,
                angular_damping,
                ccd,
                non_colliding_group,
                name: name.unwrap_or_default(),
            };
            let id = {
                let mut w = slf.borrow_mut();
                let id = w.inner.add_body(&desc).or_raise()?;
                w.order.push(id);
                w.reindex();
                id
            };
            Ok(World::body_handle(slf, id))
        })
    }

    /// Adds a joint between `body_a` and `body_b` (None: the world), its
    /// anchor and axis given in world coordinates now (the present pose is
    /// the joint's zero).
    ///
    /// Args:
    ///     kind: "fixed", "ball", "hinge", "slider" or "distance".
    ///     anchor: the anchor point (m); on a distance joint the anchor on A.
    ///     axis: hinge axis, slider direction, ball cone axis (default z).
    ///     anchor_b: distance joint, the anchor on B (default `anchor`).
    ///     limits: (lower, upper): rad (hinge, ball twist) or m (slider,
    ///         distance; (0, L) makes a rope).
    ///     swing_limit: ball joint cone half-angle (rad).
    ///     motor: hinge or slider motor, {"target_velocity": v, "max_force": f}
    ///         or {"target_position": x, "stiffness": k, "damping": c,
    ///         "max_force": f} (N m or N); a ball joint's, the same with
    ///         3-vector targets (world axes at creation, turning with B):
    ///         the angular velocity of A relative to B (rad/s), or the
    ///         rotation vector (rad) by which A is turned relative to B from
    ///         its orientation at creation, with a torque at most `max_force`
    ///         long (N m).
    ///     spring: a spring-damper (stiffness, damping) or {"stiffness": k,
    ///         "damping": c}: distance joint N/m and N s/m towards `length`;
    ///         hinge N m/rad and N m s/rad, slider N/m and N s/m, towards the
    ///         position at creation, beside the motor; ball joint N m/rad and
    ///         N m s/rad about every axis, towards the relative orientation
    ///         at creation.
    ///     length: distance joint rest length (m; default the anchors' distance).
    ///     friction: Coulomb friction on the joint's coordinate, beside the
    ///         motor and spring (N m on a hinge, and whichever way a ball
    ///         joint turns; N on a slider or rope; not on a weld or rod).
    ///     collide_connected: contacts between the two bodies (default off).
    ///
    /// Raises:
    ///     InvalidArgument: a bad value; the world is unchanged.
    #[pyo3(signature = (kind, body_a, body_b=None, *, anchor, axis=None, anchor_b=None, limits=None,
        swing_limit=None, motor=None, spring=None, length=None, friction=None, collide_connected=false,
        name=None))]
    #[allow(clippy::too_many_arguments)]
    fn add_joint(
        slf: &Bound<'_, Self>,
        kind: &str,
        body_a: PyRef<'_, Body>,
        body_b: Option<PyRef<'_, Body>>,
        anchor: &Bound<'_, PyAny>,
        axis: Option<&Bound<'_, PyAny>>,
        anchor_b: Option<&Bound<'_, PyAny>>,
        limits: Option<(f64, f64)>,
        swing_limit: Option<f64>,
        motor: Option<&Bound<'_, PyAny>>,
        spring: Option<&Bound<'_, PyAny>>,
        length: Option<f64>,
        friction: Option<f64>,
        collide_connected: bool,
        name: Option<String>,
    ) -> PyResult<Joint> {
        let args = JointArgs {
            kind,
            anchor,
            axis,
            anchor_b,
            limits,
            swing_limit,
            motor,
            spring,
            friction,
            length,
            collide_connected,
            name,
        };
        crate::joint::add_joint(slf, body_a, body_b, args)
    }

    /// Removes a joint; its handle becomes stale. Same as `joint.remove()`.
    fn remove_joint(slf: &Bound<'_, Self>, joint: PyRef<'_, Joint>) -> PyResult<()> {
        if joint.world.as_ptr() != slf.as_ptr() {
            return Err(invalid("the joint belongs to another world"));
        }
        let mut w = slf.borrow_mut();
        w.check_usable()?;
        w.inner.remove_joint(joint.id).or_raise()
    }

    /// Handles of every joint, in slot order (the rows of `joint_states()`).
    fn joints(slf: &Bound<'_, Self>) -> PyResult<Vec<Joint>> {
        let ids = slf.borrow().inner.joint_ids();
        Ok(ids
            .into_iter()
            .map(|id| Joint {
                world: slf.clone().unbind(),
                id,
            })
            .collect())
    }

    /// The state of every joint as arrays, one row per joint in `joints()`
    /// order: "position", "rate", "linear_error", "angular_error" (J,),
    /// "force", "torque", "anchor_a", "anchor_b", "axis", "rotation" (J, 3).
    fn joint_states<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        self.check_usable()?;
        crate::joint::joint_arrays(py, &self.inner)
    }

    /// Removes a body; its handle becomes stale. Same as `body.remove()`.
    fn remove_body(slf: &Bound<'_, Self>, body: PyRef<'_, Body>) -> PyResult<()> {
        let id = body.id_in(slf)?;
        guard(|| slf.borrow_mut().remove(id))
    }

    /// Allows (``True``) or forbids (``False``) contacts between two bodies
    /// from the next step on (Bullet's ``setCollisionFilterPair``, MuJoCo's
    /// ``<exclude>``). Allowing undoes only such an exclusion: bodies of one
    /// non-colliding group, or jointed without ``collide_connected``, still
    /// never touch (``contacts_allowed``). Both bodies wake if it changes
    /// anything.
    ///
    /// Raises:
    ///     InvalidArgument: a body given twice, or one of another world.
    ///     StaleBodyError: a removed body.
    fn set_contacts_between(
        slf: &Bound<'_, Self>,
        body_a: PyRef<'_, Body>,
        body_b: PyRef<'_, Body>,
        allowed: bool,
    ) -> PyResult<()> {
        let (a, b) = (body_a.id_in(slf)?, body_b.id_in(slf)?);
        guard(|| {
            let mut w = slf.try_borrow_mut().map_err(|_| busy())?;
            w.check_usable()?;
            w.inner.set_contacts_between(a, b, allowed).or_raise()
        })
    }

    /// Whether two bodies may touch: not in one non-colliding group, not
    /// jointed without ``collide_connected``, not kept apart by
    /// ``set_contacts_between``.
    ///
    /// Raises:
    ///     InvalidArgument: a body given twice, or one of another world.
    ///     StaleBodyError: a removed body.
    fn contacts_allowed(
        slf: &Bound<'_, Self>,
        body_a: PyRef<'_, Body>,
        body_b: PyRef<'_, Body>,
    ) -> PyResult<bool> {
        let (a, b) = (body_a.id_in(slf)?, body_b.id_in(slf)?);
        guard(|| {
            let w = slf.try_borrow().map_err(|_| busy())?;
            w.check_usable()?;
            w.inner.contacts_allowed(a, b).or_raise()
        })
    }

    /// The (Body, Body) pairs ``set_contacts_between`` keeps apart, each
    /// with the body added first (the lower slot) first, in that order.
    fn excluded_contact_pairs(slf: &Bound<'_, Self>) -> PyResult<Vec<(Body, Body)>> {
        let pairs = guard(|| {
            let w = slf.try_borrow().map_err(|_| busy())?;
            w.check_usable()?;
            Ok(w.inner.excluded_contact_pairs().to_vec())
        })?;
        Ok(pairs
            .into_iter()
            .map(|(a, b)| (World::body_handle(slf, a), World::body_handle(slf, b)))
            .collect())
    }

    /// Advances the world by `n` steps of `dt` each, with the GIL released.
    /// Ctrl-C stops it between two steps (KeyboardInterrupt; the steps taken
    /// so far are kept).
    ///
    /// Contact events of these steps are in `contact_events()`, the report of
    /// the last step in `step_report`. Warnings of the solver (and bodies
    /// stopped because their state became non-finite) are issued as Python
    /// RuntimeWarnings.
    #[pyo3(signature = (n=1))]
    fn step(&mut self, py: Python<'_>, n: u64) -> PyResult<()> {
        self.check_usable()?;
        let World {
            inner,
            summary,
            recorder,
            poisoned,
            ..
        } = self;
        summary.clear();
        let mut done = 0u64;
        while done < n {
            // Steps run in slices of about SIGNAL_CHECK_PERIOD with the GIL
            // released; between slices Ctrl-C (or any signal handler) can
            // stop a long step(n), always between two whole steps.
            let run = py.detach(|| {
                catch_unwind(AssertUnwindSafe(|| {
                    let start = Instant::now();
                    while done < n {
                        let r = inner.step();
                        summary.absorb(r, inner.time());
                        if let Some(rec) = recorder.as_mut() {
                            rec.after_step(inner);
                        }
                        done += 1;
                        if start.elapsed() > SIGNAL_CHECK_PERIOD {
                            break;
                        }
                    }
                }))
            });
            if let Err(payload) = run {
                let message = panic_message(payload.as_ref());
                *poisoned = Some(message.clone());
                return Err(error(
                    Kind::Internal,
                    format!("internal error in tumble during step(): {message}"),
                ));
            }
            if done < n {
                py.check_signals()?;
            }
        }
        report::warn_summary(py, &self.summary)
    }

    /// Positions of the bodies' model-frame origins (m): float64 (N, 3).
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.rows_of(py, |w, id| live3(w.pose(id).map(|p| p.position)))
    }

    /// Orientations of the bodies' model frames as (x, y, z, w): float64 (N, 4).
    #[getter]
    fn orientations<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.check_usable()?;
        let mut data = Vec::with_capacity(self.order.len() * 4);
        for &id in &self.order {
            let q = self
                .inner
                .orientation(id)
                .map(|q| q.to_array())
                .unwrap_or([f64::NAN; 4]);
            data.extend_from_slice(&q);
        }
        Ok(matrix_out(py, data, 4))
    }

    /// A copy of this world (bodies, joints, contacts and warm starts, time,
    /// settings): stepping the copy gives the trajectory this world would
    /// have, bit for bit. Meshes and their trees are shared, not copied, so
    /// a copy is cheap; recording is not copied.
    fn copy(&self) -> PyResult<World> {
        self.check_usable()?;
        Ok(World::from_parts(self.inner.clone(), self.order.clone()))
    }

    fn __copy__(&self) -> PyResult<World> {
        self.copy()
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> PyResult<World> {
        self.copy()
    }

    /// The state of every body: float64 (N, 13), columns x, y, z (model
    /// frame origin, m), qx, qy, qz, qw, vx, vy, vz (centre of mass, m/s),
    /// wx, wy, wz (rad/s), world frame. `set_states` takes the same array.
    #[getter]
    fn states<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.check_usable()?;
        Ok(matrix_out(py, self.state_rows(), STATE_COLUMNS))
    }

    /// Sets the state of every body from an (N, 13) array laid out as
    /// `states` (rows in body order). Static bodies take the pose only and
    /// must be given zero velocities. Checked whole before anything is set:
    /// on error the world is unchanged.
    fn set_states(&mut self, states: &Bound<'_, PyAny>) -> PyResult<()> {
        self.check_usable()?;
        guard(|| {
            let rows = crate::rollout::state_matrix(states, self.order.len(), "states")?;
            crate::rollout::set_states(&mut self.inner, &self.order, &rows).map_err(invalid)
        })
    }

    /// Positions and orientations in one pass: float64 (N, 7), columns
    /// x, y, z, qx, qy, qz, qw.
    fn poses<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.check_usable()?;
        let mut data = Vec::with_capacity(self.order.len() * 7);
        for &id in &self.order {
            match self.inner.pose(id) {
                Ok(p) => {
                    data.extend_from_slice(&p.position.to_array());
                    data.extend_from_slice(&p.rotation.to_array());
                }
                Err(_) => data.extend_from_slice(&[f64::NAN; 7]),
            }
        }
        Ok(matrix_out(py, data, 7))
    }

    // `velocities`, `angular_velocities` and `centers_of_mass` (and `positions`
    // above): one getter per Python array attribute, each a call of `rows_of`.
    /// Linear velocities of the centres of mass (m/s): float64 (N, 3).
    #[getter]
    fn velocities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.rows_of(py, |w, id| live3(w.linear_velocity(id)))
    }

    /// Angular velocities, world frame (rad/s): float64 (N, 3).
    #[getter]
    fn angular_velocities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.rows_of(py, |w, id| live3(w.angular_velocity(id)))
    }

    /// Centres of mass (m): float64 (N, 3).
    #[getter]
    fn centers_of_mass<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.rows_of(py, |w, id| live3(w.center_of_mass(id)))
    }

    /// The bodies, in insertion order (the rows of the arrays).
    #[getter]
    fn bodies(slf: &Bound<'_, Self>) -> PyResult<Vec<Body>> {
        let ids = slf.borrow().order.clone();
        Ok(ids.into_iter().map(|id| World::body_handle(slf, id)).collect())
    }

    /// The first body with this name, or None.
    fn find(slf: &Bound<'_, Self>, name: &str) -> Option<Body> {
        let id = {
            let w = slf.borrow();
            w.order.iter().copied().find(|&id| w.inner.name(id) == Ok(name))
        };
        id.map(|id| World::body_handle(slf, id))
    }

    /// Adds a force (N) for the next step, at the centre of mass or, if
    /// `point` is given, at that world point (adding the torque). Wakes the body.
    #[pyo3(signature = (body, force, point=None))]
    fn apply_force(
        slf: &Bound<'_, Self>,
        body: PyRef<'_, Body>,
        force: &Bound<'_, PyAny>,
        point: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let id = body.id_in(slf)?;
        crate::body::apply_force(&mut slf.borrow_mut(), id, force, point)
    }

    /// Adds one force per body (N) for the next step, at the centres of mass:
    /// float array (N, 3) in row order. Rows of zeros are skipped; a non-zero
    /// row for a static or kinematic body is an error (nothing is applied).
    fn apply_forces(&mut self, forces: &Bound<'_, PyAny>) -> PyResult<()> {
        self.check_usable()?;
        guard(|| {
            let f = convert::points(forces, "forces")?;
            if f.len() != self.order.len() {
                return Err(invalid(format!(
                    "forces: expected one row per body ({} rows), got {}",
                    self.order.len(),
                    f.len()
                )));
            }
            for (row, (&id, v)) in self.order.iter().zip(&f).enumerate() {
                if !v.is_finite() {
                    return Err(invalid(format!("forces: row {row} is not finite: {v:?}")));
                }
                if *v != DVec3::ZERO && self.inner.body(id).or_raise()?.kind() != BodyKind::Dynamic {
                    return Err(invalid(format!(
                        "forces: row {row} is a non-dynamic body; forces act on dynamic bodies only"
                    )));
                }
            }
            for (&id, v) in self.order.clone().iter().zip(f) {
                if v != DVec3::ZERO {
                    self.inner.apply_force(id, v).or_raise()?;
                }
            }
            Ok(())
        })
    }

    /// Contact points of the last step as a numpy structured array with fields
    /// body_a, body_b (int64 rows; the normal points from B towards A),
    /// point (3,), normal (3,) (world frame), distance (m, negative when
    /// penetrating), depth (= -distance), normal_impulse (N s),
    /// tangent_impulse (3,) (N s), kind (str).
    fn contacts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.check_usable()?;
        guard(|| report::contacts_array(py, self))
    }

    /// Contact begin/end events of the last `step(n)` call, in order: a list
    /// of ContactEvent(kind, body_a, body_b, time) with kind "begin" or "end".
    fn contact_events<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyList>> {
        let events = slf.borrow().summary.events.clone();
        let py = slf.py();
        let list = PyList::empty(py);
        for (begin, a, b, time) in events {
            let ev = crate::records::record(
                py,
                "ContactEvent",
                (
                    if begin { "begin" } else { "end" },
                    World::body_handle(slf, a),
                    World::body_handle(slf, b),
                    time,
                ),
            )?;
            list.append(ev)?;
        }
        Ok(list)
    }

    /// Report of the last step (counters, stage times, warnings of the last
    /// `step(n)` call).
    #[getter]
    fn step_report(slf: &Bound<'_, Self>) -> PyResult<PyStepReport> {
        let w = slf.borrow();
        let quarantined = w
            .summary
            .quarantined
            .iter()
            .map(|&id| World::body_handle(slf, id))
            .collect();
        Ok(PyStepReport::new(&w.summary, quarantined))
    }

    /// Total kinetic energy of the dynamic bodies (J).
    #[getter]
    fn kinetic_energy(&self) -> PyResult<f64> {
        self.check_usable()?;
        Ok(self.inner.kinetic_energy())
    }

    /// Gravitational potential energy of the dynamic bodies, -m g . x (J).
    #[getter]
    fn potential_energy(&self) -> PyResult<f64> {
        self.check_usable()?;
        Ok(self.inner.potential_energy())
    }

    // One-line getters like TriMesh's `volume`/`area` (trimesh.rs) and Capsule's
    // (shapes.rs): pyo3 needs a method per attribute of each class.
    /// Simulated time (s).
    #[getter]
    fn time(&self) -> f64 {
        self.inner.time()
    }

    /// Steps taken.
    #[getter]
    fn step_count(&self) -> u64 {
        self.inner.step_count()
    }

    /// Time step (s).
    #[getter]
    fn dt(&self) -> f64 {
        self.inner.settings().dt
    }

    /// The settings as a dict of keyword -> value.
    #[getter]
    fn settings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        settings::to_dict(py, self.inner.settings())
    }

    /// Changes some settings (same keywords as the constructor); validated,
    /// unchanged on error.
    #[pyo3(signature = (**settings))]
    fn update_settings(&mut self, settings: Option<&Bound<'_, PyDict>>) -> PyResult<()> {
        self.check_usable()?;
        guard(|| {
            let mut s = self.inner.settings().clone();
            settings::apply(&mut s, settings)?;
            self.inner.set_settings(s).or_raise()
        })
    }

    /// Starts recording a frame every `every` steps (and the current state
    /// now) for export_gltf / export_csv. Bodies added later are not recorded.
    #[pyo3(signature = (every=1))]
    fn start_recording(&mut self, every: u32) -> PyResult<()> {
        self.check_usable()?;
        guard(|| {
            self.recorder = Some(Recorder::start(&self.inner, every)?);
            Ok(())
        })
    }

    /// Stops recording and forgets the frames.
    fn stop_recording(&mut self) {
        self.recorder = None;
    }

    /// Frames recorded so far (0 when not recording).
    #[getter]
    fn recorded_frames(&self) -> usize {
        self.recorder.as_ref().map_or(0, Recorder::frames)
    }

    /// Writes the recording (or, when not recording, the current state as one
    /// frame) as an animated binary glTF (.glb) for the viewer and any glTF tool.
    fn export_gltf(&self, path: PathBuf) -> PyResult<()> {
        self.check_usable()?;
        guard(|| Recorder::export_glb(self.recorder.as_ref(), &self.inner, &path))
    }

    /// Writes the recording (or the current state) as a CSV trajectory table.
    fn export_csv(&self, path: PathBuf) -> PyResult<()> {
        self.check_usable()?;
        guard(|| Recorder::export_csv(self.recorder.as_ref(), &self.inner, &path))
    }

    /// Saves the complete state (settings, bodies in row order, contacts'
    /// warm-start cache, time, step count) to `path`: compact binary, or
    /// JSON when the name ends in ``.json``. `World.load(path)` continues
    /// exactly: the same steps give bit-identical arrays. Recordings and the
    /// last step's report and contacts are not saved.
    ///
    /// Raises:
    ///     FileError: the file cannot be written.
    fn save(&self, path: PathBuf) -> PyResult<()> {
        guard(|| self.snapshot()?.save(&path).map_err(snapshot_error))
    }

    /// A world from a file written by `save`.
    ///
    /// Raises:
    ///     FileError: the file cannot be read (missing, empty).
    ///     InvalidArgument: not a snapshot, corrupt, or written by a tumble
    ///         with another snapshot format version.
    #[staticmethod]
    fn load(path: PathBuf) -> PyResult<World> {
        guard(|| World::from_snapshot(&Snapshot::load(&path).map_err(snapshot_error)?))
    }

    /// The state as bytes (the binary snapshot of `save`).
    fn to_bytes<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        let bytes = guard(|| Ok(self.snapshot()?.to_bytes()))?;
        Ok(PyBytes::new(py, &bytes))
    }

    /// A world from `to_bytes()` output.
    ///
    /// Raises:
    ///     InvalidArgument: not a snapshot, corrupt, or of another format version.
    #[staticmethod]
    fn from_bytes(data: &[u8]) -> PyResult<World> {
        guard(|| World::from_snapshot(&Snapshot::from_bytes(data).map_err(snapshot_error)?))
    }

    /// Pickling (and copy.deepcopy) through the binary snapshot.
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<(Bound<'py, PyAny>, (Bound<'py, PyBytes>,))> {
        let py = slf.py();
        let bytes = slf.borrow().to_bytes(py)?;
        let from_bytes = slf.get_type().getattr("from_bytes")?;
        Ok((from_bytes, (bytes,)))
    }

    fn __len__(&self) -> usize {
        self.order.len()
    }

    fn __repr__(&self) -> String {
        format!(
            "tumble.World(bodies={}, time={:.6}, dt={}, steps={})",
            self.order.len(),
            self.inner.time(),
            self.inner.settings().dt,
            self.inner.step_count()
        )
    }
}

/// `add_body(inertia=...)`: 3 numbers (a diagonal) or a 3x3 matrix (kg m^2).
fn inertia_matrix(obj: &Bound<'_, PyAny>) -> PyResult<DMat3> {
    if let Ok(d) = convert::vec3(obj, "inertia") {
        return Ok(DMat3::from_diagonal(d));
    }
    let rows = convert::points(obj, "inertia")
        .ok()
        .filter(|rows| rows.len() == 3)
        .ok_or_else(|| {
            invalid(format!(
                "inertia: expected 3 numbers (a diagonal) or a 3x3 matrix, got {}",
                convert::describe(obj)
            ))
        })?;
    // Symmetric (checked by MassProperties::new): rows are columns.
    Ok(DMat3::from_cols(rows[0], rows[1], rows[2]))
}
