//! `visibility N (rays)`: one shadow ray per receiver pixel of a ray-traced light, walked
//! through the scene's two-level BVH in the fragment shader of a pass over the frame's surfaces
//! (depth EQUAL, as every visibility pass: `shaders-glsl/visibility/ray.frag`,
//! `shaders-glsl/ray/`), into the light's visibility image. The BVH's arrays are storage
//! buffers at set 1 of this pass's own layout: the meshes' nodes and triangles uploaded when a
//! mesh BVH is built again, the top level and instances written every frame into the frame
//! slot's own streams (so a moving caster allocates nothing, and frames in flight never share
//! them).

use super::{BvhInstance, BvhLayout, BvhNode, RayScene, MAX_STACK};
use crate::forward::{self, Bounded};
use crate::frame::PassRecorder;
use crate::gpu_scene::DrawPush;
use crate::light_surfaces::LightSurfaces;
use crate::retired::Retired;
use crate::streams::Streams;
use crate::visibility::VISIBILITY_FORMAT;
use crate::{RenderError, RenderResult};
use umbra_scene::Scene;
use umbra_vk::{
    vk, Binding, Buffer, BufferDesc, ColorTarget, Context, DescriptorSet, DescriptorSetLayout, PipelineLayout, Resource,
};

/// The meshes' arrays on the GPU (nodes and triangles), for one mesh revision of the
/// [`RayScene`]: shared by every frame slot, replaced (the old ones retired) when a mesh BVH
/// is built again.
struct MeshArrays {
    revision: u64,
    /// Counts replacements: a slot's set over older arrays is made again.
    generation: u64,
    nodes: Buffer,
    triangles: Buffer,
}

/// One frame slot's BVH set: its own top level and instances (host-written every frame into
/// the slot's streams, in place while they fit) and the shared mesh arrays, made again only
/// when one of the four buffers was replaced.
pub(crate) struct SlotRays {
    /// The generations of the top-level stream, the instance stream and the mesh arrays.
    key: (u64, u64, u64),
    /// The BVH's four buffers (the layout of [`RayPass::set_layout`]).
    pub set: DescriptorSet,
}

/// The ray pass's pipeline, its layout, the scene's BVH and its mesh arrays on the GPU.
pub(crate) struct RayPass {
    pipeline: Bounded,
    layout: PipelineLayout,
    set_layout: DescriptorSetLayout,
    scene: RayScene,
    meshes: Option<MeshArrays>,
    generation: u64,
}

impl RayPass {
    /// The pipeline over `depth_format` surfaces (and its depth-bounds twin), with its own
    /// layout: set 0 the scene's, set 1 the BVH's storage buffers, the renderer's push constants.
    pub fn new(
        ctx: &Context,
        scene_set_layout: &DescriptorSetLayout,
        depth_format: vk::Format,
        depth_bounds: bool,
        bvh: BvhLayout,
    ) -> RenderResult<Self> {
        // Read by the ray pass's fragments and the ray-traced hybrid's rays (`hybrid::rays`).
        let stages = vk::ShaderStageFlags::FRAGMENT | vk::ShaderStageFlags::COMPUTE;
        let ty = vk::DescriptorType::STORAGE_BUFFER;
        let bindings: Vec<Binding> = (0..4).map(|binding| Binding { binding, ty, stages }).collect();
        let set_layout = DescriptorSetLayout::new(ctx, "ray-traced BVH layout", &bindings)?;
        let push = std::mem::size_of::<DrawPush>() as u32;
        let layout = PipelineLayout::new(ctx, "ray-traced visibility layout", &[scene_set_layout, &set_layout], push)?;
        let target = [ColorTarget::opaque(VISIBILITY_FORMAT)];
        let frag = umbra_shaders::visibility::RAY_FRAG;
        let mut desc = forward::surface_pass_desc("visibility (shadow rays)", frag, depth_format, &[]);
        desc.color_targets = &target;
        let specialization = bvh.specialization();
        desc.specialization = &specialization;
        let pipeline = Bounded::new(ctx, &layout, &desc, depth_bounds)?;
        let scene = RayScene::empty(bvh);
        Ok(Self { pipeline, layout, set_layout, scene, meshes: None, generation: 0 })
    }

    /// Brings the BVH up to `scene`: the mesh arrays uploaded again when a mesh BVH was built
    /// again (the old ones retired: an earlier frame may still read them), the top level and
    /// instances written into this slot's `streams`, and the slot's set made again only when a
    /// buffer under it was replaced.
    pub fn prepare(
        &mut self,
        ctx: &Context,
        scene: &Scene,
        streams: &mut Streams,
        slot: &mut Option<SlotRays>,
        retired: &mut Retired,
    ) -> RenderResult<()> {
        self.scene.update(scene);
        if self.scene.stack_need() > MAX_STACK {
            return Err(RenderError::InvalidInput {
                field: "scene".into(),
                why: format!(
                    "its ray-tracing BVH ({} layout) is {} nodes deep and needs {} stack entries, more than the traversal's {MAX_STACK}",
                    self.scene.layout.name(),
                    self.scene.depth,
                    self.scene.stack_need()
                ),
            });
        }
        self.upload_meshes(ctx, retired)?;
        let s = &self.scene;
        // Never empty: an empty top level is one node with an empty box (min above max), which
        // no ray enters.
        let empty = [BvhNode { min: [f32::INFINITY; 3], max: [f32::NEG_INFINITY; 3], ..Default::default() }];
        streams.ray_top.fill(ctx, if s.top.is_empty() { &empty[..] } else { &s.top[..] })?;
        let none = [BvhInstance::default()];
        streams.ray_instances.fill(ctx, if s.instances.is_empty() { &none[..] } else { &s.instances[..] })?;
        let Some(meshes) = &self.meshes else { return Ok(()) };
        let key = (streams.ray_top.generation(), streams.ray_instances.generation(), meshes.generation);
        if slot.as_ref().is_some_and(|r| r.key == key) {
            return Ok(());
        }
        retired.take(slot);
        let (Some(top), Some(instances)) = (streams.ray_top.buffer(), streams.ray_instances.buffer()) else {
            return Ok(());
        };
        let resources = [top, instances, &meshes.nodes, &meshes.triangles].map(Resource::Buffer);
        let set = DescriptorSet::new(ctx, "ray-traced BVH", &self.set_layout, &resources)?;
        *slot = Some(SlotRays { key, set });
        Ok(())
    }

    /// The mesh arrays, uploaded again when the scene's meshes changed.
    fn upload_meshes(&mut self, ctx: &Context, retired: &mut Retired) -> RenderResult<()> {
        let revision = self.scene.mesh_revision;
        if self.meshes.as_ref().is_some_and(|m| m.revision == revision) {
            return Ok(());
        }
        retired.take(&mut self.meshes);
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let buffer = |name: &str, bytes: &[u8]| -> RenderResult<Buffer> {
            // A buffer is never empty (no mesh has a triangle): 16 bytes no ray reads.
            let bytes = if bytes.is_empty() { &[0u8; 16][..] } else { bytes };
            let mut b = Buffer::new(ctx, name, BufferDesc::cpu_to_gpu(bytes.len() as u64, usage))?;
            b.write(0, bytes)?;
            Ok(b)
        };
        self.generation += 1;
        self.meshes = Some(MeshArrays {
            revision,
            generation: self.generation,
            nodes: buffer("ray BVH mesh nodes", bytemuck::cast_slice(self.scene.mesh_node_words()))?,
            triangles: buffer("ray BVH triangles", bytemuck::cast_slice(&self.scene.triangles))?,
        });
        Ok(())
    }

    /// The BVH as last prepared.
    pub fn scene(&self) -> &RayScene {
        &self.scene
    }

    /// The layout of the BVH's set (its four storage buffers).
    pub fn set_layout(&self) -> &DescriptorSetLayout {
        &self.set_layout
    }

    /// Records the shadow rays of the light of `s` through the slot's BVH set (inside an open
    /// rendering pass with its visibility image as the one colour target and the frame's depth
    /// kept).
    pub fn record<'a>(
        &'a self,
        cx: &mut PassRecorder<'_, 'a>,
        rays: Option<&'a SlotRays>,
        s: LightSurfaces<'a, '_>,
    ) -> RenderResult<()> {
        let Some(rays) = rays else {
            return Err(RenderError::InvalidInput {
                field: format!("light {}", s.light),
                why: "its shadow rays were recorded before the BVH was prepared".into(),
            });
        };
        self.pipeline.bind(cx.rec, s.bounds);
        cx.rec.bind_descriptor_set(&self.layout, 1, &rays.set);
        s.draw(cx, &self.layout);
        Ok(())
    }
}
