//! Shadow volumes built on the GPU (issue #26): the silhouettes found in compute, so that the
//! host's cost no longer grows with the casters' triangles.
//!
//! Every mesh's welded adjacency ([`Adjacency`]: positions, triangles, edges with the faces
//! that use them) is flattened into four arrays, once per mesh. Per caster and light a
//! [`VolumeJob`] names its mesh, the light in its object space (computed on the host, as
//! `build.rs` does), its world box and the light's near-plane clip region, and two compute
//! stages run per job:
//! 1. `shadow_volume/classify.comp`: how each triangle faces the light, in the f32 operations
//!    of [`umbra_scene::facing`], `precise`, so both classify alike (hard case 06's
//!    light in the plane of a face included); its first invocation decides the job's
//!    counting mode (Everitt–Kilgard §3.4: z-fail only where the box may touch the near-plane
//!    clip region, the test `build.rs` runs for the CPU path) and sets its caps' draw;
//! 2. `shadow_volume/silhouettes.comp`: every edge's net count of casting faces, as
//!    [`umbra_scene::silhouette_edges`] counts it (open and non-manifold casters with
//!    multiplicity); edges whose count is not 0 are appended to the job's list, and their side
//!    quads to the `VkDrawIndirectCommand` of its mode ([`JobDraw`]).
//!
//! A job's list holds as many entries as its mesh's edges have faces: the most its edges can
//! count, so the list never overflows. [`GpuSilhouettes::find`] runs both stages and reads the
//! edges back: the test that the GPU finds the CPU's silhouettes, edge for edge.

use crate::RenderResult;
use glam::Vec4;
use std::sync::Arc;
use umbra_scene::Adjacency;
use umbra_vk::{
    vk, Binding, Buffer, BufferDesc, BufferState, ComputePipeline, Context, DescriptorSet, DescriptorSetLayout,
    PipelineLayout, Recorder, Resource,
};

/// Invocations per workgroup of both stages (`local_size_x`).
pub(crate) const GROUP: u32 = 64;

/// One caster's volume for one light, as `VolumeJob` in `shadow_volume/gpu_volume.glsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct VolumeJob {
    /// The light in the caster's object space.
    pub light: [f32; 4],
    /// The caster's world bounds (w unused): the counting mode's test.
    pub box_min: [f32; 4],
    pub box_max: [f32; 4],
    /// The light's near-plane clip region (`build.rs`' `NearRegion`), `near_count` planes.
    pub near: [[f32; 4]; NEAR_PLANES],
    pub triangles: u32,
    pub triangle_count: u32,
    pub edges: u32,
    pub edge_count: u32,
    /// Its first entry in the facing array.
    pub facing: u32,
    /// Its first entry in the silhouette list.
    pub list: u32,
    /// 1 for a closed 2-manifold mesh.
    pub closed: u32,
    /// Its mesh's triangles with three distinct vertices (the caps' source).
    pub faces: u32,
    pub near_count: u32,
    /// [`MODE_AUTO`] (decided on the GPU), [`MODE_ZPASS`] or [`MODE_ZFAIL`].
    pub mode: u32,
    pub pad: [u32; 2],
}

/// The most planes of a near-plane clip region: the near rectangle and its four sides.
pub(crate) const NEAR_PLANES: usize = 5;

/// A job's counting mode (`MODE_*` in `gpu_volume.glsl`): decided by `classify.comp`.
pub(crate) const MODE_AUTO: u32 = 0;
/// Z-pass, asked for or decided.
pub(crate) const MODE_ZPASS: u32 = 1;
/// Z-fail, asked for or decided.
pub(crate) const MODE_ZFAIL: u32 = 2;

/// `u32` words per job in the draws buffer (`JOB_DRAWS` uvec4s in `gpu_volume.glsl`): its
/// three `VkDrawIndirectCommand`s ([`JobDraw`]), then its counts.
pub(crate) const DRAW_WORDS: usize = 16;

/// The job's first count word in the draws buffer (`DRAW_COUNTS` in `gpu_volume.glsl`), after
/// its three draws: its edge-on faces, then its mode.
const COUNTS_WORD: usize = 12;

/// Bytes per job in the draws buffer.
pub(crate) const DRAW_STRIDE: u64 = 4 * DRAW_WORDS as u64;

/// One of a job's indirect draws (`DRAW_*` in `gpu_volume.glsl`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum JobDraw {
    /// Its sides, counted z-fail (vertices only when z-fail was decided).
    ZFailSides = 0,
    /// Its sides, counted z-pass (vertices only when z-pass was decided).
    ZPassSides = 1,
    /// Its caps (z-fail only).
    Caps = 2,
}

impl JobDraw {
    /// Where job `job`'s draw lies in the draws buffer.
    pub fn offset(self, job: u32) -> u64 {
        DRAW_STRIDE * u64::from(job) + 16 * self as u64
    }
}

/// The draws buffer's value before the stages run: per job no vertex yet, sides from its
/// list's first vertex, no mode and no count.
pub(crate) fn draw_resets(jobs: &[VolumeJob]) -> Vec<[u32; DRAW_WORDS]> {
    jobs.iter()
        .map(|j| {
            let sides = [0, 1, 6 * j.list, 0];
            let mut words = [0; DRAW_WORDS];
            words[..4].copy_from_slice(&sides);
            words[4..8].copy_from_slice(&sides);
            words
        })
        .collect()
}

/// What the stages counted and decided for one job, read back from the draws buffer.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct JobCounts {
    /// Silhouette edges listed, with multiplicity.
    pub silhouette_edges: u32,
    /// Cap triangles its z-fail draw makes: a closed caster's faces, an open caster's faces
    /// not edge-on to the light, twice (as `umbra_scene::Volume::build` makes them); 0 in
    /// z-pass.
    pub cap_triangles: u32,
    /// The counting mode `classify.comp` decided (`None`: the job never ran, an empty mesh).
    pub mode: Option<super::build::Counting>,
}

impl JobCounts {
    /// Job `index`'s counts (`job`) in the draws buffer's `words`.
    pub fn read(words: &[u32], job: &VolumeJob, index: usize) -> Self {
        use super::build::Counting;
        let at = |k: usize| words.get(DRAW_WORDS * index + k).copied().unwrap_or(0);
        // Each draw's vertex count is its first word; the counts (edge-on faces, mode) follow
        // the three draws.
        let vertices = |draw: JobDraw| at(4 * draw as usize);
        let (edge_on, mode) = (at(COUNTS_WORD), at(COUNTS_WORD + 1));
        let mode = match mode {
            MODE_ZPASS => Some(Counting::ZPass),
            MODE_ZFAIL => Some(Counting::ZFail),
            _ => None,
        };
        let cap_triangles = match (mode, job.closed) {
            (Some(Counting::ZFail), 0) => 2 * job.faces.saturating_sub(edge_on),
            (Some(Counting::ZFail), _) => job.faces,
            _ => 0,
        };
        let side_vertices = vertices(JobDraw::ZFailSides) + vertices(JobDraw::ZPassSides);
        Self { silhouette_edges: side_vertices / 6, cap_triangles, mode }
    }
}

/// Where one mesh lies in the [`AdjacencyArrays`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct MeshRange {
    pub triangles: u32,
    pub triangle_count: u32,
    pub edges: u32,
    pub edge_count: u32,
    pub closed: bool,
    /// Triangles with three distinct vertices.
    pub faces: u32,
    /// Faces over all its edges: the most silhouette entries one light can give it.
    pub list_bound: u32,
}

/// Every mesh's welded adjacency, concatenated in the layout of `gpu_volume.glsl`.
#[derive(Clone, Debug, Default)]
pub(crate) struct AdjacencyArrays {
    pub positions: Vec<[f32; 4]>,
    pub triangles: Vec<[u32; 4]>,
    pub edges: Vec<[u32; 4]>,
    pub edge_faces: Vec<u32>,
    pub meshes: Vec<MeshRange>,
}

impl AdjacencyArrays {
    /// Flattens `meshes`, in order.
    pub fn build(meshes: &[Arc<Adjacency>]) -> Self {
        let mut out = Self::default();
        for adj in meshes {
            let base = out.positions.len() as u32;
            let range = MeshRange {
                triangles: out.triangles.len() as u32,
                triangle_count: adj.triangles.len() as u32,
                edges: out.edges.len() as u32,
                edge_count: adj.edges.len() as u32,
                closed: adj.report.closed,
                faces: (adj.report.triangles - adj.report.degenerate_triangles) as u32,
                list_bound: adj.edges.iter().map(|e| e.faces.len() as u32).sum(),
            };
            out.positions.extend(adj.positions.iter().map(|p| p.extend(1.0).to_array()));
            out.triangles.extend(adj.triangles.iter().map(|t| [t[0] + base, t[1] + base, t[2] + base, 0]));
            for e in &adj.edges {
                out.edges.push([e.v[0] + base, e.v[1] + base, out.edge_faces.len() as u32, e.faces.len() as u32]);
                out.edge_faces.extend(e.faces.iter().map(|f| (f.face << 1) | u32::from(f.forward)));
            }
            out.meshes.push(range);
        }
        out
    }

    /// The job of mesh `mesh` for `light` (in the caster's object space), its facing and list
    /// entries starting at `facing` and `list`.
    pub fn job(&self, mesh: usize, light: Vec4, facing: u32, list: u32) -> Option<VolumeJob> {
        Some(self.meshes.get(mesh)?.job(light, facing, list))
    }
}

/// Every mesh's place in the [`AdjacencyArrays`], by mesh index.
pub(crate) type MeshRanges = [MeshRange];

impl MeshRange {
    /// This mesh's job for `light` (in the caster's object space), its facing and list entries
    /// starting at `facing` and `list`.
    pub fn job(&self, light: Vec4, facing: u32, list: u32) -> VolumeJob {
        VolumeJob {
            light: light.to_array(),
            triangles: self.triangles,
            triangle_count: self.triangle_count,
            edges: self.edges,
            edge_count: self.edge_count,
            facing,
            list,
            closed: u32::from(self.closed),
            faces: self.faces,
            ..VolumeJob::default()
        }
    }
}

/// The two compute stages and their set's layout.
pub struct GpuSilhouettes {
    set_layout: DescriptorSetLayout,
    layout: PipelineLayout,
    classify: ComputePipeline,
    silhouettes: ComputePipeline,
}

/// The buffers of one run of the stages (the arrays, the jobs, and what the stages write).
struct RunBuffers {
    /// The arrays and jobs, kept alive until the run completed.
    _arrays: [Buffer; 5],
    facing: Buffer,
    list: Buffer,
    draws: Buffer,
    set: DescriptorSet,
}

impl GpuSilhouettes {
    /// The pipelines of both stages.
    pub fn new(ctx: &Context) -> RenderResult<Self> {
        let (ty, stages) =
            (vk::DescriptorType::STORAGE_BUFFER, vk::ShaderStageFlags::COMPUTE | vk::ShaderStageFlags::VERTEX);
        let bindings: Vec<Binding> = (0..8).map(|binding| Binding { binding, ty, stages }).collect();
        let set_layout = DescriptorSetLayout::new(ctx, "gpu shadow volume layout", &bindings)?;
        let layout = PipelineLayout::new(ctx, "gpu shadow volume stages", &[&set_layout], 4)?;
        let classify = ComputePipeline::new(
            ctx,
            &layout,
            "shadow volume classify",
            umbra_shaders::shadow_volume::CLASSIFY_COMP,
            &[],
        )?;
        let silhouettes = ComputePipeline::new(
            ctx,
            &layout,
            "shadow volume silhouettes",
            umbra_shaders::shadow_volume::SILHOUETTES_COMP,
            &[],
        )?;
        Ok(Self { set_layout, layout, classify, silhouettes })
    }

    /// The directed silhouette edges of every job `(mesh, light in the mesh's object space)`
    /// over `meshes`, found on the GPU (one submission, waited for), each repeated with its
    /// multiplicity and in welded vertex indices as [`umbra_scene::silhouette_edges`]
    /// returns them (in the order the GPU appended them).
    pub fn find(
        &self,
        ctx: &Context,
        meshes: &[Arc<Adjacency>],
        jobs: &[(usize, Vec4)],
    ) -> RenderResult<Vec<Vec<[u32; 2]>>> {
        let arrays = AdjacencyArrays::build(meshes);
        let (mut facing, mut list) = (0u32, 0u32);
        let mut gpu_jobs = Vec::with_capacity(jobs.len());
        for (i, &(mesh, light)) in jobs.iter().enumerate() {
            let job = arrays.job(mesh, light, facing, list).ok_or_else(|| crate::RenderError::InvalidInput {
                field: format!("jobs[{i}].mesh"),
                why: format!("mesh {mesh} of {}", meshes.len()),
            })?;
            facing += job.triangle_count;
            list += arrays.meshes[mesh].list_bound;
            gpu_jobs.push(job);
        }
        let run = self.buffers(ctx, &arrays, &gpu_jobs, facing, list)?;
        let draws_bytes = DRAW_STRIDE * gpu_jobs.len().max(1) as u64;
        let draws_out = Buffer::new(ctx, "gpu shadow volume draws readback", BufferDesc::readback(draws_bytes))?;
        let list_out = Buffer::new(ctx, "gpu shadow volume list readback", BufferDesc::readback(run.list.desc.size))?;
        let mut rec = ctx.begin_commands("gpu shadow volume silhouettes")?;
        let init = draw_resets(&gpu_jobs);
        if !init.is_empty() {
            rec.update_buffer(&run.draws, bytemuck::cast_slice::<_, u32>(&init));
        }
        rec.buffer_transition(&[(&run.draws, BufferState::TransferDst, BufferState::ComputeStorage)]);
        self.record(&mut rec, &run, &gpu_jobs);
        let src = BufferState::TransferSrc;
        rec.buffer_transition(&[
            (&run.draws, BufferState::ComputeStorage, src),
            (&run.list, BufferState::ComputeStorage, src),
        ]);
        rec.copy_buffer(&run.draws, &draws_out, draws_bytes);
        rec.copy_buffer(&run.list, &list_out, run.list.desc.size);
        rec.transfer_to_host(&[&draws_out, &list_out]);
        ctx.submit_and_wait(rec)?;
        let draws: Vec<u32> = bytemuck::pod_collect_to_vec(&draws_out.read()?);
        let entries: Vec<u32> = bytemuck::pod_collect_to_vec(&list_out.read()?);
        Ok(jobs
            .iter()
            .zip(&gpu_jobs)
            .enumerate()
            .map(|(i, (&(mesh, _), job))| {
                let count = JobCounts::read(&draws, job, i).silhouette_edges;
                let range = job.list as usize..(job.list + count) as usize;
                let edges = &meshes[mesh].edges;
                entries
                    .get(range)
                    .unwrap_or_default()
                    .iter()
                    .filter_map(|&entry| {
                        let v = edges.get((entry >> 1) as usize)?.v;
                        Some(if entry & 1 == 0 { v } else { [v[1], v[0]] })
                    })
                    .collect()
            })
            .collect())
    }

    /// Records both stages for every job of `jobs` (the run's facing and draws ready in
    /// `ComputeStorage`): each job classified (its mode decided), one barrier, each job's
    /// silhouettes.
    fn record<'a>(&'a self, rec: &mut Recorder<'a>, run: &'a RunBuffers, jobs: &[VolumeJob]) {
        let (set, facing, draws) = (&run.set, &run.facing, &run.draws);
        self.record_classify(rec, set, 0, jobs);
        let storage = BufferState::ComputeStorage;
        rec.buffer_transition(&[(facing, storage, storage), (draws, storage, storage)]);
        self.record_silhouettes(rec, set, 0, jobs);
    }

    /// Stage 1 for `jobs`, the frame's jobs from index `first` on.
    pub(crate) fn record_classify<'a>(
        &'a self,
        rec: &mut Recorder<'a>,
        set: &'a DescriptorSet,
        first: usize,
        jobs: &[VolumeJob],
    ) {
        rec.bind_compute_pipeline(&self.classify);
        rec.bind_compute_set(&self.layout, 0, set);
        self.dispatch_jobs(rec, first, jobs, |j| j.triangle_count);
    }

    /// Stage 2 for `jobs`, the frame's jobs from index `first` on (after their facing).
    pub(crate) fn record_silhouettes<'a>(
        &'a self,
        rec: &mut Recorder<'a>,
        set: &'a DescriptorSet,
        first: usize,
        jobs: &[VolumeJob],
    ) {
        rec.bind_compute_pipeline(&self.silhouettes);
        rec.bind_compute_set(&self.layout, 0, set);
        self.dispatch_jobs(rec, first, jobs, |j| j.edge_count);
    }

    /// One dispatch per job with work, `items(job)` invocations each, pushing its index.
    fn dispatch_jobs<'a>(
        &'a self,
        rec: &mut Recorder<'a>,
        first: usize,
        jobs: &[VolumeJob],
        items: impl Fn(&VolumeJob) -> u32,
    ) {
        for (k, job) in jobs.iter().enumerate() {
            let n = items(job);
            if n > 0 {
                rec.push_constants(&self.layout, &((first + k) as u32));
                rec.dispatch([n.div_ceil(GROUP), 1, 1]);
            }
        }
    }

    /// The layout of the stages' set (set 1 of the volume draws).
    pub(crate) fn set_layout(&self) -> &DescriptorSetLayout {
        &self.set_layout
    }

    /// The arrays and jobs in storage buffers, with `facing` and `list` entries for what the
    /// stages write and a draw command per job, in one set.
    fn buffers(
        &self,
        ctx: &Context,
        arrays: &AdjacencyArrays,
        jobs: &[VolumeJob],
        facing: u32,
        list: u32,
    ) -> RenderResult<RunBuffers> {
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let filled = |name: &str, bytes: &[u8]| -> RenderResult<Buffer> {
            // A storage buffer is never empty: 16 bytes no stage reads.
            let bytes = if bytes.is_empty() { &[0u8; 16][..] } else { bytes };
            let mut b = Buffer::new(ctx, name, BufferDesc::cpu_to_gpu(bytes.len() as u64, storage))?;
            b.write(0, bytes)?;
            Ok(b)
        };
        let arrays = [
            filled("gpu shadow volume positions", bytemuck::cast_slice(&arrays.positions))?,
            filled("gpu shadow volume triangles", bytemuck::cast_slice(&arrays.triangles))?,
            filled("gpu shadow volume edges", bytemuck::cast_slice(&arrays.edges))?,
            filled("gpu shadow volume edge faces", bytemuck::cast_slice(&arrays.edge_faces))?,
            filled("gpu shadow volume jobs", bytemuck::cast_slice(jobs))?,
        ];
        let written = |name: &str, bytes: u64, extra: vk::BufferUsageFlags| {
            Buffer::new(ctx, name, BufferDesc::gpu_only(bytes.max(16), storage | extra))
        };
        let copy = vk::BufferUsageFlags::TRANSFER_SRC | vk::BufferUsageFlags::TRANSFER_DST;
        let facing = written("gpu shadow volume facing", 4 * u64::from(facing), vk::BufferUsageFlags::empty())?;
        let list = written("gpu shadow volume silhouettes", 4 * u64::from(list), copy)?;
        let draws = written(
            "gpu shadow volume draws",
            DRAW_STRIDE * jobs.len() as u64,
            copy | vk::BufferUsageFlags::INDIRECT_BUFFER,
        )?;
        let resources: Vec<Resource> = arrays.iter().chain([&facing, &list, &draws]).map(Resource::Buffer).collect();
        let set = DescriptorSet::new(ctx, "gpu shadow volume", &self.set_layout, &resources)?;
        Ok(RunBuffers { _arrays: arrays, facing, list, draws, set })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    use umbra_scene::primitives;

    #[test]
    fn the_arrays_offset_every_mesh_past_the_ones_before_it() {
        let cube = Arc::new(Adjacency::build(&primitives::cuboid(Vec3::ONE)));
        let plane = Arc::new(Adjacency::build(&primitives::plane(1.0)));
        let a = AdjacencyArrays::build(&[cube.clone(), plane.clone()]);
        let (c, p) = (a.meshes[0], a.meshes[1]);
        assert_eq!((c.triangles, c.edges, c.closed), (0, 0, true));
        assert_eq!((p.triangles, p.edges, p.closed), (cube.triangles.len() as u32, cube.edges.len() as u32, false));
        // The plane's vertices and edge faces follow the cube's.
        let base = cube.positions.len() as u32;
        assert_eq!(a.triangles[p.triangles as usize][0], plane.triangles[0][0] + base);
        let first = a.edges[p.edges as usize];
        assert_eq!([first[0], first[1]], plane.edges[0].v.map(|v| v + base));
        assert_eq!(first[2], cube.edges.iter().map(|e| e.faces.len() as u32).sum::<u32>());
        // A closed cube's edges have two faces each; the plane's boundary edges one.
        assert_eq!(c.list_bound, 2 * c.edge_count);
        assert!(p.list_bound < 2 * p.edge_count);
        let job = a.job(1, Vec4::W, 7, 9).expect("mesh 1");
        assert_eq!((job.triangles, job.facing, job.list, job.closed), (p.triangles, 7, 9, 0));
        assert!(a.job(2, Vec4::W, 0, 0).is_none());
    }
}
