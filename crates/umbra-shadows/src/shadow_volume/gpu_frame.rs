//! The renderer's shadow volumes built on the GPU ([`crate::VolumeBuild::Gpu`]): once a frame
//! `volume draws reset` sets every job's indirect draw (zero vertices, its list's first vertex)
//! and counts from the frame slot's initial values; then per light:
//! 1. `volume classify N` (`classify.comp`), every caster's triangles' facing;
//! 2. `volume silhouettes N` (`silhouettes.comp`), every caster's silhouette list and draw;
//! 3. `shadow_volume N`, the counting draws, all indirect: per caster its sides from its list
//!    (`gpu_sides.vert`) and in z-fail its caps from its mesh's triangles and their facing
//!    (`gpu_caps.vert`), with the counting pipelines and batches of the CPU path. A caster
//!    whose mode the GPU decides is drawn in both modes' pipelines, the draws of the mode not
//!    decided left without vertices.
//!
//! In the renderer's own frames `volume counts readback` copies the draws out after every
//! light's shadows: the report's silhouette edges and volume triangles
//! ([`super::gpu::JobCounts`]).
//!
//! The adjacency arrays are uploaded when the scene's meshes change; the facing, lists and
//! draws live on the GPU only, sized for the largest frame so far; the jobs and the draws'
//! initial values are the frame slot's, written by the host each frame (`Streams`).

use super::batches::{record_in_batches, CountBits, FULL_STENCIL};
use super::build::{CasterVolume, Counting, LightVolumes};
use super::deform::{DeformCopies, DeformPipeline};
use super::gpu::{AdjacencyArrays, GpuSilhouettes, JobDraw, MeshRange, DRAW_STRIDE};
use super::pass::{overdraw_pipeline, Counting4, VolumeInput};
use crate::frame::timing::PassLog;
use crate::gpu_scene::GpuScene;
use crate::light_surfaces::PassBounds;
use crate::mesh_buffers::VertexStream;
use crate::retired::Retired;
use crate::RenderResult;
use std::sync::Arc;
use umbra_scene::Adjacency;
use umbra_vk::{
    vk, Buffer, BufferDesc, Context, DescriptorSet, DescriptorSetLayout, GraphicsPipeline, PipelineLayout, Recorder,
    Resource,
};

/// The push constants of the volume draws: `Push` of `common/scene.glsl` with its `job`.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct JobPush {
    object: u32,
    view: u32,
    job: u32,
}

/// The meshes' adjacency on the GPU, for the meshes (and deforming meshes' position streams)
/// it was made from.
struct Arrays {
    meshes: Vec<Arc<Adjacency>>,
    streams: Vec<Option<VertexStream>>,
    ranges: Vec<MeshRange>,
    /// The deforming meshes' copies into `buffers[0]`, the positions.
    deform: Option<DeformCopies>,
    buffers: [Buffer; 4],
}

/// What the stages write, sized in entries (facing, list) and jobs.
struct Written {
    sizes: (u64, u64, u64),
    facing: Buffer,
    list: Buffer,
    draws: Buffer,
    /// The draws copied out for the report (the renderer's own frames).
    readback: Option<Buffer>,
}

/// A frame slot's set over the arrays, its jobs and what the stages write.
pub(crate) struct SlotVolumes {
    key: (u64, u64),
    set: DescriptorSet,
}

/// The pipelines and buffers of the GPU path.
pub(crate) struct GpuVolumes {
    pub stages: GpuSilhouettes,
    layout: PipelineLayout,
    sides: Counting4,
    caps: Counting4,
    /// `volume positions`, the deforming meshes' copy.
    deform: DeformPipeline,
    /// With `shadow_volume.overdraw`: the overdraw image's pipelines, for sides and caps.
    overdraw: Option<[GraphicsPipeline; 2]>,
    arrays: Option<Arrays>,
    written: Option<Written>,
    /// Counts new arrays or written buffers (a slot's set over older ones is made again).
    generation: u64,
    /// Whether the draws are read back for the report (the renderer's own frames).
    read_counts: bool,
}

impl GpuVolumes {
    /// The stages and the counting pipelines (against the scene's set and the stages' set);
    /// with `read_counts`, a readback of the draws for the report; with `overdraw`, the
    /// overdraw diagnostic's pipelines.
    pub fn new(
        ctx: &Context,
        scene_set_layout: &DescriptorSetLayout,
        depth_format: vk::Format,
        clamp: bool,
        depth_bounds: bool,
        read_counts: bool,
        overdraw: bool,
    ) -> RenderResult<Self> {
        let stages = GpuSilhouettes::new(ctx)?;
        let push = std::mem::size_of::<JobPush>() as u32;
        let layout =
            PipelineLayout::new(ctx, "gpu shadow volume draws", &[scene_set_layout, stages.set_layout()], push)?;
        let sides = Counting4::new(ctx, &layout, depth_format, clamp, depth_bounds, VolumeInput::GpuSides)?;
        let caps = Counting4::new(ctx, &layout, depth_format, clamp, depth_bounds, VolumeInput::GpuCaps)?;
        let deform = DeformPipeline::new(ctx)?;
        let overdraw = match overdraw {
            true => {
                let image = |name, input| overdraw_pipeline(ctx, &layout, name, clamp, input);
                Some([
                    image("gpu shadow volume sides overdraw", VolumeInput::GpuSides)?,
                    image("gpu shadow volume caps overdraw", VolumeInput::GpuCaps)?,
                ])
            }
            false => None,
        };
        let (arrays, written, generation) = (None, None, 0);
        Ok(Self { stages, layout, sides, caps, deform, overdraw, arrays, written, generation, read_counts })
    }

    /// The layout of every GPU-built volume draw (the scene's set, the stages' set, the job's
    /// push constants): pipelines drawn by [`Self::record_counting`] and
    /// [`Self::record_every_draw`] are built against it.
    pub fn layout(&self) -> &PipelineLayout {
        &self.layout
    }

    /// Every mesh's place in the arrays (after [`Self::prepare`]).
    pub fn ranges(&self) -> &[MeshRange] {
        self.arrays.as_ref().map_or(&[], |a| &a.ranges)
    }

    /// Uploads the meshes' adjacency when it is not `adjacency` already; `streams` (by mesh
    /// index) names the engine's position stream of each mesh that deforms on the GPU.
    pub fn prepare_arrays(
        &mut self,
        ctx: &Context,
        adjacency: &[Arc<Adjacency>],
        streams: &[Option<VertexStream>],
        retired: &mut Retired,
    ) -> RenderResult<()> {
        let same = self.arrays.as_ref().is_some_and(|a| {
            a.meshes.len() == adjacency.len()
                && a.meshes.iter().zip(adjacency).all(|(x, y)| Arc::ptr_eq(x, y))
                && a.streams == streams
        });
        if same {
            return Ok(());
        }
        retired.take(&mut self.arrays);
        let flat = AdjacencyArrays::build(adjacency);
        let buffer = |name: &str, bytes: &[u8]| -> RenderResult<Buffer> {
            let bytes = if bytes.is_empty() { &[0u8; 16][..] } else { bytes };
            // Host-visible, as the ray-traced BVH's arrays: no submission of umbra's own (an
            // engine's frame has none).
            let desc = BufferDesc::cpu_to_gpu(bytes.len() as u64, vk::BufferUsageFlags::STORAGE_BUFFER);
            let mut b = Buffer::new(ctx, name, desc)?;
            b.write(0, bytes)?;
            Ok(b)
        };
        let buffers = [
            buffer("gpu shadow volume positions", bytemuck::cast_slice(&flat.positions))?,
            buffer("gpu shadow volume triangles", bytemuck::cast_slice(&flat.triangles))?,
            buffer("gpu shadow volume edges", bytemuck::cast_slice(&flat.edges))?,
            buffer("gpu shadow volume edge faces", bytemuck::cast_slice(&flat.edge_faces))?,
        ];
        let deform = self.deform.copies(ctx, &buffers[0], adjacency, streams)?;
        self.generation += 1;
        let streams = streams.to_vec();
        self.arrays = Some(Arrays { meshes: adjacency.to_vec(), streams, ranges: flat.meshes, deform, buffers });
        Ok(())
    }

    /// The positions array when a mesh deforms on the GPU: `volume positions` writes it each
    /// frame, before the stages and draws read it.
    pub fn deformed_positions(&self) -> Option<&Buffer> {
        self.arrays.as_ref().filter(|a| a.deform.is_some()).map(|a| &a.buffers[0])
    }

    /// `volume positions`: every deforming mesh's welded positions copied from the engine's
    /// stream (the positions in `ComputeStorage`).
    pub fn record_deform<'a>(&'a self, rec: &mut Recorder<'a>) {
        if let Some(copies) = self.arrays.as_ref().and_then(|a| a.deform.as_ref()) {
            self.deform.record(rec, copies);
        }
    }

    /// Makes sure the written buffers hold `facing` and `list` entries and `jobs` draws.
    pub fn prepare_written(
        &mut self,
        ctx: &Context,
        facing: u64,
        list: u64,
        jobs: u64,
        retired: &mut Retired,
    ) -> RenderResult<()> {
        let fits = self.written.as_ref().is_some_and(|w| w.sizes.0 >= facing && w.sizes.1 >= list && w.sizes.2 >= jobs);
        if fits {
            return Ok(());
        }
        let old = self.written.as_ref().map_or((0, 0, 0), |w| w.sizes);
        retired.take(&mut self.written);
        let sizes = (facing.max(old.0).max(4), list.max(old.1).max(4), jobs.max(old.2).max(1));
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let make = |name: &str, bytes: u64, usage| Buffer::new(ctx, name, BufferDesc::gpu_only(bytes, storage | usage));
        let draws_usage = vk::BufferUsageFlags::INDIRECT_BUFFER
            | vk::BufferUsageFlags::TRANSFER_DST
            | vk::BufferUsageFlags::TRANSFER_SRC;
        let draws_bytes = DRAW_STRIDE * sizes.2;
        let readback = match self.read_counts {
            true => Some(Buffer::new(ctx, "gpu shadow volume counts readback", BufferDesc::readback(draws_bytes))?),
            false => None,
        };
        self.written = Some(Written {
            sizes,
            facing: make("gpu shadow volume facing", 4 * sizes.0, vk::BufferUsageFlags::empty())?,
            list: make("gpu shadow volume silhouettes", 4 * sizes.1, vk::BufferUsageFlags::empty())?,
            draws: make("gpu shadow volume draws", draws_bytes, draws_usage)?,
            readback,
        });
        self.generation += 1;
        Ok(())
    }

    /// The facing, list and draws buffers (after [`Self::prepare_written`]).
    pub fn written(&self) -> Option<(&Buffer, &Buffer, &Buffer)> {
        self.written.as_ref().map(|w| (&w.facing, &w.list, &w.draws))
    }

    /// Makes sure `slot` holds a set over the arrays, the slot's `jobs` (of generation
    /// `jobs_generation`) and the written buffers.
    pub fn prepare_slot(
        &self,
        ctx: &Context,
        slot: &mut Option<SlotVolumes>,
        jobs: &Buffer,
        jobs_generation: u64,
        retired: &mut Retired,
    ) -> RenderResult<()> {
        let key = (self.generation, jobs_generation);
        if slot.as_ref().is_some_and(|s| s.key == key) {
            return Ok(());
        }
        retired.take(slot);
        let (Some(a), Some(w)) = (&self.arrays, &self.written) else { return Ok(()) };
        let [p, t, e, f] = &a.buffers;
        let resources = [p, t, e, f, jobs, &w.facing, &w.list, &w.draws].map(Resource::Buffer);
        let set = DescriptorSet::new(ctx, "gpu shadow volume", self.stages.set_layout(), &resources)?;
        *slot = Some(SlotVolumes { key, set });
        Ok(())
    }

    /// `volume draws reset`: every job's draw and counts set from the slot's `init` (the draws
    /// in TransferDst).
    pub fn record_reset<'a>(&'a self, rec: &mut Recorder<'a>, init: &'a Buffer) {
        if let Some(w) = &self.written {
            rec.copy_buffer(init, &w.draws, init.desc.size.min(w.draws.desc.size));
        }
    }

    /// The draws' readback (with `read_counts`, after [`Self::prepare_written`]).
    pub fn counts_readback(&self) -> Option<&Buffer> {
        self.written.as_ref().and_then(|w| w.readback.as_ref())
    }

    /// `volume counts readback`: the frame's `jobs` draws and counts copied out (the draws in
    /// TransferSrc).
    pub fn record_counts_readback<'a>(&'a self, rec: &mut Recorder<'a>, jobs: usize) {
        if let Some((w, out)) = self.written.as_ref().and_then(|w| Some((w, w.readback.as_ref()?))) {
            rec.copy_buffer(&w.draws, out, (DRAW_STRIDE * jobs as u64).min(out.desc.size));
        }
    }

    /// The draws and counts read back (after a frame that ran `volume counts readback`).
    pub fn read_counts(&self) -> RenderResult<Vec<u32>> {
        match self.counts_readback() {
            Some(out) => Ok(bytemuck::pod_collect_to_vec(&out.read()?)),
            None => Ok(Vec::new()),
        }
    }

    /// Stage 1 for a light's jobs.
    pub fn record_classify<'a>(&'a self, rec: &mut Recorder<'a>, slot: &'a SlotVolumes, volumes: &LightVolumes) {
        if let Some((first, jobs)) = &volumes.gpu {
            self.stages.record_classify(rec, &slot.set, *first, jobs);
        }
    }

    /// Stage 2 for a light's jobs (after their facing).
    pub fn record_silhouettes<'a>(&'a self, rec: &mut Recorder<'a>, slot: &'a SlotVolumes, volumes: &LightVolumes) {
        if let Some((first, jobs)) = &volumes.gpu {
            self.stages.record_silhouettes(rec, &slot.set, *first, jobs);
        }
    }

    /// Light `light`'s counting draws (inside the stencil pass, its lists and draws written):
    /// per batch of its casters, z-fail casters' sides and caps, then z-pass casters' sides.
    pub fn record_stencil<'a>(
        &'a self,
        rec: &mut Recorder<'a>,
        draws: GpuDraws<'a, '_>,
        bounds: PassBounds,
        fold: &'a GraphicsPipeline,
        log: &mut PassLog,
    ) {
        self.record_counting(rec, draws, FULL_STENCIL, fold, log, |rec, counting, batched, caps| {
            let pipelines = if caps { &self.caps } else { &self.sides };
            pipelines.pick(counting, batched).bind(rec, bounds);
            rec.set_stencil_reference(0);
        });
    }

    /// The overdraw image's draws of a light's volumes (inside a rendering pass over the
    /// overdraw target; built with `overdraw`): every caster's sides and caps as drawn.
    pub fn record_overdraw<'a>(&'a self, rec: &mut Recorder<'a>, draws: GpuDraws<'a, '_>) {
        let Some(overdraw) = &self.overdraw else { return };
        self.record_every_draw(rec, draws, |rec, caps| {
            rec.bind_pipeline(&overdraw[usize::from(caps)]);
            true
        });
    }

    /// Every caster's sides (both modes' draws: one has no vertices) and caps, in one batch,
    /// each part's pipeline bound by `bind(rec, caps)` (false: the part is not drawn; a
    /// pipeline bound must be built against [`Self::layout`]).
    pub fn record_every_draw<'a>(
        &'a self,
        rec: &mut Recorder<'a>,
        draws: GpuDraws<'a, '_>,
        bind: impl Fn(&mut Recorder<'a>, bool) -> bool,
    ) {
        let parts: [(bool, &[JobDraw]); 2] =
            [(false, &[JobDraw::ZFailSides, JobDraw::ZPassSides]), (true, &[JobDraw::Caps])];
        for (caps, parts) in parts {
            if bind(rec, caps) {
                self.draw_casters(rec, draws, &draws.volumes.casters, parts);
            }
        }
    }

    /// Per batch of `draws`' casters, z-fail sides and caps, then z-pass sides, each drawn
    /// indirectly for every caster that may count in that mode (its mode asked for, or
    /// decided on the GPU: then the other mode's draws have no vertices), each part's
    /// pipeline and dynamic state bound by `bind(rec, counting, batched, caps)` (built against
    /// [`Self::layout`]). The hybrid counts its masked volumes through here.
    pub fn record_counting<'a>(
        &'a self,
        rec: &mut Recorder<'a>,
        draws: GpuDraws<'a, '_>,
        bits: CountBits,
        fold: &'a GraphicsPipeline,
        log: &mut PassLog,
        bind: impl Fn(&mut Recorder<'a>, Counting, bool, bool),
    ) {
        let volumes = draws.volumes;
        let Some((first, jobs)) = &volumes.gpu else { return };
        let parts = [
            (Counting::ZFail, JobDraw::ZFailSides),
            (Counting::ZFail, JobDraw::Caps),
            (Counting::ZPass, JobDraw::ZPassSides),
        ];
        record_in_batches(rec, log, volumes, bits, fold, |rec, log, batch, batched| {
            for (counting, part) in parts {
                let casters = batch.iter().filter(|c| c.job.is_some() && c.counting.is_none_or(|m| m == counting));
                if casters.clone().next().is_none() {
                    continue;
                }
                // The pipeline, then the sets, as the fold between batches binds another layout.
                let caps = part == JobDraw::Caps;
                bind(rec, counting, batched, caps);
                self.draw_casters(rec, draws, casters.clone(), &[part]);
                // Caps asked for in z-fail draw every triangle (edge-on ones off view).
                let asked = casters.filter(|c| caps && c.counting.is_some());
                for j in asked.filter_map(|c| jobs.get((c.job? as usize).wrapping_sub(*first))) {
                    log.count_draw(u64::from(j.triangle_count));
                }
            }
        });
    }

    /// The bound pipeline's draws `parts` of each of `casters` built on the GPU, after binding
    /// the scene's and the slot's sets.
    fn draw_casters<'a, 'c>(
        &'a self,
        rec: &mut Recorder<'a>,
        draws: GpuDraws<'a, '_>,
        casters: impl IntoIterator<Item = &'c CasterVolume>,
        parts: &[JobDraw],
    ) {
        let Some(w) = &self.written else { return };
        rec.bind_descriptor_set(&self.layout, 0, &draws.gpu.frame.set);
        rec.bind_descriptor_set(&self.layout, 1, &draws.slot.set);
        for c in casters {
            let Some(job) = c.job else { continue };
            rec.push_constants(&self.layout, &JobPush { object: c.object as u32, view: draws.light, job });
            for part in parts {
                rec.draw_indirect(&w.draws, part.offset(job));
            }
        }
    }
}

/// What one light's GPU-built volume draws read: the scene, the slot's set over the stages'
/// buffers, the light's volumes (jobs named) and its index.
#[derive(Clone, Copy)]
pub(crate) struct GpuDraws<'a, 'v> {
    pub gpu: &'a GpuScene,
    pub slot: &'a SlotVolumes,
    pub volumes: &'v LightVolumes,
    pub light: u32,
}
