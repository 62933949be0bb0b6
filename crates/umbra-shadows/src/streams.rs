//! Vertex data the CPU makes every frame — silhouette edges, shadow volumes, blocker boxes —
//! in host-visible buffers kept from frame to frame: written in place (the renderer waits for
//! each frame's work, so nothing reads them any more) and reallocated only to grow, so a warm
//! frame neither allocates nor submits an upload for them.

use crate::RenderResult;
use umbra_vk::{vk, Buffer, BufferDesc, Context};

/// One per-frame vertex stream.
pub(crate) struct Stream {
    name: &'static str,
    buffer: Option<Buffer>,
}

impl Stream {
    const fn new(name: &'static str) -> Self {
        Self { name, buffer: None }
    }

    /// Writes `data` into the stream's buffer (a larger one first if it does not fit) and
    /// returns it; `None` when there is nothing to draw.
    pub fn fill<T: bytemuck::Pod>(&mut self, ctx: &Context, data: &[T]) -> RenderResult<Option<&Buffer>> {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        if bytes.is_empty() {
            return Ok(None);
        }
        let buffer = match self.buffer.take() {
            Some(b) if b.desc.size >= bytes.len() as u64 => b,
            // The old one (if any) is freed before the larger one is made.
            _ => Buffer::new(
                ctx,
                self.name,
                BufferDesc::cpu_to_gpu(bytes.len() as u64, vk::BufferUsageFlags::VERTEX_BUFFER),
            )?,
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
}

impl Default for Streams {
    fn default() -> Self {
        Self {
            edges: Stream::new("silhouette edges"),
            volumes: Stream::new("shadow volume vertices"),
            blockers: Stream::new("blocker boxes"),
        }
    }
}
