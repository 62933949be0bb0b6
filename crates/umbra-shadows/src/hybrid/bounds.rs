//! The hybrid's conservative depth bounds (`hybrid bounds N`): per texel of a light's map, the
//! least depth any occluder can have over the texel's square and the greatest depth of an
//! occluder triangle that covers all of it (`shaders-glsl/hybrid/bounds.*`). The classification
//! (`hybrid classify N`) decides a pixel from them only where they cannot be wrong; see
//! `docs/techniques/hybrid.md`, "A classification that cannot be wrong".
//!
//! One D32 2D-array image per hybrid light: layer `2 f` holds face `f`'s nearest bounds, layer
//! `2 f + 1` its covering bounds (one face for spot and directional lights, six for cube maps).
//! Triangles are pulled whole from the scene's vertex and index buffers (bound as storage
//! buffers at set 1 of this pass's own layout), so that each texel's square is tested against
//! the real triangle: no `VK_EXT_conservative_rasterization` and no geometry shader needed.

use crate::frame::PassRecorder;
use crate::gpu_scene::{DrawPush, GpuScene, SceneGeometry};
use crate::retired::Retired;
use crate::shadow_map::frustum::{LightViews, MapKind};
use crate::RenderResult;
use std::sync::Arc;
use umbra_scene::{Adjacency, Scene};
use umbra_vk::{
    vk, Binding, Context, DepthAttachment, DepthState, DescriptorSet, DescriptorSetLayout, GraphicsPipeline,
    GraphicsPipelineDesc, Image, ImageDesc, ImageState, ImageView, PipelineLayout, RenderTargets, Resource,
};

/// The bounds' format: the light's depth measure as a 32-bit float.
const FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// Layers per map face: nearest, covering.
pub(crate) const LAYERS_PER_FACE: u32 = 2;

/// One light's bounds image and a view per layer to render into.
struct BoundsTarget {
    image: Image,
    layers: Vec<ImageView>,
}

/// The bounds pipelines, their layout, the scene's geometry set and every hybrid light's
/// bounds image.
pub(crate) struct BoundsPass {
    /// `[nearest, covering]`.
    pipelines: [GraphicsPipeline; 2],
    layout: PipelineLayout,
    geometry_layout: DescriptorSetLayout,
    /// The storage-buffer set of the scene geometry it was made for (remade with the geometry).
    geometry: Option<(Arc<SceneGeometry>, DescriptorSet)>,
    /// Per mesh, whether it is closed (this frame's `Adjacency`), reused from frame to frame.
    closed: Vec<bool>,
    /// Bound by lights without bounds (2 layers of depth 1, never read).
    placeholder: Image,
    targets: Vec<Option<BoundsTarget>>,
}

/// The image of a `resolution` bounds map with `faces` faces.
fn bounds_desc(resolution: u32, faces: u32) -> ImageDesc {
    let usage = vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::SAMPLED;
    let mut desc = ImageDesc::new_2d(FORMAT, resolution, resolution).usage(usage);
    desc.layers = faces * LAYERS_PER_FACE;
    desc
}

impl BoundsPass {
    /// Builds both pipelines with their own layout: set 0 the scene's (`scene_set_layout`),
    /// set 1 the geometry's storage buffers, the renderer's push constants.
    pub fn new(ctx: &Context, scene_set_layout: &DescriptorSetLayout) -> RenderResult<Self> {
        let stages = vk::ShaderStageFlags::VERTEX;
        let ty = vk::DescriptorType::STORAGE_BUFFER;
        let geometry_layout = DescriptorSetLayout::new(
            ctx,
            "hybrid bounds geometry layout",
            &[Binding { binding: 0, ty, stages }, Binding { binding: 1, ty, stages }],
        )?;
        let push = std::mem::size_of::<DrawPush>() as u32;
        let layout = PipelineLayout::new(ctx, "hybrid bounds layout", &[scene_set_layout, &geometry_layout], push)?;
        let pipeline = |name: &str, bound: u32| -> RenderResult<GraphicsPipeline> {
            let spec = [(0, bound)];
            let mut desc = GraphicsPipelineDesc::new(name, umbra_shaders::hybrid::BOUNDS_VERT);
            desc.fragment = Some(umbra_shaders::hybrid::BOUNDS_FRAG);
            desc.specialization = &spec;
            desc.cull = vk::CullModeFlags::NONE;
            desc.depth = DepthState { compare: vk::CompareOp::LESS, ..DepthState::TEST_AND_WRITE };
            desc.depth_format = FORMAT;
            Ok(GraphicsPipeline::new(ctx, &layout, &desc)?)
        };
        let pipelines = [pipeline("hybrid bounds (nearest)", 0)?, pipeline("hybrid bounds (covering)", 1)?];
        let usage = vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST;
        let placeholder = Image::new(ctx, "no hybrid bounds", bounds_desc(1, 1).usage(usage))?;
        let mut rec = ctx.begin_commands("clear the hybrid bounds placeholder")?;
        rec.transition(&[(&placeholder, ImageState::Undefined, ImageState::TransferDst)]);
        rec.clear_depth_image(&placeholder, 1.0);
        rec.transition(&[(&placeholder, ImageState::TransferDst, ImageState::FragmentRead)]);
        ctx.submit_and_wait(rec)?;
        Ok(Self {
            pipelines,
            layout,
            geometry_layout,
            geometry: None,
            closed: Vec::new(),
            placeholder,
            targets: Vec::new(),
        })
    }

    /// Binds the frame's geometry (its set made again only when the geometry was uploaded
    /// again) and notes which meshes are closed.
    pub fn bind_geometry(
        &mut self,
        ctx: &Context,
        gpu: &GpuScene,
        adjacency: &[Arc<Adjacency>],
        retired: &mut Retired,
    ) -> RenderResult<()> {
        self.closed.clear();
        self.closed.extend(adjacency.iter().map(|a| a.report.closed));
        if self.geometry.as_ref().is_some_and(|(g, _)| Arc::ptr_eq(g, &gpu.geometry)) {
            return Ok(());
        }
        retired.take(&mut self.geometry);
        let g = &gpu.geometry;
        let resources = [Resource::Buffer(&g.vertices), Resource::Buffer(&g.indices)];
        let set = DescriptorSet::new(ctx, "hybrid bounds geometry", &self.geometry_layout, &resources)?;
        self.geometry = Some((Arc::clone(g), set));
        Ok(())
    }

    /// Makes sure light `light` has a bounds image for a `resolution` map of `kind`.
    pub fn prepare(
        &mut self,
        ctx: &Context,
        light: usize,
        resolution: u32,
        kind: MapKind,
        retired: &mut Retired,
    ) -> RenderResult<()> {
        if self.targets.len() <= light {
            self.targets.resize_with(light + 1, || None);
        }
        // The hybrid's maps are 2D or cube maps, never face atlases (only silhouette maps).
        debug_assert!(kind != MapKind::FaceAtlas, "the hybrid's bounds take no face atlas");
        let faces = kind.views();
        let desc = bounds_desc(resolution, faces);
        let fits = self.targets[light]
            .as_ref()
            .is_some_and(|t| t.image.desc.width == resolution && t.image.desc.layers == desc.layers);
        if fits {
            return Ok(());
        }
        retired.take(&mut self.targets[light]);
        let name = format!("hybrid bounds light {light}");
        let image = Image::new(ctx, &name, desc)?;
        let layers = (0..desc.layers)
            .map(|layer| {
                let what = if layer % LAYERS_PER_FACE == 0 { "nearest" } else { "covering" };
                image.layer_view(layer, &format!("{name} face {} {what}", layer / LAYERS_PER_FACE))
            })
            .collect::<Result<_, _>>()?;
        self.targets[light] = Some(BoundsTarget { image, layers });
        Ok(())
    }

    /// Frees the bounds of every light for which `keep` is false (or beyond it).
    pub fn keep_only(&mut self, keep: &[bool], retired: &mut Retired) {
        crate::budget::release_unused(&mut self.targets, keep, retired);
    }

    /// Light `light`'s bounds image, or the placeholder (set 1, binding 4 of its lighting
    /// passes).
    pub fn image(&self, light: Option<usize>) -> &Image {
        light.and_then(|l| self.targets.get(l)).and_then(Option::as_ref).map_or(&self.placeholder, |t| &t.image)
    }

    /// Records light `light`'s bounds (its image in [`ImageState::DepthStencilAttachment`]):
    /// per face, the nearest then the covering bounds of the casters `views` draws into it.
    pub fn record<'a>(
        &'a self,
        cx: &mut PassRecorder<'_, 'a>,
        gpu: &'a GpuScene,
        scene: &Scene,
        light: usize,
        views: &LightViews,
    ) {
        let (Some(target), Some((_, geometry))) = (self.targets.get(light).and_then(Option::as_ref), &self.geometry)
        else {
            return;
        };
        for (layer, view) in target.layers.iter().enumerate() {
            let face = layer / LAYERS_PER_FACE as usize;
            let depth = DepthAttachment { view: Some(view), ..DepthAttachment::cleared(&target.image, 1.0, 0) };
            cx.rec.begin_rendering(&RenderTargets { color: &[], depth: Some(depth) });
            cx.rec.bind_pipeline(&self.pipelines[layer % LAYERS_PER_FACE as usize]);
            cx.rec.bind_descriptor_set(&self.layout, 0, &gpu.frame.set);
            cx.rec.bind_descriptor_set(&self.layout, 1, geometry);
            for &object in views.casters_of(face) {
                let Some(o) = scene.objects.get(object) else { continue };
                let Some(m) = gpu.geometry.meshes.get(o.mesh).filter(|m| m.index_count > 0) else { continue };
                let closed = self.closed.get(o.mesh).copied().unwrap_or(false);
                let view = (light as u32) << 4 | (face as u32) << 1 | u32::from(closed);
                cx.rec.push_constants(&self.layout, &DrawPush { object: object as u32, view });
                // Six vertices (a rectangle) per triangle: bounds.vert.
                let offset = m.vertex_offset.max(0) as u32;
                cx.rec.draw_range_as_instance(2 * m.index_count, 2 * m.first_index, offset);
                cx.log.count_draw(u64::from(m.index_count / 3));
            }
            cx.rec.end_rendering();
        }
    }
}
