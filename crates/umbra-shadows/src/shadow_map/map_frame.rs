//! One light's shadow map in one frame: the views it is rendered with, its size, who reads it
//! and what the lighting passes read of it.

use super::frustum::LightViews;
use crate::gpu_scene::GpuShadow;

/// One light's shadow map this frame.
pub(crate) struct MapFrame {
    /// Its views (one per layer) and the casters each draws.
    pub views: LightViews,
    /// Texels per side.
    pub resolution: u32,
    /// Whether it is also a silhouette map's depth map.
    pub silhouette: bool,
    /// Whether its depth map is made and drawn: by every map technique but the hybrid without
    /// blocker culling, whose classification reads only its depth bounds (the views still
    /// place them), so a depth map there could not change the image.
    pub depth: bool,
    /// What the lighting passes read of it.
    pub shadow: GpuShadow,
    /// Depth-bias clamp in map depth units (0: none, or no `depthBiasClamp`).
    pub bias_clamp: f32,
}

impl MapFrame {
    /// A map of `views` at `resolution` texels per side; `silhouette` when a silhouette map
    /// reads it, `depth` when its depth map is drawn. Its lighting inputs and bias clamp are
    /// set once its place in the frame's maps is known.
    pub fn new(views: LightViews, resolution: u32, silhouette: bool, depth: bool) -> Self {
        MapFrame { views, resolution, silhouette, depth, shadow: GpuShadow::default(), bias_clamp: 0.0 }
    }
}
