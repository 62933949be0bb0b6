//! The hybrid's conservative depth bounds (`hybrid bounds N`): per texel of a light's map, the
//! least depth any occluder can have over the texel's square and the greatest depth of an
//! occluder triangle that covers all of it (`shaders-glsl/hybrid/bounds.*`). The classification
//! (`hybrid classify N`) decides a pixel from them only where they cannot be wrong; see
//! `docs/techniques/hybrid.md`, "A classification that cannot be wrong".
//!
//! One RG32F 2D-array image per hybrid light, a layer per map face (one for spot and
//! directional lights, six for cube maps): R the nearest bounds, G the covering bounds, both
//! made in one pass per face and kept by `MIN` blending. Triangles are pulled whole from the
//! scene's vertex and index buffers (bound as storage buffers at set 1 of this pass's own
//! layout) and each is drawn once, as a triangle around the texels it may touch, so that each
//! texel's square is tested against the real triangle: no `VK_EXT_conservative_rasterization`
//! and no geometry shader needed.

use crate::frame::PassRecorder;
use crate::gpu_scene::{DrawPush, GpuScene, SceneGeometry};
use crate::retired::Retired;
use crate::shadow_map::frustum::{LightViews, MapKind};
use crate::RenderResult;
use std::sync::Arc;
use umbra_scene::{Adjacency, Scene};
use umbra_vk::{
    vk, Binding, Blend, ColorAttachment, ColorTarget, Context, DepthState, DescriptorSet, DescriptorSetLayout,
    GraphicsPipeline, GraphicsPipelineDesc, Image, ImageDesc, ImageState, ImageView, PipelineLayout, RenderTargets,
    Resource,
};

/// The bounds' format: the light's depth measure as 32-bit floats, nearest (R) and covering (G).
const FORMAT: vk::Format = vk::Format::R32G32_SFLOAT;

/// What a texel bounds before any triangle: nothing (the far end of the light's depth).
const NOTHING: [f32; 4] = [1.0; 4];

/// The bytes of a light's bounds for a map of `map_bytes` (a D32 texel per face texel): twice
/// as many, two 32-bit floats per texel.
pub(crate) fn bytes(map_bytes: u64) -> u64 {
    2 * map_bytes
}

/// One light's bounds image, a view per face to render into, and its 2D-array view (what the
/// classification samples).
struct BoundsTarget {
    image: Image,
    layers: Vec<ImageView>,
    array: ImageView,
}

/// The bounds pipeline, its layout, the scene's geometry set and every hybrid light's bounds
/// image.
pub(crate) struct BoundsPass {
    /// `None` where `R32G32_SFLOAT` cannot blend: a hybrid light is then refused.
    pipeline: Option<GraphicsPipeline>,
    layout: PipelineLayout,
    geometry_layout: DescriptorSetLayout,
    /// The storage-buffer set of the scene geometry it was made for (remade with the geometry).
    geometry: Option<(Arc<SceneGeometry>, DescriptorSet)>,
    /// Per mesh, whether it is closed (this frame's `Adjacency`), reused from frame to frame.
    closed: Vec<bool>,
    /// Bound by lights without bounds (one layer bounding nothing, never read), and its 2D-array
    /// view.
    placeholder: (Image, ImageView),
    targets: Vec<Option<BoundsTarget>>,
}

/// The image of a `resolution` bounds map with `faces` faces.
fn bounds_desc(resolution: u32, faces: u32) -> ImageDesc {
    let usage = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::SAMPLED;
    let mut desc = ImageDesc::new_2d(FORMAT, resolution, resolution).usage(usage);
    desc.layers = faces;
    desc
}

impl BoundsPass {
    /// Builds the pipeline with its own layout: set 0 the scene's (`scene_set_layout`),
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
        // Each texel keeps the least of every bound written to it.
        let least = Blend {
            src: vk::BlendFactor::ONE,
            dst: vk::BlendFactor::ONE,
            op: vk::BlendOp::MIN,
            src_alpha: vk::BlendFactor::ONE,
            dst_alpha: vk::BlendFactor::ONE,
            alpha_op: vk::BlendOp::MIN,
        };
        let target = [ColorTarget {
            format: FORMAT,
            blend: Some(least),
            write_mask: vk::ColorComponentFlags::R | vk::ColorComponentFlags::G,
        }];
        let pipeline = match ctx.capabilities().rg32f_blend {
            true => {
                let mut desc = GraphicsPipelineDesc::new("hybrid bounds", umbra_shaders::hybrid::BOUNDS_VERT);
                desc.fragment = Some(umbra_shaders::hybrid::BOUNDS_FRAG);
                desc.cull = vk::CullModeFlags::NONE;
                desc.depth = DepthState::NONE;
                desc.color_targets = &target;
                Some(GraphicsPipeline::new(ctx, &layout, &desc)?)
            }
            false => None,
        };
        let placeholder = Image::new(ctx, "no hybrid bounds", bounds_desc(1, 1))?;
        let mut rec = ctx.begin_commands("clear the hybrid bounds placeholder")?;
        rec.transition(&[(&placeholder, ImageState::Undefined, ImageState::ColorAttachment)]);
        let clear = [ColorAttachment { image: &placeholder, view: None, clear: Some(NOTHING) }];
        rec.begin_rendering(&RenderTargets { color: &clear, depth: None });
        rec.end_rendering();
        rec.transition(&[(&placeholder, ImageState::ColorAttachment, ImageState::FragmentRead)]);
        ctx.submit_and_wait(rec)?;
        let placeholder_array = placeholder.array_view("no hybrid bounds (array)")?;
        Ok(Self {
            pipeline,
            layout,
            geometry_layout,
            geometry: None,
            closed: Vec::new(),
            placeholder: (placeholder, placeholder_array),
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
        if self.pipeline.is_none() {
            let what = "the hybrid's depth bounds (blending on R32G32_SFLOAT colour attachments)";
            return Err(ctx.unsupported(what).into());
        }
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
            .map(|face| image.layer_view(face, &format!("{name} face {face}")))
            .collect::<Result<_, _>>()?;
        let array = image.array_view(&format!("{name} (array)"))?;
        self.targets[light] = Some(BoundsTarget { image, layers, array });
        Ok(())
    }

    /// Frees the bounds of every light for which `keep` is false (or beyond it).
    pub fn keep_only(&mut self, keep: &[bool], retired: &mut Retired) {
        crate::budget::release_unused(&mut self.targets, keep, retired);
    }

    fn target(&self, light: Option<usize>) -> Option<&BoundsTarget> {
        light.and_then(|l| self.targets.get(l)).and_then(Option::as_ref)
    }

    /// Light `light`'s bounds image, or the placeholder.
    pub fn image(&self, light: Option<usize>) -> &Image {
        self.target(light).map_or(&self.placeholder.0, |t| &t.image)
    }

    /// The view of light `light`'s bounds, or of the placeholder, that its lighting passes
    /// sample (set 1, binding 4).
    pub fn sampled(&self, light: Option<usize>) -> vk::ImageView {
        self.target(light).map_or(self.placeholder.1.raw, |t| t.array.raw)
    }

    /// Records light `light`'s bounds (its image in [`ImageState::ColorAttachment`]): per face,
    /// both bounds of every caster `views` draws into it.
    pub fn record<'a>(
        &'a self,
        cx: &mut PassRecorder<'_, 'a>,
        gpu: &'a GpuScene,
        scene: &Scene,
        light: usize,
        views: &LightViews,
    ) {
        let target = self.targets.get(light).and_then(Option::as_ref);
        let (Some(target), Some((_, geometry)), Some(pipeline)) = (target, &self.geometry, &self.pipeline) else {
            return;
        };
        for (face, view) in target.layers.iter().enumerate() {
            let color = [ColorAttachment { image: &target.image, view: Some(view), clear: Some(NOTHING) }];
            cx.rec.begin_rendering(&RenderTargets { color: &color, depth: None });
            cx.rec.bind_pipeline(pipeline);
            cx.rec.bind_descriptor_set(&self.layout, 0, &gpu.frame.set);
            cx.rec.bind_descriptor_set(&self.layout, 1, geometry);
            for &object in views.casters_of(face) {
                let Some(o) = scene.objects.get(object) else { continue };
                let Some(m) = gpu.geometry.meshes.get(o.mesh).filter(|m| m.index_count > 0) else { continue };
                let closed = self.closed.get(o.mesh).copied().unwrap_or(false);
                let view = (light as u32) << 4 | (face as u32) << 1 | u32::from(closed);
                cx.rec.push_constants(&self.layout, &DrawPush { object: object as u32, view });
                // One triangle around each triangle's texels: bounds.vert.
                let offset = m.vertex_offset.max(0) as u32;
                cx.rec.draw_range_as_instance(m.index_count, m.first_index, offset);
                cx.log.count_draw(u64::from(m.index_count / 3));
            }
            cx.rec.end_rendering();
        }
    }
}
