//! Data the CPU makes every frame — the scene's per-frame buffers (camera, objects, lights,
//! shadow views), vertex data (silhouette edges, shadow volumes, blocker boxes) and the
//! ray-tracing BVH's top level — in
//! host-visible buffers kept from frame to frame: written in place (the renderer waits for
//! each frame's work, so nothing reads them any more) and reallocated only to grow, so a warm
//! frame neither allocates nor submits an upload for them.

use crate::RenderResult;
use umbra_vk::{vk, Buffer, BufferDesc, Context};

/// One per-frame buffer.
pub(crate) struct Stream {
    name: &'static str,
    usage: vk::BufferUsageFlags,
    buffer: Option<Buffer>,
    /// Counts the buffer's reallocations (what was bound to the old one must be bound again).
    generation: u64,
    /// Whether the last [`Stream::fill`] had data.
    filled: bool,
    /// Whether a new buffer gets half as much again as asked for (vertex streams, whose size
    /// drifts as things move; bound buffers stay exact, as their limits are checked exactly).
    headroom: bool,
}

impl Stream {
    /// An empty stream for buffers named `name` with `usage`.
    pub const fn new(name: &'static str, usage: vk::BufferUsageFlags) -> Self {
        Self { name, usage, buffer: None, generation: 0, filled: false, headroom: false }
    }

    /// A vertex stream: a new buffer holds half as much again as the data that needed it, so
    /// that a moving scene's volumes and edges do not reallocate every few frames.
    fn vertices(name: &'static str) -> Self {
        Self { headroom: true, ..Self::new(name, vk::BufferUsageFlags::VERTEX_BUFFER) }
    }

    /// A storage stream read whole by a shader that follows indices (so room to spare is
    /// harmless): with headroom, as vertex streams.
    fn storage(name: &'static str) -> Self {
        Self { headroom: true, ..Self::new(name, vk::BufferUsageFlags::STORAGE_BUFFER) }
    }

    /// The buffer filled last, if any.
    pub fn buffer(&self) -> Option<&Buffer> {
        self.buffer.as_ref()
    }

    /// The buffer, when the last [`Stream::fill`] had data to draw.
    pub fn filled(&self) -> Option<&Buffer> {
        self.buffer.as_ref().filter(|_| self.filled)
    }

    /// Changes whenever [`Stream::fill`] had to make a new buffer.
    pub fn generation(&self) -> u64 {
        self.generation
    }

    /// Writes `data` into the stream's buffer (a larger one first if it does not fit) and
    /// returns it; `None` when there is nothing to draw.
    pub fn fill<T: bytemuck::Pod>(&mut self, ctx: &Context, data: &[T]) -> RenderResult<Option<&Buffer>> {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        self.filled = !bytes.is_empty();
        if bytes.is_empty() {
            return Ok(None);
        }
        let buffer = match self.buffer.take() {
            Some(b) if b.desc.size >= bytes.len() as u64 => b,
            // The old one (if any) is freed before the larger one is made.
            _ => {
                self.generation += 1;
                let size = bytes.len() as u64;
                let size = if self.headroom { size + size / 2 } else { size };
                Buffer::new(ctx, self.name, BufferDesc::cpu_to_gpu(size, self.usage))?
            }
        };
        let buffer = self.buffer.insert(buffer);
        buffer.write(0, bytes)?;
        Ok(Some(buffer))
    }
}

/// The renderer's per-frame vertex streams.
pub(crate) struct Streams {
    /// Silhouette-map edge instances.
    pub edges: Stream,
    /// Shadow-volume vertices.
    pub volumes: Stream,
    /// The hybrid's blocker-culling boxes.
    pub blockers: Stream,
    /// Ray-traced shadows' top-level nodes and instances (`crate::ray_traced`).
    pub ray_top: Stream,
    pub ray_instances: Stream,
    /// Shadow volumes built on the GPU: the frame's jobs and their draws' initial values
    /// (`shadow_volume/gpu_frame.rs`).
    pub volume_jobs: Stream,
    pub volume_draws: Stream,
}

impl Default for Streams {
    fn default() -> Self {
        Self {
            edges: Stream::vertices("silhouette edges"),
            volumes: Stream::vertices("shadow volume vertices"),
            blockers: Stream::vertices("blocker boxes"),
            ray_top: Stream::storage("ray BVH top nodes"),
            ray_instances: Stream::storage("ray BVH instances"),
            volume_jobs: Stream::storage("shadow volume jobs"),
            volume_draws: Stream::new("shadow volume draw resets", vk::BufferUsageFlags::TRANSFER_SRC),
        }
    }
}
