//! Graphics pipelines with the full depth/stencil state the shadow papers need.
//!
//! [`GraphicsPipelineDesc`] names every piece of fixed-function state explicitly: separate
//! front/back stencil ops with compare and write masks (two-sided stencil, wrap ops), depth
//! bounds, depth clamp, depth bias, depth compare op, colour write masks and blending.
//! Dynamic state: viewport and scissor always; depth bias, depth compare op, depth bounds and stencil reference
//! when the description enables them.

use crate::error::{CallContext, VkError, VkResult};
use crate::{Context, DescriptorSetLayout};
use ash::vk;

/// A vertex attribute at binding 0.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct VertexAttribute {
    /// Shader input location.
    pub location: u32,
    /// Attribute format.
    pub format: vk::Format,
    /// Byte offset in the vertex.
    pub offset: u32,
}

/// One face's stencil state (`VkStencilOpState` without the reference, which is dynamic).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct StencilFace {
    /// When the stencil test fails.
    pub fail: vk::StencilOp,
    /// When both stencil and depth tests pass.
    pub pass: vk::StencilOp,
    /// When the stencil test passes and the depth test fails (z-fail counts here).
    pub depth_fail: vk::StencilOp,
    /// Stencil comparison against the reference.
    pub compare: vk::CompareOp,
    /// Bits compared.
    pub compare_mask: u32,
    /// Bits written.
    pub write_mask: u32,
}

impl StencilFace {
    /// Never changes the stencil buffer and always passes.
    pub const KEEP: Self = Self {
        fail: vk::StencilOp::KEEP,
        pass: vk::StencilOp::KEEP,
        depth_fail: vk::StencilOp::KEEP,
        compare: vk::CompareOp::ALWAYS,
        compare_mask: 0xff,
        write_mask: 0xff,
    };

    fn raw(&self) -> vk::StencilOpState {
        vk::StencilOpState {
            fail_op: self.fail,
            pass_op: self.pass,
            depth_fail_op: self.depth_fail,
            compare_op: self.compare,
            compare_mask: self.compare_mask,
            write_mask: self.write_mask,
            reference: 0,
        }
    }
}

/// Depth test, write, bounds, clamp and bias.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct DepthState {
    /// Depth test enabled.
    pub test: bool,
    /// Depth writes enabled.
    pub write: bool,
    /// Comparison of the fragment's depth against the stored one.
    pub compare: vk::CompareOp,
    /// Depth-bounds test on the **stored** depth (range set with `Recorder::set_depth_bounds`);
    /// needs `Capabilities::depth_bounds`.
    pub bounds_test: bool,
    /// Clamp depth instead of clipping at near/far; needs `Capabilities::depth_clamp`.
    pub clamp: bool,
    /// Depth bias enabled (values set with `Recorder::set_depth_bias`).
    pub bias: bool,
    /// The comparison is dynamic state, set with `Recorder::set_depth_compare_op` before each
    /// draw (core in Vulkan 1.3); `compare` is then unused.
    pub compare_dynamic: bool,
}

impl DepthState {
    /// Test with `LESS_OR_EQUAL` and write.
    pub const TEST_AND_WRITE: Self = Self {
        test: true,
        write: true,
        compare: vk::CompareOp::LESS_OR_EQUAL,
        bounds_test: false,
        clamp: false,
        bias: false,
        compare_dynamic: false,
    };
    /// No depth test or write.
    pub const NONE: Self = Self {
        test: false,
        write: false,
        compare: vk::CompareOp::ALWAYS,
        bounds_test: false,
        clamp: false,
        bias: false,
        compare_dynamic: false,
    };
}

/// Blend factors and ops of one colour target.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Blend {
    /// Source colour factor.
    pub src: vk::BlendFactor,
    /// Destination colour factor.
    pub dst: vk::BlendFactor,
    /// Colour op.
    pub op: vk::BlendOp,
    /// Source alpha factor.
    pub src_alpha: vk::BlendFactor,
    /// Destination alpha factor.
    pub dst_alpha: vk::BlendFactor,
    /// Alpha op.
    pub alpha_op: vk::BlendOp,
}

impl Blend {
    /// `dst = src + dst` (one additive pass per light).
    pub const ADDITIVE: Self = Self {
        src: vk::BlendFactor::ONE,
        dst: vk::BlendFactor::ONE,
        op: vk::BlendOp::ADD,
        src_alpha: vk::BlendFactor::ZERO,
        dst_alpha: vk::BlendFactor::ONE,
        alpha_op: vk::BlendOp::ADD,
    };
}

/// A colour attachment's format, blending and write mask.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ColorTarget {
    /// Attachment format.
    pub format: vk::Format,
    /// Blending, or `None` to overwrite.
    pub blend: Option<Blend>,
    /// Channels written (`empty()` is `ColorMask(0,0,0,0)`).
    pub write_mask: vk::ColorComponentFlags,
}

impl ColorTarget {
    /// Overwrites all four channels.
    pub fn opaque(format: vk::Format) -> Self {
        Self { format, blend: None, write_mask: vk::ColorComponentFlags::RGBA }
    }
}

/// Everything a graphics pipeline is made of.
#[derive(Clone, Copy, Debug)]
pub struct GraphicsPipelineDesc<'a> {
    /// Debug name.
    pub name: &'a str,
    /// Vertex shader SPIR-V (entry point `main`).
    pub vertex: &'a [u32],
    /// Fragment shader SPIR-V, or `None` for depth/stencil-only passes.
    pub fragment: Option<&'a [u32]>,
    /// Specialization constants `(constant_id, value)`, shared by both stages.
    pub specialization: &'a [(u32, u32)],
    /// Vertex stride at binding 0 (`0`: no vertex input).
    pub vertex_stride: u32,
    /// Vertex attributes at binding 0.
    pub vertex_attributes: &'a [VertexAttribute],
    /// Whether attribute `i` of `vertex_attributes` reads binding `i` (at the attribute's
    /// offset from where the binding starts), each binding's stride set when the buffers are
    /// bound ([`crate::Recorder::bind_vertex_streams`]; the `VERTEX_INPUT_BINDING_STRIDE`
    /// dynamic state of Vulkan 1.3): attributes in any buffers, at any stride. `false`: every
    /// attribute reads binding 0, `vertex_stride` apart.
    pub vertex_streams: bool,
    /// Whether binding 0 advances per vertex or per instance (one record per instance, e.g.
    /// an edge expanded into a quad by the vertex shader).
    pub vertex_input_rate: vk::VertexInputRate,
    /// Primitive topology.
    pub topology: vk::PrimitiveTopology,
    /// Faces culled.
    pub cull: vk::CullModeFlags,
    /// Winding of front faces (with umbra's y-up viewport, `COUNTER_CLOCKWISE` as in OpenGL).
    pub front_face: vk::FrontFace,
    /// Line width (needs `Capabilities::wide_lines` unless 1.0).
    pub line_width: f32,
    /// Depth state.
    pub depth: DepthState,
    /// Front and back stencil state (two-sided stencil), or `None` for no stencil test.
    pub stencil: Option<(StencilFace, StencilFace)>,
    /// Colour targets in location order.
    pub color_targets: &'a [ColorTarget],
    /// Depth(/stencil) attachment format, or `UNDEFINED`.
    pub depth_format: vk::Format,
    /// Samples per pixel of the attachments (`TYPE_1` unless multisampled).
    pub samples: vk::SampleCountFlags,
}

impl<'a> GraphicsPipelineDesc<'a> {
    /// Triangle lists, back faces culled, depth test and write, no colour targets.
    pub fn new(name: &'a str, vertex: &'a [u32]) -> Self {
        Self {
            name,
            vertex,
            fragment: None,
            specialization: &[],
            vertex_stride: 0,
            vertex_attributes: &[],
            vertex_streams: false,
            vertex_input_rate: vk::VertexInputRate::VERTEX,
            topology: vk::PrimitiveTopology::TRIANGLE_LIST,
            cull: vk::CullModeFlags::BACK,
            front_face: vk::FrontFace::COUNTER_CLOCKWISE,
            line_width: 1.0,
            depth: DepthState::TEST_AND_WRITE,
            stencil: None,
            color_targets: &[],
            depth_format: vk::Format::UNDEFINED,
            samples: vk::SampleCountFlags::TYPE_1,
        }
    }
}

/// A pipeline layout: descriptor set layouts plus one push-constant range.
pub struct PipelineLayout {
    /// The raw layout.
    pub raw: vk::PipelineLayout,
    /// Stages of the push-constant range.
    pub push_stages: vk::ShaderStageFlags,
    ctx: Context,
}

impl PipelineLayout {
    /// Creates a layout with `sets` and `push_bytes` of push constants for the vertex,
    /// fragment and compute stages.
    pub fn new(ctx: &Context, name: &str, sets: &[&DescriptorSetLayout], push_bytes: u32) -> VkResult<Self> {
        let max = ctx.capabilities().max_push_constants_size;
        if push_bytes > max || push_bytes % 4 != 0 {
            return Err(VkError::InvalidDesc {
                what: "pipeline layout",
                why: format!("{name}: {push_bytes} push-constant bytes (multiple of 4, at most {max})"),
            });
        }
        let push_stages = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT | vk::ShaderStageFlags::COMPUTE;
        let ranges = [vk::PushConstantRange { stage_flags: push_stages, offset: 0, size: push_bytes }];
        let raw_sets: Vec<_> = sets.iter().map(|s| s.raw).collect();
        let mut info = vk::PipelineLayoutCreateInfo::default().set_layouts(&raw_sets);
        if push_bytes > 0 {
            info = info.push_constant_ranges(&ranges);
        }
        // SAFETY: valid create info; destroyed in `Drop`.
        let raw = unsafe { ctx.inner.device.create_pipeline_layout(&info, None) }.call("vkCreatePipelineLayout")?;
        ctx.set_name(raw, name);
        Ok(Self { raw, push_stages, ctx: ctx.clone() })
    }
}

impl Drop for PipelineLayout {
    fn drop(&mut self) {
        // SAFETY: umbra waits for every submission, so the layout is no longer in use.
        unsafe { self.ctx.inner.device.destroy_pipeline_layout(self.raw, None) };
    }
}

/// A graphics pipeline for dynamic rendering; destroyed on drop.
pub struct GraphicsPipeline {
    /// The raw pipeline.
    pub raw: vk::Pipeline,
    ctx: Context,
}

impl GraphicsPipeline {
    /// Builds a pipeline; `Unsupported` when the description needs a feature the device lacks.
    pub fn new(ctx: &Context, layout: &PipelineLayout, desc: &GraphicsPipelineDesc<'_>) -> VkResult<Self> {
        let caps = ctx.capabilities();
        let d = &desc.depth;
        if d.bounds_test && !caps.depth_bounds {
            return Err(ctx.unsupported(format!("{}: depth-bounds test (depthBounds)", desc.name)));
        }
        if d.clamp && !caps.depth_clamp {
            return Err(ctx.unsupported(format!("{}: depth clamp (depthClamp)", desc.name)));
        }
        if desc.line_width != 1.0 && !caps.wide_lines {
            return Err(ctx.unsupported(format!("{}: line width {} (wideLines)", desc.name, desc.line_width)));
        }
        let device = &ctx.inner.device;
        let vs = shader_module(ctx, desc.vertex, &format!("{} vertex", desc.name))?;
        let fs = match desc.fragment.map(|f| shader_module(ctx, f, &format!("{} fragment", desc.name))).transpose() {
            Ok(fs) => fs,
            Err(e) => {
                // SAFETY: unused module.
                unsafe { device.destroy_shader_module(vs, None) };
                return Err(e);
            }
        };
        let spec_entries: Vec<_> = desc
            .specialization
            .iter()
            .enumerate()
            .map(|(i, &(id, _))| vk::SpecializationMapEntry { constant_id: id, offset: 4 * i as u32, size: 4 })
            .collect();
        let spec_data: Vec<u8> = desc.specialization.iter().flat_map(|&(_, v)| v.to_ne_bytes()).collect();
        let spec = vk::SpecializationInfo::default().map_entries(&spec_entries).data(&spec_data);
        let mut stages = vec![vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::VERTEX)
            .module(vs)
            .name(c"main")
            .specialization_info(&spec)];
        if let Some(fs) = fs {
            stages.push(
                vk::PipelineShaderStageCreateInfo::default()
                    .stage(vk::ShaderStageFlags::FRAGMENT)
                    .module(fs)
                    .name(c"main")
                    .specialization_info(&spec),
            );
        }
        let streams = if desc.vertex_streams { desc.vertex_attributes.len().max(1) } else { 1 };
        let bindings: Vec<_> = (0..streams as u32)
            .map(|binding| vk::VertexInputBindingDescription {
                binding,
                stride: desc.vertex_stride,
                input_rate: desc.vertex_input_rate,
            })
            .collect();
        let attributes: Vec<_> = desc
            .vertex_attributes
            .iter()
            .enumerate()
            .map(|(i, a)| vk::VertexInputAttributeDescription {
                location: a.location,
                binding: if desc.vertex_streams { i as u32 } else { 0 },
                format: a.format,
                offset: a.offset,
            })
            .collect();
        let mut vertex_input = vk::PipelineVertexInputStateCreateInfo::default();
        if desc.vertex_stride > 0 {
            vertex_input =
                vertex_input.vertex_binding_descriptions(&bindings).vertex_attribute_descriptions(&attributes);
        }
        let input_assembly = vk::PipelineInputAssemblyStateCreateInfo::default().topology(desc.topology);
        let viewport = vk::PipelineViewportStateCreateInfo::default().viewport_count(1).scissor_count(1);
        let raster = vk::PipelineRasterizationStateCreateInfo::default()
            .depth_clamp_enable(d.clamp)
            .polygon_mode(vk::PolygonMode::FILL)
            .cull_mode(desc.cull)
            .front_face(desc.front_face)
            .depth_bias_enable(d.bias)
            .line_width(desc.line_width);
        let multisample = vk::PipelineMultisampleStateCreateInfo::default().rasterization_samples(desc.samples);
        let (front, back) = desc.stencil.unwrap_or((StencilFace::KEEP, StencilFace::KEEP));
        let depth_stencil = vk::PipelineDepthStencilStateCreateInfo::default()
            .depth_test_enable(d.test)
            .depth_write_enable(d.write)
            .depth_compare_op(d.compare)
            .depth_bounds_test_enable(d.bounds_test)
            .min_depth_bounds(0.0)
            .max_depth_bounds(1.0)
            .stencil_test_enable(desc.stencil.is_some())
            .front(front.raw())
            .back(back.raw());
        let blend_attachments: Vec<_> = desc
            .color_targets
            .iter()
            .map(|t| {
                let b = t.blend.unwrap_or(Blend::ADDITIVE);
                vk::PipelineColorBlendAttachmentState {
                    blend_enable: t.blend.is_some().into(),
                    src_color_blend_factor: b.src,
                    dst_color_blend_factor: b.dst,
                    color_blend_op: b.op,
                    src_alpha_blend_factor: b.src_alpha,
                    dst_alpha_blend_factor: b.dst_alpha,
                    alpha_blend_op: b.alpha_op,
                    color_write_mask: t.write_mask,
                }
            })
            .collect();
        let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend_attachments);
        let mut dynamic = vec![vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
        if d.bias {
            dynamic.push(vk::DynamicState::DEPTH_BIAS);
        }
        if d.compare_dynamic {
            dynamic.push(vk::DynamicState::DEPTH_COMPARE_OP);
        }
        if d.bounds_test {
            dynamic.push(vk::DynamicState::DEPTH_BOUNDS);
        }
        if desc.stencil.is_some() {
            dynamic.push(vk::DynamicState::STENCIL_REFERENCE);
        }
        if desc.vertex_streams {
            dynamic.push(vk::DynamicState::VERTEX_INPUT_BINDING_STRIDE);
        }
        let dynamic_state = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic);
        let color_formats: Vec<_> = desc.color_targets.iter().map(|t| t.format).collect();
        let aspect = crate::image::format_aspect(desc.depth_format);
        let has_depth = desc.depth_format != vk::Format::UNDEFINED;
        let mut rendering = vk::PipelineRenderingCreateInfo::default()
            .color_attachment_formats(&color_formats)
            .depth_attachment_format(if has_depth { desc.depth_format } else { vk::Format::UNDEFINED })
            .stencil_attachment_format(if has_depth && aspect.contains(vk::ImageAspectFlags::STENCIL) {
                desc.depth_format
            } else {
                vk::Format::UNDEFINED
            });
        let info = vk::GraphicsPipelineCreateInfo::default()
            .stages(&stages)
            .vertex_input_state(&vertex_input)
            .input_assembly_state(&input_assembly)
            .viewport_state(&viewport)
            .rasterization_state(&raster)
            .multisample_state(&multisample)
            .depth_stencil_state(&depth_stencil)
            .color_blend_state(&blend)
            .dynamic_state(&dynamic_state)
            .layout(layout.raw)
            .push_next(&mut rendering);
        // SAFETY: every pointer in `info` outlives the call; features were checked above.
        let result = unsafe { device.create_graphics_pipelines(vk::PipelineCache::null(), &[info], None) };
        // SAFETY: modules are no longer needed once the pipeline exists (or failed).
        unsafe {
            device.destroy_shader_module(vs, None);
            if let Some(fs) = fs {
                device.destroy_shader_module(fs, None);
            }
        }
        let raw = result.map_err(|(_, e)| e).call("vkCreateGraphicsPipelines")?[0];
        ctx.set_name(raw, desc.name);
        Ok(Self { raw, ctx: ctx.clone() })
    }
}

impl Drop for GraphicsPipeline {
    fn drop(&mut self) {
        // SAFETY: umbra waits for every submission, so the pipeline is no longer in use.
        unsafe { self.ctx.inner.device.destroy_pipeline(self.raw, None) };
    }
}

pub(crate) fn shader_module(ctx: &Context, spirv: &[u32], name: &str) -> VkResult<vk::ShaderModule> {
    if spirv.first() != Some(&0x0723_0203) {
        return Err(VkError::InvalidDesc { what: "shader module", why: "not SPIR-V (bad magic number)".into() });
    }
    let info = vk::ShaderModuleCreateInfo::default().code(spirv);
    // SAFETY: SPIR-V words checked for the magic number; the module is destroyed by the caller.
    let module = unsafe { ctx.inner.device.create_shader_module(&info, None) }.call("vkCreateShaderModule")?;
    ctx.set_name(module, name);
    Ok(module)
}
