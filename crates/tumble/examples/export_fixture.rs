//! Writes a small analytic recording as `.glb` (and optionally `.csv`) for the
//! web viewer's tests and for trying the viewer by hand:
//!
//! ```text
//! cargo run -p tumble --example export_fixture -- out/viewer-test/fixture.glb [traj.csv]
//! ```
//!
//! The motion is closed-form, not simulated: a ball bouncing with restitution
//! 0.7 while rolling in x, a box sliding to rest under Coulomb friction, a
//! torus circling overhead while spinning, above a static ground slab. Energy,
//! contacts and per-body bounding boxes (a stand-in for OBBTree roots) are
//! included in the extras so that every viewer overlay has data.

use std::error::Error;
use std::path::PathBuf;

use tumble::export::{
    write_glb, write_trajectory_csv, ContactMark, FrameExtras, ObbBox, RecordedBody, Recording,
};
use tumble_collide::mesh::{box_mesh, icosphere_mesh, torus_mesh};
use tumble_collide::{DQuat, DVec3, Pose};

const G: f64 = 9.81; // m/s^2
const FPS: f64 = 60.0;
const DURATION: f64 = 3.0; // s
const MASS: f64 = 1.0; // kg, every body

const BALL_R: f64 = 0.3; // m
const BALL_Z0: f64 = 2.0; // m, centre height at rest at t = 0
const BALL_VX: f64 = 0.4; // m/s
const RESTITUTION: f64 = 0.7;

const BOX_HALF: DVec3 = DVec3::new(0.25, 0.15, 0.1); // m
const BOX_V0: f64 = 2.0; // m/s along x
const MU: f64 = 0.3;

const TORUS_ORBIT_R: f64 = 1.2; // m
const TORUS_ORBIT_W: f64 = 1.5; // rad/s
const TORUS_SPIN_W: f64 = 4.0; // rad/s
const TORUS_Z: f64 = 1.6; // m

/// Ball centre height and vertical velocity at time `t`: free fall from rest,
/// then arcs whose launch speed shrinks by the restitution at each impact.
fn ball_z(t: f64) -> (f64, f64) {
    let v_impact = (2.0 * G * (BALL_Z0 - BALL_R)).sqrt();
    let t_first = v_impact / G;
    if t < t_first {
        return (BALL_Z0 - 0.5 * G * t * t, -G * t);
    }
    let (mut start, mut v) = (t_first, RESTITUTION * v_impact);
    while v > 1e-3 {
        let flight = 2.0 * v / G;
        if t < start + flight {
            let s = t - start;
            return (BALL_R + v * s - 0.5 * G * s * s, v - G * s);
        }
        start += flight;
        v *= RESTITUTION;
    }
    (BALL_R, 0.0)
}

/// Sliding box: x position and speed, decelerating at mu g until it stops.
fn box_x(t: f64) -> (f64, f64) {
    let t_stop = BOX_V0 / (MU * G);
    let s = t.min(t_stop);
    (-1.5 + BOX_V0 * s - 0.5 * MU * G * s * s, BOX_V0 - MU * G * s)
}

fn main() -> Result<(), Box<dyn Error>> {
    let mut args = std::env::args().skip(1);
    let glb = PathBuf::from(
        args.next()
            .unwrap_or_else(|| "out/viewer-test/fixture.glb".into()),
    );
    let csv = args.next().map(PathBuf::from);
    if let Some(dir) = glb.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)?;
    }

    let bodies = vec![
        RecordedBody {
            name: "ground".into(),
            mesh: box_mesh(DVec3::new(3.0, 3.0, 0.1))?,
            color: [0.55, 0.57, 0.6, 1.0],
            is_static: true,
        },
        RecordedBody {
            name: "ball".into(),
            mesh: icosphere_mesh(BALL_R, 2)?,
            color: [0.9, 0.35, 0.2, 1.0],
            is_static: false,
        },
        RecordedBody {
            name: "slider".into(),
            mesh: box_mesh(BOX_HALF)?,
            color: [0.2, 0.55, 0.9, 1.0],
            is_static: false,
        },
        RecordedBody {
            name: "torus".into(),
            mesh: torus_mesh(0.35, 0.12, 24, 12)?,
            color: [0.3, 0.8, 0.4, 1.0],
            is_static: false,
        },
    ];

    let n = (DURATION * FPS) as usize + 1;
    let mut rec = Recording {
        bodies,
        ..Default::default()
    };
    let spin_axis = DVec3::new(1.0, 0.0, 1.0).normalize();
    for f in 0..n {
        let t = f as f64 / FPS;
        let (bz, bvz) = ball_z(t);
        let bx = -0.5 + BALL_VX * t;
        // Rolling in +x means spinning about -y at vx / r.
        let ball = Pose::new(
            DVec3::new(bx, 0.8, bz),
            DQuat::from_rotation_y(-BALL_VX * t / BALL_R),
        )?;
        let (sx, svx) = box_x(t);
        let slider = Pose::from_translation(DVec3::new(sx, -0.8, BOX_HALF.z));
        let phase = TORUS_ORBIT_W * t;
        let torus = Pose::new(
            DVec3::new(TORUS_ORBIT_R * phase.cos(), TORUS_ORBIT_R * phase.sin(), TORUS_Z),
            DQuat::from_axis_angle(spin_axis, TORUS_SPIN_W * t),
        )?;
        let ground = Pose::from_translation(DVec3::new(0.0, 0.0, -0.1));

        // Energy: translational + the ball's rolling spin (I = 2/5 m r^2).
        let ball_w = BALL_VX / BALL_R;
        let v_torus = TORUS_ORBIT_R * TORUS_ORBIT_W;
        let kinetic = 0.5 * MASS * (BALL_VX * BALL_VX + bvz * bvz)
            + 0.5 * 0.4 * MASS * BALL_R * BALL_R * ball_w * ball_w
            + 0.5 * MASS * svx * svx
            + 0.5 * MASS * v_torus * v_torus;
        let potential = MASS * G * (bz + BOX_HALF.z + TORUS_Z);

        let mut contacts: Vec<ContactMark> = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
            .iter()
            .map(|&(u, v)| ContactMark {
                point: DVec3::new(sx + u * BOX_HALF.x, -0.8 + v * BOX_HALF.y, 0.0),
                normal: DVec3::Z,
                distance: 0.0,
            })
            .collect();
        let gap = bz - BALL_R;
        if gap < 0.03 {
            contacts.push(ContactMark {
                point: DVec3::new(bx, 0.8, 0.5 * gap),
                normal: DVec3::Z,
                distance: gap,
            });
        }
        rec.frame_times.push(t);
        rec.frames.push(vec![ground, ball, slider, torus]);
        rec.extras.push(FrameExtras {
            kinetic_energy: kinetic,
            potential_energy: potential,
            contact_count: contacts.len(),
            contacts,
        });
    }
    // Body-frame bounding boxes as depth-0 stand-ins for OBBTree roots.
    for (b, body) in rec.bodies.iter().enumerate() {
        let (lo, hi) = body.mesh.bounds();
        rec.obb_boxes.push(ObbBox {
            body: b,
            depth: 0,
            center: 0.5 * (lo + hi),
            rotation: DQuat::IDENTITY,
            half_extents: 0.5 * (hi - lo),
        });
    }

    write_glb(&rec, &glb)?;
    println!(
        "wrote {} ({} frames, {} bodies)",
        glb.display(),
        n,
        rec.bodies.len()
    );
    if let Some(csv) = csv {
        write_trajectory_csv(&rec, &csv)?;
        println!("wrote {}", csv.display());
    }
    Ok(())
}
