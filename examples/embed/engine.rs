//! The engine's renderer: its own depth and colour targets, its meshes (positions and normals,
//! interleaved), a depth pre-pass and a forward shading pass with shaders of its own
//! (`shaders-glsl/engine/shade.*`) that read each light's visibility image from umbra. Its
//! objects are made with umbra-vk's wrappers for brevity; its shading has no umbra code.

use glam::{Mat4, Vec4};
use umbra::scene::Scene;
use umbra::shadows::{DepthTarget, IndexStream, LightShadows, MeshBuffers, VertexStream};
use umbra::vk::{
    vk, Binding, Buffer, BufferDesc, BufferState, ColorAttachment, ColorTarget, ComputePipeline, Context,
    DepthAttachment, DepthState, DescriptorSet, DescriptorSetLayout, GraphicsPipeline, GraphicsPipelineDesc, Image,
    ImageDesc, ImageState, PipelineLayout, Recorder, RenderTargets, Resource, Sampler, SamplerDesc, VertexAttribute,
};

/// Lights the shading pass takes.
pub const MAX_LIGHTS: usize = 4;
const DEPTH: vk::Format = vk::Format::D32_SFLOAT_S8_UINT;
const COLOR: vk::Format = vk::Format::R8G8B8A8_UNORM;

/// The shading pass's uniforms (`Frame` in the engine's shaders).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct FrameUniforms {
    view_proj: [f32; 16],
    light_position: [[f32; 4]; MAX_LIGHTS],
    light_radiance: [[f32; 4]; MAX_LIGHTS],
    spot: [[f32; 4]; MAX_LIGHTS],
    ambient: [f32; 4],
}

/// One object's push constants.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Push {
    model: [f32; 16],
    albedo: [f32; 4],
}

/// The wave's push constants (`Push` in `shaders-glsl/engine/wave.comp`).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct WavePush {
    time: f32,
    amplitude: f32,
    frequency: f32,
    count: u32,
}

/// How far the wave moves a vertex sideways, in object-space units.
pub const WAVE_AMPLITUDE: f32 = 0.12;

/// The engine's own compute pass deforming one mesh (`--deform`): its rest pose, the pipeline
/// and the set over the rest pose and the mesh's vertices.
struct Wave {
    mesh: usize,
    vertices: u32,
    _rest: Buffer,
    layout: PipelineLayout,
    pipeline: ComputePipeline,
    set: DescriptorSet,
}

/// What one frame in flight owns: its uniforms with their set, and the set of the visibility
/// views umbra handed it (made again only when they change).
struct FrameResources {
    uniforms: Buffer,
    uniform_set: DescriptorSet,
    visibility_set: Option<(Vec<vk::ImageView>, DescriptorSet)>,
}

/// The engine's renderer.
pub struct Engine {
    ctx: Context,
    pub width: u32,
    pub height: u32,
    depth: Image,
    color: Image,
    readback: Buffer,
    meshes: Vec<(Buffer, Buffer, u32)>,
    visibility_layout: DescriptorSetLayout,
    layout: PipelineLayout,
    prepass: GraphicsPipeline,
    shading: GraphicsPipeline,
    sampler: Sampler,
    /// Bound for lights umbra handed no visibility image (never sampled).
    unshadowed: Image,
    frames: Vec<FrameResources>,
    wave: Option<Wave>,
}

impl Engine {
    /// Targets of `width` × `height`, `scene`'s meshes uploaded, `frames` frames in flight;
    /// mesh `deform`, if any, deformed by the engine's wave every frame ([`Engine::deform`]).
    pub fn new(
        ctx: &Context,
        scene: &Scene,
        width: u32,
        height: u32,
        frames: usize,
        deform: Option<usize>,
    ) -> anyhow::Result<Self> {
        let depth_usage = vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC;
        let depth = Image::new(ctx, "engine depth", ImageDesc::new_2d(DEPTH, width, height).usage(depth_usage))?;
        let color_usage = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC;
        let color = Image::new(ctx, "engine colour", ImageDesc::new_2d(COLOR, width, height).usage(color_usage))?;
        let readback = Buffer::new(ctx, "engine readback", BufferDesc::readback(4 * u64::from(width * height)))?;
        let meshes: Vec<_> = (scene.meshes.iter().enumerate())
            .map(|(i, m)| upload_mesh(ctx, m, deform == Some(i)))
            .collect::<anyhow::Result<_>>()?;
        let wave = deform.map(|mesh| Wave::new(ctx, &scene.meshes[mesh], mesh, &meshes[mesh].0)).transpose()?;
        let stages = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT;
        let uniform = [Binding { binding: 0, ty: vk::DescriptorType::UNIFORM_BUFFER, stages }];
        let uniform_layout = DescriptorSetLayout::new(ctx, "engine uniform set layout", &uniform)?;
        let samplers: Vec<Binding> = (0..MAX_LIGHTS as u32)
            .map(|binding| Binding {
                binding,
                ty: vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                stages: vk::ShaderStageFlags::FRAGMENT,
            })
            .collect();
        let visibility_layout = DescriptorSetLayout::new(ctx, "engine visibility set layout", &samplers)?;
        let push = std::mem::size_of::<Push>() as u32;
        let layout = PipelineLayout::new(ctx, "engine layout", &[&uniform_layout, &visibility_layout], push)?;
        let (prepass, shading) = pipelines(ctx, &layout)?;
        let sampler = Sampler::new(ctx, "engine visibility sampler", SamplerDesc::NEAREST_CLAMP)?;
        let desc = ImageDesc::new_2d(COLOR, 1, 1).usage(vk::ImageUsageFlags::SAMPLED);
        let unshadowed = Image::new(ctx, "engine unshadowed placeholder", desc)?;
        let mut rec = ctx.begin_commands("engine set-up")?;
        rec.transition(&[(&unshadowed, ImageState::Undefined, ImageState::FragmentRead)]);
        ctx.submit_and_wait(rec)?;
        let frames = (0..frames)
            .map(|i| {
                let desc = BufferDesc::cpu_to_gpu(
                    std::mem::size_of::<FrameUniforms>() as u64,
                    vk::BufferUsageFlags::UNIFORM_BUFFER,
                );
                let uniforms = Buffer::new(ctx, &format!("engine uniforms {i}"), desc)?;
                let name = format!("engine uniform set {i}");
                let uniform_set = DescriptorSet::new(ctx, &name, &uniform_layout, &[Resource::Buffer(&uniforms)])?;
                Ok(FrameResources { uniforms, uniform_set, visibility_set: None })
            })
            .collect::<anyhow::Result<_>>()?;
        Ok(Self {
            ctx: ctx.clone(),
            width,
            height,
            depth,
            color,
            readback,
            meshes,
            visibility_layout,
            layout,
            prepass,
            shading,
            sampler,
            unshadowed,
            frames,
            wave,
        })
    }

    /// The engine's wave through its deformed mesh at `time` (radians of phase), before the
    /// frame's passes: it waits for every earlier use of the vertices (frames in flight read
    /// them), and its writes are made visible to the pre-pass's vertex input. umbra's own first
    /// use of them waits for every earlier command.
    pub fn deform<'a>(&'a self, rec: &mut Recorder<'a>, time: f32) {
        let Some(w) = &self.wave else { return };
        let vertices = &self.meshes[w.mesh].0;
        rec.begin_label("engine wave");
        rec.buffer_transition(&[(vertices, BufferState::Unknown, BufferState::ComputeStorage)]);
        rec.bind_compute_pipeline(&w.pipeline);
        rec.bind_compute_set(&w.layout, 0, &w.set);
        let push = WavePush { time, amplitude: WAVE_AMPLITUDE, frequency: 5.0, count: w.vertices };
        rec.push_constants(&w.layout, &push);
        rec.dispatch([w.vertices.div_ceil(64), 1, 1]);
        rec.buffer_transition(&[(vertices, BufferState::ComputeStorage, BufferState::VertexInput)]);
        rec.end_label();
    }

    /// The depth umbra records its shadows over, in the layout the pre-pass leaves it in.
    pub fn depth_target(&self) -> DepthTarget {
        DepthTarget {
            image: self.depth.raw,
            view: self.depth.view,
            format: DEPTH,
            usage: self.depth.desc.usage,
            extent: vk::Extent2D { width: self.width, height: self.height },
            samples: vk::SampleCountFlags::TYPE_1,
            layout: vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
        }
    }

    /// Mesh `mesh` as it lies in the engine's buffers (positions and normals interleaved 24
    /// bytes apart, 32-bit indices), for umbra to draw in place; `bounds` is its box.
    pub fn mesh_buffers(&self, mesh: usize, bounds: umbra::scene::Aabb) -> MeshBuffers {
        let (vertices, indices, count) = &self.meshes[mesh];
        let stream = |offset| VertexStream {
            buffer: vertices.raw,
            buffer_size: vertices.desc.size,
            offset,
            stride: 24,
            format: vk::Format::R32G32B32_SFLOAT,
        };
        MeshBuffers {
            positions: stream(0),
            normals: stream(12),
            vertex_count: (vertices.desc.size / 24) as u32,
            indices: IndexStream {
                buffer: indices.raw,
                buffer_size: indices.desc.size,
                offset: 0,
                index_type: vk::IndexType::UINT32,
                count: *count,
            },
            bounds,
        }
    }

    /// The depth format umbra is told about.
    pub fn depth_format(&self) -> vk::Format {
        DEPTH
    }

    /// Writes frame slot `slot`'s uniforms (read when the frame runs: the camera for both passes
    /// and `scene`'s lights, each marked with whether umbra handed it a visibility image this
    /// frame) and binds the visibility images umbra handed over.
    pub fn write_frame(
        &mut self,
        slot: usize,
        scene: &Scene,
        view_proj: Mat4,
        shadows: &[LightShadows],
    ) -> anyhow::Result<()> {
        let mut u = FrameUniforms {
            view_proj: view_proj.to_cols_array(),
            light_position: [[0.0; 4]; MAX_LIGHTS],
            light_radiance: [[0.0; 4]; MAX_LIGHTS],
            spot: [[0.0, 0.0, 0.0, 2.0]; MAX_LIGHTS],
            ambient: scene.ambient.extend(scene.lights.len().min(MAX_LIGHTS) as f32).to_array(),
        };
        for (i, light) in scene.lights.iter().take(MAX_LIGHTS).enumerate() {
            let shadowed = shadows.iter().any(|s| s.light == i && s.visibility.is_some());
            u.light_position[i] = light.position.to_array();
            u.light_radiance[i] = light.radiance().extend(if shadowed { 1.0 } else { 0.0 }).to_array();
            if let Some(spot) = &light.spot {
                u.spot[i] = spot.direction.normalize().extend(spot.outer_deg.to_radians().cos()).to_array();
            }
        }
        self.frames[slot].uniforms.write(0, bytemuck::bytes_of(&u))?;
        let views: Vec<vk::ImageView> = (0..MAX_LIGHTS)
            .map(|i| {
                let handed = shadows.iter().find(|s| s.light == i).and_then(|s| s.visibility);
                handed.map_or(self.unshadowed.view, |v| v.view)
            })
            .collect();
        let frame = &mut self.frames[slot];
        if frame.visibility_set.as_ref().is_none_or(|(made_for, _)| *made_for != views) {
            // The slot's last frame completed (its fence), so its set may go.
            let resources: Vec<Resource> = views
                .iter()
                .map(|&view| Resource::SampledImage {
                    view,
                    sampler: self.sampler.raw,
                    layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                })
                .collect();
            let name = format!("engine visibility set {slot}");
            let set = DescriptorSet::new(&self.ctx, &name, &self.visibility_layout, &resources)?;
            frame.visibility_set = Some((views, set));
        }
        Ok(())
    }

    /// The depth pre-pass of `scene` into the engine's depth.
    pub fn depth_prepass<'a>(&'a self, rec: &mut Recorder<'a>, slot: usize, scene: &Scene) -> anyhow::Result<()> {
        rec.begin_label("engine depth pre-pass");
        rec.transition(&[(&self.depth, ImageState::Undefined, ImageState::DepthStencilAttachment)]);
        let depth = DepthAttachment::cleared(&self.depth, 1.0, 0);
        rec.begin_rendering(&RenderTargets { color: &[], depth: Some(depth) });
        rec.bind_pipeline(&self.prepass);
        rec.bind_descriptor_set(&self.layout, 0, &self.frames[slot].uniform_set);
        self.draw(rec, scene);
        rec.end_rendering();
        rec.end_label();
        Ok(())
    }

    /// The shading pass: every object lit by every light times its visibility, over the
    /// depth (EQUAL, not written).
    pub fn shade<'a>(&'a self, rec: &mut Recorder<'a>, slot: usize, scene: &Scene) -> anyhow::Result<()> {
        rec.begin_label("engine shading");
        rec.transition(&[(&self.color, ImageState::Undefined, ImageState::ColorAttachment)]);
        let color =
            [ColorAttachment { image: &self.color, view: None, clear: Some(scene.background.extend(1.0).to_array()) }];
        let depth = DepthAttachment::keep(&self.depth);
        rec.begin_rendering(&RenderTargets { color: &color, depth: Some(depth) });
        rec.bind_pipeline(&self.shading);
        let frame = &self.frames[slot];
        let (_, visibility) = frame.visibility_set.as_ref().ok_or_else(|| anyhow::anyhow!("visibility not bound"))?;
        rec.bind_descriptor_set(&self.layout, 0, &frame.uniform_set);
        rec.bind_descriptor_set(&self.layout, 1, visibility);
        self.draw(rec, scene);
        rec.end_rendering();
        rec.end_label();
        Ok(())
    }

    fn draw<'a>(&'a self, rec: &mut Recorder<'a>, scene: &Scene) {
        for o in &scene.objects {
            let (vertices, indices, count) = &self.meshes[o.mesh];
            let push = Push { model: o.transform.to_cols_array(), albedo: Vec4::from((o.albedo, 1.0)).to_array() };
            rec.push_constants(&self.layout, &push);
            rec.bind_vertex_buffer(vertices);
            rec.bind_index_buffer(indices);
            rec.draw_indexed(*count, 0, 0);
        }
    }

    /// Leaves the colour target ready to be copied out by later submissions (a swapchain's
    /// blit, `Swapchain::present_image`).
    pub fn to_transfer<'a>(&'a self, rec: &mut Recorder<'a>) {
        rec.transition(&[(&self.color, ImageState::ColorAttachment, ImageState::TransferSrc)]);
    }

    /// The colour target.
    pub fn color(&self) -> &Image {
        &self.color
    }

    /// Copies the colour target into the readback buffer (read after the frame's fence).
    pub fn copy_out<'a>(&'a self, rec: &mut Recorder<'a>) {
        rec.transition(&[(&self.color, ImageState::ColorAttachment, ImageState::TransferSrc)]);
        rec.copy_image_to_buffer(&self.color, 0, &self.readback);
        rec.transfer_to_host(&[&self.readback]);
    }

    /// The last copied frame, RGBA8.
    pub fn pixels(&self) -> anyhow::Result<Vec<u8>> {
        Ok(self.readback.read()?)
    }
}

impl Wave {
    /// The wave through `m`, mesh `mesh`, whose interleaved vertices are `vertices`.
    fn new(ctx: &Context, m: &umbra::scene::Mesh, mesh: usize, vertices: &Buffer) -> anyhow::Result<Self> {
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let rest = Buffer::with_data(ctx, &format!("engine {} rest pose", m.name), usage, &interleaved(m))?;
        let (ty, stages) = (vk::DescriptorType::STORAGE_BUFFER, vk::ShaderStageFlags::COMPUTE);
        let bindings: Vec<Binding> = (0..2).map(|binding| Binding { binding, ty, stages }).collect();
        let set_layout = DescriptorSetLayout::new(ctx, "engine wave set layout", &bindings)?;
        let push = std::mem::size_of::<WavePush>() as u32;
        let layout = PipelineLayout::new(ctx, "engine wave layout", &[&set_layout], push)?;
        let shader = umbra::shaders::get("engine/wave.comp").ok_or_else(|| anyhow::anyhow!("engine/wave.comp"))?;
        let pipeline = ComputePipeline::new(ctx, &layout, "engine wave", shader.spirv, &[])?;
        let resources = [Resource::Buffer(&rest), Resource::Buffer(vertices)];
        let set = DescriptorSet::new(ctx, "engine wave set", &set_layout, &resources)?;
        Ok(Self { mesh, vertices: m.positions.len() as u32, _rest: rest, layout, pipeline, set })
    }
}

/// `m`'s positions and normals, interleaved.
fn interleaved(m: &umbra::scene::Mesh) -> Vec<u8> {
    let vertices: Vec<[f32; 6]> =
        m.positions.iter().zip(&m.normals).map(|(p, n)| [p.x, p.y, p.z, n.x, n.y, n.z]).collect();
    bytemuck::cast_slice(&vertices).to_vec()
}

/// Interleaved positions and normals, and indices, of one mesh (storage too where the engine
/// deforms it).
fn upload_mesh(ctx: &Context, m: &umbra::scene::Mesh, deformed: bool) -> anyhow::Result<(Buffer, Buffer, u32)> {
    let vertices = interleaved(m);
    let mut usage = vk::BufferUsageFlags::VERTEX_BUFFER;
    if deformed {
        usage |= vk::BufferUsageFlags::STORAGE_BUFFER;
    }
    let v = Buffer::with_data(ctx, &format!("engine {} vertices", m.name), usage, &vertices)?;
    let usage = vk::BufferUsageFlags::INDEX_BUFFER;
    let i = Buffer::with_data(ctx, &format!("engine {} indices", m.name), usage, bytemuck::cast_slice(&m.indices))?;
    Ok((v, i, m.indices.len() as u32))
}

/// The depth pre-pass (vertex shader only, LESS and write) and the shading pass (EQUAL, no
/// write) over the same vertex shader, so that both and umbra's passes agree on depth.
fn pipelines(ctx: &Context, layout: &PipelineLayout) -> anyhow::Result<(GraphicsPipeline, GraphicsPipeline)> {
    let shader = |path| umbra::shaders::get(path).map(|s| s.spirv).ok_or_else(|| anyhow::anyhow!("no shader {path}"));
    let (vertex, fragment) = (shader("engine/shade.vert")?, shader("engine/shade.frag")?);
    let attributes = [
        VertexAttribute { location: 0, format: vk::Format::R32G32B32_SFLOAT, offset: 0 },
        VertexAttribute { location: 1, format: vk::Format::R32G32B32_SFLOAT, offset: 12 },
    ];
    let mut desc = GraphicsPipelineDesc::new("engine depth pre-pass", vertex);
    desc.vertex_stride = 24;
    desc.vertex_attributes = &attributes;
    desc.cull = vk::CullModeFlags::NONE;
    desc.depth_format = DEPTH;
    desc.depth = DepthState { compare: vk::CompareOp::LESS, ..DepthState::TEST_AND_WRITE };
    let prepass = GraphicsPipeline::new(ctx, layout, &desc)?;
    let targets = [ColorTarget { format: COLOR, blend: None, write_mask: vk::ColorComponentFlags::RGBA }];
    desc.name = "engine shading";
    desc.fragment = Some(fragment);
    desc.color_targets = &targets;
    desc.depth = DepthState { compare: vk::CompareOp::EQUAL, write: false, ..DepthState::TEST_AND_WRITE };
    let shading = GraphicsPipeline::new(ctx, layout, &desc)?;
    Ok((prepass, shading))
}
