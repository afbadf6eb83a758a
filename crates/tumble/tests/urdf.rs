//! URDF robots: the shipped arm and quadruped load with the masses and
//! joints the files give, the arm reaches a target under PD motors where
//! forward kinematics says it should be, the quadruped stands, and bad
//! files are refused with file, line and element, the world unchanged.

use tumble::collide::{DQuat, DVec3, HalfSpace};
use tumble::joint::urdf::{add_urdf, load_urdf, UrdfError, UrdfOptions, UrdfRobot};
use tumble::joint::Motor;
use tumble::world::{BodyDesc, World, WorldSettings};

fn robot_path(name: &str) -> String {
    format!("{}/../../examples/robots/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn world() -> World {
    World::new(WorldSettings {
        sleeping: false,
        ..WorldSettings::default()
    })
    .unwrap()
}

/// A robot of `examples/robots` standing on a ground plane at z = 0.
fn on_ground(name: &str, options: UrdfOptions) -> (World, UrdfRobot) {
    let mut w = world();
    w.add_body(&BodyDesc::fixed(HalfSpace::new(DVec3::Z, 0.0).unwrap()))
        .unwrap();
    let robot = load_urdf(&mut w, robot_path(name), options).unwrap();
    (w, robot)
}

#[test]
fn the_arm_loads_with_its_masses_joints_and_merged_tip() {
    let mut w = world();
    let arm = load_urdf(&mut w, robot_path("arm6.urdf"), UrdfOptions::default()).unwrap();
    assert_eq!(arm.name, "arm6");
    assert_eq!(arm.root, "base");
    assert_eq!(arm.joints.len(), 6, "the fixed tip joint is merged");
    assert_eq!(arm.links.len(), 8);
    assert_eq!(arm.links["tool"], arm.links["tool_tip"]);
    assert_eq!(w.body_count(), 7);
    // Masses as the file gives them; the tool body carries its tip.
    let total: f64 = arm.bodies.iter().map(|&b| w.body(b).unwrap().mass()).sum();
    assert!((total - 10.75).abs() < 1e-9, "{total}");
    let tool = w.body(arm.links["tool"]).unwrap();
    assert!((tool.mass() - 0.25).abs() < 1e-12);
    // Centre of mass of tool + tip: (0.2 * 0.03 + 0.05 * 0.08) / 0.25 above the tool frame.
    let frame = w.pose(arm.links["tool"]).unwrap();
    let com = frame.inverse_transform_point(w.center_of_mass(arm.links["tool"]).unwrap());
    assert!((com - DVec3::new(0.0, 0.0, 0.04)).length() < 1e-9, "{com:?}");
    assert_eq!(arm.joints["elbow"].effort, 100.0);
    // The joints start at zero.
    for j in arm.joints.values() {
        assert!(w.joint_state(j.id).unwrap().position.abs() < 1e-12);
    }
}

/// Where the arm's tool tip is for joint angles `q` (forward kinematics of
/// the file, written out here independently of the loader).
fn tool_tip(q: [f64; 6]) -> DVec3 {
    let z = DVec3::Z;
    let steps = [
        (DVec3::new(0.0, 0.0, 0.1), z),
        (DVec3::new(0.0, 0.0, 0.12), DVec3::Y),
        (DVec3::new(0.0, 0.0, 0.4), DVec3::Y),
        (DVec3::new(0.0, 0.0, 0.35), z),
        (DVec3::new(0.0, 0.0, 0.08), DVec3::Y),
        (DVec3::new(0.0, 0.0, 0.05), z),
    ];
    let (mut p, mut r) = (DVec3::ZERO, DQuat::IDENTITY);
    for ((offset, axis), angle) in steps.into_iter().zip(q) {
        p += r * offset;
        r *= DQuat::from_axis_angle(axis, angle);
    }
    p + r * DVec3::new(0.0, 0.0, 0.08)
}

#[test]
fn the_arm_reaches_a_target_under_its_pd_motors() {
    let (mut w, arm) = on_ground(
        "arm6.urdf",
        UrdfOptions {
            fixed_base: true,
            ..UrdfOptions::default()
        },
    );
    let names = [
        "shoulder_pan",
        "shoulder_lift",
        "elbow",
        "wrist_roll",
        "wrist_pitch",
        "wrist_yaw",
    ];
    let target = [0.5, 0.6, 0.8, 0.3, -0.5, 0.2];
    for (name, &angle) in names.iter().zip(&target) {
        let j = arm.joints[*name];
        let motor = Motor::Position {
            target: angle,
            stiffness: 4000.0,
            damping: 200.0,
            max_force: j.effort,
        };
        w.set_joint_motor(j.id, Some(motor)).unwrap();
    }
    for _ in 0..180 {
        w.step();
    }
    let q: Vec<f64> = names
        .iter()
        .map(|n| w.joint_state(arm.joints[*n].id).unwrap().position)
        .collect();
    for (n, (a, t)) in names.iter().zip(q.iter().zip(&target)) {
        assert!((a - t).abs() < 0.01, "{n}: {a} vs target {t}");
    }
    let tip = w
        .pose(arm.links["tool"])
        .unwrap()
        .transform_point(DVec3::new(0.0, 0.0, 0.08));
    let measured: [f64; 6] = q.clone().try_into().unwrap();
    // The simulated chain agrees with forward kinematics of its own angles
    // (joints hold), and the angles are the targets.
    assert!(
        (tip - tool_tip(measured)).length() < 1e-3,
        "{tip:?} vs {:?}",
        tool_tip(measured)
    );
    assert!(
        (tip - tool_tip(target)).length() < 0.01,
        "{tip:?} vs {:?}",
        tool_tip(target)
    );
}

#[test]
fn the_quadruped_stands_on_its_pd_held_legs() {
    let (mut w, dog) = on_ground(
        "quadruped.urdf",
        UrdfOptions {
            position: DVec3::new(0.0, 0.0, 0.34),
            ..UrdfOptions::default()
        },
    );
    assert_eq!(dog.joints.len(), 12);
    // A crouch: thighs forward, knees back.
    for (name, j) in &dog.joints {
        let target = if name.ends_with("thigh_joint") {
            0.5
        } else if name.ends_with("knee_joint") {
            -1.0
        } else {
            0.0
        };
        let motor = Motor::Position {
            target,
            stiffness: 150.0,
            damping: 5.0,
            max_force: j.effort,
        };
        w.set_joint_motor(j.id, Some(motor)).unwrap();
    }
    for _ in 0..180 {
        assert!(w.step().quarantined.is_empty());
    }
    let torso = dog.links["torso"];
    let z = w.center_of_mass(torso).unwrap().z;
    let up = w.orientation(torso).unwrap() * DVec3::Z;
    // Standing on the feet: torso to hip 0.04 + 0.02, thigh and shin 0.15
    // each at 0.5 rad from the vertical, foot radius 0.025 (a little sag
    // under the PD gains).
    let stance = 0.06 + 0.3 * 0.5f64.cos() + 0.025;
    assert!((z - stance).abs() < 0.01, "torso at {z} m, stance {stance} m");
    assert!(up.z > 0.95, "upright: {up:?}");
    assert!(w.max_joint_error().0 < 1e-3);
}

fn error_of(text: &str) -> (u32, String, String) {
    let mut w = world();
    let before = w.snapshot();
    match add_urdf(&mut w, text, "bad.urdf".as_ref(), UrdfOptions::default()) {
        Err(UrdfError::At {
            line,
            element,
            message,
            ..
        }) => {
            // Unchanged to the last slot generation: its whole snapshot.
            assert!(w.snapshot() == before, "the world changed: {message}");
            assert_eq!(w.joint_count(), 0);
            (line, element, message)
        }
        other => panic!("expected a located error, got {other:?}"),
    }
}

const TWO_LINKS: &str = r#"<robot name="r">
  <link name="a"><collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>
  <link name="b"><collision><geometry><sphere radius="0.05"/></geometry></collision></link>
  <joint name="j" type="revolute">
    <parent link="a"/><child link="b"/>
    <origin xyz="0 0 0.2"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" effort="5" velocity="2"/>
  </joint>
</robot>"#;

#[test]
fn a_small_robot_loads() {
    let mut w = world();
    let r = add_urdf(&mut w, TWO_LINKS, "ok.urdf".as_ref(), UrdfOptions::default()).unwrap();
    assert_eq!((w.body_count(), w.joint_count()), (2, 1));
    // Without <inertial>, the mass comes from the shapes (density 1000).
    assert!(
        (w.body(r.links["b"]).unwrap().mass() - 1000.0 * 4.0 / 3.0 * std::f64::consts::PI * 0.05f64.powi(3))
            .abs()
            < 1e-9
    );
    let e = load_urdf(&mut w, "no/such/robot.urdf", UrdfOptions::default()).unwrap_err();
    assert!(matches!(e, UrdfError::Read { .. }));
    assert!(e.to_string().contains("no/such/robot.urdf"));
}

#[test]
fn bad_files_name_the_line_and_element() {
    let (line, element, message) = error_of(&TWO_LINKS.replace("<child link=\"b\"/>", "<child link=\"c\"/>"));
    assert_eq!((line, element.as_str()), (5, "child"));
    assert!(message.contains("no link is named `c`"), "{message}");

    let (line, element, message) = error_of(&TWO_LINKS.replace("type=\"revolute\"", "type=\"floating\""));
    assert_eq!((line, element.as_str()), (4, "joint name=\"j\""));
    assert!(message.contains("not supported"), "{message}");

    let (_, element, message) =
        error_of(&TWO_LINKS.replace("lower=\"-1\" upper=\"1\"", "lower=\"1\" upper=\"-1\""));
    assert_eq!(element, "limit");
    assert!(message.contains("lower 1 > upper -1"), "{message}");

    let (_, element, message) =
        error_of(&TWO_LINKS.replace("<axis xyz=\"0 1 0\"/>", "<axis xyz=\"0 one 0\"/>"));
    assert_eq!(element, "axis");
    assert!(message.contains("3 numbers"), "{message}");

    let (line, element, _) = error_of(&TWO_LINKS.replace("</robot>", "<robot>"));
    assert_eq!(element, "xml");
    assert!(line > 0);

    let (_, _, message) = error_of(&TWO_LINKS.replace(
        "<parent link=\"a\"/><child link=\"b\"/>",
        "<parent link=\"b\"/><child link=\"b\"/>",
    ));
    assert!(message.contains("same link"), "{message}");

    let no_joint = TWO_LINKS.replace(
        &TWO_LINKS[TWO_LINKS.find("  <joint").unwrap()..TWO_LINKS.find("</robot>").unwrap()],
        "",
    );
    let (_, _, message) = error_of(&no_joint);
    assert!(message.contains("one root"), "{message}");

    let (_, element, message) = error_of(&TWO_LINKS.replace(
        "<sphere radius=\"0.05\"/>",
        "<mesh filename=\"package://r/b.stl\"/>",
    ));
    assert_eq!(element, "mesh");
    assert!(message.contains("ROS packages"), "{message}");

    let (_, _, message) = error_of(&TWO_LINKS.replace(
        "<link name=\"b\">",
        "<link name=\"b\"><inertial><mass value=\"-1\"/><inertia ixx=\"1\" iyy=\"1\" izz=\"1\"/></inertial>",
    ));
    assert!(message.contains("mass"), "{message}");

    // Refused by the world itself, after the root link's body went in:
    // a ball so small its mass properties underflow.
    let (_, element, message) = error_of(&TWO_LINKS.replace("radius=\"0.05\"", "radius=\"1e-320\""));
    assert_eq!(element, "link name=\"b\"");
    assert!(message.contains("shapes[0]"), "{message}");
}

#[test]
fn saturated_motors_in_a_chain_hold_their_bound_and_the_chain_holds() {
    // Shoulder and elbow motors of 10 N m asked to move 0.3 rad at once
    // with stiff gains: they saturate, and 10 N m cannot hold the arm
    // (about 16 N m sin(angle) of gravity torque at the shoulder), so it
    // sags past its target; the chain stays together, each motor within
    // its bound, nothing blows up. (Wrist links of a few grams under a saturated motor spin at
    // 20-50 rad/s, a tenth of a radian per sub-step, where the joints open
    // by millimetres: more sub-steps are the remedy there.)
    let mut w = world();
    let arm = load_urdf(
        &mut w,
        robot_path("arm6.urdf"),
        UrdfOptions {
            fixed_base: true,
            ..UrdfOptions::default()
        },
    )
    .unwrap();
    let lift = arm.joints["shoulder_lift"].id;
    for (name, j) in &arm.joints {
        let weak = ["shoulder_pan", "shoulder_lift", "elbow"].contains(&name.as_str());
        let motor = Motor::Position {
            target: if weak { 0.3 } else { 0.0 },
            stiffness: 4000.0,
            damping: 200.0,
            max_force: if weak { 10.0 } else { j.effort },
        };
        w.set_joint_motor(j.id, Some(motor)).unwrap();
    }
    let mut saturated = false;
    let mut worst = (0.0f64, 0.0f64);
    for _ in 0..120 {
        let report = w.step();
        let torque = w.joint_state(lift).unwrap().torque;
        saturated |= torque.dot(w.joint_state(lift).unwrap().axis).abs() > 9.9;
        assert!(report.quarantined.is_empty());
        worst = (
            worst.0.max(w.max_joint_error().0),
            worst.1.max(w.max_joint_error().1),
        );
        let s = w.joint_state(lift).unwrap();
        // The reaction about the axis is the motor's (plus the limit's when
        // the arm reaches it). The reaction is the last sub-step's, the axis
        // where B is at the end of the step: B turns by w h in between, and
        // the hinge's torque across the axis (tens of N m) leaks into the
        // projection by that angle.
        let across = (s.torque - s.axis * s.torque.dot(s.axis)).length();
        let about_axis = s.torque.dot(s.axis).abs();
        let leak = across * 0.1;
        assert!(
            about_axis < 10.0 + leak || s.position.abs() > 1.99,
            "{about_axis} N m at {}",
            s.position
        );
    }
    assert!(saturated, "the lift motor reached its bound");
    // Millimetres, and a few hundredths of a radian while the light wrist
    // links whip (20-50 rad/s).
    assert!(worst.0 < 5e-3 && worst.1 < 0.05, "joint errors {worst:?}");
    assert!(
        w.joint_state(lift).unwrap().position > 0.3,
        "sagged past the target"
    );
}
