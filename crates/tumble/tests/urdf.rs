//! URDF robots: the shipped arm and quadruped load with the masses and
//! joints the files give, the arm reaches a target under PD motors where
//! forward kinematics says it should be, the quadruped stands, and bad
//! files are refused with file, line and element, the world unchanged.

use tumble::collide::{DQuat, DVec3, HalfSpace};
use tumble::joint::urdf::{add_urdf, load_urdf, UrdfError, UrdfOptions, UrdfRobot};
use tumble::joint::{Gear, Motor, Spring};
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

/// [`TWO_LINKS`] with link b given an `<inertial>` of these elements.
fn b_with_inertial(inertial: &str) -> String {
    TWO_LINKS.replace(
        "<link name=\"b\">",
        &format!("<link name=\"b\"><inertial>{inertial}</inertial>"),
    )
}

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
    // A directory (or a device) is not read at all.
    let e = load_urdf(&mut w, env!("CARGO_MANIFEST_DIR"), UrdfOptions::default()).unwrap_err();
    assert!(e.to_string().contains("not a regular file"), "{e}");
}

#[test]
fn bad_files_name_the_line_and_element() {
    let (line, element, message) = error_of(&TWO_LINKS.replace("<child link=\"b\"/>", "<child link=\"c\"/>"));
    assert_eq!((line, element.as_str()), (5, "child"));
    assert!(message.contains("no link is named `c`"), "{message}");

    let (line, element, message) = error_of(&TWO_LINKS.replace("type=\"revolute\"", "type=\"planar\""));
    assert_eq!((line, element.as_str()), (4, "joint name=\"j\""));
    assert!(message.contains("not supported"), "{message}");

    let (_, element, message) = error_of(&b_with_inertial(
        "<mass value=\"1\"/><inertia ixx=\"1\" iyy=\"1\"/>",
    ));
    assert_eq!(element, "inertia");
    assert!(message.contains("`izz`"), "{message}");

    // A point mass without geometry to take an inertia from: named at its
    // <inertial>, not as a shape.
    let (_, element, message) = error_of(
        &b_with_inertial("<mass value=\"1\"/><inertia ixx=\"0\" iyy=\"0\" izz=\"0\"/>").replace(
            "<collision><geometry><sphere radius=\"0.05\"/></geometry></collision>",
            "",
        ),
    );
    assert_eq!(element, "inertial");
    assert!(message.contains("point mass"), "{message}");

    // A massless frame between two moving joints, in a robot none of
    // whose moving links has a mass to size its stand-in from (the root
    // is static, the leaf has neither geometry nor mass).
    let (_, element, message) = error_of(
        &TWO_LINKS
            .replace(
                "<link name=\"b\"><collision><geometry><sphere radius=\"0.05\"/></geometry></collision></link>",
                "<link name=\"b\"/><link name=\"c\"/>\
                 <joint name=\"k\" type=\"continuous\"><parent link=\"b\"/><child link=\"c\"/></joint>",
            )
            .replace("<link name=\"a\">", "<link name=\"a\"><inertial><mass value=\"0\"/><inertia ixx=\"0\" iyy=\"0\" izz=\"0\"/></inertial>"),
    );
    assert_eq!(element, "link name=\"b\"");
    assert!(message.contains("no link of the robot has a mass"), "{message}");

    let (_, element, message) =
        error_of(&TWO_LINKS.replace("<axis xyz=\"0 1 0\"/>", "<axis xyz=\"0 one 0\"/>"));
    assert_eq!(element, "axis");
    assert!(message.contains("3 numbers"), "{message}");

    let (_, element, message) = error_of("<robot name=\"r\"><link name=\"world\"/></robot>");
    assert_eq!(element, "robot name=\"r\"");
    assert!(message.contains("no link of the robot is a body"), "{message}");

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
    assert!(message.contains("no directory named `r`"), "{message}");

    let (_, _, message) = error_of(&b_with_inertial(
        "<mass value=\"-1\"/><inertia ixx=\"1\" iyy=\"1\" izz=\"1\"/>",
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
    let lift_damping = w.joint(lift).unwrap().spring.expect("a damper").damping;
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
        // The reaction about the axis is the motor's plus the joint's
        // damper's (<dynamics damping>, c |w|), and the limit's when the
        // arm reaches it. The reaction is the last sub-step's, the axis
        // where B is at the end of the step: B turns by w h in between, and
        // the hinge's torque across the axis (tens of N m) leaks into the
        // projection by that angle.
        let across = (s.torque - s.axis * s.torque.dot(s.axis)).length();
        let about_axis = s.torque.dot(s.axis).abs();
        let leak = across * 0.1;
        let damper = lift_damping * s.rate.abs() * 1.01;
        assert!(
            about_axis < 10.0 + damper + leak || s.position.abs() > 1.99,
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

/// `text` loaded into a fresh world on a ground plane.
fn loaded(text: &str, options: UrdfOptions) -> (World, UrdfRobot) {
    let mut w = world();
    w.add_body(&BodyDesc::fixed(HalfSpace::new(DVec3::Z, 0.0).unwrap()).named("ground"))
        .unwrap();
    let robot = add_urdf(&mut w, text, "other_engine.urdf".as_ref(), options).unwrap();
    (w, robot)
}

fn steps(w: &mut World, n: usize) {
    for _ in 0..n {
        w.step();
    }
}

#[test]
fn a_root_without_geometry_or_mass_stands_for_the_world() {
    // ROS's `world` link: the box slides along x on a joint to the world,
    // so gravity cannot pull it down; a push along x moves it freely.
    let text = r#"<robot name="r">
  <link name="world"/>
  <link name="box"><collision><geometry><box size="0.2 0.2 0.2"/></geometry></collision></link>
  <joint name="rail" type="prismatic">
    <parent link="world"/><child link="box"/>
    <origin xyz="0 0 1"/><axis xyz="1 0 0"/>
    <limit lower="-5" upper="5" effort="10" velocity="1"/>
  </joint>
</robot>"#;
    let (mut w, r) = loaded(text, UrdfOptions::default());
    assert_eq!((w.body_count(), w.joint_count()), (2, 1), "ground and the box");
    assert!(!r.links.contains_key("world"));
    let rail = r.joints["rail"].id;
    assert_eq!(w.joint(rail).unwrap().body_b, None, "attached to the world");
    assert!(r.warnings.iter().any(|m| m.contains("stands for the world")));
    let b = r.links["box"];
    w.set_velocity(b, DVec3::new(0.5, 0.0, 0.0), DVec3::ZERO).unwrap();
    steps(&mut w, 60);
    let p = w.pose(b).unwrap().position;
    assert!((p.z - 1.0).abs() < 1e-3, "held up by the rail: {p:?}");
    assert!((p.x - 0.5).abs() < 0.01, "slid 0.5 m in 1 s: {p:?}");
}

#[test]
fn a_massless_root_is_static_and_its_links_move_on_it() {
    // PyBullet's convention: a mass of 0 makes the base static (a table,
    // a fixed arm's base); its pendulum swings from it.
    let text = r#"<robot name="r">
  <link name="base">
    <inertial><mass value="0"/><inertia ixx="0" iyy="0" izz="0"/></inertial>
    <collision><geometry><box size="0.2 0.2 0.2"/></geometry></collision>
  </link>
  <link name="bob">
    <inertial><origin xyz="0.5 0 0"/><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01"/></inertial>
    <collision><origin xyz="0.5 0 0"/><geometry><sphere radius="0.05"/></geometry></collision>
  </link>
  <joint name="pivot" type="continuous">
    <parent link="base"/><child link="bob"/>
    <origin xyz="0 0 0.5"/><axis xyz="0 1 0"/>
  </joint>
</robot>"#;
    let (mut w, r) = loaded(
        text,
        UrdfOptions {
            position: DVec3::new(0.0, 0.0, 1.0),
            ..UrdfOptions::default()
        },
    );
    let base = r.links["base"];
    assert_eq!(w.body(base).unwrap().kind(), tumble::body::BodyKind::Static);
    assert!(r
        .warnings
        .iter()
        .any(|m| m.contains("mass of 0") && m.contains("static")));
    let before = w.pose(base).unwrap();
    steps(&mut w, 30);
    assert_eq!(w.pose(base).unwrap(), before, "a static base does not move");
    let swung = w.joint_state(r.joints["pivot"].id).unwrap().position;
    assert!(
        swung.abs() > 0.1,
        "the bob swings down from the horizontal: {swung} rad"
    );
}

#[test]
fn a_leaf_link_without_geometry_or_mass_is_left_out_with_its_joint() {
    // A tool or sensor frame on a moving joint (a gripper's auxiliary
    // link): it carries nothing, so nothing of it is simulated.
    let text = TWO_LINKS.replace(
        "</robot>",
        r#"  <link name="tool_frame"/>
  <joint name="aux" type="prismatic">
    <parent link="b"/><child link="tool_frame"/>
    <axis xyz="1 0 0"/><limit lower="0" upper="0.1" effort="1" velocity="1"/>
  </joint>
</robot>"#,
    );
    let (w, r) = loaded(&text, UrdfOptions::default());
    assert_eq!((w.body_count(), w.joint_count()), (3, 1));
    assert!(!r.links.contains_key("tool_frame") && !r.joints.contains_key("aux"));
    assert!(r
        .warnings
        .iter()
        .any(|m| m.contains("tool_frame") && m.contains("`aux`")));
}

#[test]
fn bullet_extensions_and_conventions_read_as_pybullet_reads_them() {
    use tumble::collide::Shape;
    use tumble::joint::JointKind;
    // A blank line before the XML declaration; a capsule; a ball joint
    // ("spherical"); a floating joint (no joint); a <limit> with lower >
    // upper (no limit); a fixed joint with a zero axis; an inertia that
    // gives only its moments.
    let text = r#"
<?xml version="1.0"?>
<robot name="r">
  <link name="a">
    <inertial><mass value="2"/><inertia ixx="0.1" iyy="0.2" izz="0.3"/></inertial>
    <collision><geometry><capsule radius="0.1" length="0.4"/></geometry></collision>
  </link>
  <link name="b"><collision><geometry><sphere radius="0.05"/></geometry></collision></link>
  <link name="c"><collision><geometry><sphere radius="0.05"/></geometry></collision></link>
  <link name="d"><collision><geometry><sphere radius="0.05"/></geometry></collision></link>
  <link name="e"><collision><geometry><sphere radius="0.05"/></geometry></collision></link>
  <joint name="ball" type="spherical"><parent link="a"/><child link="b"/><origin xyz="0 0 0.5"/>
    <dynamics damping="0.5" friction="0.2"/></joint>
  <joint name="free" type="floating"><parent link="a"/><child link="c"/><origin xyz="1 0 0"/></joint>
  <joint name="hinge" type="revolute">
    <parent link="a"/><child link="d"/><origin xyz="0 1 0"/><axis xyz="0 0 1"/>
    <limit lower="1" upper="0" effort="1" velocity="1"/>
  </joint>
  <joint name="weld" type="fixed"><parent link="a"/><child link="e"/><origin xyz="0 -1 0"/><axis xyz="0 0 0"/></joint>
</robot>"#;
    let (w, r) = loaded(
        text,
        UrdfOptions {
            position: DVec3::new(0.0, 0.0, 2.0),
            ..UrdfOptions::default()
        },
    );
    // Bodies: a (with e welded on), b, c, d; joints: the ball and the hinge.
    assert_eq!((w.body_count(), w.joint_count()), (5, 2));
    assert_eq!(r.links["a"], r.links["e"]);
    let capsule = w
        .colliders(r.links["a"])
        .unwrap()
        .iter()
        .find_map(|c| match &c.shape {
            Shape::Capsule(k) => Some((k.radius(), k.half_height())),
            _ => None,
        });
    assert_eq!(capsule, Some((0.1, 0.2)), "length is between the caps' centres");
    let ball = w.joint(r.joints["ball"].id).unwrap();
    assert_eq!(ball.kind, JointKind::Ball);
    // Its damping is a damper about every axis, its friction Coulomb
    // friction about each: both simulated, neither warned about.
    assert_eq!(
        (ball.spring, ball.friction),
        (
            Some(Spring {
                stiffness: 0.0,
                damping: 0.5
            }),
            Some(0.2)
        )
    );
    assert!(
        !r.warnings
            .iter()
            .any(|m| m.contains("damping") || m.contains("friction")),
        "{:?}",
        r.warnings
    );
    assert!(!r.joints.contains_key("free"));
    assert_eq!(w.joint(r.joints["hinge"].id).unwrap().limits, None);
    assert!(r
        .warnings
        .iter()
        .any(|m| m.contains("`hinge`") && m.contains("no limit")));
    let coupled = TWO_LINKS.replace(
        "<limit lower=\"-1\" upper=\"1\" effort=\"5\" velocity=\"2\"/>",
        "<limit lower=\"-1\" upper=\"1\" effort=\"5\" velocity=\"2\"/>\
         <dynamics damping=\"0.1\" friction=\"0.5\"/>",
    );
    let (coupled_world, r) = loaded(&coupled, UrdfOptions::default());
    // A damping and a friction both act: a damper (a spring of stiffness
    // 0) and the joint's Coulomb friction, with no motor.
    assert!(
        !r.warnings.iter().any(|m| m.contains("friction")),
        "{:?}",
        r.warnings
    );
    let j = coupled_world.joint(r.joints["j"].id).unwrap();
    assert_eq!(
        j.spring,
        Some(Spring {
            stiffness: 0.0,
            damping: 0.1
        })
    );
    assert_eq!((j.friction, j.motor), (Some(0.5), None));
    // The products of inertia default to 0: the moments are the principal ones.
    let mut moments = w.body(r.links["a"]).unwrap().principal_inertia().to_array();
    moments.sort_by(f64::total_cmp);
    // (e has no <inertial>: where a merged link gives one, the body's
    // mass is what the inertials give.)
    assert_eq!(w.body(r.links["a"]).unwrap().mass(), 2.0);
    for (m, want) in moments.iter().zip([0.1, 0.2, 0.3]) {
        assert!((m - want).abs() < 1e-12, "{moments:?}");
    }
}

#[test]
fn a_robots_links_touch_each_other_only_when_asked() {
    // Link c hangs from b, which turns on a: a and c are linked by no joint.
    // As written, c's ball lies inside a's box; with `C_OUT` it starts out
    // beside the box and swings down into it.
    let text = r#"<robot name="r">
  <link name="a"><collision><geometry><box size="0.4 0.4 0.4"/></geometry></collision></link>
  <link name="b"><collision><origin xyz="0 0 0.5"/><geometry><sphere radius="0.05"/></geometry></collision></link>
  <link name="c"><collision><origin xyz="C_AT"/><geometry><sphere radius="0.1"/></geometry></collision></link>
  <joint name="j1" type="continuous"><parent link="a"/><child link="b"/></joint>
  <joint name="j2" type="revolute">
    <parent link="b"/><child link="c"/><origin xyz="0 0 0.5"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/>
  </joint>
</robot>"#;
    const C_IN: &str = "0 0 -0.5";
    const C_OUT: &str = "0.5 0 0";
    let load = |c_at: &str, self_collision: bool| {
        loaded(
            &text.replace("C_AT", c_at),
            UrdfOptions {
                position: DVec3::new(0.0, 0.0, 1.0),
                fixed_base: true,
                self_collision,
                ..UrdfOptions::default()
            },
        )
    };
    let a_c_touch = |w: &World, r: &UrdfRobot| {
        let (a, c) = (r.links["a"], r.links["c"]);
        w.contacts()
            .iter()
            .any(|k| (k.body_a == a && k.body_b == c) || (k.body_a == c && k.body_b == a))
    };
    // Without self-collision, the robot's links share a group and never
    // touch: c swings down through a.
    let (mut w, r) = load(C_OUT, false);
    let groups: Vec<u32> = r
        .bodies
        .iter()
        .map(|&b| w.non_colliding_group(b).unwrap())
        .collect();
    assert!(groups.iter().all(|&g| g == groups[0] && g != 0), "{groups:?}");
    let mut touched = false;
    for _ in 0..120 {
        w.step();
        touched |= a_c_touch(&w, &r);
    }
    assert!(!touched, "without self-collision, a and c do not touch");
    assert!(r.no_contact.is_empty());
    // With it, c starts clear of a and strikes it on the way down.
    let (mut w, r) = load(C_OUT, true);
    assert!(r.bodies.iter().all(|&b| w.non_colliding_group(b).unwrap() == 0));
    assert!(r.no_contact.is_empty(), "{:?}", r.no_contact);
    let mut touched = false;
    for _ in 0..120 {
        w.step();
        touched |= a_c_touch(&w, &r);
    }
    assert!(touched, "with self-collision, c strikes a");
    // Links that overlap in the file's pose never touch, even with
    // self-collision (their contacts would fight the joints): the robot
    // moves to the very same bits as without self-collision, where no
    // other pair of its links can meet.
    let (mut off, _) = load(C_IN, false);
    let (mut on, r) = load(C_IN, true);
    assert_eq!(r.no_contact, vec![(r.links["a"], r.links["c"])]);
    assert!(!on.contacts_allowed(r.links["a"], r.links["c"]).unwrap());
    for _ in 0..120 {
        off.step();
        on.step();
        assert!(!a_c_touch(&on, &r));
    }
    let pose = |w: &World| r.bodies.iter().map(|&b| w.pose(b).unwrap()).collect::<Vec<_>>();
    assert_eq!(pose(&on), pose(&off));
    // Allowed again, they touch at the next step.
    on.set_contacts_between(r.links["c"], r.links["a"], true).unwrap();
    on.step();
    assert!(a_c_touch(&on, &r), "an exclusion taken back lets the pair touch");
    // A scene file's self-colliding robot keeps the same pair apart.
    let dir = std::env::temp_dir().join(format!("tumble-urdf-overlap-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("r.urdf"), text.replace("C_AT", C_IN)).unwrap();
    let scene = format!(
        "[[robots]]\nfile = \"{}\"\nfixed_base = true\nself_collision = true\n",
        dir.join("r.urdf").display()
    );
    let scene = tumble::scene::parse_scene(&scene, tumble::scene::Format::Toml, "s.toml".as_ref()).unwrap();
    assert_eq!(scene.scene.no_contact, vec![(0, 2)]);
    let (w, ids) = scene.build().unwrap();
    assert!(!w.contacts_allowed(ids[0], ids[2]).unwrap());
    assert!(
        w.contacts_allowed(ids[0], ids[1]).is_ok_and(|allowed| !allowed),
        "jointed"
    );
    std::fs::remove_dir_all(&dir).unwrap();
    // A second robot takes a group of its own: its links touch the first's.
    let mut w = world();
    let first = add_urdf(&mut w, TWO_LINKS, "one.urdf".as_ref(), UrdfOptions::default()).unwrap();
    let second = add_urdf(&mut w, TWO_LINKS, "two.urdf".as_ref(), UrdfOptions::default()).unwrap();
    let group = |r: &UrdfRobot| w.non_colliding_group(r.bodies[0]).unwrap();
    assert_ne!(group(&first), group(&second));
    // Past the last group a world can name, a free one is found.
    let mut w = world();
    let top = BodyDesc {
        non_colliding_group: u32::MAX,
        ..BodyDesc::dynamic(tumble::collide::Sphere::new(0.1).unwrap())
    };
    w.add_body(&top).unwrap();
    let r = add_urdf(&mut w, TWO_LINKS, "three.urdf".as_ref(), UrdfOptions::default()).unwrap();
    assert_eq!(w.non_colliding_group(r.bodies[0]).unwrap(), 1);
}

#[test]
fn a_link_with_a_mass_and_no_geometry_is_a_body_that_touches_nothing() {
    // A pan-tilt head whose base link gives only its <inertial>: a body
    // without shapes, welded to the world here, carrying the head.
    let text = r#"<robot name="r">
  <link name="base"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1"/></inertial></link>
  <link name="head">
    <inertial><origin xyz="0.3 0 0"/><mass value="0.5"/><inertia ixx="0.01" iyy="0.01" izz="0.01"/></inertial>
    <collision><origin xyz="0.3 0 0"/><geometry><sphere radius="0.05"/></geometry></collision>
  </link>
  <joint name="tilt" type="continuous">
    <parent link="base"/><child link="head"/><axis xyz="0 1 0"/>
  </joint>
</robot>"#;
    let (mut w, r) = loaded(
        text,
        UrdfOptions {
            position: DVec3::new(0.0, 0.0, 1.0),
            fixed_base: true,
            ..UrdfOptions::default()
        },
    );
    let base = r.links["base"];
    assert!(w.colliders(base).unwrap().is_empty());
    assert_eq!(w.body(base).unwrap().mass(), 1.0);
    steps(&mut w, 30);
    let tilt = w.joint_state(r.joints["tilt"].id).unwrap();
    assert!(
        tilt.position.abs() > 0.1,
        "the head swings down: {} rad",
        tilt.position
    );
    assert!(tilt.linear_error < 1e-3);
}

#[test]
fn ros_package_meshes_are_found_in_the_package_the_file_lies_in() {
    // A ROS package laid out as ROS lays it out: pkg/urdf/r.urdf naming
    // package://pkg/meshes/cube.obj, and the same file outside any package.
    let root = std::env::temp_dir().join(format!("tumble-urdf-package-{}", std::process::id()));
    let pkg = root.join("cube_description");
    std::fs::create_dir_all(pkg.join("urdf")).unwrap();
    std::fs::create_dir_all(pkg.join("meshes")).unwrap();
    // A unit cube, 12 outward triangles.
    let mut obj = String::new();
    for i in 0..8 {
        let c = |bit: usize| if i & bit != 0 { 0.5 } else { -0.5 };
        obj += &format!("v {} {} {}\n", c(1), c(2), c(4));
    }
    for f in [
        [1, 3, 4, 2],
        [5, 6, 8, 7],
        [1, 2, 6, 5],
        [3, 7, 8, 4],
        [1, 5, 7, 3],
        [2, 4, 8, 6],
    ] {
        obj += &format!("f {} {} {}\nf {} {} {}\n", f[0], f[1], f[2], f[0], f[2], f[3]);
    }
    std::fs::write(pkg.join("meshes/cube.obj"), obj).unwrap();
    let text = r#"<robot name="cube"><link name="c">
  <inertial><mass value="1"/><inertia ixx="0.1667" iyy="0.1667" izz="0.1667"/></inertial>
  <collision><geometry><mesh filename="package://cube_description/meshes/cube.obj"/></geometry></collision>
</link></robot>"#;
    let file = pkg.join("urdf/cube.urdf");
    std::fs::write(&file, text).unwrap();
    let mut w = world();
    let r = load_urdf(&mut w, &file, UrdfOptions::default()).unwrap();
    let volume = w
        .colliders(r.links["c"])
        .unwrap()
        .iter()
        .find_map(|c| match &c.shape {
            tumble::collide::Shape::Mesh(m) => Some(m.mesh().signed_volume()),
            _ => None,
        });
    assert!((volume.unwrap() - 1.0).abs() < 1e-12, "{volume:?}");
    // Beside the package (a workspace holding it), found there too.
    let beside = root.join("cube.urdf");
    std::fs::write(&beside, text).unwrap();
    assert!(load_urdf(&mut w, &beside, UrdfOptions::default()).is_ok());
    // Away from it, found nowhere, and said so.
    let away = std::env::temp_dir().join(format!("tumble-urdf-away-{}", std::process::id()));
    std::fs::create_dir_all(&away).unwrap();
    std::fs::write(away.join("cube.urdf"), text).unwrap();
    let e = load_urdf(&mut w, away.join("cube.urdf"), UrdfOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("no directory named `cube_description`"), "{e}");
    std::fs::remove_dir_all(&root).unwrap();
    std::fs::remove_dir_all(&away).unwrap();
}

#[test]
fn an_inertia_no_body_could_have_is_refused_or_balanced_on_request() {
    // Moments 0, 0 and 1.5 (a flat disc's, idealised too far): 0 + 0 < 1.5.
    let text = b_with_inertial("<mass value=\"2\"/><inertia ixx=\"0\" iyy=\"0\" izz=\"1.5\"/>");
    let (_, element, message) = error_of(&text);
    assert_eq!(element, "inertial");
    assert!(
        message.contains("triangle inequality") && message.contains("balance_inertia"),
        "{message}"
    );
    let (w, r) = loaded(
        &text,
        UrdfOptions {
            balance_inertia: true,
            ..UrdfOptions::default()
        },
    );
    // The isotropic inertia of the same trace: 0.5 kg m^2 about every axis.
    let b = w.body(r.links["b"]).unwrap();
    assert_eq!(b.mass(), 2.0);
    for m in b.principal_inertia().to_array() {
        assert!((m - 0.5).abs() < 1e-12, "{:?}", b.principal_inertia());
    }
    assert!(r
        .warnings
        .iter()
        .any(|m| m.contains("link `b`") && m.contains("balance_inertia")));
}

#[test]
fn a_ball_of_three_hinges_through_massless_links_swings_and_spins_as_a_ball_joint() {
    // MuJoCo's humanoid exported to URDF composes a hip of three hinges
    // (x, y, z) through two links with neither geometry nor mass. They
    // become light stand-ins, and the bob below hangs from a ball joint:
    // swung in a vertical plane that no single hinge's, it keeps the
    // compound pendulum's period 2 pi sqrt(I_pivot / (m g d)); spun about
    // the vertical, it keeps its rate (no torque about it).
    let text = r#"<robot name="hip">
  <link name="base">
    <inertial><mass value="0"/><inertia ixx="0" iyy="0" izz="0"/></inertial>
    <collision><geometry><box size="0.2 0.2 0.2"/></geometry></collision>
  </link>
  <link name="hx"><inertial><mass value="0"/><inertia ixx="0" iyy="0" izz="0"/></inertial></link>
  <link name="hy"/>
  <link name="bob">
    <inertial><origin xyz="0 0 -0.5"/><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01"/></inertial>
    <collision><origin xyz="0 0 -0.5"/><geometry><sphere radius="0.05"/></geometry></collision>
  </link>
  <joint name="x" type="continuous"><parent link="base"/><child link="hx"/><axis xyz="1 0 0"/></joint>
  <joint name="y" type="continuous"><parent link="hx"/><child link="hy"/><axis xyz="0 1 0"/></joint>
  <joint name="z" type="continuous"><parent link="hy"/><child link="bob"/><axis xyz="0 0 1"/></joint>
</robot>"#;
    let pivot = DVec3::new(0.0, 0.0, 2.0);
    let options = UrdfOptions {
        position: pivot,
        ..UrdfOptions::default()
    };
    let (mut w, r) = loaded(text, options);
    assert_eq!(w.joint_count(), 3);
    let bob = r.links["bob"];
    for link in ["hx", "hy"] {
        let m = w.body(r.links[link]).unwrap().mass();
        assert!((m - 1e-3).abs() < 1e-15, "{link}: {m} kg");
    }
    assert!(r
        .warnings
        .iter()
        .any(|m| m.contains("`hx`, `hy`") && m.contains("carrying other links")));

    // Swung about the horizontal diagonal (1, 1, 0) / sqrt 2.
    let (g, d, i_pivot) = (9.81, 0.5, 0.01 + 0.25);
    let omega = 0.2 * DVec3::new(1.0, 1.0, 0.0).normalize();
    let arm = w.center_of_mass(bob).unwrap() - pivot;
    w.set_velocity(bob, omega.cross(arm), omega).unwrap();
    let (mut crossings, mut last_x, mut widest) = (Vec::new(), 0.0, [0.0f64; 2]);
    for _ in 0..600 {
        w.step();
        let c = w.center_of_mass(bob).unwrap() - pivot;
        if (last_x > 0.0) != (c.x > 0.0) {
            crossings.push(w.time() - w.settings().dt * c.x.abs() / (c.x - last_x).abs());
        }
        last_x = c.x;
        widest = [widest[0].max(c.x.abs()), widest[1].max(c.y.abs())];
        assert!(
            (c.x + c.y).abs() < 1e-3 * widest[0].max(1e-3),
            "in its plane: {c:?}"
        );
    }
    let n = crossings.len() - 1;
    assert!(n >= 10, "it swings: {crossings:?}");
    let period = 2.0 * (crossings[n] - crossings[0]) / n as f64;
    let amplitude = widest[0].hypot(widest[1]) / d;
    let exact =
        2.0 * std::f64::consts::PI * (i_pivot / (g * d)).sqrt() * (1.0 + amplitude * amplitude / 16.0);
    assert!(
        (period / exact - 1.0).abs() < 1e-3,
        "period {period} s, exact {exact} s"
    );
    assert!(
        (widest[0] / widest[1] - 1.0).abs() < 0.01,
        "both hinges swing: {widest:?}"
    );

    // Spun about the vertical through the bob.
    let (mut w, r) = loaded(text, options);
    let bob = r.links["bob"];
    let below = w.center_of_mass(bob).unwrap();
    w.set_velocity(bob, DVec3::ZERO, DVec3::Z).unwrap();
    steps(&mut w, 120);
    let spin = w.angular_velocity(bob).unwrap();
    assert!((spin.z - 1.0).abs() < 1e-3, "kept its spin: {spin:?}");
    let moved = (w.center_of_mass(bob).unwrap() - below).length();
    assert!(moved < 1e-4, "and hangs still: {moved} m");
    assert!(w.max_joint_error().0 < 1e-4);
}

#[test]
fn a_point_or_line_mass_on_a_link_with_geometry_takes_the_geometrys_inertia() {
    // PyBullet's data set gives some spheres an <inertial> of mass only
    // (moments 0): the file's mass and centre, the sphere's 2/5 m r^2.
    let text = b_with_inertial(
        "<origin xyz=\"0.01 0 0\"/><mass value=\"3\"/><inertia ixx=\"0\" iyy=\"0\" izz=\"0\"/>",
    );
    let (w, r) = loaded(&text, UrdfOptions::default());
    let b = w.body(r.links["b"]).unwrap();
    assert_eq!(b.mass(), 3.0);
    for m in b.principal_inertia().to_array() {
        assert!(
            (m - 0.4 * 3.0 * 0.05 * 0.05).abs() < 1e-12,
            "{:?}",
            b.principal_inertia()
        );
    }
    // The body frame is the file's centre of mass, 1 cm off the sphere's
    // centre along the link's x (the link b frame is 0.2 m above a).
    let com = w.center_of_mass(r.links["b"]).unwrap();
    let a = w.center_of_mass(r.links["a"]).unwrap();
    assert!((com - a - DVec3::new(0.01, 0.0, 0.2)).length() < 1e-12, "{com:?}");
    assert!(r
        .warnings
        .iter()
        .any(|m| m.contains("link `b`") && m.contains("principal moment of 0")));
    // A line mass (a rod idealised to no thickness, as PyBullet's cart-pole
    // files give it) alike.
    let rod = b_with_inertial("<mass value=\"3\"/><inertia ixx=\"0\" iyy=\"0.01\" izz=\"0.01\"/>");
    let (w, r) = loaded(&rod, UrdfOptions::default());
    let moments = w.body(r.links["b"]).unwrap().principal_inertia();
    assert!(
        (moments - DVec3::splat(0.4 * 3.0 * 0.05 * 0.05)).length() < 1e-12,
        "{moments:?}"
    );
}

#[test]
fn a_scene_files_robots_are_the_robots_load_urdf_adds() {
    use tumble::scene::{parse_scene, Format, SceneError};
    // The arm through a scene file beside a payload welded to its tool,
    // and the quadruped beside it: named ROBOT/LINK, each robot in a
    // non-colliding group of its own.
    let text = format!(
        r#"
[settings]
sleeping = false
[[bodies]]
name = "ground"
kind = "static"
shapes = [{{ type = "half_space" }}]
[[robots]]
file = "{arm}"
name = "arm"
fixed_base = true
[[robots]]
file = "{dog}"
position = [2, 0, 0.4]
[[bodies]]
name = "payload"
shapes = [{{ type = "box", half_extents = [0.02, 0.02, 0.02] }}]
mass = 0.5
position = [5, 0, 0.02]
[[joints]]
kind = "fixed"
body_a = "payload"
body_b = "quadruped/torso"
anchor = [5, 0, 0.02]
"#,
        arm = robot_path("arm6.urdf"),
        dog = robot_path("quadruped.urdf"),
    );
    let scene = parse_scene(&text, Format::Toml, "robots.toml".as_ref()).unwrap();
    let (mut w, ids) = scene.build().unwrap();
    let name = |k: usize| w.name(ids[k]).unwrap().to_string();
    let arm_bodies: Vec<usize> = (0..ids.len()).filter(|&k| name(k).starts_with("arm/")).collect();
    assert_eq!(arm_bodies.len(), 7);
    assert!(arm_bodies.iter().any(|&k| name(k) == "arm/tool+tool_tip"));
    let group = |k: usize| w.non_colliding_group(ids[k]).unwrap();
    let dog = (0..ids.len()).find(|&k| name(k) == "quadruped/torso").unwrap();
    assert!(group(arm_bodies[0]) != 0 && group(dog) != 0 && group(arm_bodies[0]) != group(dog));
    assert_eq!(group(0), 0);

    // Bit for bit what load_urdf gives in the same world (the bodies
    // before the arm, the arm, then nothing else).
    let only_arm = format!(
        "[settings]\nsleeping = false\n[[bodies]]\nname = \"ground\"\nkind = \"static\"\n\
         shapes = [{{ type = \"half_space\" }}]\n[[robots]]\nfile = \"{}\"\nfixed_base = true\n",
        robot_path("arm6.urdf")
    );
    let (mut from_scene, scene_ids) = parse_scene(&only_arm, Format::Toml, "arm.toml".as_ref())
        .unwrap()
        .build()
        .unwrap();
    let mut direct = world();
    direct
        .add_body(&BodyDesc::fixed(HalfSpace::new(DVec3::Z, 0.0).unwrap()).named("ground"))
        .unwrap();
    let arm = load_urdf(
        &mut direct,
        robot_path("arm6.urdf"),
        UrdfOptions {
            fixed_base: true,
            ..UrdfOptions::default()
        },
    )
    .unwrap();
    assert_eq!(from_scene.joint_count(), direct.joint_count());
    let start = direct.pose(arm.links["tool"]).unwrap().position;
    // Standing straight up it would stay: pushed, it falls over.
    let by_name = |w: &World, ids: &[tumble::world::BodyId], n: &str| {
        *ids.iter().find(|&&id| w.name(id).unwrap() == n).unwrap()
    };
    let push = DVec3::new(0.3, 0.2, 0.0);
    let forearm = by_name(&from_scene, &scene_ids, "arm6/forearm");
    from_scene.set_velocity(forearm, push, DVec3::ZERO).unwrap();
    direct
        .set_velocity(arm.links["forearm"], push, DVec3::ZERO)
        .unwrap();
    steps(&mut from_scene, 60);
    steps(&mut direct, 60);
    let tool_scene = by_name(&from_scene, &scene_ids, "arm6/tool+tool_tip");
    assert_eq!(
        from_scene.pose(tool_scene).unwrap(),
        direct.pose(arm.links["tool"]).unwrap()
    );
    let moved = (direct.pose(arm.links["tool"]).unwrap().position - start).length();
    assert!(moved > 0.01, "the arm sags under gravity: {moved} m");

    // The whole scene steps, the payload held to the quadruped.
    steps(&mut w, 60);
    assert!(w.max_joint_error().0 < 1e-3);

    // A missing file, at its field, naming the file.
    let missing = text.replace("arm6.urdf", "arm7.urdf");
    match parse_scene(&missing, Format::Toml, "robots.toml".as_ref()) {
        Err(SceneError::At { path, message, .. }) => {
            assert_eq!(path, "robots[0].file");
            assert!(message.contains("arm7.urdf"), "{message}");
        }
        other => panic!("expected a located error, got {other:?}"),
    }
    // Motors: a joint the robot does not have, a motor the world refuses.
    for (motor, wanted) in [
        (
            "nope = { type = \"velocity\", target = 1.0, max_force = 5.0 }",
            "no moving joint named `nope`",
        ),
        (
            "elbow = { type = \"velocity\", target = 1.0, max_force = -5.0 }",
            "must be >= 0",
        ),
    ] {
        let bad = text.replace(
            "fixed_base = true\n",
            &format!("fixed_base = true\nmotors = {{ {motor} }}\n"),
        );
        match parse_scene(&bad, Format::Toml, "robots.toml".as_ref()) {
            Err(SceneError::At { path, message, .. }) => {
                assert!(path.starts_with("robots[0].motors."), "{path}");
                assert!(
                    wanted != "must be >= 0" || path == "robots[0].motors.elbow.max_force",
                    "{path}"
                );
                assert!(message.contains(wanted), "{message}");
            }
            other => panic!("expected a located error, got {other:?}"),
        }
    }
}

#[test]
fn the_arm_reach_scene_holds_its_payload_at_the_pd_targets() {
    // examples/scenes/arm_reach.toml: the arm through a scene file, its
    // motors from the file, a payload welded to its tool.
    let path = format!(
        "{}/../../examples/scenes/arm_reach.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    let scene = tumble::scene::load_scene(&path).unwrap();
    let (mut w, _) = scene.build().unwrap();
    steps(&mut w, scene.scene.steps);
    let state = |name: &str| {
        let id = w
            .joint_ids()
            .into_iter()
            .find(|&j| w.joint(j).unwrap().name == name)
            .unwrap_or_else(|| panic!("no joint {name}"));
        w.joint_state(id).unwrap()
    };
    for (name, target) in [
        ("arm/shoulder_pan", 0.5),
        ("arm/shoulder_lift", 0.6),
        ("arm/elbow", 0.8),
    ] {
        let s = state(name);
        // The load's torque over the stiffness leaves a few mrad.
        assert!((s.position - target).abs() < 0.02, "{name}: {} rad", s.position);
        assert!(s.rate.abs() < 1e-3, "{name}: still at {} rad/s", s.rate);
    }
    assert!(w.max_joint_error().0 < 1e-3);
}

#[test]
fn joint_friction_holds_below_it_and_opposes_motion_above_it() {
    // A 1 kg bob 0.5 m out on a horizontal arm, its hinge's <dynamics
    // friction> f: gravity's torque m g d = 4.905 N m. Above it the arm
    // stays; below it the arm starts to fall at (m g d - f) / I_pivot
    // (Coulomb friction on the joint, as MuJoCo's frictionloss).
    let arm = |friction: f64| {
        format!(
            r#"<robot name="r">
  <link name="base">
    <inertial><mass value="0"/><inertia ixx="0" iyy="0" izz="0"/></inertial>
    <collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>
  </link>
  <link name="arm">
    <inertial><origin xyz="0.5 0 0"/><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01"/></inertial>
  </link>
  <joint name="pivot" type="continuous">
    <parent link="base"/><child link="arm"/><axis xyz="0 1 0"/>
    <dynamics friction="{friction}"/>
  </joint>
</robot>"#
        )
    };
    let (g, d, i_pivot) = (9.81, 0.5, 0.01 + 0.25);
    let torque = g * d;
    let rate_after = |friction: f64, n: usize| {
        let (mut w, r) = loaded(
            &arm(friction),
            UrdfOptions {
                position: DVec3::new(0.0, 0.0, 2.0),
                ..UrdfOptions::default()
            },
        );
        steps(&mut w, n);
        let s = w.joint_state(r.joints["pivot"].id).unwrap();
        (s.position, s.rate, w.time())
    };
    let (held, rate, _) = rate_after(6.0, 60);
    assert!(
        held.abs() < 1e-6 && rate.abs() < 1e-6,
        "held: {held} rad, {rate} rad/s"
    );
    for friction in [0.0, 3.0] {
        let (_, rate, t) = rate_after(friction, 6);
        let expected = (torque - friction) / i_pivot * t;
        assert!(
            (rate.abs() / expected - 1.0).abs() < 0.01,
            "f {friction}: {rate} rad/s, expected {expected}"
        );
    }
}

#[test]
fn joint_damping_and_friction_slow_a_wheel_by_the_analytic_law() {
    // A wheel on a vertical continuous joint (gravity turns it not), I =
    // 0.5 kg m^2 about it, <dynamics damping c = 0.2 N m s friction f =
    // 0.1 N m>, spun at w0 = 5 rad/s: I w' = -c w - f, so w(t) = (w0 + f /
    // c) e^(-c t / I) - f / c until it stops at t* = (I / c) ln(1 + c w0 /
    // f) = 6.0 s, and stays.
    let text = r#"<robot name="r">
  <link name="world"/>
  <link name="wheel">
    <inertial><mass value="1"/><inertia ixx="0.3" iyy="0.3" izz="0.5"/></inertial>
  </link>
  <joint name="axle" type="continuous">
    <parent link="world"/><child link="wheel"/><origin xyz="0 0 1"/><axis xyz="0 0 1"/>
    <dynamics damping="0.2" friction="0.1"/>
  </joint>
</robot>"#;
    let (i, c, f, w0) = (0.5, 0.2, 0.1, 5.0);
    let (mut w, r) = loaded(text, UrdfOptions::default());
    let (wheel, axle) = (r.links["wheel"], r.joints["axle"].id);
    w.set_velocity(wheel, DVec3::ZERO, DVec3::new(0.0, 0.0, w0))
        .unwrap();
    let rate = |w: &World| w.joint_state(axle).unwrap().rate;
    steps(&mut w, 120);
    let t = w.time();
    let expected = (w0 + f / c) * (-c * t / i).exp() - f / c;
    assert!(
        (rate(&w) / expected - 1.0).abs() < 0.005,
        "{} rad/s at {t} s, expected {expected}",
        rate(&w)
    );
    let stop = (i / c) * (1.0 + c * w0 / f).ln();
    while w.time() < stop - 0.05 {
        w.step();
        assert!(rate(&w) > 0.0, "stopped at {} s, before {stop}", w.time());
    }
    steps(&mut w, 6);
    assert!(rate(&w).abs() < 1e-9, "still at {} rad/s", rate(&w));
    // A motor set now acts beside the friction and the damper: a velocity
    // motor of at most tau = 0.4 N m towards a speed it cannot reach spins
    // the wheel up against both, I w' = tau - f - c w, to (tau - f) / c:
    // w(t) = ((tau - f) / c) (1 - e^(-c t / I)).
    let tau = 0.4;
    w.set_joint_motor(
        axle,
        Some(Motor::Velocity {
            target: 100.0,
            max_force: tau,
        }),
    )
    .unwrap();
    let start = w.time();
    steps(&mut w, 120);
    let t = w.time() - start;
    let expected = (tau - f) / c * (1.0 - (-c * t / i).exp());
    assert!(
        (rate(&w) / expected - 1.0).abs() < 0.005,
        "{} rad/s after {t} s of the motor, expected {expected}",
        rate(&w)
    );
}

#[test]
fn a_scene_robots_ball_motor_target_turns_with_the_robot() {
    // A `spherical` joint driven from a scene file's motor table: its
    // target is in the file's axes, so the same table on the robot placed
    // turned by R gives the joint the target R t in the world, and the
    // child link turns (relative to its parent) by exactly that: the robot
    // placed turned does what it does unturned, turned.
    let text = r#"<robot name="r">
  <link name="a"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="b"><inertial><origin xyz="0 0 0.3"/><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="ball" type="spherical"><parent link="a"/><child link="b"/><origin xyz="0 0 0.5"/></joint>
</robot>"#;
    let dir = std::env::temp_dir().join(format!("tumble-urdf-ball-motor-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("r.urdf"), text).unwrap();
    let target = DVec3::new(0.3, -0.4, 0.2);
    let run = |orientation: DQuat| {
        let q = orientation.to_array();
        let scene = format!(
            "[settings]\ngravity = [0, 0, 0]\nsleeping = false\n[[robots]]\nfile = \"{}\"\nfixed_base = true\n\
             orientation = [{}, {}, {}, {}]\n\
             motors = {{ ball = {{ type = \"orientation\", target = [{}, {}, {}], stiffness = 1.0, damping = 0.2, max_force = 100.0 }} }}\n",
            dir.join("r.urdf").display(),
            q[0],
            q[1],
            q[2],
            q[3],
            target.x,
            target.y,
            target.z,
        );
        let (mut w, _) = tumble::scene::parse_scene(&scene, tumble::scene::Format::Toml, "s.toml".as_ref())
            .unwrap()
            .build()
            .unwrap();
        steps(&mut w, 900);
        let j = w.joint_ids()[0];
        w.joint_state(j).unwrap().rotation
    };
    let plain = run(DQuat::IDENTITY);
    assert!((plain - target).length() < 1e-6, "{plain} against {target}");
    let turn = DQuat::from_scaled_axis(DVec3::new(0.7, -1.9, 0.4));
    let turned = run(turn);
    assert!(
        (turned - turn * target).length() < 1e-6,
        "{turned} against {}",
        turn * target
    );
}

/// A gripper: a palm welded to the world and two fingers on sliders
/// across it, the second mimicking the first (`multiplier` -1: they close
/// together), and a wrist-like wheel mimicking the first finger's slide at
/// 10 rad/m with an offset.
const GRIPPER: &str = r#"<robot name="gripper">
  <link name="world"/>
  <link name="palm"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="left"><inertial><mass value="0.1"/><inertia ixx="1e-4" iyy="1e-4" izz="1e-4" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="right"><inertial><mass value="0.1"/><inertia ixx="1e-4" iyy="1e-4" izz="1e-4" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="dial"><inertial><mass value="0.2"/><inertia ixx="1e-3" iyy="1e-3" izz="1e-3" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="base" type="fixed"><parent link="world"/><child link="palm"/><origin xyz="0 0 1"/></joint>
  <joint name="left_slide" type="prismatic">
    <parent link="palm"/><child link="left"/><origin xyz="0 0.05 0"/><axis xyz="0 1 0"/>
    <limit lower="-0.04" upper="0.04" effort="50" velocity="1"/>
  </joint>
  <joint name="right_slide" type="prismatic">
    <parent link="palm"/><child link="right"/><origin xyz="0 -0.05 0"/><axis xyz="0 1 0"/>
    <limit lower="-0.04" upper="0.04" effort="50" velocity="1"/>
    <mimic joint="left_slide" multiplier="-1"/>
  </joint>
  <joint name="dial_turn" type="continuous">
    <parent link="palm"/><child link="dial"/><origin xyz="0.1 0 0"/><axis xyz="1 0 0"/>
    <mimic joint="left_slide" multiplier="10" offset="0.2"/>
  </joint>
</robot>"#;

#[test]
fn mimic_joints_follow_their_leader() {
    // The left finger driven to 0.02 m by its PD servo: the right one
    // mirrors it (-0.02 m) and the dial turns to 10 x 0.02 + 0.2 rad,
    // each within a micrometre or microradian of its gear, no gravity
    // acting along the slides (they are horizontal).
    let mut w = world();
    let r = add_urdf(&mut w, GRIPPER, "gripper.urdf".as_ref(), UrdfOptions::default()).unwrap();
    assert!(
        r.warnings.iter().all(|m| !m.contains("mimic")),
        "{:?}",
        r.warnings
    );
    let [left, right, dial] = ["left_slide", "right_slide", "dial_turn"].map(|n| r.joints[n].id);
    assert_eq!(w.joint_gear(right).unwrap(), Some(Gear::new(left, -1.0)));
    assert_eq!(
        w.joint_gear(dial).unwrap(),
        Some(Gear::new(left, 10.0).with_offset(0.2))
    );
    w.set_joint_motor(
        left,
        Some(Motor::Position {
            target: 0.02,
            stiffness: 200.0,
            damping: 20.0,
            max_force: 50.0,
        }),
    )
    .unwrap();
    for _ in 0..240 {
        w.step();
    }
    let position = |j| w.joint_state(j).unwrap().position;
    assert!(
        (position(left) - 0.02).abs() < 1e-4,
        "left finger at {}",
        position(left)
    );
    assert!(
        (position(right) + position(left)).abs() < 1e-6,
        "right finger at {}",
        position(right)
    );
    assert!(
        (position(dial) - (10.0 * position(left) + 0.2)).abs() < 1e-6,
        "dial at {}",
        position(dial)
    );
    assert!(
        w.max_joint_error().0 < 1e-6 && w.max_joint_error().1 < 1e-6,
        "{:?}",
        w.max_joint_error()
    );
}

#[test]
fn a_mimic_of_a_joint_the_robot_does_not_move_is_refused_at_the_mimic_element() {
    for leader in ["nothing", "base"] {
        let text = GRIPPER.replace(
            "<mimic joint=\"left_slide\" multiplier=\"-1\"/>",
            &format!("<mimic joint=\"{leader}\" multiplier=\"-1\"/>"),
        );
        let (line, element, message) = error_of(&text);
        assert_eq!(element, "mimic", "{message}");
        assert_eq!(line, 15, "{message}");
        assert!(message.contains(&format!("`{leader}`")), "{message}");
    }
    // A mimic with no joint to follow.
    let text = GRIPPER.replace(
        "<mimic joint=\"left_slide\" multiplier=\"-1\"/>",
        "<mimic multiplier=\"-1\"/>",
    );
    let (_, element, message) = error_of(&text);
    assert!(
        element == "mimic" && message.contains("joint="),
        "{element} {message}"
    );
    // A multiplier or offset beyond what a gear takes (1e6 either way).
    for mimic in [
        "<mimic joint=\"left_slide\" multiplier=\"-1e7\"/>",
        "<mimic joint=\"left_slide\" multiplier=\"-1\" offset=\"2e6\"/>",
    ] {
        let text = GRIPPER.replace("<mimic joint=\"left_slide\" multiplier=\"-1\"/>", mimic);
        let (line, element, message) = error_of(&text);
        assert_eq!((line, element.as_str()), (15, "mimic"), "{message}");
        assert!(message.contains("gear."), "{message}");
    }
}

/// A URDF ring welded to the world (a torus mesh of major radius 0.3 m and tube radius
/// 0.08 m, lying flat with its centre at z = 0.5 m) in a world with a
/// ground plane, and a ball of radius 0.1 m dropped onto its middle from
/// z = 1 m: `(world, ring, ball)`. Written as an OBJ file into `dir`.
fn ring_and_ball(
    dir: &std::path::Path,
    convex_meshes: bool,
) -> (World, tumble::world::BodyId, tumble::world::BodyId) {
    let torus = tumble::collide::mesh::torus_mesh(0.3, 0.08, 32, 16).unwrap();
    let mut obj = String::new();
    for v in torus.vertices() {
        obj += &format!("v {} {} {}\n", v.x, v.y, v.z);
    }
    for t in torus.triangles() {
        obj += &format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    std::fs::write(dir.join("ring.obj"), obj).unwrap();
    let text = r#"<robot name="ring"><link name="ring">
  <collision><geometry><mesh filename="ring.obj"/></geometry></collision>
</link></robot>"#;
    std::fs::write(dir.join("ring.urdf"), text).unwrap();
    let mut w = world();
    w.add_body(&BodyDesc::fixed(HalfSpace::new(DVec3::Z, 0.0).unwrap()))
        .unwrap();
    let options = UrdfOptions {
        position: DVec3::new(0.0, 0.0, 0.5),
        fixed_base: true,
        convex_meshes,
        ..UrdfOptions::default()
    };
    let robot = load_urdf(&mut w, dir.join("ring.urdf"), options).unwrap();
    let ball = w
        .add_body(
            &BodyDesc::dynamic(tumble::collide::Sphere::new(0.1).unwrap()).at(DVec3::new(0.0, 0.0, 1.0)),
        )
        .unwrap();
    (w, robot.links["ring"], ball)
}

#[test]
fn mesh_links_are_exact_or_their_convex_hulls_on_request() {
    let dir = std::env::temp_dir().join(format!("tumble-urdf-convex-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let torus = tumble::collide::mesh::torus_mesh(0.3, 0.08, 32, 16).unwrap();
    for convex in [false, true] {
        let (mut w, ring, ball) = ring_and_ball(&dir, convex);
        let colliders = w.colliders(ring).unwrap();
        assert_eq!(colliders.len(), 1);
        match (&colliders[0].shape, convex) {
            (tumble::collide::Shape::Mesh(_), false) => {}
            (tumble::collide::Shape::ConvexHull(hull), true) => {
                // The hull reaches exactly as far as the mesh in every
                // direction (what a convex hull of its vertices is), and
                // has no vertex the mesh does not.
                use tumble::collide::shape::Polytope;
                for k in 0..64 {
                    let (a, b) = (k as f64 * 0.7, k as f64 * 1.3);
                    let d = DVec3::new(a.cos() * b.sin(), a.sin() * b.sin(), b.cos());
                    let reach = torus.vertices().iter().map(|v| v.dot(d)).fold(f64::MIN, f64::max);
                    let hull_reach = hull.vertex(hull.support_vertex(d)).dot(d);
                    assert!(
                        (hull_reach - reach).abs() < 1e-12,
                        "{d}: {hull_reach} against {reach}"
                    );
                }
                for i in 0..hull.vertex_count() {
                    assert!(torus.vertices().contains(&hull.vertex(i)));
                }
            }
            (shape, _) => panic!("convex_meshes = {convex}: {shape:?}"),
        }
        // Through the hole onto the ground, or onto the hull's lid.
        steps(&mut w, 150);
        let z = w.pose(ball).unwrap().position.z;
        let rest = if convex { 0.5 + 0.08 + 0.1 } else { 0.1 };
        assert!(
            (z - rest).abs() < 2e-3,
            "convex_meshes = {convex}: the ball at z = {z}, not {rest}"
        );
        assert!(w.body(ball).unwrap().velocity().length() < 1e-2);
    }
    // A flat mesh has no hull: refused at its element, the world unchanged.
    std::fs::write(
        dir.join("flat.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\nf 1 3 2\nf 2 3 4\n",
    )
    .unwrap();
    let text = "<robot name=\"flat\"><link name=\"f\">\n  <collision><geometry><mesh filename=\"flat.obj\"/></geometry></collision>\n</link></robot>";
    std::fs::write(dir.join("flat.urdf"), text).unwrap();
    let mut w = world();
    let before = w.body_ids().len();
    let e = load_urdf(
        &mut w,
        dir.join("flat.urdf"),
        UrdfOptions {
            convex_meshes: true,
            ..UrdfOptions::default()
        },
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("flat.urdf:2:") && e.contains("<mesh") && e.contains("convex hull"),
        "{e}"
    );
    assert_eq!(w.body_ids().len(), before);
    // A scene file's robot takes the option too.
    for convex in [false, true] {
        let scene = format!(
            "[[robots]]\nfile = \"{}\"\nconvex_meshes = {convex}\n",
            dir.join("ring.urdf").display()
        );
        let scene =
            tumble::scene::parse_scene(&scene, tumble::scene::Format::Toml, "s.toml".as_ref()).unwrap();
        let (w, ids) = scene.build().unwrap();
        let shape = &w.colliders(ids[0]).unwrap()[0].shape;
        assert_eq!(
            matches!(shape, tumble::collide::Shape::ConvexHull(_)),
            convex,
            "{shape:?}"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
