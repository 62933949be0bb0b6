//! The per-light visibility image: the one product of every shadow technique. Per shadowed
//! light, the technique's passes write a frame-sized image (`shaders-glsl/visibility/image.glsl`)
//! whose red channel is the light's visibility (1 lit, 0 shadowed, fractions only on a filtered
//! shadow map's edges) and whose green channel is 1 where the light's shadow is in question (a
//! receiver the light reaches). The lighting pass (`forward/light.frag`) multiplies the light's
//! contribution by it; the accuracy measurements compare it with the exact reference
//! ([`VisibilityImage::shadow_mask`]).
//!
//! Who writes it, per technique:
//! - shadow maps and silhouette maps: `visibility N` (`declare_map_light`), a pass over the
//!   frame's surfaces (depth EQUAL, interpolated world positions) with the map lookup
//!   (`visibility/map.frag`);
//! - shadow volumes: `visibility N (stencil)` (`shadow_volume/frame.rs`), the same surfaces
//!   drawn twice through complementary stencil tests, count 0 lit and any other count
//!   shadowed (`visibility/stencil.frag`);
//! - ray tracing: `visibility N (rays)` (`ray_traced/frame.rs`), a shadow ray per pixel;
//! - the hybrid (`hybrid/frame.rs`): its classification writes the map-decided pixels,
//!   `hybrid visibility N` the silhouette pixels from their stencil counts
//!   (`hybrid/classify.frag`, `hybrid/resolve.frag`), or its rays.
//!
//! Each shadowed light has an image of its own (made when the light first needs it, kept while
//! it does), so that every light's shadows are recorded before any light is lit, as an engine
//! records umbra's shadows before its own lighting; RG32F keeps the filtered fractions exact,
//! so the lighting is bit for bit what it was when each pass did its own lookup.

use crate::forward::{self, Bounded};
use crate::frame::{PassId, PassRecorder, Stage, Use};
use crate::light_surfaces::{over_surfaces, LightSurfaces};
use crate::retired::Retired;
use crate::{RenderError, RenderResult};
use std::path::Path;
use umbra_vk::{
    vk, Binding, Buffer, BufferDesc, Capabilities, ColorTarget, Context, DescriptorSet, DescriptorSetLayout,
    GraphicsPipelineDesc, Image, ImageDesc, ImageState, PipelineLayout, Recorder, Resource, Sampler, SamplerDesc,
    StencilFace,
};

/// The visibility image's format: R = visibility, G = 1 where the shadow is in question. 32-bit
/// floats hold a filter's fractions (k/9, k/25) exactly as the lookup computed them.
pub const VISIBILITY_FORMAT: vk::Format = vk::Format::R32G32_SFLOAT;

/// A light's visibility image read back ([`crate::RendererDesc::read_visibility`]), row 0 at the
/// top.
#[derive(Clone, Debug, PartialEq)]
pub struct VisibilityImage {
    /// Index of the light.
    pub light: usize,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Per pixel `[visibility, in question]`: visibility 1 lit, 0 shadowed, in between on a
    /// filtered map's edges; in question 1 on a receiver the light reaches, 0 elsewhere (then
    /// visibility is 1 on surfaces that do not receive shadows, 0 where the light does not reach
    /// and where no surface is).
    pub texels: Vec<[f32; 2]>,
}

impl VisibilityImage {
    /// The visibility at `(x, y)`.
    ///
    /// # Panics
    /// When `(x, y)` lies outside the image, like slice indexing.
    pub fn visibility(&self, x: u32, y: u32) -> f32 {
        self.texels[(y * self.width + x) as usize][0]
    }

    /// The light's shadow mask: per pixel `Some(true)` shadowed, `Some(false)` lit (visibility
    /// over one half, the lighting's threshold for counting a filtered pixel as lit), `None`
    /// where the shadow is not in question.
    pub fn shadow_mask(&self) -> Vec<Option<bool>> {
        self.texels.iter().map(|&[v, decided]| (decided > 0.5).then_some(v <= 0.5)).collect()
    }

    /// Pixels where `classes` (the light's classification mask,
    /// [`crate::LightDiagnostics::shadow_mask`]) decides and this image's mask does not agree.
    /// 0 when both come from the same decisions: where two fragments cover a pixel at one depth
    /// the image keeps the one the light reaches, where the classification may keep the other.
    pub fn disagreements_with(&self, classes: &[Option<bool>]) -> u64 {
        self.shadow_mask().iter().zip(classes).filter(|(v, c)| c.is_some() && v != c).count() as u64
    }

    /// Writes the image as a float EXR: R = G = B = visibility, A = 1 where the shadow is in
    /// question.
    pub fn save_exr(&self, path: &Path) -> RenderResult<()> {
        exr::prelude::write_rgba_file(path, self.width as usize, self.height as usize, |x, y| {
            let [v, decided] = self.texels[y * self.width as usize + x];
            (v, v, v, decided)
        })
        .map_err(|e| RenderError::Output { path: path.to_owned(), message: e.to_string() })
    }
}

/// One shadowed light's frame-sized visibility image and the set its lighting reads it through.
pub(crate) struct LightVisibility {
    pub image: Image,
    /// Set 2 of the light's lighting pass: the image, fetched per pixel.
    pub set: DescriptorSet,
}

/// The shadowed lights' images, the placeholder set of unshadowed lights and the pipelines that
/// write the images for shadow-map, silhouette-map and shadow-volume lights.
pub(crate) struct VisibilityPass {
    /// Per light, its image while it is shadowed.
    images: Vec<Option<LightVisibility>>,
    width: u32,
    height: u32,
    /// Whether the images are also storage images ([`storage_supported`]).
    storage: bool,
    /// Set 2 of an unshadowed light's lighting pass, which never reads it: a 1×1 placeholder.
    pub unshadowed_set: DescriptorSet,
    _placeholder: Image,
    set_layout: DescriptorSetLayout,
    sampler: Sampler,
    map: Bounded,
    /// Shadow volumes: where the stencil count is 0, and where it is not.
    stencil_lit: Bounded,
    stencil_shadowed: Bounded,
}

/// Whether the visibility images are also storage images a technique may write from shaders:
/// fragment shaders store (`fragmentStoresAndAtomics`), RG32F is a storage format
/// (`shaderStorageImageExtendedFormats`) and the graphics queue runs compute.
pub(crate) fn storage_supported(caps: &Capabilities) -> bool {
    caps.fragment_stores_and_atomics && caps.storage_image_extended_formats && caps.compute_queue
}

/// The layout of set 2: the visibility image, read by the lighting pass.
pub(crate) fn set_layout(ctx: &Context) -> RenderResult<DescriptorSetLayout> {
    let binding =
        Binding { binding: 0, ty: vk::DescriptorType::COMBINED_IMAGE_SAMPLER, stages: vk::ShaderStageFlags::FRAGMENT };
    Ok(DescriptorSetLayout::new(ctx, "visibility set layout", &[binding])?)
}

/// The description of the visibility image of a `width` × `height` frame; with `storage`,
/// also a storage image (the ray-traced hybrid's rays write it from a compute shader).
pub(crate) fn image_desc(width: u32, height: u32, storage: bool) -> ImageDesc {
    let mut usage =
        vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_SRC;
    if storage {
        usage |= vk::ImageUsageFlags::STORAGE;
    }
    ImageDesc::new_2d(VISIBILITY_FORMAT, width, height).usage(usage)
}

impl VisibilityPass {
    /// The images' size (`width` × `height`), their sets' layout (`set_layout`, kept) and the
    /// pipelines (against the renderer's `layout`; with `depth_bounds`, their depth-bounds
    /// twins). No light's image is made yet ([`VisibilityPass::keep`]).
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        ctx: &Context,
        layout: &PipelineLayout,
        set_layout: DescriptorSetLayout,
        depth_format: vk::Format,
        lookup: [(u32, u32); 2],
        width: u32,
        height: u32,
        depth_bounds: bool,
    ) -> RenderResult<Self> {
        let sampler = Sampler::new(ctx, "visibility sampler (nearest)", SamplerDesc::NEAREST_CLAMP)?;
        let read = |image: &Image| sampled(image, &sampler);
        // Bound, never read (its contents stay undefined): the pipeline uses set 2 statically.
        let desc = ImageDesc::new_2d(VISIBILITY_FORMAT, 1, 1).usage(vk::ImageUsageFlags::SAMPLED);
        let placeholder = Image::new(ctx, "no visibility image", desc)?;
        let mut rec = ctx.begin_commands("visibility placeholder")?;
        rec.transition(&[(&placeholder, ImageState::Undefined, ImageState::FragmentRead)]);
        ctx.submit_and_wait(rec)?;
        let unshadowed_set =
            DescriptorSet::new(ctx, "visibility set (unshadowed)", &set_layout, &[read(&placeholder)])?;
        let target = [ColorTarget::opaque(VISIBILITY_FORMAT)];
        let frag = umbra_shaders::visibility::MAP_FRAG;
        let mut desc = forward::surface_pass_desc("visibility (map lookup)", frag, depth_format, &lookup);
        desc.color_targets = &target;
        let map = Bounded::new(ctx, layout, &desc, depth_bounds)?;
        let stencil = |name, lit: bool, compare| -> RenderResult<Bounded> {
            let spec = [(0, u32::from(lit))];
            let frag = umbra_shaders::visibility::STENCIL_FRAG;
            let mut desc: GraphicsPipelineDesc = forward::surface_pass_desc(name, frag, depth_format, &spec);
            desc.color_targets = &target;
            let face = StencilFace { compare, write_mask: 0, ..StencilFace::KEEP };
            desc.stencil = Some((face, face));
            Bounded::new(ctx, layout, &desc, depth_bounds)
        };
        let stencil_lit = stencil("visibility (stencil == 0)", true, vk::CompareOp::EQUAL)?;
        let stencil_shadowed = stencil("visibility (stencil != 0)", false, vk::CompareOp::NOT_EQUAL)?;
        Ok(Self {
            images: Vec::new(),
            width,
            height,
            storage: storage_supported(ctx.capabilities()),
            unshadowed_set,
            _placeholder: placeholder,
            set_layout,
            sampler,
            map,
            stencil_lit,
            stencil_shadowed,
        })
    }

    /// Keeps an image for every light `shadowed` marks (made where missing) and releases the
    /// others.
    pub fn keep(&mut self, ctx: &Context, shadowed: &[bool], retired: &mut Retired) -> RenderResult<()> {
        crate::budget::release_unused(&mut self.images, shadowed, retired);
        self.images.resize_with(shadowed.len(), || None);
        for (l, (kept, &wanted)) in self.images.iter_mut().zip(shadowed).enumerate() {
            if wanted && kept.is_none() {
                let desc = image_desc(self.width, self.height, self.storage);
                let image = Image::new(ctx, &format!("visibility image (light {l})"), desc)?;
                let name = format!("visibility set (light {l})");
                let set = DescriptorSet::new(ctx, &name, &self.set_layout, &[sampled(&image, &self.sampler)])?;
                *kept = Some(LightVisibility { image, set });
            }
        }
        Ok(())
    }

    /// Light `light`'s image and set (kept by [`VisibilityPass::keep`]).
    pub fn light(&self, light: usize) -> RenderResult<&LightVisibility> {
        self.images.get(light).and_then(Option::as_ref).ok_or_else(|| RenderError::InvalidInput {
            field: format!("visibility image of light {light}"),
            why: "recorded before it was kept".into(),
        })
    }

    /// A shadow-map or silhouette-map light's visibility (inside an open rendering pass with the
    /// image as its one colour target), its maps bound by `shadow_set`.
    pub fn record_map<'a>(
        &'a self,
        cx: &mut PassRecorder<'_, 'a>,
        layout: &'a PipelineLayout,
        s: LightSurfaces<'a, '_>,
        shadow_set: &'a DescriptorSet,
    ) {
        self.map.bind(cx.rec, s.bounds);
        cx.rec.bind_descriptor_set(layout, 1, shadow_set);
        s.draw(cx, layout);
    }

    /// A shadow-volume light's visibility from its stencil counts (inside an open rendering pass
    /// with the image as its colour target and the counted depth/stencil).
    pub fn record_stencil<'a>(
        &'a self,
        cx: &mut PassRecorder<'_, 'a>,
        layout: &'a PipelineLayout,
        s: LightSurfaces<'a, '_>,
    ) {
        for pipeline in [&self.stencil_lit, &self.stencil_shadowed] {
            pipeline.bind(cx.rec, s.bounds);
            cx.rec.set_stencil_reference(0);
            s.draw(cx, layout);
        }
    }
}

/// What a light's visibility pass writes: its visibility image, over the frame's depth (kept,
/// for the EQUAL test).
#[derive(Clone, Copy)]
pub(crate) struct VisibilityTarget<'a> {
    pub image: &'a Image,
    pub depth: &'a Image,
}

impl<'a> VisibilityTarget<'a> {
    /// The images a visibility pass uses: the image as colour target, the depth as attachment.
    pub fn uses(&self) -> [Use<'a>; 2] {
        [
            Use::Image(self.image, ImageState::ColorAttachment),
            Use::Image(self.depth, ImageState::DepthStencilAttachment),
        ]
    }

    /// Begins the pass: the image cleared to 0 (shadowed, nothing in question), the depth kept.
    pub fn begin(&self, rec: &mut Recorder<'a>) {
        over_surfaces(rec, self.image, Some([0.0; 4]), self.depth);
    }
}

/// A shadow-map or silhouette-map light's `visibility N`: its map looked up at every surface,
/// through `shadow_set` (which binds its maps; `reads`: the maps' images).
pub(crate) fn declare_map_light<'a>(
    stage: &mut Stage<'a>,
    pass: &'a VisibilityPass,
    layout: &'a PipelineLayout,
    s: LightSurfaces<'a, 'a>,
    shadow_set: &'a DescriptorSet,
    target: VisibilityTarget<'a>,
    reads: &[Use<'a>],
) {
    let uses = [&target.uses()[..], reads].concat();
    stage.pass(PassId::MapVisibility(s.light as usize), &uses, move |cx| {
        target.begin(cx.rec);
        pass.record_map(cx, layout, s, shadow_set);
        cx.rec.end_rendering();
        Ok(())
    });
}

/// A visibility image as the lighting samples it (nearest, in `FragmentRead`).
fn sampled<'a>(image: &Image, sampler: &Sampler) -> Resource<'a> {
    Resource::SampledImage { view: image.view, sampler: sampler.raw, layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL }
}

/// A host-visible copy of one light's visibility image, kept from frame to frame.
pub(crate) struct VisibilityReadback {
    pub buffer: Buffer,
}

impl VisibilityReadback {
    pub fn new(ctx: &Context, width: u32, height: u32) -> RenderResult<Self> {
        let size = 8 * u64::from(width) * u64::from(height);
        Ok(Self { buffer: Buffer::new(ctx, "visibility readback", BufferDesc::readback(size))? })
    }

    /// The copy, as light `light`'s image of a `width` × `height` frame.
    pub fn read(&self, light: usize, width: u32, height: u32) -> RenderResult<VisibilityImage> {
        let texels = rg32f_texels(&self.buffer.read()?);
        Ok(VisibilityImage { light, width, height, texels })
    }
}

/// The texels of a tightly packed RG32F copy (little-endian, as every Vulkan device umbra
/// runs on stores them).
pub(crate) fn rg32f_texels(raw: &[u8]) -> Vec<[f32; 2]> {
    let f = |b: &[u8]| f32::from_le_bytes([b[0], b[1], b[2], b[3]]);
    raw.chunks_exact(8).map(|c| [f(&c[..4]), f(&c[4..])]).collect()
}
