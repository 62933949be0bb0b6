//! Meshes an engine deforms on the GPU ([`crate::Shadows::add_deforming_mesh`]): the shadow
//! volumes built on the GPU read each frame's pose without any host work per vertex or
//! triangle.
//!
//! The mesh's connectivity comes from its rest pose, welded once on the host
//! ([`Adjacency::build`]); each frame, before any light's `volume classify`, the `volume
//! positions` pass (`shadow_volume/deform.comp`) copies every welded position of the mesh from
//! the engine's position stream, at the first vertex welded into it
//! ([`Adjacency::welded_from`]), into the volumes' position array. The copy is of bits: the
//! volumes see exactly the positions the engine's buffers draw, so classify, the silhouettes
//! and the sides and caps follow the pose as the CPU path would follow the same positions.

use super::gpu::GROUP;
use crate::mesh_buffers::VertexStream;
use crate::RenderResult;
use std::sync::Arc;
use umbra_scene::Adjacency;
use umbra_vk::{
    vk, Binding, Buffer, BufferDesc, BufferState, ComputePipeline, Context, DescriptorSet, DescriptorSetLayout,
    PipelineLayout, Recorder, Resource,
};

/// The meshes registered as deforming, by mesh index: their rest pose's connectivity and the
/// engine's position stream. Kept between frames: nothing is made per frame.
#[derive(Default)]
pub(crate) struct Deforming {
    adjacency: Vec<Option<Arc<Adjacency>>>,
    streams: Vec<Option<VertexStream>>,
}

impl Deforming {
    /// Mesh `mesh` deforms: welded from `rest`, its positions read from `stream`. The rest
    /// pose's convexity is not kept (a pose may bend it), so its volumes count as a concave
    /// mesh's.
    pub fn set(&mut self, mesh: usize, rest: &umbra_scene::Mesh, stream: VertexStream) {
        let mut adjacency = Adjacency::build(rest);
        adjacency.convex = false;
        if self.adjacency.len() <= mesh {
            self.adjacency.resize(mesh + 1, None);
            self.streams.resize(mesh + 1, None);
        }
        self.adjacency[mesh] = Some(Arc::new(adjacency));
        self.streams[mesh] = Some(stream);
    }

    /// Mesh `mesh` no longer deforms (it was removed).
    pub fn clear(&mut self, mesh: usize) {
        if let (Some(a), Some(s)) = (self.adjacency.get_mut(mesh), self.streams.get_mut(mesh)) {
            (*a, *s) = (None, None);
        }
    }

    /// Whether mesh `mesh` deforms.
    pub fn holds(&self, mesh: usize) -> bool {
        self.adjacency.get(mesh).is_some_and(Option::is_some)
    }

    /// Puts each deforming mesh's rest-pose connectivity in place of `adjacency`'s (which the
    /// scene's bounds-only placeholder gave).
    pub fn substitute(&self, adjacency: &mut [Arc<Adjacency>]) {
        for (a, d) in adjacency.iter_mut().zip(&self.adjacency) {
            if let Some(d) = d {
                *a = Arc::clone(d);
            }
        }
    }

    /// The engine's position stream of each deforming mesh, by mesh index.
    pub fn streams(&self) -> &[Option<VertexStream>] {
        &self.streams
    }
}

/// The push constants of `deform.comp`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, bytemuck::Pod, bytemuck::Zeroable)]
struct DeformPush {
    first_word: u32,
    stride_words: u32,
    first_position: u32,
    first_map: u32,
    count: u32,
}

/// One deforming mesh's copy: its set (the engine's buffer, the map, the positions) and push.
struct MeshCopy {
    set: DescriptorSet,
    push: DeformPush,
}

/// The copies of every deforming mesh into one positions array, with the map they read.
pub(crate) struct DeformCopies {
    copies: Vec<MeshCopy>,
    /// Every deforming mesh's `welded_from`, concatenated (the sets read it).
    _map: Buffer,
}

/// The `volume positions` pipeline.
pub(crate) struct DeformPipeline {
    set_layout: DescriptorSetLayout,
    layout: PipelineLayout,
    pipeline: ComputePipeline,
}

impl DeformPipeline {
    /// The pipeline and its layout (three storage buffers, the push constants).
    pub fn new(ctx: &Context) -> RenderResult<Self> {
        let (ty, stages) = (vk::DescriptorType::STORAGE_BUFFER, vk::ShaderStageFlags::COMPUTE);
        let bindings: Vec<Binding> = (0..3).map(|binding| Binding { binding, ty, stages }).collect();
        let set_layout = DescriptorSetLayout::new(ctx, "volume positions layout", &bindings)?;
        let push = std::mem::size_of::<DeformPush>() as u32;
        let layout = PipelineLayout::new(ctx, "volume positions", &[&set_layout], push)?;
        let spirv = umbra_shaders::shadow_volume::DEFORM_COMP;
        let pipeline = ComputePipeline::new(ctx, &layout, "volume positions", spirv, &[])?;
        Ok(Self { set_layout, layout, pipeline })
    }

    /// The copies of the meshes `streams` names (by mesh index: the engine's position stream
    /// of a deforming mesh) into `positions`, the flat array of `adjacency` (every mesh's
    /// welded positions in mesh order); `None` when no mesh deforms.
    pub fn copies(
        &self,
        ctx: &Context,
        positions: &Buffer,
        adjacency: &[Arc<Adjacency>],
        streams: &[Option<VertexStream>],
    ) -> RenderResult<Option<DeformCopies>> {
        let mut map: Vec<u32> = Vec::new();
        let mut pushes = Vec::new();
        let mut first_position = 0u32;
        for (i, adj) in adjacency.iter().enumerate() {
            if let Some(Some(s)) = streams.get(i) {
                pushes.push((
                    s,
                    DeformPush {
                        first_word: (s.offset / 4) as u32,
                        stride_words: s.stride / 4,
                        first_position,
                        first_map: map.len() as u32,
                        count: adj.welded_from.len() as u32,
                    },
                ));
                map.extend_from_slice(&adj.welded_from);
            }
            first_position += adj.positions.len() as u32;
        }
        if pushes.is_empty() {
            return Ok(None);
        }
        let bytes: &[u8] = bytemuck::cast_slice(&map);
        let desc = BufferDesc::cpu_to_gpu(bytes.len().max(4) as u64, vk::BufferUsageFlags::STORAGE_BUFFER);
        let mut map_buffer = Buffer::new(ctx, "volume positions map", desc)?;
        map_buffer.write(0, bytes)?;
        let copies = pushes
            .into_iter()
            .enumerate()
            .map(|(k, (s, push))| {
                let engine = Resource::ExternalBuffer { buffer: s.buffer, size: s.buffer_size };
                let resources = [engine, Resource::Buffer(&map_buffer), Resource::Buffer(positions)];
                let name = format!("volume positions {k}");
                Ok(MeshCopy { set: DescriptorSet::new(ctx, &name, &self.set_layout, &resources)?, push })
            })
            .collect::<RenderResult<_>>()?;
        Ok(Some(DeformCopies { copies, _map: map_buffer }))
    }

    /// Records every mesh's copy (the positions in `ComputeStorage`), after a global memory
    /// barrier that makes every earlier write visible to it: the engine's pose, written by
    /// whatever it likes (a compute pass, a copy, the host) into buffers umbra does not track.
    pub fn record<'a>(&'a self, rec: &mut Recorder<'a>, copies: &'a DeformCopies) {
        rec.memory_barrier(BufferState::Unknown, BufferState::ComputeRead);
        rec.bind_compute_pipeline(&self.pipeline);
        for c in &copies.copies {
            rec.bind_compute_set(&self.layout, 0, &c.set);
            rec.push_constants(&self.layout, &c.push);
            rec.dispatch([c.push.count.div_ceil(GROUP), 1, 1]);
        }
    }
}
