//! The renderer: records a frame's passes into a headless target and reads the colour back.
//!
//! [`Renderer::render`] checks the input, records the frame through [`Renderer::frame`]
//! (`record.rs`), the same frame [`crate::Shadows::record`] records into an engine's command
//! buffer — plan (`crate::plan`), prepare each light's technique on the CPU (`prepare.rs`),
//! upload what changed and bind each light's maps (`bind.rs`), declare the passes into the
//! frame graph (`declare.rs`, `crate::frame`) — runs it, then reads back and reports
//! (`results.rs`). Every pass is a debug label with timestamps around it, emitted by the frame
//! graph; the [`FrameReport`] lists them by name and the graph keys them by
//! [`crate::frame::PassId`].

mod bind;
mod declare;
mod desc;
mod diagnostics;
mod engine;
mod lights;
mod prepare;
mod ray_stats;
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
use crate::hybrid::pass::HybridPass;
use crate::hybrid::rays::HybridRays;
use crate::hybrid::MaskKind;
use crate::mesh_cache::MeshCache;
use crate::ray_traced::pass::RayPass;
use crate::ray_traced::stats::RayStats;
use crate::shadow_map::pass::{self, ShadowMapPass};
use crate::shadow_volume::pass::{ShadowVolumePass, VolumeInput};
use crate::shadow_volume::FarPlane;
use crate::silhouette_map::pass::SilhouetteMapPass;
use crate::targets::{depth_desc, COLOR_FORMAT};
use crate::visibility::{self, VisibilityPass};
use crate::{RenderError, RenderResult};
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
    shadow_map: ShadowMapPass,
    shadow_volume: ShadowVolumePass,
    silhouette_map: SilhouetteMapPass,
    hybrid: HybridPass,
    /// Ray-traced lights' BVH and shadow rays.
    rays: RayPass,
    /// The ray-traced hybrid's pipelines and ray list (`None` where the device cannot run it:
    /// [`crate::visibility::storage_supported`]).
    hybrid_rays: Option<HybridRays>,
    /// The shadow rays' counted twins and counters (with `diagnostics`, in umbra's own frames).
    ray_stats: Option<RayStats>,
    /// The scene's meshes as last validated and measured, by revision (checked every frame,
    /// read again only when one changed).
    pub(crate) checked: CheckedMeshes,
    /// Each light's receiver grid samples, kept while their inputs do not change.
    grid_samples: crate::shadow_map::samples::GridSamples,
    /// Every map light's fitted views, kept while their inputs are the same bits.
    fits: crate::shadow_map::fits::Fits,
    /// The visibility image every shadowed light's technique writes and its lighting reads.
    visibility: VisibilityPass,
    /// How volume vertices reach the GPU: as built, or clipped to the view on the host.
    volume_input: VolumeInput,
    /// Shadow volumes built on the GPU (`shadow_volume.build`: `VolumeBuild::Gpu`).
    gpu_volumes: Option<crate::shadow_volume::gpu_frame::GpuVolumes>,
    /// The computation mask of hybrid lights (`desc.hybrid.mask`, or the device's best).
    mask: MaskKind,
    /// Classification and silhouette-point targets (with `diagnostics`).
    diagnostic_targets: Option<DiagnosticTargets>,
    /// Welded connectivity per mesh, kept while the mesh keeps its revision.
    meshes: MeshCache,
    /// The scene's meshes on the GPU, reused while every mesh keeps its revision.
    geometry: Option<Arc<SceneGeometry>>,
    /// Per mesh, the engine's buffers it is copied from instead of its CPU data (engine only:
    /// `Shadows::add_mesh_buffers`).
    pub(crate) engine_meshes: Vec<Option<crate::mesh_buffers::MeshBuffers>>,
    /// The engine's meshes that deform on the GPU (`Shadows::add_deforming_mesh`).
    pub(crate) deforming: crate::shadow_volume::deform::Deforming,
    /// The frame's host-written buffers, sets and query pools, kept between frames.
    slot: FrameSlot,
    /// Per light, its diagnostic readbacks (with `diagnostics`), kept while they fit.
    readbacks: Vec<lights::LightReadbacks>,
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
        let mask = desc.hybrid.mask.unwrap_or(MaskKind::best_for(caps.depth_bounds));
        if mask == MaskKind::DepthBounds && !caps.depth_bounds {
            return Err(ctx.unsupported("the hybrid's depth-bounds computation mask (depthBounds)").into());
        }
        check_frame_size(ctx, &desc, depth_format, mask)?;
        let own = own.then(|| OwnTargets::new(ctx, depth_format, &desc)).transpose()?;
        let scene_set_layout = gpu_scene::scene_set_layout(ctx)?;
        let shadow_set_layout = pass::shadow_set_layout(ctx)?;
        let visibility_set_layout = visibility::set_layout(ctx)?;
        let push = std::mem::size_of::<gpu_scene::DrawPush>() as u32;
        let sets = [&scene_set_layout, &shadow_set_layout, &visibility_set_layout];
        let layout = PipelineLayout::new(ctx, "scene layout", &sets, push)?;
        // Bounded lights' depth bounds need the test in their pipelines.
        let bounds = desc.cull && caps.depth_bounds;
        let lookup = desc.shadow_map.lookup_spec();
        let forward = Forward::new(ctx, &layout, COLOR_FORMAT, depth_format, lookup, desc.diagnostics, bounds)?;
        let shadow_map = ShadowMapPass::new(ctx, &layout, desc.shadow_map)?;
        if desc.shadow_volume.far_plane == FarPlane::DepthClamp && !caps.depth_clamp {
            return Err(ctx.unsupported("shadow volumes with FarPlane::DepthClamp (depthClamp)").into());
        }
        let volume_input = match desc.shadow_volume.host_clip.applies(caps.watertight_clipping) {
            true => VolumeInput::HostClipped,
            false => VolumeInput::Built,
        };
        let shadow_volume =
            ShadowVolumePass::new(ctx, &layout, depth_format, &desc.shadow_volume, bounds, volume_input)?;
        let gpu_volumes =
            gpu_volumes(ctx, &desc, &scene_set_layout, depth_format, volume_input, bounds, own.is_some())?;
        let silhouette_map = SilhouetteMapPass::new(ctx, &layout, COLOR_FORMAT, depth_format, &desc.shadow_map)?;
        let clamp = desc.shadow_volume.far_plane == FarPlane::DepthClamp;
        let hybrid =
            HybridPass::new(ctx, &layout, depth_format, &scene_set_layout, &desc.shadow_map, clamp, volume_input)?;
        let hybrid = match &gpu_volumes {
            Some(g) => hybrid.with_gpu_volumes(ctx, g, clamp, desc.shadow_volume.overdraw)?,
            None => hybrid,
        };
        let rays = RayPass::new(ctx, &scene_set_layout, depth_format, bounds, desc.bvh)?;
        let hybrid_rays = match crate::hybrid::rays::supported(caps) {
            true => Some(HybridRays::new(
                ctx,
                &scene_set_layout,
                &shadow_set_layout,
                rays.set_layout(),
                depth_format,
                &desc.shadow_map,
                desc.bvh,
            )?),
            false => None,
        };
        let ray_stats = match (desc.diagnostics, &own) {
            (true, Some(_)) => {
                let listed = hybrid_rays.as_ref().map(|h| {
                    let [list, output] = h.set_layouts();
                    [rays.set_layout(), list, output]
                });
                let bvh = (rays.set_layout(), desc.bvh);
                Some(RayStats::new(ctx, &scene_set_layout, bvh, listed, depth_format, bounds)?)
            }
            _ => None,
        };
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
            shadow_map,
            shadow_volume,
            silhouette_map,
            hybrid,
            rays,
            hybrid_rays,
            ray_stats,
            checked: CheckedMeshes::default(),
            grid_samples: Default::default(),
            fits: Default::default(),
            visibility,
            volume_input,
            gpu_volumes,
            mask,
            diagnostic_targets,
            meshes: MeshCache::default(),
            geometry: None,
            engine_meshes: Vec::new(),
            deforming: Default::default(),
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
        self.mask
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

/// The GPU path of shadow volumes, when `desc` asks for it: refused (naming the setting) where
/// the device needs volumes clipped on the host, or on a graphics queue that runs no compute.
/// With `own` (the renderer's own frames) the counts are read back for the report.
fn gpu_volumes(
    ctx: &Context,
    desc: &RendererDesc,
    scene_set_layout: &DescriptorSetLayout,
    depth_format: vk::Format,
    input: VolumeInput,
    bounds: bool,
    own: bool,
) -> RenderResult<Option<crate::shadow_volume::gpu_frame::GpuVolumes>> {
    let settings = &desc.shadow_volume;
    if settings.build != crate::VolumeBuild::Gpu {
        return Ok(None);
    }
    let refuse = |why: &str| {
        Err(RenderError::InvalidInput { field: "shadow_volume.build".into(), why: format!("VolumeBuild::Gpu {why}") })
    };
    if input == VolumeInput::HostClipped {
        return refuse(
            "cannot clip volumes on the host, which this device needs (set host_clip to Never to draw them unclipped)",
        );
    }
    if !ctx.capabilities().compute_queue {
        return refuse(&format!("needs compute on the graphics queue, which {} lacks", ctx.capabilities().device_name));
    }
    let clamp = settings.far_plane == FarPlane::DepthClamp;
    let overdraw = settings.overdraw;
    let volumes = crate::shadow_volume::gpu_frame::GpuVolumes::new(
        ctx,
        scene_set_layout,
        depth_format,
        clamp,
        bounds,
        own,
        overdraw,
    )?;
    Ok(Some(volumes))
}
