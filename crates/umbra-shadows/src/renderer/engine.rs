//! An engine's frame ([`crate::Shadows`]): the frame [`Renderer::render`] runs
//! ([`Renderer::frame`], `record.rs`), recorded into the engine's command buffer over the
//! engine's depth and ended by the hand-off; no submission, no wait, no readback. Blocker culling, which needs a
//! query result mid-frame, is off (`Shadows::new` refuses it), and so are the diagnostics.

use super::record::Output;
use super::slot::FrameSlot;
use super::Renderer;
use crate::frame::timing::PassReport;
use crate::plan::LightPlan;
use crate::techniques::FrameView;
use crate::view::View;
use crate::RenderResult;
use umbra_scene::Scene;
use umbra_vk::{vk, Image, ImageState};

/// The engine's depth for one frame: the image and the state it is in (and is left in).
pub(crate) struct EngineDepth<'a> {
    pub image: &'a Image,
    pub state: ImageState,
}

/// The depth an engine's frame is recorded over.
pub(crate) enum FrameDepth<'a> {
    /// The engine's, drawn in umbra's convention and with a stencil where one is needed:
    /// umbra's passes test against it and leave it as it was.
    Engine(EngineDepth<'a>),
    /// umbra's own, re-drawn first (`crate::depth_rebuild`): the engine's depth is not touched.
    Rebuilt,
}

/// What one light got in an engine's frame.
pub(crate) struct RecordedLight {
    pub plan: LightPlan,
    /// Whether its technique wrote its visibility image (else it is lit unshadowed).
    pub shadowed: bool,
    /// Whether its shadow map was drawn (its views are in `plan.shadow_map`).
    pub map: bool,
}

/// What an engine's frame recorded.
pub(crate) struct RecordedFrame {
    pub lights: Vec<RecordedLight>,
    /// The passes recorded, in order, their GPU times not read yet.
    pub passes: Vec<PassReport>,
    /// Bytes of mesh data uploaded for it (0 when the meshes were unchanged).
    pub geometry_uploaded_bytes: u64,
}

impl Renderer {
    /// A frame slot for an engine's frames in flight.
    pub(crate) fn new_slot(&self, index: usize) -> RenderResult<FrameSlot> {
        FrameSlot::new(&self.ctx, &format!("shadow sets (frame slot {index})"), &self.shadow_set_layout)
    }

    /// Records the shadows of `scene` seen through `view` into `cmd` (an engine's command
    /// buffer, recording), over `depth`, with `slot`'s host-written buffers, sets and queries:
    /// [`Renderer::frame`], ended by the hand-off.
    pub(crate) fn record_into(
        &mut self,
        slot: &mut FrameSlot,
        scene: &Scene,
        view: View,
        depth: FrameDepth<'_>,
        cmd: vk::CommandBuffer,
    ) -> RenderResult<RecordedFrame> {
        if let FrameDepth::Rebuilt = depth {
            let ctx = self.ctx.clone();
            self.rebuild()?.image(&ctx)?;
        }
        let view = FrameView { view, boxes: scene.object_bounds_with(&self.checked) };
        std::mem::swap(&mut self.slot, slot);
        let recorded = self.frame(scene, view, Output::Engine { depth, cmd });
        std::mem::swap(&mut self.slot, slot);
        let r = recorded?;
        let queries = &r.run.queries;
        let lights = r
            .lights
            .into_iter()
            .map(|l| RecordedLight { shadowed: queries[l.light()].shadowed, map: l.map_drawn(), plan: l.plan })
            .collect();
        Ok(RecordedFrame { lights, passes: r.run.recorded, geometry_uploaded_bytes: r.geometry_uploaded })
    }

    /// The depth rebuild (engine renderers only).
    fn rebuild(&mut self) -> RenderResult<&mut crate::depth_rebuild::DepthRebuild> {
        self.depth_rebuild.as_mut().ok_or_else(not_engine)
    }

    pub(super) fn rebuild_ref(&self) -> RenderResult<&crate::depth_rebuild::DepthRebuild> {
        self.depth_rebuild.as_ref().ok_or_else(not_engine)
    }

    /// Light `light`'s visibility image (while it is shadowed).
    pub(crate) fn visibility_image(&self, light: usize) -> RenderResult<&Image> {
        Ok(&self.visibility.light(light)?.image)
    }

    /// Light `light`'s shadow map (while it has one).
    pub(crate) fn shadow_map_image(&self, light: usize) -> RenderResult<&Image> {
        self.techniques.shadow_map_image(light)
    }
}

fn not_engine() -> crate::RenderError {
    crate::RenderError::InvalidInput {
        field: "Renderer".into(),
        why: "only a renderer recording into an engine's frame rebuilds depth".into(),
    }
}
