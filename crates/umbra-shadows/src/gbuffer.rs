//! The G-buffer pass (with `RendererDesc::gbuffer`): after the depth pass, every object drawn
//! again over the frame's depth (EQUAL) into two RGBA32F targets, world position and geometric
//! normal (`shaders-glsl/debug/gbuffer.frag`), then copied out. The exact reference
//! (`umbra-reference`) casts its shadow rays from these points, the very ones the lighting
//! passes shaded.

use crate::diagnostics::GBuffer;
use crate::forward::surface_pass_desc;
use crate::frame::{PassRecorder, Use};
use crate::gpu_scene::GpuScene;
use crate::RenderResult;
use umbra_scene::Scene;
use umbra_vk::{
    vk, Buffer, BufferDesc, ColorAttachment, ColorTarget, Context, DepthAttachment, GraphicsPipeline, Image, ImageDesc,
    ImageState, PipelineLayout, RenderTargets,
};

/// Both targets' format: 32-bit floats, so positions keep every bit the shader computed.
const FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;

/// Each G-buffer target of a `width` × `height` frame.
pub(crate) fn target_desc(width: u32, height: u32) -> ImageDesc {
    let usage = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC;
    ImageDesc::new_2d(FORMAT, width, height).usage(usage)
}

/// The G-buffer's pipeline, targets and readbacks.
pub(crate) struct GBufferPass {
    pipeline: GraphicsPipeline,
    position: Image,
    normal: Image,
    position_readback: Buffer,
    normal_readback: Buffer,
}

impl GBufferPass {
    pub fn new(
        ctx: &Context,
        layout: &PipelineLayout,
        depth_format: vk::Format,
        width: u32,
        height: u32,
    ) -> RenderResult<Self> {
        let mut desc = surface_pass_desc("g-buffer", umbra_shaders::debug::GBUFFER_FRAG, depth_format, &[]);
        let targets = [ColorTarget::opaque(FORMAT), ColorTarget::opaque(FORMAT)];
        desc.color_targets = &targets;
        let pipeline = GraphicsPipeline::new(ctx, layout, &desc)?;
        let image = |name| Image::new(ctx, name, target_desc(width, height));
        let bytes = 16 * u64::from(width) * u64::from(height);
        Ok(Self {
            pipeline,
            position: image("g-buffer: position")?,
            normal: image("g-buffer: normal")?,
            position_readback: Buffer::new(ctx, "g-buffer readback: position", BufferDesc::readback(bytes))?,
            normal_readback: Buffer::new(ctx, "g-buffer readback: normal", BufferDesc::readback(bytes))?,
        })
    }

    /// What the pass uses besides the frame's depth (in DepthStencilAttachment): both targets
    /// as attachments and both readbacks.
    pub fn uses(&self) -> [Use<'_>; 4] {
        [
            Use::Image(&self.position, ImageState::ColorAttachment),
            Use::Image(&self.normal, ImageState::ColorAttachment),
            Use::Readback(&self.position_readback),
            Use::Readback(&self.normal_readback),
        ]
    }

    /// Records the `g-buffer` diagnostic pass over `depth`, then copies both targets out.
    pub fn record<'a>(
        &'a self,
        cx: &mut PassRecorder<'_, 'a>,
        layout: &'a PipelineLayout,
        gpu: &'a GpuScene,
        scene: &Scene,
        depth: &'a Image,
    ) {
        let (p, n) = (&self.position, &self.normal);
        let color = [
            ColorAttachment { image: p, view: None, clear: Some([0.0; 4]) },
            ColorAttachment { image: n, view: None, clear: Some([0.0; 4]) },
        ];
        cx.rec.begin_rendering(&RenderTargets { color: &color, depth: Some(DepthAttachment::keep(depth)) });
        cx.rec.bind_pipeline(&self.pipeline);
        crate::light_surfaces::draw_objects(cx.rec, layout, gpu, scene, 0, cx.log);
        cx.rec.end_rendering();
        cx.enter(&[(p, ImageState::TransferSrc), (n, ImageState::TransferSrc)]);
        cx.rec.copy_image_to_buffer(p, 0, &self.position_readback);
        cx.rec.copy_image_to_buffer(n, 0, &self.normal_readback);
    }

    /// The G-buffer of the last submitted frame that recorded this pass.
    pub fn read(&self) -> RenderResult<GBuffer> {
        let floats = |b: &Buffer| -> RenderResult<Vec<[f32; 4]>> {
            let bytes = b.read()?;
            Ok(bytes
                .chunks_exact(16)
                .map(|c| {
                    std::array::from_fn(|k| f32::from_le_bytes([c[4 * k], c[4 * k + 1], c[4 * k + 2], c[4 * k + 3]]))
                })
                .collect())
        };
        Ok(GBuffer { position: floats(&self.position_readback)?, normal: floats(&self.normal_readback)? })
    }
}
