//! An engine's frame: a minimal "engine" (its own command buffer, depth image, depth pre-pass
//! shader and vertex buffers) records umbra's shadows with `Shadows::record` and reads the
//! visibility images back itself. Over a depth drawn the way umbra draws its own, they equal
//! umbra's own renderer's, bit for bit, for every technique; over depth drawn any other way
//! (reversed-Z, finite far, no stencil, D24S8) too, umbra re-drawing its own where it must;
//! moving an instance re-uploads nothing and allocates nothing; frames in flight each get
//! their slot.

mod common;

use glam::{Mat4, Vec3};
use umbra::scene::{Scene, Technique};
use umbra::shadows::{
    DepthTarget, FrameInputs, IndexStream, Instance, InstanceId, MeshBuffers, RebuildReason, Renderer, RendererDesc,
    ShadowFrame, Shadows, ShadowsDesc, VertexStream,
};
use umbra::vk::{
    vk, Buffer, BufferDesc, Context, DepthAttachment, GraphicsPipeline, GraphicsPipelineDesc, Image, ImageDesc,
    ImageState, PipelineLayout, Recorder, RenderTargets, VertexAttribute,
};

const W: u32 = 256;
const H: u32 = 192;

/// How an engine draws its depth: the format, samples, reversed-Z or not, and its far plane.
#[derive(Clone, Copy, Debug)]
struct Convention {
    format: vk::Format,
    samples: vk::SampleCountFlags,
    reversed: bool,
    far: Option<f32>,
}

impl Convention {
    /// umbra's own: standard depth, far plane at infinity, the device's depth/stencil format.
    fn umbra(ctx: &Context) -> Self {
        let format = ctx.capabilities().depth_stencil_format;
        Self { format, samples: vk::SampleCountFlags::TYPE_1, reversed: false, far: None }
    }

    /// The projection an engine of this convention builds for `scene`'s camera (glam's builders).
    fn projection(&self, scene: &Scene) -> Mat4 {
        let (c, aspect) = (&scene.camera, W as f32 / H as f32);
        let fov = c.fov_y_deg.to_radians();
        match (self.reversed, self.far) {
            (false, far) => umbra::scene::Camera { far, ..*c }.projection(aspect),
            (true, None) => Mat4::perspective_infinite_reverse_rh(fov, aspect, c.near),
            (true, Some(far)) => Mat4::perspective_rh(fov, aspect, far, c.near),
        }
    }
}

/// The engine: its depth buffer, its depth pre-pass and its copy of every mesh's positions.
struct Engine {
    convention: Convention,
    depth: Image,
    layout: PipelineLayout,
    pipeline: GraphicsPipeline,
    meshes: Vec<(Buffer, Buffer, u32)>,
}

impl Engine {
    fn new(ctx: &Context, scene: &Scene) -> Engine {
        Engine::with(ctx, scene, Convention::umbra(ctx))
    }

    fn with(ctx: &Context, scene: &Scene, convention: Convention) -> Engine {
        let format = convention.format;
        let usage = vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC;
        let desc = ImageDesc::new_2d(format, W, H).usage(usage).samples(convention.samples);
        let depth = Image::new(ctx, "engine depth", desc).unwrap();
        let layout = PipelineLayout::new(ctx, "engine depth layout", &[], 128).unwrap();
        let vertex = umbra::shaders::get("engine/depth.vert").unwrap().spirv;
        let attributes = [VertexAttribute { location: 0, format: vk::Format::R32G32B32_SFLOAT, offset: 0 }];
        let mut desc = GraphicsPipelineDesc::new("engine depth pre-pass", vertex);
        desc.vertex_stride = 12;
        desc.vertex_attributes = &attributes;
        desc.cull = vk::CullModeFlags::NONE;
        desc.depth_format = format;
        desc.samples = convention.samples;
        if convention.reversed {
            desc.depth.compare = vk::CompareOp::GREATER_OR_EQUAL;
        }
        let pipeline = GraphicsPipeline::new(ctx, &layout, &desc).unwrap();
        let meshes = scene
            .meshes
            .iter()
            .map(|m| {
                let positions: Vec<[f32; 3]> = m.positions.iter().map(|p| p.to_array()).collect();
                let v = Buffer::with_data(
                    ctx,
                    "engine vertices",
                    vk::BufferUsageFlags::VERTEX_BUFFER,
                    bytemuck::cast_slice(&positions),
                );
                let i = Buffer::with_data(
                    ctx,
                    "engine indices",
                    vk::BufferUsageFlags::INDEX_BUFFER,
                    bytemuck::cast_slice(&m.indices),
                );
                (v.unwrap(), i.unwrap(), m.indices.len() as u32)
            })
            .collect();
        Engine { convention, depth, layout, pipeline, meshes }
    }

    /// The depth pre-pass of `scene`'s objects seen through `view_proj`.
    fn depth_pass<'a>(&'a self, rec: &mut Recorder<'a>, scene: &Scene, view_proj: Mat4) {
        rec.transition(&[(&self.depth, ImageState::Undefined, ImageState::DepthStencilAttachment)]);
        let far = if self.convention.reversed { 0.0 } else { 1.0 };
        let depth = DepthAttachment::cleared(&self.depth, far, 0);
        rec.begin_rendering(&RenderTargets { color: &[], depth: Some(depth) });
        rec.bind_pipeline(&self.pipeline);
        for o in &scene.objects {
            let (vertices, indices, count) = &self.meshes[o.mesh];
            rec.push_constants(&self.layout, &[view_proj.to_cols_array(), o.transform.to_cols_array()]);
            rec.bind_vertex_buffer(vertices);
            rec.bind_index_buffer(indices);
            rec.draw_indexed(*count, 0, 0);
        }
        rec.end_rendering();
    }

    /// umbra's shadows for this engine's depth with `frames` in flight, `scene` registered.
    fn shadows(&self, ctx: &Context, scene: &Scene, frames: u32) -> (Shadows, Vec<InstanceId>) {
        let settings = RendererDesc::new(W, H);
        let desc = ShadowsDesc { settings, depth_format: self.depth.desc.format, frames_in_flight: frames };
        let mut shadows = Shadows::new(ctx, desc).unwrap();
        let ids = register(&mut shadows, scene);
        (shadows, ids)
    }

    fn depth_target(&self) -> DepthTarget {
        DepthTarget {
            image: self.depth.raw,
            view: self.depth.view,
            format: self.depth.desc.format,
            usage: self.depth.desc.usage,
            extent: vk::Extent2D { width: W, height: H },
            samples: self.convention.samples,
            layout: vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
        }
    }
}

/// Registers `scene`'s meshes and objects, in order.
fn register(shadows: &mut Shadows, scene: &Scene) -> Vec<InstanceId> {
    let meshes: Vec<_> = scene.meshes.iter().map(|m| shadows.add_mesh(m.clone()).unwrap()).collect();
    scene.objects.iter().map(|o| shadows.add_instance(Instance::of_object(o, meshes[o.mesh])).unwrap()).collect()
}

fn inputs<'a>(engine: &Engine, scene: &'a Scene, frame_index: u64) -> FrameInputs<'a> {
    FrameInputs {
        depth: engine.depth_target(),
        view: scene.camera.view(),
        proj: engine.convention.projection(scene),
        lights: &scene.lights,
        frame_index,
    }
}

/// One engine frame: depth pre-pass, umbra's shadows, then the engine copies every visibility
/// image out. Returns what `record` said and each shadowed light's texels (as bits).
fn engine_frame(
    ctx: &Context,
    engine: &Engine,
    shadows: &mut Shadows,
    scene: &Scene,
    index: u64,
) -> (ShadowFrame, Vec<(usize, Vec<u32>)>) {
    // Declared first: the recording borrows them until it is submitted.
    let (images, readbacks): (Vec<(usize, Image)>, Vec<Buffer>);
    let mut rec = ctx.begin_commands("engine frame").unwrap();
    let i = inputs(engine, scene, index);
    engine.depth_pass(&mut rec, scene, i.proj * i.view);
    let frame = shadows.record(rec.raw(), &i).unwrap();
    images = frame
        .lights
        .iter()
        .filter_map(|l| l.visibility.map(|v| (l.light, v)))
        .map(|(l, v)| (l, Image::external(ctx, v.image, v.view, ImageDesc::new_2d(v.format, W, H))))
        .collect();
    readbacks = images
        .iter()
        .map(|_| Buffer::new(ctx, "engine readback", BufferDesc::readback(8 * u64::from(W * H))).unwrap())
        .collect();
    for ((_, image), buffer) in images.iter().zip(&readbacks) {
        rec.transition(&[(image, ImageState::FragmentRead, ImageState::TransferSrc)]);
        rec.copy_image_to_buffer(image, 0, buffer);
        rec.transition(&[(image, ImageState::TransferSrc, ImageState::FragmentRead)]);
    }
    rec.transfer_to_host(&readbacks.iter().collect::<Vec<_>>());
    ctx.submit_and_wait(rec).unwrap();
    let texels = images
        .iter()
        .zip(&readbacks)
        .map(|((l, _), b)| (*l, bytemuck::cast_slice::<u8, u32>(&b.read().unwrap()).to_vec()))
        .collect();
    (frame, texels)
}

/// `name` with every light using `technique`, seen through an infinite far plane (the depth
/// convention umbra's renderer uses whenever a light needs volumes, so one for all techniques).
fn scene(name: &str, technique: Technique) -> Scene {
    let mut scene = umbra::scene::load(name).unwrap();
    scene.camera.far = None;
    for light in &mut scene.lights {
        light.technique = technique;
    }
    scene
}

/// umbra's own renderer's visibility images of `scene`: each shadowed light's texels as bits.
fn renderer_bits(ctx: &Context, scene: &Scene) -> Vec<(usize, Vec<u32>)> {
    renderer_bits_with(ctx, scene, RendererDesc::new(W, H))
}

/// [`renderer_bits`] with the settings of `desc`.
fn renderer_bits_with(ctx: &Context, scene: &Scene, mut desc: RendererDesc) -> Vec<(usize, Vec<u32>)> {
    desc.read_visibility = true;
    let own = Renderer::new(ctx, desc).unwrap().render(scene).unwrap();
    let bits = |image: &umbra::shadows::VisibilityImage| {
        image.texels.iter().flat_map(|t| [t[0].to_bits(), t[1].to_bits()]).collect()
    };
    own.visibility.iter().map(|image| (image.light, bits(image))).collect()
}

/// Texels (of every light, two channels each) where `a` and `b` differ; the same lights
/// shadowed in both.
fn differing(a: &[(usize, Vec<u32>)], b: &[(usize, Vec<u32>)]) -> usize {
    let lights = |x: &[(usize, Vec<u32>)]| x.iter().map(|(l, _)| *l).collect::<Vec<_>>();
    assert_eq!(lights(a), lights(b), "shadowed lights");
    let texel = |bits: &[u32], i: usize| [bits[2 * i], bits[2 * i + 1]];
    a.iter().zip(b).map(|((_, x), (_, y))| (0..x.len() / 2).filter(|&i| texel(x, i) != texel(y, i)).count()).sum()
}

#[test]
fn the_engines_visibility_images_equal_the_renderers_bit_for_bit() {
    common::with_context(|ctx| {
        let cases = [
            ("cubes", Technique::ShadowMap),
            ("cubes", Technique::ShadowVolume),
            ("cubes", Technique::Hybrid),
            ("pins", Technique::SilhouetteMap),
            ("pins", Technique::Hybrid),
            ("cubes", Technique::RayTraced),
            ("pins", Technique::RayTraced),
            ("cubes", Technique::HybridRt),
            ("pins", Technique::HybridRt),
        ];
        for (name, technique) in cases {
            let mut scene = scene(name, technique);
            if technique == Technique::SilhouetteMap {
                for light in &mut scene.lights {
                    if light.kind() == umbra::scene::LightKind::Point {
                        let p = light.position.truncate();
                        *light = umbra::scene::Light::spot(p, Vec3::ZERO - p, 40.0, 50.0, 1.0);
                        light.technique = technique;
                    }
                }
            }
            let own = renderer_bits(ctx, &scene);
            let engine = Engine::new(ctx, &scene);
            let (mut shadows, _) = engine.shadows(ctx, &scene, 1);
            let (frame, texels) = engine_frame(ctx, &engine, &mut shadows, &scene, 0);
            assert_eq!(frame.depth_rebuilt, None, "{name} {technique:?}: umbra's convention is used as it is");
            assert!(!own.is_empty(), "{name} {technique:?}: the renderer shadowed no light");
            let differ = differing(&texels, &own);
            assert_eq!(differ, 0, "{name} {technique:?}: {differ} texels differ");
            println!("{name} {technique:?}: {} lights' visibility images identical", texels.len());
        }
    });
}

#[test]
fn moving_an_instance_uploads_and_allocates_nothing_after_the_first_frame() {
    common::with_context(|ctx| {
        let mut scene = scene("cubes", Technique::Hybrid);
        let engine = Engine::new(ctx, &scene);
        let (mut shadows, ids) = engine.shadows(ctx, &scene, 1);
        let (moving, start) = (scene.objects.len() - 1, scene.objects.last().unwrap().transform);
        let mut images = Vec::new();
        for frame in 0..10u64 {
            let t = Mat4::from_translation(Vec3::new(0.05 * frame as f32, 0.0, 0.0)) * start;
            scene.objects[moving].transform = t;
            shadows.set_transform(ids[moving], t).unwrap();
            let (report, texels) = engine_frame(ctx, &engine, &mut shadows, &scene, frame);
            if frame == 0 {
                assert!(report.geometry_uploaded_bytes > 0, "the first frame uploads the meshes");
            } else {
                assert_eq!(report.geometry_uploaded_bytes, 0, "frame {frame} uploaded mesh data");
                assert_eq!(report.memory_allocations, 0, "frame {frame} allocated Vulkan memory");
                assert!(report.earlier_passes.is_some(), "frame {frame}: the slot's earlier passes");
            }
            images.push(texels);
        }
        assert!(images.windows(2).all(|w| w[0] != w[1]), "the moving instance's shadow moved every frame");
        println!("10 frames: one upload and every allocation in frame 0, shadows moved every frame");
    });
}

#[test]
fn a_mesh_added_between_frames_is_uploaded_inside_the_engines_frame() {
    common::with_context(|ctx| {
        // `full` has one more mesh and object than `start`: a copy of the last object's mesh,
        // beside it.
        let mut full = scene("cubes", Technique::Hybrid);
        let last = full.objects.last().unwrap().clone();
        full.meshes.push(full.meshes[last.mesh].clone());
        let mut added = last.clone();
        added.mesh = full.meshes.len() - 1;
        added.transform = Mat4::from_translation(Vec3::new(-1.5, 0.0, 1.0)) * last.transform;
        full.objects.push(added.clone());
        let mut start = full.clone();
        start.meshes.pop();
        start.objects.pop();
        let engine = Engine::new(ctx, &full);
        let (mut shadows, _) = engine.shadows(ctx, &start, 1);
        let (first, texels) = engine_frame(ctx, &engine, &mut shadows, &start, 0);
        assert!(first.geometry_uploaded_bytes > 0, "the first frame uploads the meshes");
        assert_eq!(differing(&texels, &renderer_bits(ctx, &start)), 0, "before the mesh is added");
        let mesh = shadows.add_mesh(full.meshes.last().unwrap().clone()).unwrap();
        shadows.add_instance(Instance::of_object(&added, mesh)).unwrap();
        let (frame, texels) = engine_frame(ctx, &engine, &mut shadows, &full, 1);
        assert!(frame.geometry_uploaded_bytes > 0, "the new mesh is uploaded");
        assert_eq!((first.submissions, frame.submissions), (0, 0), "umbra submitted inside record");
        let own = renderer_bits(ctx, &full);
        assert!(differing(&own, &renderer_bits(ctx, &start)) > 0, "the added object changes the shadows");
        assert_eq!(differing(&texels, &own), 0, "after the mesh is added");
        let passes = engine_frame(ctx, &engine, &mut shadows, &full, 2).0.earlier_passes.unwrap();
        assert_eq!(passes.first().map(|p| p.name.as_str()), Some("mesh upload"), "{passes:?}");
        println!(
            "a mesh added between frames: {} bytes uploaded by the frame's own first pass, no submission",
            frame.geometry_uploaded_bytes
        );
    });
}

/// The position and normal streams of 32-byte vertices in `v`: a float, the position, the
/// normal, a float.
fn interleaved_streams(v: &Buffer) -> (VertexStream, VertexStream) {
    let stream = |offset| VertexStream {
        buffer: v.raw,
        buffer_size: v.desc.size,
        offset,
        stride: 32,
        format: vk::Format::R32G32B32_SFLOAT,
    };
    (stream(4), stream(16))
}

/// `mesh` in buffers laid out the way an engine might keep it: vertices interleaved 32 bytes
/// apart (a float, the position, the normal, a float), 16-bit indices where they fit unless
/// `wide`, else 32-bit, 16 bytes into their buffer.
fn engine_mesh(ctx: &Context, mesh: &umbra::scene::Mesh, wide: bool) -> (Buffer, Buffer, MeshBuffers) {
    let vertices: Vec<[f32; 8]> =
        mesh.positions.iter().zip(&mesh.normals).map(|(p, n)| [-7.0, p.x, p.y, p.z, n.x, n.y, n.z, 9.0]).collect();
    let short = !wide && mesh.positions.len() <= usize::from(u16::MAX);
    let indices: Vec<u8> = match short {
        true => {
            [u16::MAX; 8].into_iter().chain(mesh.indices.iter().map(|&i| i as u16)).flat_map(u16::to_le_bytes).collect()
        }
        false => [u32::MAX; 4].into_iter().chain(mesh.indices.iter().copied()).flat_map(u32::to_le_bytes).collect(),
    };
    let usage = vk::BufferUsageFlags::VERTEX_BUFFER;
    let v = Buffer::with_data(ctx, "engine mesh vertices", usage, bytemuck::cast_slice(&vertices)).unwrap();
    let i = Buffer::with_data(ctx, "engine mesh indices", vk::BufferUsageFlags::INDEX_BUFFER, &indices).unwrap();
    let (positions, normals) = interleaved_streams(&v);
    let buffers = MeshBuffers {
        positions,
        normals,
        vertex_count: mesh.positions.len() as u32,
        indices: IndexStream {
            buffer: i.raw,
            buffer_size: i.desc.size,
            offset: 16,
            index_type: if short { vk::IndexType::UINT16 } else { vk::IndexType::UINT32 },
            count: mesh.indices.len() as u32,
        },
        bounds: mesh.bounds(),
    };
    (v, i, buffers)
}

/// The error of a frame `shadows` must refuse (nothing recorded), printed.
fn refused_record(ctx: &Context, engine: &Engine, shadows: &mut Shadows, scene: &Scene) -> String {
    let rec = ctx.begin_commands("refused frame").unwrap();
    let err = shadows.record(rec.raw(), &inputs(engine, scene, 99)).map(|_| ()).unwrap_err().to_string();
    println!("{err}");
    err
}

#[test]
fn meshes_in_the_engines_own_buffers_give_the_same_shadow_maps() {
    common::with_context(|ctx| {
        let mut scene = scene("cubes", Technique::ShadowMap);
        let engine = Engine::new(ctx, &scene);
        let settings = RendererDesc::new(W, H);
        let desc = ShadowsDesc { settings, depth_format: engine.depth.desc.format, frames_in_flight: 1 };
        let mut shadows = Shadows::new(ctx, desc).unwrap();
        let buffers: Vec<_> = scene.meshes.iter().enumerate().map(|(i, m)| engine_mesh(ctx, m, i % 2 == 0)).collect();
        let meshes: Vec<_> = buffers.iter().map(|(_, _, b)| shadows.add_mesh_buffers(*b).unwrap()).collect();
        for o in &scene.objects {
            shadows.add_instance(Instance::of_object(o, meshes[o.mesh])).unwrap();
        }
        let own = renderer_bits(ctx, &scene);
        let (first, texels) = engine_frame(ctx, &engine, &mut shadows, &scene, 0);
        let differ = differing(&texels, &own);
        println!(
            "{} meshes drawn from the engine's buffers ({} with 16-bit indices): {} bytes uploaded, {differ} texels differ",
            meshes.len(),
            buffers.iter().filter(|b| b.2.indices.index_type == vk::IndexType::UINT16).count(),
            first.geometry_uploaded_bytes
        );
        assert_eq!(differ, 0, "shadow maps of meshes drawn from the engine's buffers");
        assert_eq!(first.submissions, 0, "umbra submitted inside record");
        let (second, again) = engine_frame(ctx, &engine, &mut shadows, &scene, 1);
        assert_eq!((second.geometry_uploaded_bytes, second.memory_allocations), (0, 0), "second frame");
        assert_eq!(differing(&again, &own), 0, "second frame");
        // A light that builds volumes on the CPU cannot use them: a typed error naming it.
        scene.lights[0].technique = Technique::ShadowVolume;
        let err = refused_record(ctx, &engine, &mut shadows, &scene);
        assert!(err.starts_with("FrameInputs::lights[0].technique: ShadowVolume builds shadows"), "{err}");
        drop(shadows);
        drop(buffers);
    });
}

#[test]
fn three_frames_in_flight_each_record_into_their_own_slot() {
    common::with_context(|ctx| {
        let mut scene = scene("cubes", Technique::ShadowVolume);
        let engine = Engine::new(ctx, &scene);
        let (mut shadows, ids) = engine.shadows(ctx, &scene, 3);
        let device = ctx.device();
        // SAFETY: the engine's own frame resources, destroyed below once every fence signalled.
        let (pool, cmds, fences, queue) = unsafe {
            let info = vk::CommandPoolCreateInfo::default()
                .queue_family_index(ctx.queue_family())
                .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
            let pool = device.create_command_pool(&info, None).unwrap();
            let alloc = vk::CommandBufferAllocateInfo::default().command_pool(pool).command_buffer_count(3);
            let cmds = device.allocate_command_buffers(&alloc).unwrap();
            let signalled = vk::FenceCreateInfo::default().flags(vk::FenceCreateFlags::SIGNALED);
            let fences: Vec<vk::Fence> = (0..3).map(|_| device.create_fence(&signalled, None).unwrap()).collect();
            (pool, cmds, fences, device.get_device_queue(ctx.queue_family(), 0))
        };
        let moving = scene.objects.len() - 1;
        let start = scene.objects[moving].transform;
        for frame in 0..9u64 {
            let slot = (frame % 3) as usize;
            let (cmd, fence) = (cmds[slot], fences[slot]);
            // SAFETY: the engine waits for its own slot's fence before reusing the slot.
            unsafe {
                device.wait_for_fences(&[fence], true, u64::MAX).unwrap();
                device.reset_fences(&[fence]).unwrap();
                device.reset_command_buffer(cmd, vk::CommandBufferResetFlags::empty()).unwrap();
                device.begin_command_buffer(cmd, &vk::CommandBufferBeginInfo::default()).unwrap();
            }
            let t = Mat4::from_translation(Vec3::new(0.0, 0.0, 0.05 * frame as f32)) * start;
            scene.objects[moving].transform = t;
            // Every other frame the light's maps go (volumes) and come back (the hybrid), while
            // the frames before, which use them, may still run.
            let technique = if frame % 2 == 0 { Technique::Hybrid } else { Technique::ShadowVolume };
            scene.lights.iter_mut().for_each(|l| l.technique = technique);
            shadows.set_transform(ids[moving], t).unwrap();
            let i = inputs(&engine, &scene, frame);
            let recorded = {
                let mut rec = ctx.record_into(cmd);
                engine.depth_pass(&mut rec, &scene, i.proj * i.view);
                shadows.record(cmd, &i).unwrap()
            };
            assert_eq!(recorded.slot, slot);
            assert_eq!(recorded.earlier_passes.is_some(), frame >= 3, "frame {frame}: the slot's earlier frame");
            // SAFETY: the engine ends and submits its own command buffer, signalling its slot's fence.
            unsafe {
                device.end_command_buffer(cmd).unwrap();
                let cmd_info = [vk::CommandBufferSubmitInfo::default().command_buffer(cmd)];
                let submit = [vk::SubmitInfo2::default().command_buffer_infos(&cmd_info)];
                device.queue_submit2(queue, &submit, fence).unwrap();
            }
        }
        // SAFETY: every frame completed before its resources go.
        unsafe {
            device.wait_for_fences(&fences, true, u64::MAX).unwrap();
            for f in fences {
                device.destroy_fence(f, None);
            }
            device.destroy_command_pool(pool, None);
        }
        println!("9 frames over 3 slots, a fence each, recorded without a wait inside umbra; maps released and made every frame");
    });
}

/// Every way an engine may draw its depth that umbra's passes cannot test as it is — 4× MSAA,
/// reversed-Z, no stencil, a finite far plane where volumes must reach infinity — and a finite
/// far plane and D24S8 that they can. `None`: the depth is used as it is.
fn conventions(ctx: &Context, far: f32) -> Vec<(Convention, Technique, Option<RebuildReason>)> {
    let (d32s8, d32, d24s8) = (vk::Format::D32_SFLOAT_S8_UINT, vk::Format::D32_SFLOAT, vk::Format::D24_UNORM_S8_UINT);
    let one = vk::SampleCountFlags::TYPE_1;
    let c = |format, reversed, far| Convention { format, samples: one, reversed, far };
    let msaa = Convention { samples: vk::SampleCountFlags::TYPE_4, ..c(d32s8, false, None) };
    let mut cases = Vec::new();
    for t in [Technique::ShadowMap, Technique::ShadowVolume, Technique::Hybrid] {
        cases.push((msaa, t, Some(RebuildReason::Multisampled)));
        cases.push((c(d32s8, true, None), t, Some(RebuildReason::ReversedZ)));
        cases.push((c(d32, false, None), t, Some(RebuildReason::NoStencil)));
        cases.push((c(d24s8, false, None), t, None));
    }
    cases.push((c(d32s8, false, Some(far)), Technique::ShadowMap, None));
    // Shadow rays need neither a stencil nor a far plane at infinity.
    cases.push((c(d32s8, false, Some(far)), Technique::RayTraced, None));
    cases.push((c(d32s8, false, Some(far)), Technique::HybridRt, None));
    cases.push((c(d32s8, false, Some(far)), Technique::ShadowVolume, Some(RebuildReason::FiniteFar)));
    cases.push((c(d32s8, true, Some(far)), Technique::Hybrid, Some(RebuildReason::ReversedZ)));
    let formats = &ctx.capabilities().depth_stencil_formats;
    cases.retain(|(c, t, _)| {
        let supported = c.format == d32 || formats.contains(&format!("{:?}", c.format));
        if !supported {
            println!(
                "SKIPPED {c:?} {t:?}: {} has no {:?} attachments (covered on lavapipe)",
                ctx.capabilities().driver(),
                c.format
            );
        }
        supported
    });
    cases
}

#[test]
fn every_depth_convention_gives_the_renderers_shadows() {
    common::with_context(|ctx| {
        let base = scene("cubes", Technique::ShadowMap);
        let far = base.camera.position.distance(base.camera.target);
        for (convention, technique, rebuilt) in conventions(ctx, far) {
            let scene = scene("cubes", technique);
            let engine = Engine::with(ctx, &scene, convention);
            let (mut shadows, _) = engine.shadows(ctx, &scene, 1);
            let (frame, texels) = engine_frame(ctx, &engine, &mut shadows, &scene, 0);
            let case = format!("{convention:?} {technique:?}");
            assert_eq!(frame.depth_rebuilt, rebuilt, "{case}");
            let (again, _) = engine_frame(ctx, &engine, &mut shadows, &scene, 1);
            let passes = again.earlier_passes.unwrap();
            let rebuild_pass = passes.iter().any(|p| p.name == "depth rebuild");
            assert_eq!(rebuild_pass, rebuilt.is_some(), "{case}: the depth rebuild pass in the frame report");
            // What umbra should see: the renderer through the same camera (its far plane where
            // umbra tested the engine's finite-far depth, at infinity where it re-drew its own).
            let mut reference = scene.clone();
            reference.camera.far = if rebuilt.is_none() { convention.far } else { None };
            let own = renderer_bits(ctx, &reference);
            if let (Some(_), None) = (convention.far, rebuilt) {
                let infinite = renderer_bits(ctx, &scene);
                assert!(differing(&own, &infinite) > 0, "{case}: the far plane cuts some of the scene");
            }
            let differ = differing(&texels, &own);
            let total = own.len() * (W * H) as usize;
            println!(
                "{case}: depth {}, {differ} of {total} texels differ from the renderer's",
                match rebuilt {
                    Some(r) => format!("rebuilt ({r})"),
                    None => "used as it is".into(),
                }
            );
            // glam builds x and y of a finite and an infinite perspective one ulp apart, which
            // moves a few edge pixels; where the engine's rows are the renderer's, none may differ.
            let (proj, own_proj) = (convention.projection(&scene), reference.camera.projection(W as f32 / H as f32));
            if (proj.x_axis.x, proj.y_axis.y) == (own_proj.x_axis.x, own_proj.y_axis.y) {
                assert_eq!(differ, 0, "{case}");
            } else {
                assert!(differ <= total / 1000, "{case}: {differ} texels differ, more than one ulp of x and y moves");
            }
        }
    });
}

/// Runs the example engine (`examples/embed`) headless on the test's device, validation on.
fn run_example(out: &std::path::Path, extra: &[&str]) -> String {
    let run = std::process::Command::new(common::example("embed"))
        .args(["--frames", "3", "--size", "160x90", "--out"])
        .arg(out)
        .args(extra)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .env("UMBRA_VALIDATION", "1")
        .output()
        .expect("the example runs");
    let output = format!("{}{}", String::from_utf8_lossy(&run.stdout), String::from_utf8_lossy(&run.stderr));
    assert!(run.status.success(), "examples/embed {extra:?} failed:\n{output}");
    output
}

#[test]
fn the_example_engine_shades_with_umbras_shadows_without_umbra_submitting() {
    let out = common::output_dir("embed-example");
    let shadowed = run_example(&out.join("shadowed"), &[]);
    print!("{shadowed}");
    let frames: Vec<&str> = shadowed.lines().filter(|l| l.starts_with("frame ")).collect();
    assert_eq!(frames.len(), 3, "{shadowed}");
    assert!(frames.iter().all(|l| l.contains("2/2 lights shadowed") && l.contains(" 0 submissions by umbra")));
    assert!(frames[2].contains("uploaded 0 B, 0 allocations"), "warm frame: {}", frames[2]);
    run_example(&out.join("unshadowed"), &["--technique", "unshadowed"]);
    let load = |dir: &str| image::open(out.join(dir).join("embed-frame-2.png")).unwrap().to_rgba8();
    let (with, without) = (load("shadowed"), load("unshadowed"));
    // Shadows only take light away: every differing pixel is darker with them.
    let (mut darker, mut brighter) = (0, 0);
    for (a, b) in with.pixels().zip(without.pixels()) {
        let (sa, sb): (u32, u32) =
            (a.0[..3].iter().map(|&c| u32::from(c)).sum(), b.0[..3].iter().map(|&c| u32::from(c)).sum());
        darker += usize::from(sa < sb);
        brighter += usize::from(sa > sb);
    }
    println!(
        "the engine's shading with umbra's shadows: {darker} of {} pixels darker, {brighter} brighter",
        with.len() / 4
    );
    assert!(darker > with.len() / 4 / 50, "shadows darken at least 2% of the frame");
    assert_eq!(brighter, 0, "a shadow made a pixel brighter");
}

/// The deforming-mesh scene at rest: a floor, a sphere and a box (whose faces have vertices of
/// their own, welded at its corners) under one shadow-volume point light.
fn deforming_rest() -> Scene {
    use umbra::scene::{primitives, Camera, Light};
    let mut s = Scene::new("deforming");
    let floor = s.add_mesh(primitives::cuboid(Vec3::new(4.0, 0.05, 4.0)));
    s.add_object(floor, Mat4::from_translation(Vec3::new(0.0, -0.05, 0.0)), Vec3::splat(0.8));
    let sphere = primitives::displaced_sphere(0.7, 32, 20, |_, _| 1.0);
    let sphere = s.add_mesh(deformed_mesh(&sphere, |p| p));
    s.add_object(sphere, Mat4::from_translation(Vec3::new(-0.9, 1.3, 0.0)), Vec3::new(0.8, 0.6, 0.4));
    let bar = s.add_mesh(deformed_mesh(&primitives::cuboid(Vec3::new(0.3, 0.8, 0.3)), |p| p));
    s.add_object(bar, Mat4::from_translation(Vec3::new(1.0, 0.9, 0.4)), Vec3::new(0.4, 0.6, 0.8));
    s.lights.push(Light::point(Vec3::new(1.5, 5.0, 2.0), 30.0));
    s.lights[0].technique = Technique::ShadowVolume;
    s.camera = Camera::look_at(Vec3::new(-2.5, 4.0, 5.5), Vec3::new(0.0, 0.6, 0.0));
    s.camera.far = None;
    s
}

/// `mesh` with every position moved by `f` (a function of the rest position, so vertices
/// welded at rest stay together) and smooth normals of the new pose.
fn deformed_mesh(mesh: &umbra::scene::Mesh, f: impl Fn(Vec3) -> Vec3) -> umbra::scene::Mesh {
    let positions = mesh.positions.iter().map(|&p| f(p)).collect();
    umbra::scene::Mesh::with_smooth_normals(mesh.name.clone(), positions, mesh.indices.clone()).unwrap()
}

/// The pose at `time`: a wave through the sphere, a twist through the box.
fn deforming_pose(rest: &Scene, time: f32) -> Scene {
    let mut s = rest.clone();
    s.meshes[1] = deformed_mesh(&rest.meshes[1], |p| p * (1.0 + 0.2 * (6.0 * p.y + 2.0 * time).sin()));
    s.meshes[2] = deformed_mesh(&rest.meshes[2], |p| glam::Mat3::from_rotation_y(0.9 * time.sin() * p.y) * p);
    s
}

/// A deforming mesh's buffers: positions and normals interleaved 32 bytes apart, 4 bytes in
/// (as `engine_mesh`), in memory the test writes each pose into, with bounds holding every pose.
fn deforming_buffers(
    ctx: &Context,
    mesh: &umbra::scene::Mesh,
    bounds: umbra::scene::Aabb,
) -> (Buffer, Buffer, MeshBuffers) {
    let usage = vk::BufferUsageFlags::VERTEX_BUFFER | vk::BufferUsageFlags::STORAGE_BUFFER;
    let v =
        Buffer::new(ctx, "engine deforming vertices", BufferDesc::cpu_to_gpu(32 * mesh.positions.len() as u64, usage))
            .unwrap();
    let i = Buffer::with_data(
        ctx,
        "engine deforming indices",
        vk::BufferUsageFlags::INDEX_BUFFER,
        bytemuck::cast_slice(&mesh.indices),
    )
    .unwrap();
    let (positions, normals) = interleaved_streams(&v);
    let indices = IndexStream {
        buffer: i.raw,
        buffer_size: i.desc.size,
        offset: 0,
        index_type: vk::IndexType::UINT32,
        count: mesh.indices.len() as u32,
    };
    let buffers = MeshBuffers { positions, normals, vertex_count: mesh.positions.len() as u32, indices, bounds };
    (v, i, buffers)
}

/// Writes `mesh`'s pose into its deforming buffer, as an engine's skinning pass would.
fn write_pose(buffer: &mut Buffer, mesh: &umbra::scene::Mesh) {
    let vertices: Vec<[f32; 8]> =
        mesh.positions.iter().zip(&mesh.normals).map(|(p, n)| [-7.0, p.x, p.y, p.z, n.x, n.y, n.z, 9.0]).collect();
    buffer.write(0, bytemuck::cast_slice(&vertices)).unwrap();
}

/// Pixels where `bits` (one light's visibility texels) disagree with the exact reference of
/// `scene`, and how many were compared.
fn against_reference(scene: &Scene, bits: &[u32]) -> (usize, usize) {
    let reference = common::exact::Reference::new(scene);
    let vp = scene.camera.view_proj(W as f32 / H as f32);
    let (mut compared, mut wrong) = (0, 0);
    for y in 0..H {
        for x in 0..W {
            let Some(shadowed) = reference.pixel(vp, W, H, x, y) else { continue };
            let i = (y * W + x) as usize;
            let (visibility, decided) = (f32::from_bits(bits[2 * i]), f32::from_bits(bits[2 * i + 1]));
            if decided < 0.5 {
                continue; // a surface that receives no shadow (the reference's facing aside)
            }
            compared += 1;
            wrong += usize::from((visibility <= 0.5) != shadowed);
        }
    }
    (compared, wrong)
}

#[test]
fn meshes_deformed_on_the_gpu_keep_exact_volume_shadows() {
    common::with_context(|ctx| {
        let rest = deforming_rest();
        // The CPU path it is compared with clips alike: not on the host (which the GPU path
        // cannot, and SwiftShader would otherwise ask for).
        let mut cpu = RendererDesc::new(W, H);
        cpu.shadow_volume.host_clip = umbra::shadows::HostClip::Never;
        let mut settings = cpu;
        settings.shadow_volume.build = umbra::shadows::VolumeBuild::Gpu;
        let format = Convention::umbra(ctx).format;
        let mut shadows =
            Shadows::new(ctx, ShadowsDesc { settings, depth_format: format, frames_in_flight: 1 }).unwrap();
        let floor = shadows.add_mesh(rest.meshes[0].clone()).unwrap();
        let bounds = [
            umbra::scene::Aabb { min: Vec3::splat(-0.85), max: Vec3::splat(0.85) },
            umbra::scene::Aabb { min: Vec3::new(-0.45, -0.8, -0.45), max: Vec3::new(0.45, 0.8, 0.45) },
        ];
        let mut buffers: Vec<_> = (1..3).map(|m| deforming_buffers(ctx, &rest.meshes[m], bounds[m - 1])).collect();
        // A rest pose that is not the buffers' mesh is refused, naming the field.
        let err = shadows.add_deforming_mesh(buffers[0].2, &rest.meshes[2]).unwrap_err().to_string();
        println!("{err}");
        assert!(err.starts_with("rest.positions: 24 vertices, but buffers.vertex_count is"), "{err}");
        let mut meshes = vec![floor];
        for (m, (_, _, b)) in (1..3).zip(&buffers) {
            meshes.push(shadows.add_deforming_mesh(*b, &rest.meshes[m]).unwrap());
        }
        for o in &rest.objects {
            shadows.add_instance(Instance::of_object(o, meshes[o.mesh])).unwrap();
        }
        for (frame, time) in [0.0f32, 0.9, 2.1, 3.7].into_iter().enumerate() {
            let pose = deforming_pose(&rest, time);
            for (m, (v, _, _)) in (1..3).zip(&mut buffers) {
                write_pose(v, &pose.meshes[m]);
            }
            let engine = Engine::new(ctx, &pose);
            let (recorded, texels) = engine_frame(ctx, &engine, &mut shadows, &pose, frame as u64);
            let own = renderer_bits_with(ctx, &pose, cpu);
            let differ = differing(&texels, &own);
            let (compared, wrong) = against_reference(&pose, &texels[0].1);
            // The slot's previous frame's passes (one frame in flight: the pose before).
            let earlier = recorded.earlier_passes.as_deref().unwrap_or_default();
            let positions = earlier.iter().filter(|p| p.name == "volume positions").count();
            println!(
                "pose {frame} (t = {time}): {differ} texels differ from the CPU path's; {wrong} of {compared} pixels \
                 disagree with the exact reference; the frame before: {positions} volume positions pass; {} bytes uploaded",
                recorded.geometry_uploaded_bytes
            );
            assert_eq!(differ, 0, "pose {frame}: the GPU-built volumes of the engine's pose against the CPU path's");
            assert!(compared > 5000, "pose {frame}: the reference decides most pixels ({compared})");
            assert_eq!(wrong, 0, "pose {frame}: against the exact reference");
            assert_eq!(positions, usize::from(frame > 0), "pose {frame}: one copy of the deformed positions a frame");
        }
        // Lights that would read the CPU's copy are refused, naming the light and the mesh.
        let mut refused = deforming_pose(&rest, 0.0);
        refused.lights[0].technique = Technique::Hybrid;
        let err = refused_record(ctx, &Engine::new(ctx, &refused), &mut shadows, &refused);
        assert!(err.starts_with("FrameInputs::lights[0].technique: Hybrid cannot shadow with"), "{err}");
        drop(shadows);
        drop(buffers);
    });
}

#[test]
fn the_example_engine_deforms_a_mesh_on_the_gpu_under_volume_shadows() {
    let out = common::output_dir("embed-example-deform");
    let run = run_example(&out, &["--deform"]);
    print!("{run}");
    assert!(run.contains("deforming suzanne on the GPU"), "{run}");
    let frames: Vec<&str> = run.lines().filter(|l| l.starts_with("frame ")).collect();
    assert_eq!(frames.len(), 3, "{run}");
    assert!(frames.iter().all(|l| l.contains("2/2 lights shadowed [ShadowVolume, ShadowVolume]")), "{run}");
    assert!(frames[2].contains("uploaded 0 B, 0 allocations"), "warm frame: {}", frames[2]);
    let unowned = run.lines().find(|l| l.trim_start().starts_with("no light:")).unwrap_or_default();
    assert!(unowned.contains("volume positions"), "the pose copied once a frame: {unowned}");
    assert!(run.contains("validation messages: 0"), "{run}");
}
