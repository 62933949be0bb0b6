//! The forward lighting passes: one pass lays down depth and the ambient term, then one
//! additive pass per light applies Lambert's law where the depth is EQUAL.
//!
//! Both pipelines share `forward/mesh.vert` (with `invariant gl_Position`), so the EQUAL test
//! sees bit-identical depths. Faces are not culled: open meshes show their inside, lit from
//! that side.

use crate::gpu_scene::{self, DrawPush, GpuScene};
use crate::timing::PassLog;
use crate::RenderResult;
use umbra_scene::Scene;
use umbra_vk::{
    vk, Blend, ColorTarget, Context, DepthState, DescriptorSetLayout, GraphicsPipeline, GraphicsPipelineDesc,
    PipelineLayout, Recorder,
};

/// The forward pipelines and their layout.
pub(crate) struct Forward {
    pub set_layout: DescriptorSetLayout,
    pub layout: PipelineLayout,
    ambient: GraphicsPipeline,
    light: GraphicsPipeline,
}

impl Forward {
    pub fn new(ctx: &Context, color_format: vk::Format, depth_format: vk::Format) -> RenderResult<Self> {
        let set_layout = gpu_scene::scene_set_layout(ctx)?;
        let layout =
            PipelineLayout::new(ctx, "forward layout", &[&set_layout], std::mem::size_of::<DrawPush>() as u32)?;
        let mut desc = GraphicsPipelineDesc::new("forward ambient + depth", umbra_shaders::forward::MESH_VERT);
        desc.fragment = Some(umbra_shaders::forward::AMBIENT_FRAG);
        desc.vertex_stride = gpu_scene::VERTEX_STRIDE;
        desc.vertex_attributes = &gpu_scene::VERTEX_ATTRIBUTES;
        desc.cull = vk::CullModeFlags::NONE;
        desc.depth = DepthState { compare: vk::CompareOp::LESS, ..DepthState::TEST_AND_WRITE };
        desc.depth_format = depth_format;
        let opaque = [ColorTarget::opaque(color_format)];
        desc.color_targets = &opaque;
        let ambient = GraphicsPipeline::new(ctx, &layout, &desc)?;

        desc.name = "forward light (additive)";
        desc.fragment = Some(umbra_shaders::forward::LIGHT_FRAG);
        desc.depth = DepthState { write: false, compare: vk::CompareOp::EQUAL, ..DepthState::TEST_AND_WRITE };
        let additive = [ColorTarget { blend: Some(Blend::ADDITIVE), ..ColorTarget::opaque(color_format) }];
        desc.color_targets = &additive;
        let light = GraphicsPipeline::new(ctx, &layout, &desc)?;
        Ok(Self { set_layout, layout, ambient, light })
    }

    /// Draws every object with the ambient pipeline (inside an open rendering pass).
    pub fn record_ambient<'a>(&'a self, rec: &mut Recorder<'a>, gpu: &'a GpuScene, scene: &Scene, log: &mut PassLog) {
        rec.bind_pipeline(&self.ambient);
        self.draw_objects(rec, gpu, scene, 0, log);
    }

    /// Draws every object lit by light `light` (inside an open rendering pass).
    pub fn record_light<'a>(
        &'a self,
        rec: &mut Recorder<'a>,
        gpu: &'a GpuScene,
        scene: &Scene,
        light: u32,
        log: &mut PassLog,
    ) {
        rec.bind_pipeline(&self.light);
        self.draw_objects(rec, gpu, scene, light, log);
    }

    fn draw_objects<'a>(
        &'a self,
        rec: &mut Recorder<'a>,
        gpu: &'a GpuScene,
        scene: &Scene,
        light: u32,
        log: &mut PassLog,
    ) {
        rec.bind_descriptor_set(&self.layout, 0, &gpu.set);
        rec.bind_vertex_buffer(&gpu.vertices);
        rec.bind_index_buffer(&gpu.indices);
        for (i, o) in scene.objects.iter().enumerate() {
            let Some(m) = gpu.meshes.get(o.mesh) else {
                continue;
            };
            if m.index_count == 0 {
                continue;
            }
            rec.push_constants(&self.layout, &DrawPush { object: i as u32, light });
            rec.draw_indexed(m.index_count, m.first_index, m.vertex_offset);
            log.count_draw(u64::from(m.index_count / 3));
        }
    }
}
