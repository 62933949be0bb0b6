//! What one light's shadow volumes report for a frame (the frame report's
//! `shadow_volume` field).

use crate::view::DepthPrecision;
use serde::Serialize;

/// A light's shadow volumes as built and counted in one frame.
#[derive(Clone, Debug, Serialize)]
pub struct ShadowVolumeReport {
    /// Casters with a non-empty volume.
    pub casters: usize,
    /// Casters counted with z-pass.
    pub zpass_casters: usize,
    /// Casters counted with z-fail.
    pub zfail_casters: usize,
    /// Silhouette edges extruded (with multiplicity).
    pub silhouette_edges: usize,
    /// Volume triangles drawn (sides, plus caps for z-fail casters; after clipping, when
    /// `host_clipped`).
    pub volume_triangles: usize,
    /// Whether the volumes were clipped to the view on the host before they were drawn
    /// (`ShadowVolumeSettings::host_clip`; on drivers whose clipping is not watertight).
    pub host_clipped: bool,
    /// Batches the casters were counted in: 1 when their count bounds fit the count (at most
    /// 255; 127 under the hybrid's stencil mask), else runs whose bounds fit a narrower count
    /// (127; 63), each folded into one stencil bit before the next
    /// (`shadow_volume/batches.rs`).
    pub count_batches: usize,
    /// CPU time to build every caster's volume (facing, silhouettes, caps) and, when
    /// `host_clipped`, to clip them.
    pub cpu_build_ms: f64,
    /// Rasterized volume fragments (from the overdraw pass's occlusion query), when the
    /// renderer was built with `overdraw`.
    pub volume_fragments: Option<u64>,
    /// Per caster: object index, name and the mode it was counted with.
    pub caster_modes: Vec<CasterMode>,
    /// Whether the volumes were built on the GPU (`VolumeBuild::Gpu`): the host only named the
    /// casters (`cpu_build_ms` is the naming's time). The renderer's own frames read the
    /// counts back from the GPU after the frame (`volume counts readback`), so `casters`,
    /// `silhouette_edges`, `volume_triangles` and `caster_modes` are those of the CPU path;
    /// `count_batches` is planned on the host from bounds on every named caster.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub gpu_built: bool,
    /// The camera's depth step at the scene's farthest point, where the near plane is closer
    /// than [`umbra_scene::Camera::EXACT_NEAR_RATIO`] of that distance: volume faces and surfaces
    /// nearer each other in depth than `step` may count on the wrong side of each other there.
    /// `None` (and left out of the JSON) where the depth is as fine as where shadow volumes are
    /// measured exact.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub depth_precision: Option<DepthPrecision>,
}

/// The counting mode one caster used.
#[derive(Clone, Debug, Serialize)]
pub struct CasterMode {
    /// Object index.
    pub object: usize,
    /// Object name.
    pub name: String,
    /// `zpass` or `zfail`; `gpu` for volumes built on the GPU in `auto` mode, whose mode the
    /// GPU decides each frame, in a frame whose counts are not read back (an engine's frame).
    pub mode: &'static str,
    /// Volume triangles drawn for it.
    pub triangles: usize,
}
