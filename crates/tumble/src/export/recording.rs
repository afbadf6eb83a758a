//! The recording type that exporters consume: a list of bodies (mesh in the
//! body frame, colour) and, for each frame, the time and every body's pose.
//!
//! It is deliberately independent of the world type so that anything that can
//! produce poses (the simulator, an analytic trajectory, a replay) can export.
//! Validation is done once here, so the writers can assume finite data.

use std::path::PathBuf;

use tumble_collide::{Contact, DQuat, DVec3, Pose, TriMesh};

/// Why a recording could not be exported.
#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    /// No bodies or no frames.
    #[error("recording is empty: {bodies} bodies, {frames} frames (need at least 1 of each)")]
    Empty {
        /// Number of bodies found.
        bodies: usize,
        /// Number of frames found.
        frames: usize,
    },
    /// `frame_times` and `frames` (or `extras`) have different lengths.
    #[error("{what} has {found} entries but there are {expected} frame times")]
    FrameCountMismatch {
        /// Which list is the wrong length (`"frames"` or `"extras"`).
        what: &'static str,
        /// Its length.
        found: usize,
        /// `frame_times.len()`.
        expected: usize,
    },
    /// A frame does not hold exactly one pose per body.
    #[error("frame {frame} has {found} poses but there are {expected} bodies")]
    BodyCountMismatch {
        /// Frame index.
        frame: usize,
        /// Poses in that frame.
        found: usize,
        /// `bodies.len()`.
        expected: usize,
    },
    /// A pose has a non-finite component or a non-unit quaternion.
    #[error("frame {frame}, body {body}: pose must be finite with a unit quaternion, got {pose:?}")]
    BadPose {
        /// Frame index.
        frame: usize,
        /// Body index.
        body: usize,
        /// The offending pose.
        pose: Pose,
    },
    /// Frame times must be finite, non-negative and strictly increasing even
    /// after rounding to `f32` (glTF animation inputs are `f32`).
    #[error("frame time {frame} is {time} s; times must be finite, >= 0 and strictly increasing in f32")]
    BadTime {
        /// Frame index.
        frame: usize,
        /// The offending time (s).
        time: f64,
    },
    /// A body colour component is outside [0, 1] or not finite.
    #[error("body {body} colour {color:?}: components must be finite and in [0, 1]")]
    BadColor {
        /// Body index.
        body: usize,
        /// The colour (linear RGBA).
        color: [f32; 4],
    },
    /// A per-frame extra value (energy, contact point or normal) is not finite.
    #[error("frame {frame}: extra data `{what}` is not finite")]
    NonFiniteExtra {
        /// Frame index.
        frame: usize,
        /// Which value.
        what: &'static str,
    },
    /// An OBB box refers to a missing body or has non-finite / negative data.
    #[error("OBB box {index}: {reason}")]
    BadObbBox {
        /// Index into [`Recording::obb_boxes`].
        index: usize,
        /// What is wrong.
        reason: String,
    },
    /// A joint refers to a missing body or has a non-finite anchor or axis.
    #[error("joint {index}: {reason}")]
    BadJoint {
        /// Index into [`Recording::joints`].
        index: usize,
        /// What is wrong.
        reason: String,
    },
    /// The export is larger than a GLB file can address (4 GiB).
    #[error("export too large for GLB: {0} bytes")]
    TooLarge(usize),
    /// A results table that cannot be written (ragged columns, bad path).
    #[error("results table: {0}")]
    BadTable(String),
    /// Writing the file failed.
    #[error("cannot write {path}: {source}")]
    Io {
        /// The file being written.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
}

/// One body as it appears in a recording.
#[derive(Debug, Clone)]
pub struct RecordedBody {
    /// Display name (becomes the glTF node name).
    pub name: String,
    /// Surface mesh in the body frame (m).
    pub mesh: TriMesh,
    /// Linear RGBA colour, each component in [0, 1]; alpha < 1 makes the
    /// material blended.
    pub color: [f32; 4],
    /// Static bodies whose pose never changes get no animation channels.
    pub is_static: bool,
}

/// A contact to draw: a world-frame point and normal (z up).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactMark {
    /// Contact point in the world frame (m).
    pub point: DVec3,
    /// Unit normal in the world frame, from body B to body A.
    pub normal: DVec3,
    /// Signed distance (m): > 0 gap, < 0 penetration.
    pub distance: f64,
}

impl From<&Contact> for ContactMark {
    fn from(c: &Contact) -> Self {
        ContactMark {
            point: c.point,
            normal: c.normal,
            distance: c.distance,
        }
    }
}

/// Optional per-frame data for the viewer's plots and overlays.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FrameExtras {
    /// Total kinetic energy (J).
    pub kinetic_energy: f64,
    /// Total gravitational potential energy (J), relative to any fixed datum.
    pub potential_energy: f64,
    /// Number of contacts in the frame (may exceed `contacts.len()` when only
    /// some are kept for drawing).
    pub contact_count: usize,
    /// Contacts to draw.
    pub contacts: Vec<ContactMark>,
}

/// An oriented bounding box of a body's OBBTree, in the body frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ObbBox {
    /// Index of the body in [`Recording::bodies`].
    pub body: usize,
    /// Depth in the tree (0 = root).
    pub depth: u32,
    /// Centre in the body frame (m).
    pub center: DVec3,
    /// Orientation of the box axes relative to the body frame.
    pub rotation: DQuat,
    /// Half extents along the box axes (m), each >= 0.
    pub half_extents: DVec3,
}

/// A joint to draw: its anchor and axis fixed in body A's recorded frame, so
/// that they move with A.
#[derive(Debug, Clone, PartialEq)]
pub struct RecordedJoint {
    /// The joint's name (may be empty).
    pub name: String,
    /// "fixed", "ball", "hinge", "slider" or "distance".
    pub kind: String,
    /// Index of body A in [`Recording::bodies`].
    pub body_a: usize,
    /// Index of body B, or `None` for the world (or a body not recorded).
    pub body_b: Option<usize>,
    /// The anchor in body A's recorded frame (m).
    pub anchor: DVec3,
    /// The joint axis in body A's recorded frame (unit).
    pub axis: DVec3,
}

/// A recorded simulation: `frames[f][b]` is the pose of body `b` at time
/// `frame_times[f]` (frame-major).
#[derive(Debug, Clone, Default)]
pub struct Recording {
    /// The bodies, in a fixed order shared by every frame.
    pub bodies: Vec<RecordedBody>,
    /// Time of each frame (s), strictly increasing.
    pub frame_times: Vec<f64>,
    /// Poses, `frames[f][b]`.
    pub frames: Vec<Vec<Pose>>,
    /// Per-frame viewer data; empty for none, otherwise one entry per frame.
    pub extras: Vec<FrameExtras>,
    /// OBBTree boxes to draw (body frame); may be empty.
    pub obb_boxes: Vec<ObbBox>,
    /// Joints to draw; may be empty.
    pub joints: Vec<RecordedJoint>,
}

impl Recording {
    /// Checks every invariant the exporters rely on.
    pub fn validate(&self) -> Result<(), ExportError> {
        let n_frames = self.frame_times.len();
        for (index, j) in self.joints.iter().enumerate() {
            let bad = j.body_a >= self.bodies.len() || j.body_b.is_some_and(|b| b >= self.bodies.len());
            if bad || !j.anchor.is_finite() || !j.axis.is_finite() {
                return Err(ExportError::BadJoint {
                    index,
                    reason: format!(
                        "bodies {} and {:?} of {}, anchor {:?}, axis {:?}",
                        j.body_a,
                        j.body_b,
                        self.bodies.len(),
                        j.anchor,
                        j.axis
                    ),
                });
            }
        }
        if self.bodies.is_empty() || n_frames == 0 {
            return Err(ExportError::Empty {
                bodies: self.bodies.len(),
                frames: n_frames,
            });
        }
        if self.frames.len() != n_frames {
            return Err(ExportError::FrameCountMismatch {
                what: "frames",
                found: self.frames.len(),
                expected: n_frames,
            });
        }
        if !self.extras.is_empty() && self.extras.len() != n_frames {
            return Err(ExportError::FrameCountMismatch {
                what: "extras",
                found: self.extras.len(),
                expected: n_frames,
            });
        }
        let mut previous: Option<f32> = None;
        for (frame, &time) in self.frame_times.iter().enumerate() {
            let t32 = time as f32;
            let ok = time.is_finite() && time >= 0.0 && !matches!(previous, Some(p) if t32 <= p);
            if !ok {
                return Err(ExportError::BadTime { frame, time });
            }
            previous = Some(t32);
        }
        for (body, b) in self.bodies.iter().enumerate() {
            if !b.color.iter().all(|c| c.is_finite() && (0.0..=1.0).contains(c)) {
                return Err(ExportError::BadColor { body, color: b.color });
            }
        }
        for (frame, poses) in self.frames.iter().enumerate() {
            if poses.len() != self.bodies.len() {
                return Err(ExportError::BodyCountMismatch {
                    frame,
                    found: poses.len(),
                    expected: self.bodies.len(),
                });
            }
            for (body, pose) in poses.iter().enumerate() {
                if Pose::new(pose.position, pose.rotation).is_err() {
                    return Err(ExportError::BadPose {
                        frame,
                        body,
                        pose: *pose,
                    });
                }
            }
        }
        for (frame, e) in self.extras.iter().enumerate() {
            if !e.kinetic_energy.is_finite() {
                return Err(ExportError::NonFiniteExtra {
                    frame,
                    what: "kinetic_energy",
                });
            }
            if !e.potential_energy.is_finite() {
                return Err(ExportError::NonFiniteExtra {
                    frame,
                    what: "potential_energy",
                });
            }
            for c in &e.contacts {
                if !(c.point.is_finite() && c.normal.is_finite() && c.distance.is_finite()) {
                    return Err(ExportError::NonFiniteExtra {
                        frame,
                        what: "contacts",
                    });
                }
            }
        }
        for (index, b) in self.obb_boxes.iter().enumerate() {
            let reason = if b.body >= self.bodies.len() {
                Some(format!(
                    "body {} does not exist ({} bodies)",
                    b.body,
                    self.bodies.len()
                ))
            } else if !(b.center.is_finite() && b.half_extents.is_finite()) {
                Some("centre and half extents must be finite".to_string())
            } else if b.half_extents.min_element() < 0.0 {
                Some(format!("half extents must be >= 0, got {:?}", b.half_extents))
            } else if Pose::new(b.center, b.rotation).is_err() {
                Some(format!(
                    "rotation must be a unit quaternion, got {:?}",
                    b.rotation
                ))
            } else {
                None
            };
            if let Some(reason) = reason {
                return Err(ExportError::BadObbBox { index, reason });
            }
        }
        Ok(())
    }

    /// Whether body `b` needs animation channels: it is dynamic, or its pose
    /// changes at some frame.
    pub fn is_animated(&self, b: usize) -> bool {
        !self.bodies[b].is_static || self.frames.iter().any(|f| f[b] != self.frames[0][b])
    }
}
