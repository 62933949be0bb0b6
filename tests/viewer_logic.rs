//! The windowed viewer's pure parts (examples/common): the animated light, the camera rig,
//! and the key bindings as documented in docs/window.md.

#[path = "../examples/common/animate.rs"]
#[allow(dead_code)]
mod animate;
#[path = "../examples/common/controls.rs"]
mod controls;

use glam::Vec3;
use umbra::scene::{Camera, Light};

#[test]
fn no_turn_leaves_a_light_bit_for_bit() {
    let light = Light::spot(Vec3::new(1.3, 4.7, -2.1), Vec3::new(-0.3, -1.0, 0.4), 20.0, 30.0, 5.0);
    assert_eq!(animate::turned(&light, Vec3::new(0.1, 0.2, 0.3), 0.0, 0.0), light);
}

#[test]
fn a_full_orbit_comes_back_and_the_spot_keeps_aiming_at_the_centre() {
    let centre = Vec3::new(0.5, 0.0, -1.0);
    let position = Vec3::new(3.0, 4.0, 2.0);
    let light = Light::spot(position, centre - position, 20.0, 30.0, 5.0);
    let full = animate::turned(&light, centre, std::f32::consts::TAU, 0.0);
    assert!((full.position - light.position).length() < 1e-4, "{:?}", full.position);
    let quarter = animate::turned(&light, centre, animate::orbit_angle(animate::ORBIT_SECONDS / 4.0), 0.0);
    let p = quarter.position.truncate();
    assert!((p.y - position.y).abs() < 1e-4, "orbits keep the height: {p:?}");
    assert!(((p - centre).length() - (position - centre).length()).abs() < 1e-4, "and the distance");
    assert!(p.distance(position) > 1.0, "a quarter turn moves it");
    let aim = quarter.spot.expect("still a spot").direction.normalize();
    assert!(aim.dot((centre - p).normalize()) > 0.9999, "the cone turns with the light: {aim:?}");
}

#[test]
fn directional_lights_turn_their_direction_and_pitch_stays_off_the_pole() {
    let light = Light::directional(Vec3::new(1.0, 1.0, 0.0), 2.0);
    let turned = animate::turned(&light, Vec3::ZERO, 0.0, 10.0);
    assert_eq!(turned.position.w, 0.0);
    let d = turned.position.truncate().normalize();
    assert!(d.y < 1.0 && d.y > 0.99, "pitched up to just below the pole: {d:?}");
    let frame_times: Vec<f32> = (0..3).map(animate::frame_time).collect();
    assert_eq!(frame_times, [0.0, 1.0 / 60.0, 2.0 / 60.0]);
}

#[test]
fn the_rig_starts_at_the_scene_camera_and_moves_only_when_asked() {
    let camera = Camera {
        position: Vec3::new(3.0, 2.0, 6.0),
        target: Vec3::new(0.0, 0.5, 0.0),
        up: Vec3::Y,
        fov_y_deg: 50.0,
        near: 0.1,
        far: Some(100.0),
    };
    let mut rig = controls::CameraRig::new(camera);
    assert_eq!(rig.camera(), camera, "untouched, the scene's camera bit for bit");
    rig.orbit(0.0, 0.0);
    let same = rig.camera();
    assert!(same.position.distance(camera.position) < 1e-4, "a zero orbit stays put: {:?}", same.position);
    rig.zoom(1.0);
    let closer = rig.camera();
    let d = |c: &Camera| c.position.distance(c.target);
    assert!((d(&closer) - 0.9 * d(&camera)).abs() < 1e-3, "a wheel line is 10% closer");
    let before = rig.camera();
    rig.pan(100.0, 0.0);
    let panned = rig.camera();
    assert!(panned.target.distance(before.target) > 0.1, "a drag pans the target");
    assert!((d(&panned) - d(&before)).abs() < 1e-3, "panning keeps the distance");
    assert!((panned.target - before.target).dot(before.target - before.position) < 1e-3, "in the view plane");
    rig.fly(1.0, 0.0, 0.0, 1.0);
    assert!(rig.camera().target.distance(camera.target) > 0.99, "flying moves the target");
    rig.reset();
    assert_eq!(rig.camera(), camera);
}

#[test]
fn every_binding_is_documented() {
    let doc = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/window.md")).expect("docs/window.md");
    for (key, what) in controls::BINDINGS {
        let row = format!("| {key} | {what} |");
        assert!(doc.contains(&row), "docs/window.md lacks the row {row:?}");
    }
}
