//! Compute pipelines: one shader, its layout and specialization constants; destroyed on drop.

use crate::error::{CallContext, VkResult};
use crate::pipeline::{shader_module, PipelineLayout};
use crate::Context;
use ash::vk;

/// A compute pipeline; destroyed on drop.
pub struct ComputePipeline {
    /// The raw pipeline.
    pub raw: vk::Pipeline,
    ctx: Context,
}

impl ComputePipeline {
    /// Builds `name` from the compute shader `spirv` against `layout`, with
    /// `specialization` as `(constant_id, value)` pairs of 32-bit constants.
    pub fn new(
        ctx: &Context,
        layout: &PipelineLayout,
        name: &str,
        spirv: &[u32],
        specialization: &[(u32, u32)],
    ) -> VkResult<Self> {
        let module = shader_module(ctx, spirv, &format!("{name} compute"))?;
        let entries: Vec<_> = specialization
            .iter()
            .enumerate()
            .map(|(i, &(id, _))| vk::SpecializationMapEntry { constant_id: id, offset: 4 * i as u32, size: 4 })
            .collect();
        let data: Vec<u8> = specialization.iter().flat_map(|&(_, v)| v.to_ne_bytes()).collect();
        let spec = vk::SpecializationInfo::default().map_entries(&entries).data(&data);
        let stage = vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::COMPUTE)
            .module(module)
            .name(c"main")
            .specialization_info(&spec);
        let info = vk::ComputePipelineCreateInfo::default().stage(stage).layout(layout.raw);
        let device = &ctx.inner.device;
        // SAFETY: every pointer in `info` outlives the call.
        let result = unsafe { device.create_compute_pipelines(vk::PipelineCache::null(), &[info], None) };
        // SAFETY: the module is no longer needed once the pipeline exists (or failed).
        unsafe { device.destroy_shader_module(module, None) };
        let raw = result.map_err(|(_, e)| e).call("vkCreateComputePipelines")?[0];
        ctx.set_name(raw, name);
        Ok(Self { raw, ctx: ctx.clone() })
    }
}

impl Drop for ComputePipeline {
    fn drop(&mut self) {
        // SAFETY: umbra waits for every submission, so the pipeline is no longer in use.
        unsafe { self.ctx.inner.device.destroy_pipeline(self.raw, None) };
    }
}
