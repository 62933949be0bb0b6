//! umbra's own depth for an engine's frame whose depth its passes cannot use as it is: a
//! reversed-Z or finite-far projection where volumes must reach infinity, or a depth without
//! stencil. umbra re-draws every object's depth, through the engine's matrices brought to its
//! own convention (standard depth, far plane at infinity: [`crate::shadows`]), into a
//! depth/stencil image of its own, with the vertex shader and transform of its other passes,
//! so that their EQUAL tests stay exact. It costs one depth-only pass over the scene and one
//! frame-sized depth/stencil image (`docs/embedding.md`).

use crate::forward::surface_pass_desc;
use crate::frame::timing::PassLog;
use crate::gpu_scene::GpuScene;
use crate::light_surfaces::draw_objects;
use crate::RenderResult;
use umbra_scene::Scene;
use umbra_vk::{
    vk, Context, DepthAttachment, DepthState, GraphicsPipeline, Image, PipelineLayout, Recorder, RenderTargets,
};

/// The depth-only pipeline and, once a frame needed it, the image it draws into.
pub(crate) struct DepthRebuild {
    pipeline: GraphicsPipeline,
    image: Option<Image>,
    format: vk::Format,
    extent: (u32, u32),
}

impl DepthRebuild {
    /// The pipeline for a `format` depth of `width` × `height` (the image is made on first use).
    pub fn new(
        ctx: &Context,
        layout: &PipelineLayout,
        format: vk::Format,
        width: u32,
        height: u32,
    ) -> RenderResult<Self> {
        let mut desc = surface_pass_desc("depth rebuild", &[], format, &[]);
        desc.fragment = None;
        // Laid down as umbra's own frame lays it (the ambient pass): LESS and write.
        desc.depth = DepthState { compare: vk::CompareOp::LESS, ..DepthState::TEST_AND_WRITE };
        let pipeline = GraphicsPipeline::new(ctx, layout, &desc)?;
        Ok(Self { pipeline, image: None, format, extent: (width, height) })
    }

    /// The image, made the first time it is asked for.
    pub fn image(&mut self, ctx: &Context) -> RenderResult<&Image> {
        if self.image.is_none() {
            let (width, height) = self.extent;
            let desc = crate::targets::depth_desc(self.format, width, height);
            self.image = Some(Image::new(ctx, "rebuilt depth/stencil", desc)?);
        }
        self.made()
    }

    /// The image, once made.
    pub fn made(&self) -> RenderResult<&Image> {
        self.image.as_ref().ok_or_else(|| crate::RenderError::InvalidInput {
            field: "depth rebuild".into(),
            why: "the rebuilt depth is used before it was made".into(),
        })
    }

    /// Clears the image and draws every object's depth into it (in
    /// [`umbra_vk::ImageState::DepthStencilAttachment`]).
    pub fn record<'a>(
        &'a self,
        rec: &mut Recorder<'a>,
        layout: &'a PipelineLayout,
        gpu: &'a GpuScene,
        scene: &Scene,
        log: &mut PassLog,
    ) -> RenderResult<()> {
        let depth = DepthAttachment::cleared(self.made()?, 1.0, 0);
        rec.begin_rendering(&RenderTargets { color: &[], depth: Some(depth) });
        rec.bind_pipeline(&self.pipeline);
        draw_objects(rec, layout, gpu, scene, 0, log);
        rec.end_rendering();
        Ok(())
    }
}
