//! A scene uploaded to the GPU: one vertex and one index buffer for every mesh, the object and
//! light storage buffers, the frame uniforms, and the descriptor set that binds them.
//! Layouts mirror `shaders-glsl/common/scene.glsl`.

use crate::mesh_buffers::MeshBuffers;
use crate::streams::Stream;
use crate::{RenderError, RenderResult};
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};
use std::sync::Arc;
use umbra_scene::{Mesh, Scene};
use umbra_vk::{
    vk, Binding, Buffer, BufferDesc, Capabilities, Context, DescriptorSet, DescriptorSetLayout, Limit, Recorder,
    Resource, VertexAttribute, VertexStreamBinding,
};

/// Interleaved vertex: position then normal.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub(crate) struct Vertex {
    position: [f32; 3],
    normal: [f32; 3],
}

/// The surface pipelines' vertex input ([`umbra_vk::GraphicsPipelineDesc::vertex_streams`]):
/// the position at binding 0, the normal at binding 1, each where its binding starts, so that
/// umbra's interleaved [`Vertex`] buffer and an engine's buffers are bound alike.
pub(crate) const VERTEX_ATTRIBUTES: [VertexAttribute; 2] = [
    VertexAttribute { location: 0, format: vk::Format::R32G32B32_SFLOAT, offset: 0 },
    VertexAttribute { location: 1, format: vk::Format::R32G32B32_SFLOAT, offset: 0 },
];

/// Bytes per vertex.
pub(crate) const VERTEX_STRIDE: u32 = std::mem::size_of::<Vertex>() as u32;

/// `Frame` uniform block (std140).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct FrameUniforms {
    view_proj: [f32; 16],
    camera_position: [f32; 4],
    ambient: [f32; 4],
}

/// One `Object` (std430).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct GpuObject {
    model: [f32; 16],
    normal_matrix: [f32; 16],
    albedo: [f32; 4],
}

/// One `Light` (std430).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct GpuLight {
    position: [f32; 4],
    radiance: [f32; 4],
    spot_direction: [f32; 4],
    spot_params: [f32; 4],
    shadow_params: [f32; 4],
}

/// What the lighting pass needs to know of a light's shadow map this frame.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct GpuShadow {
    /// `SHADOW_NONE` (0), `SHADOW_2D` (1), `SHADOW_CUBE` (2), `SHADOW_SILHOUETTE` (3) or
    /// `SHADOW_SILHOUETTE_CUBE` (4) (`shaders-glsl/common/scene.glsl`).
    pub kind: u32,
    /// Index of the light's first view in the shadow-view buffer.
    pub first_view: u32,
    /// World-space normal offset of the lookup point.
    pub normal_offset: f32,
    /// 1 / the texels per side of one view (a face atlas's faces with their borders).
    pub texel: f32,
    /// Near and far view depths of perspective maps (spot, cube faces).
    pub near: f32,
    pub far: f32,
}

/// Push constants of the forward passes.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub(crate) struct DrawPush {
    /// Index into the object buffer.
    pub object: u32,
    /// Index into the light buffer (forward passes) or the shadow-view buffer (shadow passes).
    pub view: u32,
}

/// Where one mesh's indices and vertices sit: in the shared buffers, or in the engine's.
#[derive(Clone, Copy, Debug)]
pub(crate) struct MeshRange {
    pub first_index: u32,
    pub index_count: u32,
    pub vertex_offset: i32,
    /// The engine's buffers the mesh is drawn from (`Shadows::add_mesh_buffers`).
    pub engine: Option<MeshBuffers>,
}

/// Which mesh buffers a pass has bound, so that consecutive draws rebind only on a change.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Bound {
    Nothing,
    Shared,
    Engine(usize),
}

/// Every mesh of a scene packed in one vertex and one index buffer, kept from frame to frame
/// while every mesh keeps its [revision](umbra_scene::Mesh::revision).
pub(crate) struct SceneGeometry {
    pub vertices: Buffer,
    pub indices: Buffer,
    pub meshes: Vec<MeshRange>,
    /// The revision of each mesh packed, in mesh order.
    revisions: Vec<u64>,
}

impl SceneGeometry {
    /// Mesh `mesh`'s range, `None` for a mesh out of range or without triangles.
    pub fn drawable(&self, mesh: usize) -> Option<&MeshRange> {
        self.meshes.get(mesh).filter(|m| m.index_count > 0)
    }

    /// Draws `mesh` (a [`SceneGeometry::drawable`] one) with the bound surface pipeline,
    /// binding its buffers first unless `bound` says they are; its first `attributes`
    /// streams (1: the position only). Returns the triangles drawn.
    pub fn draw<'a>(&'a self, rec: &mut Recorder<'a>, mesh: usize, attributes: usize, bound: &mut Bound) -> u64 {
        let Some(m) = self.drawable(mesh) else { return 0 };
        let wanted = if m.engine.is_some() { Bound::Engine(mesh) } else { Bound::Shared };
        if *bound != wanted {
            match &m.engine {
                Some(e) => {
                    rec.bind_vertex_streams(&e.streams()[..attributes]);
                    rec.bind_index_stream(e.indices.buffer, e.indices.offset, e.indices.index_type);
                }
                None => {
                    let stream = |offset| VertexStreamBinding {
                        buffer: self.vertices.raw,
                        offset,
                        stride: u64::from(VERTEX_STRIDE),
                    };
                    rec.bind_vertex_streams(&[stream(0), stream(12)][..attributes]);
                    rec.bind_index_stream(self.indices.raw, 0, vk::IndexType::UINT32);
                }
            }
            *bound = wanted;
        }
        match m.engine {
            Some(_) => rec.draw_indexed(m.index_count, 0, 0),
            None => rec.draw_indexed(m.index_count, m.first_index, m.vertex_offset),
        }
        u64::from(m.index_count / 3)
    }

    /// Whether these buffers hold exactly `scene`'s meshes as they are now.
    fn holds(&self, scene: &Scene) -> bool {
        self.revisions.len() == scene.meshes.len()
            && self.revisions.iter().zip(&scene.meshes).all(|(&r, m)| r == m.revision())
    }
}

/// The per-frame buffers — frame uniforms, objects, lights, shadow views — as [`Stream`]s,
/// with the descriptor set that binds them, made again only when a buffer was. Shaders index
/// them by push constants and instance ids, never by their length.
pub(crate) struct FrameBuffers {
    streams: [Stream; 4],
    /// The streams' generations the set was made for.
    generations: [u64; 4],
    pub set: DescriptorSet,
}

impl FrameBuffers {
    /// `previous`'s buffers (new ones where they are too small) holding `data`, with its set
    /// when no buffer changed.
    fn write(
        ctx: &Context,
        layout: &DescriptorSetLayout,
        previous: Option<FrameBuffers>,
        data: [&[u8]; 4],
    ) -> RenderResult<Self> {
        let (mut streams, old) = match previous {
            Some(f) => (f.streams, Some((f.generations, f.set))),
            None => {
                let ssbo = vk::BufferUsageFlags::STORAGE_BUFFER;
                let streams = [
                    Stream::new("frame uniforms", vk::BufferUsageFlags::UNIFORM_BUFFER),
                    Stream::new("objects", ssbo),
                    Stream::new("lights", ssbo),
                    Stream::new("shadow views", ssbo),
                ];
                (streams, None)
            }
        };
        for (stream, d) in streams.iter_mut().zip(data) {
            stream.fill(ctx, d)?;
        }
        let generations = streams.each_ref().map(Stream::generation);
        let set = match old {
            Some((made_for, set)) if made_for == generations => set,
            _ => {
                let resources: Option<Vec<_>> = streams.iter().map(|s| s.buffer().map(Resource::Buffer)).collect();
                let resources = resources.ok_or(umbra_vk::VkError::InvalidDesc {
                    what: "scene set",
                    why: "a per-frame buffer was empty".into(),
                })?;
                DescriptorSet::new(ctx, "scene set", layout, &resources)?
            }
        };
        Ok(Self { streams, generations, set })
    }
}

/// The scene's GPU buffers and descriptor set.
pub(crate) struct GpuScene {
    /// The meshes (shared with the frames before, while unchanged).
    pub geometry: Arc<SceneGeometry>,
    /// Bytes of mesh data this frame uploaded (0 when the geometry was reused).
    pub geometry_uploaded: u64,
    /// Camera, objects, lights and shadow views, with the scene descriptor set.
    pub frame: FrameBuffers,
    /// The meshes' data, when they changed: copied into `geometry` by the frame's first pass.
    pub upload: Option<MeshUpload>,
}

/// The staging buffers of a mesh upload: the frame's `mesh upload` pass copies them into the
/// scene's vertex and index buffers; they live until that frame completed (its slot keeps them).
pub(crate) struct MeshUpload {
    vertices: Buffer,
    indices: Buffer,
}

impl MeshUpload {
    /// Copies the staged meshes into `geometry`'s buffers, visible to every later read.
    pub fn record<'a>(&'a self, rec: &mut Recorder<'a>, geometry: &'a SceneGeometry) {
        rec.copy_staged(&[(&self.vertices, &geometry.vertices), (&self.indices, &geometry.indices)]);
    }
}

/// The set-0 layout every forward pass uses.
pub(crate) fn scene_set_layout(ctx: &Context) -> RenderResult<DescriptorSetLayout> {
    let stages = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT;
    Ok(DescriptorSetLayout::new(
        ctx,
        "scene set layout",
        &[
            Binding { binding: 0, ty: vk::DescriptorType::UNIFORM_BUFFER, stages },
            Binding { binding: 1, ty: vk::DescriptorType::STORAGE_BUFFER, stages },
            Binding { binding: 2, ty: vk::DescriptorType::STORAGE_BUFFER, stages },
            Binding { binding: 3, ty: vk::DescriptorType::STORAGE_BUFFER, stages },
        ],
    )?)
}

/// How many of each thing a frame uploads, for [`check_limits`].
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct SceneCounts {
    pub vertices: usize,
    pub indices: usize,
    pub objects: usize,
    pub lights: usize,
    pub shadow_views: usize,
}

impl SceneCounts {
    /// The counts of `scene` (every mesh packed once), with `shadow_views` views.
    pub fn of(scene: &Scene, shadow_views: usize) -> Self {
        Self::with_engine_meshes(scene, &[], shadow_views)
    }

    /// [`SceneCounts::of`] without the engine's meshes (`imports[i]` for mesh `i`), which
    /// stay in the engine's buffers.
    pub fn with_engine_meshes(scene: &Scene, imports: &[Option<MeshBuffers>], shadow_views: usize) -> Self {
        let count = |i: usize, m: &Mesh| match imports.get(i).and_then(Option::as_ref) {
            Some(_) => (0, 0),
            None => (m.positions.len(), m.indices.len()),
        };
        let counts = || scene.meshes.iter().enumerate().map(|(i, m)| count(i, m));
        Self {
            vertices: counts().map(|c| c.0).sum(),
            indices: counts().map(|c| c.1).sum(),
            objects: scene.objects.len(),
            lights: scene.lights.len(),
            shadow_views,
        }
    }
}

/// A typed [`RenderError::DeviceLimit`] when a buffer of the frame would not fit its device
/// limit: the object, light and shadow-view storage buffers `maxStorageBufferRange` (bound
/// whole), the frame uniforms `maxUniformBufferRange`, the vertex and index buffers
/// `maxBufferSize` and `maxMemoryAllocationSize`. Checked before anything is packed or
/// allocated.
pub(crate) fn check_limits(caps: &Capabilities, counts: SceneCounts) -> RenderResult<()> {
    let storage = Limit::bytes("maxStorageBufferRange", caps.max_storage_buffer_range);
    let uniform = Limit::bytes("maxUniformBufferRange", caps.max_uniform_buffer_range);
    let buffer = [
        Limit::bytes("maxBufferSize", caps.max_buffer_size),
        Limit::bytes("maxMemoryAllocationSize", caps.max_memory_allocation_size),
    ];
    let buffer = if buffer[1].value < buffer[0].value { buffer[1] } else { buffer[0] };
    let checks = [
        (counts.vertices, std::mem::size_of::<Vertex>(), "vertices", "vertex buffer", buffer),
        (counts.indices, std::mem::size_of::<u32>(), "indices", "index buffer", buffer),
        (1, std::mem::size_of::<FrameUniforms>(), "frame", "frame uniforms", uniform),
        (counts.objects, std::mem::size_of::<GpuObject>(), "objects", "object buffer", storage),
        (counts.lights, std::mem::size_of::<GpuLight>(), "lights", "light buffer", storage),
        (counts.shadow_views, std::mem::size_of::<[f32; 16]>(), "shadow views", "shadow-view buffer", storage),
    ];
    for (count, stride, items, buffer, limit) in checks {
        let bytes = (count as u64).saturating_mul(stride as u64);
        if bytes > limit.value {
            return Err(RenderError::DeviceLimit {
                what: format!(
                    "{count} {items} need {bytes} bytes ({}) of {buffer} ({stride} bytes each)",
                    umbra_vk::human_bytes(bytes)
                ),
                limit,
                device: caps.device_name.clone(),
            });
        }
    }
    Ok(())
}

impl GpuScene {
    /// Uploads `scene` as seen from `view`, with each light's shadow-map
    /// parameters (`shadows[i]` for light `i`) and every shadow view-projection. The meshes are
    /// uploaded only when `geometry` does not hold them as they are now, and `frame`'s buffers
    /// (the frame slot's, from its last frame) are rewritten where they are large enough.
    /// Mesh `i` with `imports[i]` is drawn from the engine's buffers instead of its CPU data.
    #[allow(clippy::too_many_arguments)]
    pub fn upload(
        ctx: &Context,
        layout: &DescriptorSetLayout,
        scene: &Scene,
        imports: &[Option<MeshBuffers>],
        view: &crate::view::View,
        shadows: &[GpuShadow],
        shadow_views: &[Mat4],
        geometry: Option<Arc<SceneGeometry>>,
        frame: Option<FrameBuffers>,
    ) -> RenderResult<Self> {
        // `scene` was validated by `Renderer::render`, which alone calls this.
        check_limits(ctx.capabilities(), SceneCounts::with_engine_meshes(scene, imports, shadow_views.len()))?;
        let (reused, previous_frame) = (geometry.filter(|g| g.holds(scene)), frame);
        let packed = if reused.is_none() { Some(pack_meshes(&scene.meshes, imports)) } else { None };

        let frame = FrameUniforms {
            view_proj: view.view_proj.to_cols_array(),
            camera_position: view.position.extend(1.0).to_array(),
            ambient: scene.ambient.extend(0.0).to_array(),
        };
        let objects: Vec<GpuObject> = scene
            .objects
            .iter()
            .map(|o| GpuObject {
                model: o.transform.to_cols_array(),
                normal_matrix: normal_matrix(o.transform).to_cols_array(),
                albedo: o.albedo.extend(if o.receives_shadows { 1.0 } else { 0.0 }).to_array(),
            })
            .collect();
        let lights: Vec<GpuLight> = scene
            .lights
            .iter()
            .enumerate()
            .map(|(i, l)| {
                let sh = shadows.get(i).copied().unwrap_or_default();
                let spot =
                    l.spot.unwrap_or(umbra_scene::Spot { direction: -Vec3::Y, inner_deg: 180.0, outer_deg: 180.0 });
                GpuLight {
                    position: l.position.to_array(),
                    radiance: l.radiance().extend(l.bounded_range().unwrap_or(0.0)).to_array(),
                    spot_direction: spot.direction.extend(spot.outer_deg.to_radians().cos()).to_array(),
                    spot_params: [
                        spot.inner_deg.to_radians().cos(),
                        if l.spot.is_some() { 1.0 } else { 0.0 },
                        sh.kind as f32,
                        sh.first_view as f32,
                    ],
                    shadow_params: [sh.normal_offset, sh.texel, sh.near, sh.far],
                }
            })
            .collect();
        let views: Vec<[f32; 16]> = shadow_views.iter().map(Mat4::to_cols_array).collect();
        let data = [
            bytemuck::bytes_of(&frame),
            nonempty(bytemuck::cast_slice(&objects)),
            nonempty(bytemuck::cast_slice(&lights)),
            nonempty(bytemuck::cast_slice(&views)),
        ];
        let frame = FrameBuffers::write(ctx, layout, previous_frame, data)?;
        let (geometry, staged) = match (reused, packed) {
            (Some(g), _) => (g, None),
            (None, packed) => {
                let (vertices, indices, meshes) = packed.unwrap_or_default();
                let (vertices, indices) =
                    (nonempty(bytemuck::cast_slice(&vertices)), nonempty(bytemuck::cast_slice(&indices)));
                // Storage too: the hybrid's bounds pull whole triangles.
                let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
                let buffer =
                    |name, usage, data: &[u8]| Buffer::new(ctx, name, BufferDesc::gpu_only(data.len() as u64, usage));
                let staged = MeshUpload {
                    vertices: Buffer::staging(ctx, "scene vertices", vertices)?,
                    indices: Buffer::staging(ctx, "scene indices", indices)?,
                };
                let geometry = SceneGeometry {
                    vertices: buffer("scene vertices", usage | vk::BufferUsageFlags::VERTEX_BUFFER, vertices)?,
                    indices: buffer("scene indices", usage | vk::BufferUsageFlags::INDEX_BUFFER, indices)?,
                    meshes,
                    revisions: scene.meshes.iter().map(|m| m.revision()).collect(),
                };
                (Arc::new(geometry), Some(staged))
            }
        };
        let geometry_uploaded = staged.as_ref().map_or(0, |s| s.vertices.desc.size + s.indices.desc.size);
        Ok(Self { geometry, geometry_uploaded, frame, upload: staged })
    }
}

/// Inverse transpose of the model matrix (normals stay perpendicular under non-uniform scale).
fn normal_matrix(model: Mat4) -> Mat4 {
    let m = glam::Mat3::from_mat4(model);
    if m.determinant().abs() < 1e-20 {
        return Mat4::IDENTITY;
    }
    Mat4::from_mat3(m.inverse().transpose())
}

/// Buffers may not be empty: an empty scene still uploads a few zero bytes (never drawn).
fn nonempty(bytes: &[u8]) -> &[u8] {
    const ZEROS: [u8; 16] = [0; 16];
    if bytes.is_empty() {
        &ZEROS
    } else {
        bytes
    }
}

/// Packs `meshes` into one vertex and one index buffer's data; mesh `i` with `imports[i]` is
/// not packed but drawn from the engine's buffers.
fn pack_meshes(meshes: &[Mesh], imports: &[Option<MeshBuffers>]) -> (Vec<Vertex>, Vec<u32>, Vec<MeshRange>) {
    let import = |i: usize| imports.get(i).copied().flatten();
    let cpu = || meshes.iter().enumerate().filter(|(i, _)| import(*i).is_none()).map(|(_, m)| m);
    let mut vertices = Vec::with_capacity(cpu().map(|m| m.positions.len()).sum());
    let mut indices = Vec::with_capacity(cpu().map(|m| m.indices.len()).sum());
    let mut ranges = Vec::with_capacity(meshes.len());
    for (i, m) in meshes.iter().enumerate() {
        let engine = import(i);
        ranges.push(MeshRange {
            first_index: indices.len() as u32,
            index_count: engine.map_or(m.indices.len() as u32, |e| e.indices.count),
            vertex_offset: vertices.len() as i32,
            engine,
        });
        if engine.is_none() {
            let vertex = |(p, n): (&Vec3, &Vec3)| Vertex { position: p.to_array(), normal: n.to_array() };
            vertices.extend(m.positions.iter().zip(&m.normals).map(vertex));
            indices.extend_from_slice(&m.indices);
        }
    }
    (vertices, indices, ranges)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn caps() -> Capabilities {
        Capabilities {
            device_name: "test device".into(),
            max_storage_buffer_range: 128 << 20,
            max_uniform_buffer_range: 1 << 16,
            max_buffer_size: 1 << 30,
            max_memory_allocation_size: 2 << 30,
            ..Capabilities::default()
        }
    }

    #[test]
    fn every_bound_buffer_is_checked_against_its_limit() {
        let max_objects = (128 << 20) / std::mem::size_of::<GpuObject>();
        assert_eq!(max_objects, 932_067, "lavapipe's figure from the fuzzing report");
        let ok = SceneCounts { objects: max_objects, lights: 1, shadow_views: 6, vertices: 3, indices: 3 };
        check_limits(&caps(), ok).expect("at the limit");
        let over_on = |caps: &Capabilities, counts: SceneCounts, limit: &str, text: &str| {
            let err = check_limits(caps, counts).unwrap_err();
            let message = err.to_string();
            assert!(matches!(&err, RenderError::DeviceLimit { limit: l, .. } if l.name == limit), "{message}");
            assert!(message.contains(text) && message.contains("on test device"), "{message}");
        };
        let over = |counts, limit: &str, text: &str| over_on(&caps(), counts, limit, text);
        over(
            SceneCounts { objects: 1_000_000, ..ok },
            "maxStorageBufferRange",
            "1000000 objects need 144000000 bytes (137.3 MiB) of object buffer (144 bytes each), but \
             maxStorageBufferRange is 134217728 bytes (128 MiB)",
        );
        over(SceneCounts { lights: (128 << 20) / 80 + 1, ..ok }, "maxStorageBufferRange", "of light buffer");
        over(SceneCounts { shadow_views: (128 << 20) / 64 + 1, ..ok }, "maxStorageBufferRange", "shadow-view buffer");
        over(SceneCounts { vertices: (1 << 30) / 24 + 1, ..ok }, "maxBufferSize", "of vertex buffer");
        let small_allocations = Capabilities { max_memory_allocation_size: 256 << 20, ..caps() };
        let indices = SceneCounts { indices: (256 << 20) / 4 + 1, ..ok };
        over_on(&small_allocations, indices, "maxMemoryAllocationSize", "of index buffer");
        let tiny = Capabilities { max_uniform_buffer_range: 64, ..caps() };
        let err = check_limits(&tiny, ok).unwrap_err();
        assert!(err.to_string().contains("frame uniforms"), "{err}");
    }
}
