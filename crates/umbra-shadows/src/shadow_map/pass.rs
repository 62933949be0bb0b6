//! The shadow-map pass (Williams' first pass): depth from the light into a D32 map or cube
//! map, then the descriptor set through which the lighting pass compares against it.

use super::atlas;
use super::frustum::MapKind;
use super::map_frame::MapFrame;
use super::settings::{ShadowFilter, ShadowMapSettings};
use crate::frame::PassRecorder;
use crate::gpu_scene::{self, Bound, DrawPush, GpuScene};
use crate::retired::Retired;
use crate::{RenderError, RenderResult};
use umbra_scene::Scene;
use umbra_vk::{
    vk, Binding, Context, DepthAttachment, DepthState, DescriptorArena, DescriptorSetLayout, GraphicsPipeline,
    GraphicsPipelineDesc, Image, ImageDesc, ImageLimits, ImageState, ImageView, Limit, PipelineLayout, Recorder,
    RenderTargets, Resource, Sampler, SamplerDesc,
};

/// Shadow maps are single-channel 32-bit float depth.
pub(crate) const FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// Bytes per texel of [`FORMAT`].
const MAP_TEXEL_BYTES: u64 = 4;

/// The image of a `resolution` map of `kind`: a depth attachment that is sampled.
fn map_desc(resolution: u32, kind: MapKind) -> ImageDesc {
    let usage = vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::SAMPLED;
    match kind {
        MapKind::Single => ImageDesc::new_2d(FORMAT, resolution, resolution).usage(usage),
        MapKind::Cube => ImageDesc::new_cube(FORMAT, resolution).usage(usage),
        MapKind::FaceAtlas => {
            let (width, height) = kind.extent(resolution);
            ImageDesc::new_2d(FORMAT, width, height).usage(usage)
        }
    }
}

/// The largest `resolution` whose map of `kind` stays within `limits`, and the limit that sets it.
fn max_resolution(kind: MapKind, limits: &ImageLimits) -> (u64, Limit) {
    // Faces across and down one image, and the texels each face adds to the resolution.
    let (across, down, border) = match kind {
        MapKind::Single | MapKind::Cube => (1, 1, 0),
        MapKind::FaceAtlas => (u64::from(atlas::COLUMNS), u64::from(atlas::ROWS), u64::from(2 * atlas::FACE_BORDER)),
    };
    let by_width = (limits.width, (limits.width.value / across).saturating_sub(border));
    let by_height = (limits.height, (limits.height.value / down).saturating_sub(border));
    let face_texels = limits.bytes.value / (u64::from(kind.views()) * MAP_TEXEL_BYTES);
    let by_bytes = (limits.bytes, face_texels.isqrt().saturating_sub(border));
    let (limit, max) = [by_width, by_height, by_bytes].into_iter().min_by_key(|&(_, max)| max).unwrap_or(by_width);
    (max, limit)
}

/// One light's shadow map: the image, its resolution (texels per side, or per face interior
/// of a face atlas) and, for cube maps, a view per face to render into.
pub(crate) struct ShadowTarget {
    image: Image,
    resolution: u32,
    faces: Vec<ImageView>,
}

/// Pipelines, sampler and targets of the shadow-map technique.
pub(crate) struct ShadowMapPass {
    settings: ShadowMapSettings,
    pipeline: GraphicsPipeline,
    sampler: Sampler,
    /// Nearest, no comparison: raw depth and silhouette points.
    raw_sampler: Sampler,
    placeholder_2d: Image,
    placeholder_cube: Image,
    targets: Vec<Option<ShadowTarget>>,
}

/// Set 1 of the lighting pass, for the light being drawn: 0 its 2D map and 1 its cube map
/// (comparison sampler), 2 its 2D map read raw, 3 its silhouette map, 4 the hybrid's depth
/// bounds (all three nearest, no comparison). Lights without one bind placeholders.
pub(crate) fn shadow_set_layout(ctx: &Context) -> RenderResult<DescriptorSetLayout> {
    let ty = vk::DescriptorType::COMBINED_IMAGE_SAMPLER;
    let stages = vk::ShaderStageFlags::FRAGMENT;
    let bindings: Vec<Binding> = (0..5).map(|binding| Binding { binding, ty, stages }).collect();
    Ok(DescriptorSetLayout::new(ctx, "shadow set layout", &bindings)?)
}

impl ShadowMapPass {
    /// Builds the depth pipeline (against the renderer's shared `layout`) and the sampler.
    pub fn new(ctx: &Context, layout: &PipelineLayout, settings: ShadowMapSettings) -> RenderResult<Self> {
        if !ctx.capabilities().depth32_sampled {
            return Err(ctx.unsupported("D32_SFLOAT as a sampled depth attachment (shadow maps)").into());
        }
        let mut desc = GraphicsPipelineDesc::new("shadow map depth", umbra_shaders::shadow_map::DEPTH_VERT);
        desc.vertex_stride = gpu_scene::VERTEX_STRIDE;
        desc.vertex_attributes = &gpu_scene::VERTEX_ATTRIBUTES[..1];
        desc.vertex_streams = true;
        // Open meshes and mirrored cube faces: both sides of every triangle occlude.
        desc.cull = vk::CullModeFlags::NONE;
        desc.depth = DepthState { compare: vk::CompareOp::LESS, bias: true, ..DepthState::TEST_AND_WRITE };
        desc.depth_format = FORMAT;
        let pipeline = GraphicsPipeline::new(ctx, layout, &desc)?;
        let filter = match settings.filter {
            ShadowFilter::Pcf2x2 => vk::Filter::LINEAR,
            _ => vk::Filter::NEAREST,
        };
        let sampler = Sampler::new(
            ctx,
            &format!("shadow map sampler ({})", settings.filter.name()),
            SamplerDesc {
                filter,
                address: vk::SamplerAddressMode::CLAMP_TO_EDGE,
                compare: Some(vk::CompareOp::LESS_OR_EQUAL),
            },
        )?;
        let raw_sampler = Sampler::new(
            ctx,
            "shadow map raw sampler",
            SamplerDesc { filter: vk::Filter::NEAREST, address: vk::SamplerAddressMode::CLAMP_TO_EDGE, compare: None },
        )?;
        let usage = vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST;
        let placeholder_2d = Image::new(ctx, "no shadow map", ImageDesc::new_2d(FORMAT, 1, 1).usage(usage))?;
        let placeholder_cube = Image::new(ctx, "no shadow cube", ImageDesc::new_cube(FORMAT, 1).usage(usage))?;
        let mut rec = ctx.begin_commands("clear shadow placeholders")?;
        let (undefined, dst, read) = (ImageState::Undefined, ImageState::TransferDst, ImageState::FragmentRead);
        rec.transition(&[(&placeholder_2d, undefined, dst), (&placeholder_cube, undefined, dst)]);
        rec.clear_depth_image(&placeholder_2d, 1.0);
        rec.clear_depth_image(&placeholder_cube, 1.0);
        rec.transition(&[(&placeholder_2d, dst, read), (&placeholder_cube, dst, read)]);
        ctx.submit_and_wait(rec)?;
        Ok(Self { settings, pipeline, sampler, raw_sampler, placeholder_2d, placeholder_cube, targets: Vec::new() })
    }

    /// The settings the pass was built with.
    pub fn settings(&self) -> &ShadowMapSettings {
        &self.settings
    }

    /// Checks that light `light` can have a `resolution` map of `kind` on this device: at
    /// least [`ShadowMapSettings::MIN_RESOLUTION`] and within every limit of a sampled D32 depth
    /// attachment ([`Context::image_limits`]); returns the bytes its texels take.
    pub fn check(&self, ctx: &Context, light: usize, resolution: u32, kind: MapKind) -> RenderResult<u64> {
        let desc = map_desc(resolution.max(1), kind);
        let limits = ctx.image_limits(&desc)?;
        // The largest side every limit takes (texel bytes included), and the limit that sets it.
        let (max, binding) = max_resolution(kind, &limits);
        let min = ShadowMapSettings::MIN_RESOLUTION;
        let over = u64::from(resolution) > max || limits.broken_by(&desc).is_some();
        if resolution < min || over {
            let device = &ctx.capabilities().device_name;
            return Err(RenderError::InvalidShadowMap {
                light,
                resolution,
                why: format!("must be {min}..={max} texels per side on {device}: {binding}"),
                limit: over.then_some(binding),
            });
        }
        Ok(crate::budget::desc_bytes(&desc, MAP_TEXEL_BYTES))
    }

    /// Makes sure light `light` has a map of `resolution` and `kind`, (re)creating it if not;
    /// a new map is checked first ([`Self::check`]), a kept one was when it was made.
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
        let desc = map_desc(resolution, kind);
        let fits = self.targets[light].as_ref().is_some_and(|t| {
            let d = &t.image.desc;
            (d.width, d.height, d.cube) == (desc.width, desc.height, desc.cube)
        });
        if fits {
            return Ok(());
        }
        self.check(ctx, light, resolution, kind)?;
        retired.take(&mut self.targets[light]);
        let name = format!("shadow map light {light}");
        let image = Image::new(ctx, &name, desc)?;
        let faces = match kind {
            MapKind::Single | MapKind::FaceAtlas => Vec::new(),
            MapKind::Cube => {
                (0..atlas::FACES).map(|f| image.layer_view(f, &format!("{name} face {f}"))).collect::<Result<_, _>>()?
            }
        };
        self.targets[light] = Some(ShadowTarget { image, resolution, faces });
        Ok(())
    }

    /// Frees the maps of every light for which `keep` is false (or beyond it): a frame holds
    /// only the maps it uses.
    pub fn keep_only(&mut self, keep: &[bool], retired: &mut Retired) {
        crate::budget::release_unused(&mut self.targets, keep, retired);
    }

    /// Records the depth pass of light `light` (prepared with [`ShadowMapPass::prepare`], its map
    /// in [`ImageState::DepthStencilAttachment`]): one rendering per map layer, casters front
    /// to back; a face atlas is one rendering, each face drawn into its tile.
    /// The map's `bias_clamp` limits the depth bias (map depth units, 0 = no limit).
    pub fn record<'a>(
        &'a self,
        cx: &mut PassRecorder<'_, 'a>,
        layout: &'a PipelineLayout,
        gpu: &'a GpuScene,
        scene: &Scene,
        light: usize,
        map: &MapFrame,
    ) -> RenderResult<()> {
        let (rec, log) = (&mut *cx.rec, &mut *cx.log);
        let (views, first_view, bias_clamp) = (&map.views, map.shadow.first_view, map.bias_clamp);
        let target = self.target(light)?;
        // A depth rendering into one cube face, or into the whole map, cleared to 1.
        let begin = |rec: &mut Recorder<'a>, view: Option<&'a ImageView>| {
            rec.begin_rendering(&RenderTargets {
                color: &[],
                depth: Some(DepthAttachment { view, ..DepthAttachment::cleared(&target.image, 1.0, 0) }),
            });
            rec.bind_pipeline(&self.pipeline);
            rec.set_depth_bias(self.settings.bias.constant, bias_clamp, self.settings.effective_slope());
            rec.bind_descriptor_set(layout, 0, &gpu.frame.set);
        };
        // View `layer`'s casters, with its view-projection.
        let mut draw = |rec: &mut Recorder<'a>, layer: usize| {
            let mut bound = Bound::Nothing;
            for &object in views.casters_of(layer) {
                let Some(mesh) = scene.objects.get(object).map(|o| o.mesh) else { continue };
                if gpu.geometry.drawable(mesh).is_none() {
                    continue;
                }
                rec.push_constants(layout, &DrawPush { object: object as u32, view: first_view + layer as u32 });
                log.count_draw(gpu.geometry.draw(rec, mesh, 1, &mut bound));
            }
        };
        match views.kind {
            // One rendering: each face drawn into its tile.
            MapKind::FaceAtlas => {
                begin(rec, None);
                for face in 0..views.views.len() {
                    rec.set_viewport_rect(atlas::face_rect(face as u32, target.resolution));
                    draw(rec, face);
                }
                rec.end_rendering();
            }
            MapKind::Single | MapKind::Cube => {
                for layer in 0..views.views.len() {
                    begin(rec, target.faces.get(layer));
                    draw(rec, layer);
                    rec.end_rendering();
                }
            }
        }
        Ok(())
    }

    /// Set 1 for light `light`: its map, or the placeholders (depth 1, never sampled: the
    /// light's shadow kind is `SHADOW_NONE`) when it has none this frame, compared through the
    /// settings' filter; and
    /// `technique_image` at binding 3 (the light's silhouette map, the hybrid's silhouette-pixel
    /// classes, or a placeholder) and `bounds` at binding 4 (the view of the hybrid's depth
    /// bounds, or of a placeholder).
    /// The set comes from `arena` (this frame's); its index there is returned.
    pub fn descriptor_set(
        &self,
        arena: &mut DescriptorArena,
        layout: &DescriptorSetLayout,
        light: Option<usize>,
        technique_image: &Image,
        bounds: vk::ImageView,
    ) -> RenderResult<usize> {
        let target = light.and_then(|l| self.targets.get(l)).and_then(Option::as_ref);
        let (single, cube) = match target {
            Some(t) if t.image.desc.cube => (&self.placeholder_2d, &t.image),
            Some(t) => (&t.image, &self.placeholder_cube),
            None => (&self.placeholder_2d, &self.placeholder_cube),
        };
        let view = |view: vk::ImageView, sampler: &Sampler| Resource::SampledImage {
            view,
            sampler: sampler.raw,
            layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        };
        let sampled = |image: &Image, sampler: &Sampler| view(image.view, sampler);
        let name = match light {
            Some(l) => format!("shadow set light {l}"),
            None => "shadow set (none)".to_owned(),
        };
        let (compare, raw) = (&self.sampler, &self.raw_sampler);
        let resources = [
            sampled(single, compare),
            sampled(cube, compare),
            sampled(single, raw),
            sampled(technique_image, raw),
            view(bounds, raw),
        ];
        Ok(arena.allocate(&name, layout, &resources)?)
    }

    /// Light `light`'s map (after [`Self::prepare`]).
    pub fn image(&self, light: usize) -> RenderResult<&Image> {
        Ok(&self.target(light)?.image)
    }

    fn target(&self, light: usize) -> RenderResult<&ShadowTarget> {
        self.targets.get(light).and_then(Option::as_ref).ok_or(RenderError::InvalidShadowMap {
            light,
            resolution: 0,
            why: "recorded before `prepare`".into(),
            limit: None,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn limits(width: u64, height: u64, bytes: u64) -> ImageLimits {
        let limit = |name, value, bytes| Limit { name, value, bytes };
        ImageLimits {
            width: limit("maxImageDimension2D", width, false),
            height: limit("maxFramebufferHeight", height, false),
            layers: limit("maxImageArrayLayers", 2048, false),
            bytes: limit("maxMemoryAllocationSize", bytes, true),
        }
    }

    #[test]
    fn the_largest_resolution_of_each_kind_names_its_limit() {
        let (max, limit) = max_resolution(MapKind::Single, &limits(16384, 8192, u64::MAX));
        assert_eq!((max, limit.name), (8192, "maxFramebufferHeight"));
        // Six faces of 4-byte texels in 1 GiB: 6 * 4 * 6688² fits, 6689² does not.
        let (max, limit) = max_resolution(MapKind::Cube, &limits(16384, 16384, 1 << 30));
        assert_eq!((max, limit.name), (6688, "maxMemoryAllocationSize"));
        // A face atlas: three faces with their borders across 16384 texels, two down 16384.
        let (max, limit) = max_resolution(MapKind::FaceAtlas, &limits(16384, 16384, u64::MAX));
        assert_eq!((max, limit.name), (16384 / 3 - 4, "maxImageDimension2D"));
        let (w, h) = MapKind::FaceAtlas.extent(max as u32);
        assert!(w <= 16384 && h <= 16384);
        assert!(MapKind::FaceAtlas.extent(max as u32 + 1).0 > 16384, "one more texel breaks the width");
        let (max, limit) = max_resolution(MapKind::FaceAtlas, &limits(32768, 32768, 1 << 30));
        assert_eq!((max, limit.name), (6688 - 4, "maxMemoryAllocationSize"));
    }
}
