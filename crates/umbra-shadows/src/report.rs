//! The frame report: what a frame did, on which device, and what it cost on the GPU.

use crate::plan::{FramePlan, LightPlan};
use crate::shadow_map::ShadowMapSettings;
use crate::shadow_volume::ShadowVolumeSettings;
use crate::timing::PassReport;
use serde::Serialize;
use umbra_scene::Scene;
use umbra_vk::Capabilities;

/// The scene a frame rendered, in numbers.
#[derive(Clone, Debug, Serialize)]
pub struct SceneSummary {
    /// Scene name.
    pub name: String,
    /// Placed objects.
    pub objects: usize,
    /// Distinct meshes.
    pub meshes: usize,
    /// Triangles per full-scene pass.
    pub triangles: usize,
    /// Lights in the scene (recorded or not).
    pub lights: usize,
}

impl SceneSummary {
    /// Summarises `scene`.
    pub fn of(scene: &Scene) -> Self {
        Self {
            name: scene.name.clone(),
            objects: scene.objects.len(),
            meshes: scene.meshes.len(),
            triangles: scene.triangle_count(),
            lights: scene.lights.len(),
        }
    }
}

/// What one frame did. Serialises to JSON with [`FrameReport::to_json`].
#[derive(Clone, Debug, Serialize)]
pub struct FrameReport {
    /// Device name (same as `capabilities.device_name`).
    pub device: String,
    /// Driver name and version.
    pub driver: String,
    /// The device's capabilities as umbra uses them.
    pub capabilities: Capabilities,
    /// The scene.
    pub scene: SceneSummary,
    /// Target width in pixels.
    pub width: u32,
    /// Target height in pixels.
    pub height: u32,
    /// Shadow-map settings the renderer was built with.
    pub shadow_map_settings: ShadowMapSettings,
    /// Shadow-volume settings the renderer was built with.
    pub shadow_volume_settings: ShadowVolumeSettings,
    /// The frame plan in numbers: lights recorded, skipped and shadowed, casters culled per
    /// reason.
    pub plan: FramePlan,
    /// Per light: technique, passes recorded, what was culled and why, and its technique's
    /// figures.
    pub lights: Vec<LightPlan>,
    /// Every recorded pass, in order, with its GPU time.
    pub passes: Vec<PassReport>,
    /// Sum of the GPU times of the passes that make the image (`None` without timestamps);
    /// diagnostic passes are not included.
    pub total_gpu_ms: Option<f64>,
    /// Sum of the diagnostic passes' GPU times (0 when there were none).
    pub diagnostic_gpu_ms: Option<f64>,
    /// CPU wall time of recording, submission and wait, in milliseconds.
    pub cpu_frame_ms: f64,
}

impl FrameReport {
    /// Pretty-printed JSON.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"))
    }

    /// The pass named `name`, if recorded.
    pub fn pass(&self, name: &str) -> Option<&PassReport> {
        self.passes.iter().find(|p| p.name == name)
    }
}
