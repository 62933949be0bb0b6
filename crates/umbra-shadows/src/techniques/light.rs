//! What one frame knows of each light, in one place per light (indexed by light), and what the
//! whole frame shares: the camera and every object's bounds.

use crate::diagnostics::{ClassReadback, DiagnosticReadback};
use crate::frame::QueryId;
use crate::hybrid::frame::HybridQueries;
use crate::plan::LightPlan;
use crate::shadow_map::MapFrame;
use crate::shadow_volume::build::LightVolumes;
use crate::silhouette_map::edges::LightEdges;
use crate::technique::{needs, Lighting};
use crate::view::View;
use crate::visibility::VisibilityReadback;
use umbra_scene::Aabb;
use umbra_vk::DescriptorSet;

/// The view of a frame and the bounds every step uses.
pub(crate) struct FrameView {
    /// The view drawn with (`P_inf` when shadow volumes need it).
    pub view: View,
    /// Each object's world bounds (`Scene::object_bounds`).
    pub boxes: Vec<Option<Aabb>>,
}

impl FrameView {
    /// What its camera sees, for a frame of `height` pixel rows.
    pub fn seen(&self, height: u32) -> crate::shadow_map::texels::Seen<'_> {
        crate::shadow_map::texels::Seen { view: &self.view, height }
    }

    /// The camera's depth precision at the farthest corner of any object's bounds, where it is
    /// coarser than where shadow volumes are measured exact (`View::depth_precision`).
    pub fn depth_precision(&self) -> Option<crate::view::DepthPrecision> {
        let eye = self.view.position;
        let farthest = |b: &Aabb| (b.min - eye).abs().max((b.max - eye).abs()).length();
        let reach = self.boxes.iter().flatten().map(farthest).fold(0.0, f32::max);
        self.view.depth_precision(reach)
    }
}

/// One light in one frame: its plan and what its technique prepared.
pub(crate) struct LightFrame {
    /// What the plan decided (and, once the frame ran, what the light's passes reported).
    pub plan: LightPlan,
    /// Its shadow map (shadow maps, silhouette maps, the hybrid).
    pub map: Option<MapFrame>,
    /// Its silhouette edges (silhouette maps).
    pub edges: Option<LightEdges>,
    /// Its volumes (shadow volumes, the hybrid), culled casters left out.
    pub volumes: Option<LightVolumes>,
    /// Whether its shadows are ray traced this frame (the scene's BVH is prepared).
    pub rays: bool,
    /// Casters blocker culling dropped, when its boxes were queried.
    pub culled_blockers: Option<usize>,
}

impl LightFrame {
    /// A planned light, nothing prepared yet.
    pub fn new(plan: LightPlan) -> Self {
        Self { plan, map: None, edges: None, volumes: None, rays: false, culled_blockers: None }
    }

    /// Whether its shadow map was drawn this frame (an engine may sample it).
    pub fn map_drawn(&self) -> bool {
        self.map.as_ref().is_some_and(|m| m.depth)
    }

    /// Index of the light.
    pub fn light(&self) -> usize {
        self.plan.light
    }

    /// Whether the hybrid's own passes run for it: a hybrid light with a map and volumes, or
    /// a ray-traced hybrid's with a map and rays (its classification, then rays for volumes).
    pub fn hybrid(&self) -> bool {
        needs(self.plan.technique).lighting == Lighting::Hybrid
            && self.map.is_some()
            && (self.volumes.is_some() || self.rays)
    }

    /// Whether it is a ray-traced hybrid light whose classification runs (its silhouette
    /// pixels decided by rays, `crate::hybrid::rays`).
    pub fn hybrid_rays(&self) -> bool {
        self.hybrid() && self.rays
    }

    /// Whether its technique may write its visibility image this frame: it is recorded and has
    /// a map, volumes (with no volume triangle at all it is lit unshadowed) or rays.
    pub fn may_shadow(&self) -> bool {
        self.plan.recorded && (self.map.is_some() || self.volumes.is_some() || self.rays)
    }
}

/// One light's descriptor sets this frame, as indices into the renderer's arena.
#[derive(Clone, Copy, Default)]
pub(crate) struct LightSets {
    pub shadow_set: Option<usize>,
    pub depth_set: Option<usize>,
}

/// The readbacks of one light's diagnostic views, kept from frame to frame while they fit.
#[derive(Default)]
pub(crate) struct LightReadbacks {
    /// Its silhouette-map diagnostics (silhouette-map lights, with diagnostics).
    pub silhouette: Option<DiagnosticReadback>,
    /// Its classes (and stencil) diagnostics (shadow-map, shadow-volume and hybrid lights).
    pub classes: Option<ClassReadback>,
    /// Its visibility image (shadowed lights, with `read_visibility`).
    pub visibility: Option<VisibilityReadback>,
}

/// One light's descriptor sets and readbacks this frame.
#[derive(Clone, Copy, Default)]
pub(crate) struct LightBindings<'a> {
    /// Set 1 of its lighting passes (recorded lights).
    pub shadow_set: Option<&'a DescriptorSet>,
    /// Set 1 of its silhouette-point pass: the depth map raw, a placeholder for the map it writes.
    pub depth_set: Option<&'a DescriptorSet>,
    /// Its silhouette-map diagnostics.
    pub silhouette_readback: Option<&'a DiagnosticReadback>,
    /// Its classes (and stencil) diagnostics.
    pub class_readback: Option<&'a ClassReadback>,
    /// Its visibility image's copy.
    pub visibility_readback: Option<&'a VisibilityReadback>,
}

/// The occlusion queries of one light, reserved when its passes were declared.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct LightQueries {
    /// The hybrid's mask samples and masked fragments.
    pub hybrid: Option<HybridQueries>,
    /// Its volumes' fragments (with `overdraw`).
    pub volume_fragments: Option<QueryId>,
    /// Whether its technique wrote its visibility image (else it was lit unshadowed).
    pub shadowed: bool,
}
