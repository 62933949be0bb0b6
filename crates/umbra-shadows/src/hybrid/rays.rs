//! The ray-traced hybrid (`Technique::HybridRt`): Chan–Durand's classification with shadow rays
//! where the paper draws volumes, as AMD's FidelityFX Hybrid Shadows and Hertel et al. (2009)
//! do. Per light, after its shadow map's depth bounds (`hybrid bounds N`):
//! 1. `hybrid ray list N`: the list's header reset (a `VkDispatchIndirectCommand` of 0, 1, 1
//!    and a count of 0);
//! 2. `hybrid classify N` (`hybrid/classify_rays.frag`): the hybrid's conservative
//!    classification writes the visibility of every pixel the bounds decide and appends the
//!    exact reference's shadow ray of every other one, a *silhouette pixel*, to the list,
//!    counting the dispatch's workgroups as it goes;
//! 3. `hybrid rays N` (`hybrid/rays.comp`): one invocation per listed ray, dispatched
//!    indirectly, walks the scene's BVH (`crate::ray_traced`) and writes its pixel's
//!    visibility. Its cost follows the silhouette pixels (P), not the volumes' fill.
//!
//! The list is sized for one ray per pixel of the frame (bounded by `maxStorageBufferRange`):
//! two fragments at one pixel and one depth both append, and rays beyond the list are counted,
//! not cast ([`crate::HybridRtReport::rays_dropped`]). A workgroup casts 64 rays (`RAY_GROUP`
//! in `hybrid/ray_list.glsl`, the local size of `hybrid/rays.comp`).

use crate::forward;
use crate::frame::PassRecorder;
use crate::gpu_scene::{DrawPush, GpuScene};
use crate::retired::Retired;
use crate::shadow_map::ShadowMapSettings;
use crate::visibility::VISIBILITY_FORMAT;
use crate::RenderResult;
use umbra_scene::Scene;
use umbra_vk::{
    vk, Binding, Buffer, BufferDesc, Capabilities, ColorAttachment, ColorTarget, ComputePipeline, Context,
    DepthAttachment, DescriptorSet, DescriptorSetLayout, GraphicsPipeline, Image, ImageDesc, PipelineLayout,
    RenderTargets, Resource,
};

/// Bytes of one list entry (`RayEntry`: origin, pixel, direction, extent).
const ENTRY_BYTES: u64 = 32;

/// Bytes of the list's header: the dispatch's workgroup counts and the rays appended.
const HEADER_BYTES: u64 = 16;

/// Whether the device runs the ray-traced hybrid: its classification appends to the list from
/// fragment shaders and its rays write the visibility image from a compute shader on the
/// graphics queue ([`crate::visibility::storage_supported`]).
pub(crate) fn supported(caps: &Capabilities) -> bool {
    crate::visibility::storage_supported(caps)
}

/// Why the device cannot run the ray-traced hybrid (for [`crate::RenderError::UnsupportedLight`]).
pub(crate) const UNSUPPORTED: &str = "the ray-traced hybrid needs fragmentStoresAndAtomics, \
     shaderStorageImageExtendedFormats and a graphics queue that runs compute; use ray_traced";

/// The list of one frame's rays (shared by the hybrid-RT lights of a frame, one after the other,
/// and by frames in flight: the frame graph orders every use), and per pixel the index + 1 of
/// the ray that decides it (R32_UINT, written as the classification's third attachment: the
/// later fragment in primitive order wins, as in every visibility pass).
struct RayList {
    /// Rays it holds.
    capacity: u64,
    header: Buffer,
    entries: Buffer,
    set: DescriptorSet,
    pixel_rays: Image,
}

/// The format of the per-pixel ray index.
const PIXEL_RAYS_FORMAT: vk::Format = vk::Format::R32_UINT;

/// The pipelines, the ray list and the per-light sets of the ray-traced hybrid.
pub(crate) struct HybridRays {
    classify: GraphicsPipeline,
    classify_layout: PipelineLayout,
    trace: ComputePipeline,
    trace_layout: PipelineLayout,
    list_layout: DescriptorSetLayout,
    output_layout: DescriptorSetLayout,
    list: Option<RayList>,
    /// Per light, the set of its visibility image as the rays write it.
    outputs: Vec<Option<(vk::Image, DescriptorSet)>>,
    /// Per light, its list header copied out for the report (umbra's own frames).
    counts: Vec<Option<Buffer>>,
}

/// What one hybrid-RT light's passes read and write.
#[derive(Clone, Copy)]
pub(crate) struct RaysLight<'a> {
    /// Index of the light.
    pub light: usize,
    pub gpu: &'a GpuScene,
    pub scene: &'a Scene,
    /// Set 1 of the classification: its depth bounds and the classes image.
    pub shadow_set: &'a DescriptorSet,
    /// Set 0 of the rays: the scene's BVH (`crate::ray_traced`), this frame slot's.
    pub bvh: &'a DescriptorSet,
    /// Its visibility image, the classes image and the frame's depth.
    pub visibility: &'a Image,
    pub classes: &'a Image,
    pub depth: &'a Image,
}

impl HybridRays {
    /// The pipelines: the classification against the renderer's sets 0 and 1 plus the list,
    /// the rays against the BVH's set layout (`bvh_layout`), the list and the output image.
    pub fn new(
        ctx: &Context,
        scene_set_layout: &DescriptorSetLayout,
        shadow_set_layout: &DescriptorSetLayout,
        bvh_layout: &DescriptorSetLayout,
        depth_format: vk::Format,
        shadow: &ShadowMapSettings,
        bvh: crate::ray_traced::BvhLayout,
    ) -> RenderResult<Self> {
        let storage = vk::DescriptorType::STORAGE_BUFFER;
        let both = vk::ShaderStageFlags::FRAGMENT | vk::ShaderStageFlags::COMPUTE;
        let list = [0, 1].map(|binding| Binding { binding, ty: storage, stages: both });
        let list_layout = DescriptorSetLayout::new(ctx, "hybrid ray list layout", &list)?;
        let (ty, stages) = (vk::DescriptorType::STORAGE_IMAGE, vk::ShaderStageFlags::COMPUTE);
        let images = [0, 1].map(|binding| Binding { binding, ty, stages });
        let output_layout = DescriptorSetLayout::new(ctx, "hybrid ray output layout", &images)?;
        let push = std::mem::size_of::<DrawPush>() as u32;
        let sets = [scene_set_layout, shadow_set_layout, &list_layout];
        let classify_layout = PipelineLayout::new(ctx, "hybrid classify (rays) layout", &sets, push)?;
        let spec = [(1, u32::from(shadow.outside_lit))];
        let frag = umbra_shaders::hybrid::CLASSIFY_RAYS_FRAG;
        let mut desc = forward::surface_pass_desc("hybrid classify (rays)", frag, depth_format, &spec);
        let targets = [
            ColorTarget::opaque(VISIBILITY_FORMAT),
            ColorTarget::opaque(crate::targets::COLOR_FORMAT),
            ColorTarget::opaque(PIXEL_RAYS_FORMAT),
        ];
        desc.color_targets = &targets;
        let classify = GraphicsPipeline::new(ctx, &classify_layout, &desc)?;
        let sets = [bvh_layout, &list_layout, &output_layout];
        let trace_layout = PipelineLayout::new(ctx, "hybrid rays layout", &sets, 0)?;
        let comp = umbra_shaders::hybrid::RAYS_COMP;
        let trace = ComputePipeline::new(ctx, &trace_layout, "hybrid rays", comp, &bvh.specialization())?;
        Ok(Self {
            classify,
            classify_layout,
            trace,
            trace_layout,
            list_layout,
            output_layout,
            list: None,
            outputs: Vec::new(),
            counts: Vec::new(),
        })
    }

    /// Makes sure the list holds a ray per pixel of a `width` × `height` frame (as many as
    /// `maxStorageBufferRange` allows), each of `lights` (index and visibility image) has its
    /// output set and, with `counted`, its header readback.
    pub fn prepare(
        &mut self,
        ctx: &Context,
        width: u32,
        height: u32,
        lights: &[(usize, &Image)],
        counted: bool,
        retired: &mut Retired,
    ) -> RenderResult<()> {
        let range = u64::from(ctx.capabilities().max_storage_buffer_range);
        let capacity = (u64::from(width) * u64::from(height)).min(range / ENTRY_BYTES).max(1);
        let fits = self.list.as_ref().is_some_and(|l| {
            l.capacity == capacity && (l.pixel_rays.desc.width, l.pixel_rays.desc.height) == (width, height)
        });
        if !fits {
            retired.take(&mut self.list);
            // Every light's output set names the old list's pixel image.
            self.outputs.iter_mut().for_each(|o| retired.take(o));
            self.list = Some(self.make_list(ctx, capacity, width, height)?);
        }
        let Some(list) = &self.list else { return Ok(()) };
        let n = lights.iter().map(|&(l, _)| l + 1).max().unwrap_or(0);
        if self.outputs.len() < n {
            self.outputs.resize_with(n, || None);
            self.counts.resize_with(n, || None);
        }
        for &(l, image) in lights {
            if self.outputs[l].as_ref().is_none_or(|(raw, _)| *raw != image.raw) {
                retired.take(&mut self.outputs[l]);
                let resource = [Resource::StorageImage(image.view), Resource::StorageImage(list.pixel_rays.view)];
                let name = format!("hybrid ray output (light {l})");
                self.outputs[l] = Some((image.raw, DescriptorSet::new(ctx, &name, &self.output_layout, &resource)?));
            }
            if counted && self.counts[l].is_none() {
                let name = format!("hybrid ray count readback (light {l})");
                self.counts[l] = Some(Buffer::new(ctx, &name, BufferDesc::readback(HEADER_BYTES))?);
            }
        }
        Ok(())
    }

    fn make_list(&self, ctx: &Context, capacity: u64, width: u32, height: u32) -> RenderResult<RayList> {
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER
            | vk::BufferUsageFlags::INDIRECT_BUFFER
            | vk::BufferUsageFlags::TRANSFER_DST
            | vk::BufferUsageFlags::TRANSFER_SRC;
        let header = Buffer::new(ctx, "hybrid ray list header", BufferDesc::gpu_only(HEADER_BYTES, usage))?;
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let entries = Buffer::new(ctx, "hybrid ray list", BufferDesc::gpu_only(capacity * ENTRY_BYTES, usage))?;
        let resources = [Resource::Buffer(&header), Resource::Buffer(&entries)];
        let set = DescriptorSet::new(ctx, "hybrid ray list", &self.list_layout, &resources)?;
        let usage = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::STORAGE;
        let desc = ImageDesc::new_2d(PIXEL_RAYS_FORMAT, width, height).usage(usage);
        let pixel_rays = Image::new(ctx, "hybrid pixel rays", desc)?;
        Ok(RayList { capacity, header, entries, set, pixel_rays })
    }

    /// The list's header, entries and per-pixel ray index (after [`Self::prepare`]), for the
    /// passes' declarations.
    pub fn list(&self) -> Option<(&Buffer, &Buffer, &Image)> {
        self.list.as_ref().map(|l| (&l.header, &l.entries, &l.pixel_rays))
    }

    /// The layouts of the list's set and of the per-light output sets (sets 1 and 2 of the rays).
    pub fn set_layouts(&self) -> [&DescriptorSetLayout; 2] {
        [&self.list_layout, &self.output_layout]
    }

    /// The list's set and light `light`'s output set (after [`Self::prepare`]).
    pub fn sets(&self, light: usize) -> Option<(&DescriptorSet, &DescriptorSet)> {
        let output = self.outputs.get(light).and_then(Option::as_ref).map(|(_, set)| set)?;
        self.list.as_ref().map(|l| (&l.set, output))
    }

    /// Rays the list holds.
    pub fn capacity(&self) -> u64 {
        self.list.as_ref().map_or(0, |l| l.capacity)
    }

    /// Light `light`'s header readback (umbra's own frames).
    pub fn count_readback(&self, light: usize) -> Option<&Buffer> {
        self.counts.get(light).and_then(Option::as_ref)
    }

    /// Step 1 (the header in TransferDst): no rays, no workgroups.
    pub fn record_reset<'a>(&'a self, cx: &mut PassRecorder<'_, 'a>) {
        if let Some(list) = &self.list {
            cx.rec.update_buffer(&list.header, &[0, 1, 1, 0]);
        }
    }

    /// Step 2 (visibility and classes as colour attachments, the list written by fragments):
    /// the classification, appending the silhouette pixels' rays.
    pub fn record_classify<'a>(&'a self, cx: &mut PassRecorder<'_, 'a>, r: &RaysLight<'a>) {
        let Some(list) = &self.list else { return };
        let color = [
            ColorAttachment { image: r.visibility, view: None, clear: Some([0.0; 4]) },
            ColorAttachment { image: r.classes, view: None, clear: Some([0.0; 4]) },
            ColorAttachment { image: &list.pixel_rays, view: None, clear: Some([0.0; 4]) },
        ];
        cx.rec.begin_rendering(&RenderTargets { color: &color, depth: Some(DepthAttachment::keep(r.depth)) });
        cx.rec.bind_pipeline(&self.classify);
        cx.rec.bind_descriptor_set(&self.classify_layout, 1, r.shadow_set);
        cx.rec.bind_descriptor_set(&self.classify_layout, 2, &list.set);
        crate::light_surfaces::draw_objects(cx.rec, &self.classify_layout, r.gpu, r.scene, r.light as u32, cx.log);
        cx.rec.end_rendering();
    }

    /// Step 3 (the visibility image in ComputeWrite, the list read): the rays, dispatched with
    /// the workgroups the classification counted.
    pub fn record_rays<'a>(&'a self, cx: &mut PassRecorder<'_, 'a>, r: &RaysLight<'a>) {
        let (Some(list), Some(Some((_, output)))) = (&self.list, self.outputs.get(r.light)) else { return };
        cx.rec.bind_compute_pipeline(&self.trace);
        cx.rec.bind_compute_set(&self.trace_layout, 0, r.bvh);
        cx.rec.bind_compute_set(&self.trace_layout, 1, &list.set);
        cx.rec.bind_compute_set(&self.trace_layout, 2, output);
        cx.rec.dispatch_indirect(&list.header, 0);
    }

    /// The header (in TransferSrc) copied into light `light`'s readback.
    pub fn record_count<'a>(&'a self, cx: &mut PassRecorder<'_, 'a>, light: usize) {
        if let (Some(list), Some(out)) = (&self.list, self.count_readback(light)) {
            cx.rec.copy_buffer(&list.header, out, HEADER_BYTES);
        }
    }
}

/// Rays a light's classification appended, read from its header readback once its frame
/// completed.
pub(crate) fn read_count(readback: &Buffer) -> RenderResult<u64> {
    let bytes = readback.read()?;
    let word = |i: usize| bytes.get(4 * i..4 * i + 4).map_or(0, |b| u32::from_ne_bytes([b[0], b[1], b[2], b[3]]));
    Ok(u64::from(word(3)))
}
