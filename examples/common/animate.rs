//! The animated default: light 0 orbits the scene's vertical axis, frame-locked so a windowed
//! run and a headless `--time` render of the same frame agree exactly.

use glam::{Quat, Vec3};
use umbra::scene::{Light, Scene};

/// Animation seconds per rendered frame (frame-locked: frame `k` is at `k / FPS` seconds).
pub const FPS: f32 = 60.0;
/// Seconds for one full orbit of the animated light.
pub const ORBIT_SECONDS: f32 = 12.0;

/// The animation time of frame `k`.
pub fn frame_time(k: u64) -> f32 {
    k as f32 / FPS
}

/// `light` turned by `yaw` about the vertical axis through `centre` and raised by `pitch`
/// (radians) about the horizontal axis facing it; directional lights turn their direction.
/// No turn at all returns the light unchanged, bit for bit.
pub fn turned(light: &Light, centre: Vec3, yaw: f32, pitch: f32) -> Light {
    let mut out = light.clone();
    if yaw == 0.0 && pitch == 0.0 {
        return out;
    }
    let p = light.position.truncate();
    let offset = if light.position.w == 0.0 { p } else { p - centre };
    let side = Vec3::Y.cross(offset).try_normalize().unwrap_or(Vec3::X);
    // Keep clear of the pole, where the vertical axis and the offset would align.
    let elevation = offset.y.atan2(glam::Vec2::new(offset.x, offset.z).length());
    let pitch = pitch.clamp(-1.5 - elevation, 1.5 - elevation);
    let q = Quat::from_rotation_y(yaw) * Quat::from_axis_angle(side, -pitch);
    let moved = q * offset;
    out.position = match light.position.w {
        0.0 => moved.extend(0.0),
        _ => (centre + moved).extend(1.0),
    };
    if let Some(spot) = out.spot.as_mut() {
        spot.direction = q * spot.direction;
    }
    out
}

/// Light 0 of `scene` moved to where the animation has it at `time` seconds (0: as loaded).
pub fn apply(scene: &mut Scene, time: f32) {
    if time == 0.0 {
        return;
    }
    let centre = scene.bounds().center();
    if let Some(light) = scene.lights.first_mut() {
        *light = turned(light, centre, orbit_angle(time), 0.0);
    }
}

/// The animated light's yaw at `time`.
pub fn orbit_angle(time: f32) -> f32 {
    std::f32::consts::TAU * time / ORBIT_SECONDS
}
