//! The renderer: records a frame's passes into a headless target and reads the colour back.
//!
//! [`Renderer::render`] checks the input, records the frame through [`Renderer::frame`]
//! (`record.rs`), the same frame [`crate::Shadows::record`] records into an engine's command
//! buffer — plan (`crate::plan`), prepare each light's technique on the CPU (through the
//! technique set, `crate::techniques`, the one seam to the techniques), upload what changed
//! (`prepare.rs`), bind each light's maps (the technique set), declare the passes into the
//! frame graph (`declare.rs`, `crate::frame`) — runs it, then reads back and reports
//! (`results.rs`). Every pass is a debug label with timestamps around it, emitted by the frame
//! graph; the [`FrameReport`] lists them by name and the graph keys them by
//! [`crate::frame::PassId`].

mod declare;
mod desc;
mod diagnostics;
mod engine;
mod prepare;
mod record;
mod results;
mod slot;

pub use desc::{Frame, RendererDesc};
pub(crate) use engine::{EngineDepth, FrameDepth, RecordedLight};
pub(crate) use slot::FrameSlot;

use crate::depth_rebuild::DepthRebuild;
use crate::diagnostics::DiagnosticTargets;
use crate::forward::Forward;
use crate::gbuffer::GBufferPass;
use crate::gpu_scene::{self, SceneCounts, SceneGeometry};
use crate::hybrid::MaskKind;
use crate::mesh_cache::MeshCache;
use crate::targets::{depth_desc, COLOR_FORMAT};
use crate::techniques::{self, LightReadbacks, Setup, Techniques};
use crate::visibility::{self, VisibilityPass};
use crate::RenderResult;
use desc::{check_frame_size, frame_target};
use record::Output;
use std::sync::Arc;
use std::time::Instant;
use umbra_scene::{CheckedMeshes, Scene};
use umbra_vk::{vk, Buffer, BufferDesc, Context, DescriptorSetLayout, Image, PipelineLayout};

/// Renders scenes into a headless target of a fixed size.
pub struct Renderer {
    ctx: Context,
    desc: RendererDesc,
    /// Its own colour and depth targets and colour readback; `None` recording into an
    /// engine's frame ([`crate::Shadows`]), over the engine's depth.
    own: Option<OwnTargets>,
    scene_set_layout: DescriptorSetLayout,
    shadow_set_layout: DescriptorSetLayout,
    layout: PipelineLayout,
    forward: Forward,
    /// Every technique's pipelines and caches: the one seam to them.
    pub(crate) techniques: Techniques,
    /// The scene's meshes as last validated and measured, by revision (checked every frame,
    /// read again only when one changed).
    pub(crate) checked: CheckedMeshes,
    /// The visibility image every shadowed light's technique writes and its lighting reads.
    visibility: VisibilityPass,
    /// Classification and silhouette-point targets (with `diagnostics`).
    diagnostic_targets: Option<DiagnosticTargets>,
    /// Welded connectivity per mesh, kept while the mesh keeps its revision.
    meshes: MeshCache,
    /// The scene's meshes on the GPU, reused while every mesh keeps its revision.
    geometry: Option<Arc<SceneGeometry>>,
    /// Per mesh, the engine's buffers it is copied from instead of its CPU data (engine only:
    /// `Shadows::add_mesh_buffers`).
    pub(crate) engine_meshes: Vec<Option<crate::mesh_buffers::MeshBuffers>>,
    /// The frame's host-written buffers, sets and query pools, kept between frames.
    slot: FrameSlot,
    /// Per light, its diagnostic readbacks (with `diagnostics`), kept while they fit.
    readbacks: Vec<LightReadbacks>,
    /// Volume overdraw target and its readback (with `shadow_volume.overdraw`).
    overdraw: Option<(Image, Buffer)>,
    /// The G-buffer pass (with `gbuffer`).
    gbuffer: Option<GBufferPass>,
    /// umbra's own depth for engine frames whose depth its passes cannot use (engine only).
    depth_rebuild: Option<crate::depth_rebuild::DepthRebuild>,
}

impl Renderer {
    /// Creates the targets and pipelines, after checking `desc`: the shadow-map settings
    /// ([`crate::ShadowMapSettings::validate`]) and the target size against every device limit of the
    /// frame-sized images ([`crate::RenderError::InvalidSize`] naming the limit).
    pub fn new(ctx: &Context, desc: RendererDesc) -> RenderResult<Self> {
        let depth_format = ctx.capabilities().depth_stencil_format;
        if depth_format == vk::Format::UNDEFINED {
            return Err(ctx.unsupported("any depth/stencil attachment format").into());
        }
        Self::build(ctx, desc, depth_format, true)
    }

    /// The pipelines for an engine's depth of `depth_format` (checked by the caller), without
    /// targets of its own: frames are recorded into the engine's command buffer
    /// ([`Renderer::record_into`]).
    pub(crate) fn for_engine(ctx: &Context, desc: RendererDesc, depth_format: vk::Format) -> RenderResult<Self> {
        Self::build(ctx, desc, depth_format, false)
    }

    fn build(ctx: &Context, desc: RendererDesc, depth_format: vk::Format, own: bool) -> RenderResult<Self> {
        let caps = ctx.capabilities();
        desc.shadow_map.validate()?;
        let mask = techniques::mask_for(ctx, &desc.hybrid)?;
        check_frame_size(ctx, &desc, depth_format, mask)?;
        let own = own.then(|| OwnTargets::new(ctx, depth_format, &desc)).transpose()?;
        let scene_set_layout = gpu_scene::scene_set_layout(ctx)?;
        let shadow_set_layout = techniques::shadow_set_layout(ctx)?;
        let visibility_set_layout = visibility::set_layout(ctx)?;
        let push = std::mem::size_of::<gpu_scene::DrawPush>() as u32;
        let sets = [&scene_set_layout, &shadow_set_layout, &visibility_set_layout];
        let layout = PipelineLayout::new(ctx, "scene layout", &sets, push)?;
        // Bounded lights' depth bounds need the test in their pipelines.
        let bounds = desc.cull && caps.depth_bounds;
        let lookup = desc.shadow_map.lookup_spec();
        let forward = Forward::new(ctx, &layout, COLOR_FORMAT, depth_format, lookup, desc.diagnostics, bounds)?;
        let setup = Setup {
            width: desc.width,
            height: desc.height,
            shadow_map: desc.shadow_map,
            shadow_volume: desc.shadow_volume,
            hybrid: desc.hybrid,
            bvh: desc.bvh,
            cull: desc.cull,
            diagnostics: desc.diagnostics,
            read_visibility: desc.read_visibility,
            budget_bytes: desc.shadow_map_budget_bytes,
            own: own.is_some(),
            depth_format,
        };
        let layouts = [&scene_set_layout, &shadow_set_layout];
        let techniques = Techniques::new(ctx, setup, layouts, &layout, mask, bounds)?;
        let (width, height) = (desc.width, desc.height);
        let visibility =
            VisibilityPass::new(ctx, &layout, visibility_set_layout, depth_format, lookup, width, height, bounds)?;
        let diagnostic_targets = if desc.diagnostics {
            Some(DiagnosticTargets {
                classification: frame_target(ctx, "diagnostics: classification", desc.width, desc.height)?,
                points: frame_target(ctx, "diagnostics: silhouette points", desc.width, desc.height)?,
            })
        } else {
            None
        };
        let overdraw = if desc.shadow_volume.overdraw {
            let image = frame_target(ctx, "volume overdraw", desc.width, desc.height)?;
            let readback = Buffer::new(
                ctx,
                "overdraw readback",
                BufferDesc::readback(4 * desc.width as u64 * desc.height as u64),
            )?;
            Some((image, readback))
        } else {
            None
        };
        let gbuffer = match desc.gbuffer {
            true => Some(GBufferPass::new(ctx, &layout, depth_format, desc.width, desc.height)?),
            false => None,
        };
        let slot = FrameSlot::new(ctx, "shadow sets", &shadow_set_layout)?;
        let depth_rebuild = match &own {
            Some(_) => None,
            None => Some(DepthRebuild::new(ctx, &layout, depth_format, desc.width, desc.height)?),
        };
        Ok(Self {
            ctx: ctx.clone(),
            desc,
            own,
            scene_set_layout,
            shadow_set_layout,
            layout,
            forward,
            techniques,
            checked: CheckedMeshes::default(),
            visibility,
            diagnostic_targets,
            meshes: MeshCache::default(),
            geometry: None,
            engine_meshes: Vec::new(),
            slot,
            readbacks: Vec::new(),
            overdraw,
            gbuffer,
            depth_rebuild,
        })
    }

    /// Command buffers this renderer has submitted to the GPU so far (a frame whose scene is
    /// rejected by validation submits none).
    pub fn submissions(&self) -> u64 {
        self.slot.graph.submissions()
    }

    /// The target size and settings it was created with.
    pub fn desc(&self) -> RendererDesc {
        self.desc
    }

    /// How `auto` lights choose their technique: `RendererDesc::auto`, or the device's default
    /// ([`crate::AutoPolicy::for_device`]).
    pub fn auto_policy(&self) -> crate::AutoPolicy {
        self.desc.auto.unwrap_or_else(|| crate::AutoPolicy::for_device(self.ctx.capabilities()))
    }

    /// The computation mask hybrid lights use on this device.
    pub fn mask(&self) -> MaskKind {
        self.techniques.mask()
    }

    /// Renders one frame of `scene` and reads it back.
    pub fn render(&mut self, scene: &Scene) -> RenderResult<Frame> {
        let started = Instant::now();
        let allocations_before = self.ctx.memory_allocations();
        // 1. A typed error, before any GPU work, for non-finite or out-of-range input, and for
        //    more objects or lights than the device's buffers can bind.
        scene.validate_with(&mut self.checked)?;
        gpu_scene::check_limits(self.ctx.capabilities(), SceneCounts::of(scene, 0))?;
        // 2. Its own targets, the readback poisoned so that a copy that never happened cannot
        //    pass for a frame.
        if let Some(readback) = self.own_mut()?.readback.as_mut() {
            readback.fill_host(0xCD)?;
        }
        // 3. The frame (`record.rs`): planned, prepared, uploaded, bound, declared and run in
        //    one submission (two with blocker culling).
        let view = self.frame_view(scene);
        let r = self.frame(scene, view, Output::Own)?;
        // 4. Read back and report.
        let stages = &r.run.stages;
        let (submit_wait_ms, submissions) = (stages.iter().map(|s| s.submit_wait_ms).sum(), stages.len());
        let mut frame = self.finish(scene, &r.adjacency, r.lights, &r.sets, r.run)?;
        frame.report.cpu_prepare_ms = (r.prepared - started).as_secs_f64() * 1e3;
        frame.report.cpu_submit_wait_ms = submit_wait_ms;
        frame.report.cpu_record_ms = (r.run_ms - submit_wait_ms).max(0.0);
        frame.report.submissions = submissions as u64;
        frame.report.cpu_frame_ms = started.elapsed().as_secs_f64() * 1e3;
        frame.report.geometry_uploaded_bytes = r.geometry_uploaded;
        frame.report.memory_allocations = self.ctx.memory_allocations() - allocations_before;
        Ok(frame)
    }
}

/// The renderer's own targets: what an engine brings itself.
struct OwnTargets {
    color: Image,
    depth: Image,
    /// With `RendererDesc::read_color`.
    readback: Option<Buffer>,
}

impl OwnTargets {
    fn new(ctx: &Context, depth_format: vk::Format, desc: &RendererDesc) -> RenderResult<Self> {
        let (width, height) = (desc.width, desc.height);
        let readback = desc
            .read_color
            .then(|| Buffer::new(ctx, "colour readback", BufferDesc::readback(4 * width as u64 * height as u64)));
        Ok(Self {
            color: frame_target(ctx, "colour target", width, height)?,
            depth: Image::new(ctx, "depth/stencil target", depth_desc(depth_format, width, height))?,
            readback: readback.transpose()?,
        })
    }
}

impl Renderer {
    /// The colour target of the last frame [`Renderer::render`] drew, in
    /// `TRANSFER_SRC_OPTIMAL` with its writes visible to every transfer stage of later
    /// submissions (to present it without reading it back:
    /// `umbra_vk::Swapchain::present_image`). The next `render` writes it again after waiting
    /// for every earlier command on the queue.
    pub fn color_image(&self) -> RenderResult<&Image> {
        Ok(&self.own()?.color)
    }

    /// Its own targets; an error recording into an engine's frame, which has none.
    fn own(&self) -> RenderResult<&OwnTargets> {
        self.own.as_ref().ok_or_else(no_targets)
    }

    fn own_mut(&mut self) -> RenderResult<&mut OwnTargets> {
        self.own.as_mut().ok_or_else(no_targets)
    }
}

fn no_targets() -> crate::RenderError {
    crate::RenderError::InvalidInput {
        field: "Renderer::render".into(),
        why: "this renderer records into an engine's frame (Shadows::record) and has no targets of its own".into(),
    }
}
