//! The window's camera (orbit, pan, zoom, fly) and its key bindings.

use glam::Vec3;
use umbra::scene::Camera;

/// Every binding of the windowed examples, as printed at start and in `docs/window.md`.
pub const BINDINGS: &[(&str, &str)] = &[
    ("left drag", "orbit the camera around its target"),
    ("right or middle drag", "pan"),
    ("wheel", "zoom"),
    ("W A S D, Q E", "fly forward, left, back, right; down, up"),
    ("arrows", "move the selected light: around the scene (left, right), up and down"),
    ("Tab", "select the next light"),
    ("1 2 3 4 5 6", "every light: shadow map, silhouette map, shadow volume, hybrid, ray traced, ray-traced hybrid"),
    ("0", "back to the techniques the example started with"),
    ("M", "cycle the shadow-map size: 512, 1024, 2048, 4096, the example's"),
    ("K", "cycle the hybrid's computation mask: depth-bounds (if the device has it), stencil, none"),
    ("V", "cycle the view: image, classification, volume overdraw, stencil"),
    ("Space or P", "pause or resume the animation (light 0 orbits the scene)"),
    ("R", "reset camera, lights and animation"),
    ("F12", "save a screenshot (the --screenshot file, or OUT/EXAMPLE-window-FRAME.png)"),
    ("Esc", "quit"),
];

/// An orbit camera around a target, starting exactly at the scene's camera.
#[derive(Clone, Debug)]
pub struct CameraRig {
    start: Camera,
    target: Vec3,
    yaw: f32,
    pitch: f32,
    distance: f32,
    /// Whether the user moved it (until then the scene's camera is used bit for bit).
    moved: bool,
}

impl CameraRig {
    /// A rig at `camera`.
    pub fn new(camera: Camera) -> Self {
        let offset = camera.position - camera.target;
        let distance = offset.length().max(1e-3);
        Self {
            start: camera,
            target: camera.target,
            yaw: offset.x.atan2(offset.z),
            pitch: (offset.y / distance).clamp(-1.0, 1.0).asin(),
            distance,
            moved: false,
        }
    }

    /// Back to the scene's camera.
    pub fn reset(&mut self) {
        *self = Self::new(self.start);
    }

    /// The camera now.
    pub fn camera(&self) -> Camera {
        if !self.moved {
            return self.start;
        }
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        let offset = Vec3::new(cp * sy, sp, cp * cy) * self.distance;
        Camera { position: self.target + offset, target: self.target, up: Vec3::Y, ..self.start }
    }

    /// Turns around the target by a mouse movement in pixels.
    pub fn orbit(&mut self, dx: f32, dy: f32) {
        self.yaw -= dx * 0.005;
        self.pitch = (self.pitch + dy * 0.005).clamp(-1.5, 1.5);
        self.moved = true;
    }

    /// Moves target and eye in the view plane by a mouse movement in pixels.
    pub fn pan(&mut self, dx: f32, dy: f32) {
        let (right, up, _) = self.axes();
        self.target += (right * -dx + up * dy) * self.distance * 0.0015;
        self.moved = true;
    }

    /// Moves the eye towards (positive) or away from the target by wheel lines.
    pub fn zoom(&mut self, lines: f32) {
        self.distance = (self.distance * 0.9f32.powf(lines)).max(1e-3);
        self.moved = true;
    }

    /// Flies eye and target along the view (`forward`), sideways (`right`) and vertically
    /// (`up`), each in -1..=1, by `step` world units.
    pub fn fly(&mut self, forward: f32, right: f32, up: f32, step: f32) {
        let (r, _, f) = self.axes();
        self.target += (f * forward + r * right + Vec3::Y * up) * step;
        self.moved = true;
    }

    /// Right, up and forward of the view.
    fn axes(&self) -> (Vec3, Vec3, Vec3) {
        let forward = (self.target - self.camera().position).normalize_or(Vec3::NEG_Z);
        let right = forward.cross(Vec3::Y).normalize_or(Vec3::X);
        (right, right.cross(forward), forward)
    }
}
