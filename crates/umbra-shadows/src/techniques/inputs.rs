//! What every pass of a frame reads: the scene on the GPU, each light's plan and bindings, the
//! frame's depth and streams, and the shared passes' layout and visibility images.

use super::light::{LightBindings, LightFrame};
use super::TechniqueSlot;
use crate::gpu_scene::GpuScene;
use crate::light_surfaces::{LightSurfaces, PassBounds};
use crate::visibility::{VisibilityPass, VisibilityTarget};
use crate::RenderResult;
use umbra_scene::Scene;
use umbra_vk::{Buffer, Image, PipelineLayout};

/// What every pass of a frame reads.
#[derive(Clone, Copy)]
pub(crate) struct FrameInputs<'a> {
    pub scene: &'a Scene,
    pub gpu: &'a GpuScene,
    pub lights: &'a [LightFrame],
    pub bindings: &'a [LightBindings<'a>],
    /// The frame's depth (and stencil): the renderer's own, the engine's, or umbra's rebuilt
    /// one for an engine's frame.
    pub depth: &'a Image,
    /// An engine's frame whose depth umbra re-draws into `depth` before anything tests it.
    pub rebuild: Option<&'a crate::depth_rebuild::DepthRebuild>,
    /// The frame's silhouette edges and shadow-volume vertices (none when empty).
    pub edges: Option<&'a Buffer>,
    pub volumes: Option<&'a Buffer>,
    /// The draws' initial values of the shadow volumes built on the GPU (when any).
    pub volume_resets: Option<&'a Buffer>,
    /// The scene's pipeline layout (sets: scene, a light's maps, its visibility).
    pub layout: &'a PipelineLayout,
    /// Every shadowed light's visibility image, which its technique writes.
    pub visibility: &'a VisibilityPass,
    /// The frame slot's sets over the BVH and the GPU-built volumes.
    pub slot: &'a TechniqueSlot,
    /// The classification and silhouette-point targets (with `diagnostics`).
    pub diagnostic_targets: Option<&'a crate::diagnostics::DiagnosticTargets>,
    /// The volume overdraw image (with `shadow_volume.overdraw`, in umbra's own frames).
    pub overdraw: Option<&'a Image>,
}

impl<'a> FrameInputs<'a> {
    /// `light`'s passes over the frame's surfaces: this frame's scene, the light, its bounds.
    pub fn surfaces(&self, light: &LightFrame) -> LightSurfaces<'a, 'a> {
        let bounds = PassBounds { scissor: light.plan.scissor, depth: light.plan.depth_bounds };
        LightSurfaces { gpu: self.gpu, scene: self.scene, light: light.light() as u32, bounds }
    }

    /// What `light`'s visibility pass writes: its visibility image over the frame's depth.
    pub fn visibility_target(&self, light: &LightFrame) -> RenderResult<VisibilityTarget<'a>> {
        Ok(VisibilityTarget { image: &self.visibility.light(light.light())?.image, depth: self.depth })
    }
}
