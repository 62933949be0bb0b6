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
use umbra_scene::{Aabb, Technique};
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
    /// What its technique prepared for its passes.
    pub prepared: Prepared,
    /// Casters blocker culling dropped, when its boxes were queried.
    pub culled_blockers: Option<usize>,
}

/// What one light's technique prepared this frame: one variant per way a light is shadowed,
/// each holding what its passes draw from. Every step of the frame that depends on the
/// technique matches on it.
pub(crate) enum Prepared {
    /// Nothing shadows it this frame: not recorded, not shadowed, or no caster can shadow a
    /// visible receiver (it is lit unshadowed).
    Nothing,
    /// A shadow map, looked up per pixel (shadow maps).
    Map(MapFrame),
    /// A shadow map and its silhouette edges, which draw the silhouette map (silhouette maps).
    SilhouetteMap(MapFrame, LightEdges),
    /// Volumes whose stencil counts decide every pixel (shadow volumes), culled casters left
    /// out.
    Volumes(LightVolumes),
    /// Shadow rays through the scene's BVH (ray-traced shadows, and a ray-traced hybrid light
    /// without a map this frame).
    Rays,
    /// The hybrid: a map whose silhouette pixels its z-fail volumes decide.
    Hybrid(MapFrame, LightVolumes),
    /// The ray-traced hybrid: a map whose silhouette pixels shadow rays decide.
    HybridRays(MapFrame),
}

/// What each stage of a light's preparation made, before they are one [`Prepared`].
#[derive(Default)]
pub(crate) struct Parts {
    /// Its shadow map (the maps stage).
    pub map: Option<MapFrame>,
    /// Its silhouette edges (the maps stage, silhouette maps).
    pub edges: Option<LightEdges>,
    /// Its volumes (the volumes stage).
    pub volumes: Option<LightVolumes>,
    /// Whether it casts shadow rays (the rays stage).
    pub rays: bool,
}

impl Parts {
    /// Whether these parts, for a light of `technique`, are a ray-traced hybrid's: its
    /// classification runs, then rays for its silhouette pixels.
    pub fn hybrid_rays(&self, technique: Technique) -> bool {
        needs(technique).lighting == Lighting::Hybrid && self.map.is_some() && self.rays
    }

    /// The parts of a light of `technique` as what its passes draw from.
    pub fn assemble(self, technique: Technique) -> Prepared {
        let hybrid = needs(technique).lighting == Lighting::Hybrid;
        let hybrid_rays = self.hybrid_rays(technique);
        match self {
            Parts { map: Some(map), .. } if hybrid_rays => Prepared::HybridRays(map),
            Parts { map: Some(map), volumes: Some(volumes), .. } if hybrid => Prepared::Hybrid(map, volumes),
            Parts { map: Some(map), edges: Some(edges), .. } => Prepared::SilhouetteMap(map, edges),
            Parts { map: Some(map), .. } => Prepared::Map(map),
            Parts { volumes: Some(volumes), .. } => Prepared::Volumes(volumes),
            Parts { rays: true, .. } => Prepared::Rays,
            Parts { .. } => Prepared::Nothing,
        }
    }
}

impl LightFrame {
    /// A planned light, nothing prepared yet.
    pub fn new(plan: LightPlan) -> Self {
        Self { plan, prepared: Prepared::Nothing, culled_blockers: None }
    }

    /// Index of the light.
    pub fn light(&self) -> usize {
        self.plan.light
    }

    /// Its shadow map (shadow maps, silhouette maps, the hybrids).
    pub fn map(&self) -> Option<&MapFrame> {
        match &self.prepared {
            Prepared::Map(m) | Prepared::SilhouetteMap(m, _) | Prepared::Hybrid(m, _) | Prepared::HybridRays(m) => {
                Some(m)
            }
            Prepared::Nothing | Prepared::Volumes(_) | Prepared::Rays => None,
        }
    }

    /// Whether its shadow map was drawn this frame (an engine may sample it).
    pub fn map_drawn(&self) -> bool {
        self.map().is_some_and(|m| m.depth)
    }

    /// Its silhouette edges (silhouette maps).
    pub fn edges(&self) -> Option<LightEdges> {
        match &self.prepared {
            Prepared::SilhouetteMap(_, e) => Some(*e),
            Prepared::Nothing
            | Prepared::Map(_)
            | Prepared::Volumes(_)
            | Prepared::Rays
            | Prepared::Hybrid(..)
            | Prepared::HybridRays(_) => None,
        }
    }

    /// Its volumes (shadow volumes, the hybrid).
    pub fn volumes(&self) -> Option<&LightVolumes> {
        match &self.prepared {
            Prepared::Volumes(v) | Prepared::Hybrid(_, v) => Some(v),
            Prepared::Nothing
            | Prepared::Map(_)
            | Prepared::SilhouetteMap(..)
            | Prepared::Rays
            | Prepared::HybridRays(_) => None,
        }
    }

    /// Its volumes, to drop culled casters and plan their batches.
    pub fn volumes_mut(&mut self) -> Option<&mut LightVolumes> {
        match &mut self.prepared {
            Prepared::Volumes(v) | Prepared::Hybrid(_, v) => Some(v),
            Prepared::Nothing
            | Prepared::Map(_)
            | Prepared::SilhouetteMap(..)
            | Prepared::Rays
            | Prepared::HybridRays(_) => None,
        }
    }

    /// Whether it casts shadow rays this frame (the scene's BVH is prepared).
    pub fn rays(&self) -> bool {
        match &self.prepared {
            Prepared::Rays | Prepared::HybridRays(_) => true,
            Prepared::Nothing
            | Prepared::Map(_)
            | Prepared::SilhouetteMap(..)
            | Prepared::Volumes(_)
            | Prepared::Hybrid(..) => false,
        }
    }

    /// Whether the hybrid's own passes run for it: a hybrid light with a map and volumes, or
    /// a ray-traced hybrid's with a map and rays (its classification, then rays for volumes).
    pub fn hybrid(&self) -> bool {
        match &self.prepared {
            Prepared::Hybrid(..) | Prepared::HybridRays(_) => true,
            Prepared::Nothing
            | Prepared::Map(_)
            | Prepared::SilhouetteMap(..)
            | Prepared::Volumes(_)
            | Prepared::Rays => false,
        }
    }

    /// Whether it is a ray-traced hybrid light whose classification runs (its silhouette
    /// pixels decided by rays, `crate::hybrid::rays`).
    pub fn hybrid_rays(&self) -> bool {
        match &self.prepared {
            Prepared::HybridRays(_) => true,
            Prepared::Nothing
            | Prepared::Map(_)
            | Prepared::SilhouetteMap(..)
            | Prepared::Volumes(_)
            | Prepared::Rays
            | Prepared::Hybrid(..) => false,
        }
    }

    /// Whether its technique may write its visibility image this frame: it is recorded and has
    /// a map, volumes (with no volume triangle at all it is lit unshadowed) or rays.
    pub fn may_shadow(&self) -> bool {
        let prepared = match &self.prepared {
            Prepared::Nothing => false,
            Prepared::Map(_)
            | Prepared::SilhouetteMap(..)
            | Prepared::Volumes(_)
            | Prepared::Rays
            | Prepared::Hybrid(..)
            | Prepared::HybridRays(_) => true,
        };
        self.plan.recorded && prepared
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
