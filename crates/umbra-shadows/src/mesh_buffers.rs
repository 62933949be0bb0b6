//! Meshes an engine keeps in its own `VkBuffer`s ([`crate::Shadows::add_mesh_buffers`]).
//!
//! umbra neither reads nor copies them: every pass that draws the mesh (shadow maps, the
//! visibility passes, a depth rebuild) binds the engine's buffers at their offsets and strides
//! (umbra's surface pipelines take their vertex strides as dynamic state). On the CPU umbra
//! keeps only the bounds the engine gave, as a mesh of two points and no triangle, which is all
//! culling and shadow-map fitting read. Shadow volumes, the hybrid and silhouette maps build geometry from the triangles on
//! the CPU, so a light using them refuses instances of such meshes that cast shadows.

use crate::{RenderError, RenderResult};
use glam::Vec3;
use umbra_scene::limits::{MAX_INDICES, MAX_VERTICES};
use umbra_scene::{Aabb, Mesh, MAX_COORDINATE};
use umbra_vk::{vk, VertexStreamBinding};

/// One vertex attribute in an engine's buffer: three 32-bit floats per vertex, `stride`
/// bytes apart.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct VertexStream {
    /// The buffer: created with `VERTEX_BUFFER` usage.
    pub buffer: vk::Buffer,
    /// The buffer's size in bytes: umbra checks every read against it.
    pub buffer_size: u64,
    /// Byte offset of the first vertex's attribute: a multiple of 4.
    pub offset: u64,
    /// Bytes from one vertex's attribute to the next: a multiple of 4, at least the format's
    /// size, at most 2048 (the smallest `maxVertexInputBindingStride`).
    pub stride: u32,
    /// `R32G32B32_SFLOAT`, or `R32G32B32A32_SFLOAT` whose fourth component is ignored.
    pub format: vk::Format,
}

/// A triangle list's indices in an engine's buffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct IndexStream {
    /// The buffer: created with `INDEX_BUFFER` usage.
    pub buffer: vk::Buffer,
    /// The buffer's size in bytes: umbra checks every read against it.
    pub buffer_size: u64,
    /// Byte offset of the first index: a multiple of the index size.
    pub offset: u64,
    /// `UINT16` or `UINT32`.
    pub index_type: vk::IndexType,
    /// Number of indices: a multiple of 3, each below the mesh's `vertex_count` (umbra cannot
    /// check values it never reads on the CPU).
    pub count: u32,
}

/// A mesh whose positions, normals and indices stay in the engine's buffers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshBuffers {
    /// Object-space positions.
    pub positions: VertexStream,
    /// Unit object-space normals (the visibility passes' normal offset and facing use them).
    pub normals: VertexStream,
    /// Number of vertices in each stream.
    pub vertex_count: u32,
    /// The triangles.
    pub indices: IndexStream,
    /// Object-space bounds of the positions: culling and shadow-map fitting use them, so a
    /// box smaller than the mesh cuts shadows off, a larger one only costs map resolution.
    pub bounds: Aabb,
}

/// The largest stride accepted: the smallest `maxVertexInputBindingStride` Vulkan allows.
const MAX_STRIDE: u32 = 2048;

/// The bytes of one vertex attribute umbra's shaders read.
const ATTRIBUTE_BYTES: u64 = 12;

impl MeshBuffers {
    /// A typed error naming the first field umbra cannot use.
    pub(crate) fn validate(&self) -> RenderResult<()> {
        let count = |what: &str, n: u32, limit: usize| match n as usize {
            0 => Err(field(what, "must be at least 1".into())),
            n if n > limit => Err(field(what, format!("{n} is over umbra's limit of {limit}"))),
            _ => Ok(()),
        };
        count("vertex_count", self.vertex_count, MAX_VERTICES)?;
        count("indices.count", self.indices.count, MAX_INDICES)?;
        self.positions.validate("positions", self.vertex_count)?;
        self.normals.validate("normals", self.vertex_count)?;
        self.indices.validate()?;
        let b = self.bounds;
        let inside = |v: Vec3| v.is_finite() && v.abs().max_element() <= MAX_COORDINATE;
        if !(inside(b.min) && inside(b.max) && b.min.cmple(b.max).all()) {
            let why = format!("{b:?}: needs finite corners within ±{MAX_COORDINATE:e}, min ≤ max on every axis");
            return Err(field("bounds", why));
        }
        Ok(())
    }

    /// What umbra keeps on the CPU: the bounds' two corners, no triangle.
    pub(crate) fn placeholder(&self, name: String) -> RenderResult<Mesh> {
        let (b, up) = (self.bounds, Vec3::Y);
        Ok(Mesh::new(name, vec![b.min, b.max], vec![up, up], Vec::new())?)
    }

    /// The vertex bindings of umbra's surface pipelines: positions, then normals.
    pub(crate) fn streams(&self) -> [VertexStreamBinding; 2] {
        let bind =
            |s: VertexStream| VertexStreamBinding { buffer: s.buffer, offset: s.offset, stride: s.stride.into() };
        [bind(self.positions), bind(self.normals)]
    }
}

impl VertexStream {
    fn validate(&self, name: &str, vertices: u32) -> RenderResult<()> {
        let at = |f: &str| format!("{name}.{f}");
        if self.buffer == vk::Buffer::null() {
            return Err(field(&at("buffer"), "is VK_NULL_HANDLE".into()));
        }
        let size = match self.format {
            vk::Format::R32G32B32_SFLOAT => 12,
            vk::Format::R32G32B32A32_SFLOAT => 16,
            f => return Err(field(&at("format"), format!("{f:?}: R32G32B32_SFLOAT or R32G32B32A32_SFLOAT"))),
        };
        if !(size..=MAX_STRIDE).contains(&self.stride) || self.stride % 4 != 0 {
            let why = format!("{}: a multiple of 4 from the format's {size} bytes to {MAX_STRIDE}", self.stride);
            return Err(field(&at("stride"), why));
        }
        if self.offset % 4 != 0 {
            return Err(field(&at("offset"), format!("{} is not a multiple of 4", self.offset)));
        }
        let end = u64::from(vertices - 1)
            .checked_mul(u64::from(self.stride))
            .and_then(|e| e.checked_add(self.offset))
            .and_then(|e| e.checked_add(ATTRIBUTE_BYTES));
        within(&at("offset"), end, self.buffer_size, &format!("{vertices} vertices {} bytes apart", self.stride))
    }
}

impl IndexStream {
    /// Bytes per index.
    pub(crate) fn index_size(&self) -> u64 {
        if self.index_type == vk::IndexType::UINT16 {
            2
        } else {
            4
        }
    }

    fn validate(&self) -> RenderResult<()> {
        if self.buffer == vk::Buffer::null() {
            return Err(field("indices.buffer", "is VK_NULL_HANDLE".into()));
        }
        if !matches!(self.index_type, vk::IndexType::UINT16 | vk::IndexType::UINT32) {
            return Err(field("indices.index_type", format!("{:?}: UINT16 or UINT32", self.index_type)));
        }
        if self.count % 3 != 0 {
            return Err(field("indices.count", format!("{} is not a multiple of 3", self.count)));
        }
        let size = self.index_size();
        if self.offset % size != 0 {
            return Err(field("indices.offset", format!("{} is not a multiple of the index size {size}", self.offset)));
        }
        let end = self.offset.checked_add(size * u64::from(self.count));
        within("indices.offset", end, self.buffer_size, &format!("{} indices", self.count))
    }
}

/// An error unless the read ending at byte `end` lies inside a buffer of `size` bytes.
fn within(name: &str, end: Option<u64>, size: u64, what: &str) -> RenderResult<()> {
    match end {
        Some(end) if end <= size => Ok(()),
        Some(end) => Err(field(name, format!("{what} end at byte {end}, past the buffer's {size} bytes"))),
        None => Err(field(name, format!("{what} overflow a 64-bit offset"))),
    }
}

fn field(name: &str, why: String) -> RenderError {
    RenderError::InvalidInput { field: format!("MeshBuffers::{name}"), why }
}

#[cfg(test)]
mod tests {
    use super::*;
    use umbra_vk::vk::Handle;

    fn stream(buffer: u64, offset: u64, stride: u32) -> VertexStream {
        VertexStream {
            buffer: vk::Buffer::from_raw(buffer),
            buffer_size: 1 << 20,
            offset,
            stride,
            format: vk::Format::R32G32B32_SFLOAT,
        }
    }

    fn mesh(positions: VertexStream, normals: VertexStream) -> MeshBuffers {
        MeshBuffers {
            positions,
            normals,
            vertex_count: 4,
            indices: IndexStream {
                buffer: vk::Buffer::from_raw(9),
                buffer_size: 1 << 20,
                offset: 8,
                index_type: vk::IndexType::UINT32,
                count: 6,
            },
            bounds: Aabb { min: Vec3::ZERO, max: Vec3::ONE },
        }
    }

    #[test]
    fn the_engines_layout_is_bound_as_it_is() {
        let [p, n] = mesh(stream(1, 4, 32), stream(2, 16, 32)).streams();
        assert_eq!((p.buffer.as_raw(), p.offset, p.stride), (1, 4, 32));
        assert_eq!((n.buffer.as_raw(), n.offset, n.stride), (2, 16, 32));
    }

    #[test]
    fn every_unusable_field_is_named() {
        let ok = mesh(stream(1, 0, 24), stream(1, 12, 24));
        ok.validate().unwrap();
        type Spoil = fn(&mut MeshBuffers);
        let cases: [(&str, Spoil); 11] = [
            ("MeshBuffers::vertex_count", |m| m.vertex_count = 0),
            ("MeshBuffers::positions.stride", |m| m.positions.stride = 8),
            ("MeshBuffers::positions.stride", |m| m.positions.stride = 4096),
            ("MeshBuffers::normals.offset", |m| m.normals.offset = 2),
            ("MeshBuffers::normals.format", |m| m.normals.format = vk::Format::R16G16B16A16_SFLOAT),
            ("MeshBuffers::positions.offset", |m| m.positions.buffer_size = 80),
            ("MeshBuffers::indices.index_type", |m| m.indices.index_type = vk::IndexType::UINT8_EXT),
            ("MeshBuffers::indices.offset", |m| m.indices.offset = 6),
            ("MeshBuffers::indices.count", |m| m.indices.count = 5),
            ("MeshBuffers::indices.offset", |m| m.indices.offset = u64::MAX - 3),
            ("MeshBuffers::bounds", |m| m.bounds.max = Vec3::splat(f32::NAN)),
        ];
        for (name, spoil) in cases {
            let mut m = ok;
            spoil(&mut m);
            match m.validate() {
                Err(RenderError::InvalidInput { field, why }) => {
                    assert_eq!(field, name, "{why}");
                    println!("{field}: {why}");
                }
                other => panic!("{name}: {other:?}"),
            }
        }
    }
}
