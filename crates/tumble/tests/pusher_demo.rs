//! The pusher demo (`examples/pusher.rs`): the kinematic paddle follows its
//! prescribed path exactly, and the box it pushes moves with it and stops
//! against it, square to the push, on the table.

#[allow(dead_code)]
#[path = "../examples/pusher.rs"]
mod pusher;

use pusher::*;

#[test]
fn kinematic_paddle_follows_its_profile_and_pushes_the_box() {
    let run = run(3.2, |_| {}).unwrap();
    // The paddle: exactly the integral of the prescribed velocity, at every step.
    for &(t, paddle_x, _) in &run.samples {
        let expected = profile_position(t);
        assert!(
            (paddle_x - expected).abs() < 1e-9,
            "t = {t}: paddle at {paddle_x}, prescribed {expected}"
        );
    }
    let pose = run.world.pose(run.paddle).unwrap();
    assert_eq!(
        pose.rotation,
        tumble::collide::DQuat::IDENTITY,
        "never pushed back, never turned"
    );
    assert!(
        (pose.position.y).abs() < 1e-12
            && (pose.position.z - (TABLE_TOP + PADDLE_HALF.z + 0.002)).abs() < 1e-12
    );

    // Before the paddle reaches it, the box rests where it was put.
    let contact_x = -PADDLE_HALF.x - BOX_HALF;
    for &(t, paddle_x, cube_x) in &run.samples {
        if paddle_x < contact_x - 0.01 {
            assert!(
                cube_x.abs() < 1e-3,
                "t = {t}: the box moved before the paddle arrived"
            );
        }
    }
    // While the paddle cruises after the impact, the box keeps pace: a
    // friction deceleration of mu g = 4.9 m/s^2 stops any lead at once.
    let (t_contact, _, _) = *run.samples.iter().find(|s| s.1 >= contact_x).unwrap();
    for &(t, paddle_x, cube_x) in &run.samples {
        if t > t_contact + 0.1 && t < RAMP + CRUISE {
            let gap = cube_x - (paddle_x + PADDLE_HALF.x + BOX_HALF);
            assert!(gap.abs() < 5e-3, "t = {t}: box {gap} m from the paddle face");
        }
    }
    // At the end the paddle stopped (its deceleration, 0.4 m/s^2, is below
    // mu g, so the box did not slide on) and the box rests against it.
    let cube = run.world.center_of_mass(run.cube).unwrap();
    let paddle_end = profile_position(10.0);
    let expected_x = paddle_end + PADDLE_HALF.x + BOX_HALF;
    assert!(
        (cube.x - expected_x).abs() < 5e-3,
        "box at {}, expected {expected_x}",
        cube.x
    );
    assert!(cube.y.abs() < 0.01, "pushed square: sideways drift {}", cube.y);
    assert!(
        (cube.z - (TABLE_TOP + BOX_HALF)).abs() < 2e-3,
        "on the table: z = {}",
        cube.z
    );
    assert!(yaw(run.world.orientation(run.cube).unwrap()).abs() < 0.05);
    assert!(
        run.world.linear_velocity(run.cube).unwrap().length() < 0.01,
        "at rest"
    );
}
