//! The pipelines and recording of a hybrid light's GPU passes (Chan–Durand §3–4), after its
//! shadow map: `hybrid classify N` (step 2), `computation mask N` (§4), `hybrid volumes N`
//! (step 3, the stencil pass), `hybrid visibility N` (step 4: the silhouette pixels' visibility
//! from their counts), plus blocker culling (§6.3) and the diagnostic readbacks. The light's
//! lighting pass then reads the visibility image like every other technique's. `hybrid::frame` declares them, with the images each uses.

use super::bounds::BoundsPass;
use super::cull::BOX_VERTICES;
use super::masked::{GpuMasked, MaskedCounting, MaskedFragments};
use super::settings::{MaskKind, COUNT_BITS, SILHOUETTE_BIT};
use crate::diagnostics::ClassReadback;
use crate::forward;
use crate::frame::{PassRecorder, QueryId};
use crate::gpu_scene::{DrawPush, GpuScene};
use crate::light_surfaces::{LightSurfaces, PassBounds};
use crate::retired::Retired;
use crate::shadow_map::{self, ShadowMapSettings};
use crate::shadow_volume::batches::{fold_desc, record_in_batches, CountBits, FULL_STENCIL};
use crate::shadow_volume::build::LightVolumes;
use crate::shadow_volume::frame::{VolumeLight, VolumeSource};
use crate::shadow_volume::gpu_frame::GpuVolumes;
use crate::shadow_volume::pass as volume_pass;
use crate::visibility::VISIBILITY_FORMAT;
use crate::RenderResult;
use umbra_scene::Scene;
use umbra_vk::{
    vk, Buffer, ColorAttachment, ColorTarget, Context, DepthAttachment, DepthState, DescriptorSet, DescriptorSetLayout,
    GraphicsPipeline, GraphicsPipelineDesc, Image, ImageDesc, ImageState, PipelineLayout, RenderTargets, StencilFace,
};

/// The frame-sized images of the hybrid, reused by every hybrid light of a frame.
struct Targets {
    /// Per-pixel classes (`hybrid/classes.glsl`): the silhouette-pixel mask.
    classes: Image,
    /// The frame's depth copied, then masked (`depth-bounds` only; the frame's own depth must
    /// survive for later lights).
    masked_depth: Option<Image>,
}

/// The frame-sized images of the hybrid for a `width` × `height` frame: the silhouette classes
/// and the masked depth copy (in `depth_format`).
pub(crate) fn target_descs(depth_format: vk::Format, width: u32, height: u32) -> (ImageDesc, ImageDesc) {
    let usage =
        vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_SRC;
    let classes = ImageDesc::new_2d(crate::targets::COLOR_FORMAT, width, height).usage(usage);
    let usage = vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT
        | vk::ImageUsageFlags::TRANSFER_DST
        | vk::ImageUsageFlags::TRANSFER_SRC;
    (classes, ImageDesc::new_2d(depth_format, width, height).usage(usage))
}

/// Pipelines and targets of the hybrid technique.
pub(crate) struct HybridPass {
    classify: GraphicsPipeline,
    mask_depth_bounds: GraphicsPipeline,
    mask_stencil: GraphicsPipeline,
    mask_none: GraphicsPipeline,
    /// Step 3's z-fail counting under each mask, alone and in a batch's bits ([`count_bits`];
    /// `shadow_volume/batches.rs`), and the folds between batches, over the whole stencil and
    /// under the silhouette bit.
    volumes: MaskedCounting,
    fold: GraphicsPipeline,
    fold_under_silhouette: GraphicsPipeline,
    /// Step 4, per counting target: silhouette pixels lit where the count (the whole stencil, or
    /// its count bits with the stencil mask) is 0, shadowed where it is not.
    resolve: [GraphicsPipeline; 2],
    resolve_count_bits: [GraphicsPipeline; 2],
    /// Diagnostic: volume fragments the mask lets through (depth and stencil untouched).
    fragments: MaskedFragments,
    /// Step 3 and its diagnostic over volumes built on the GPU ([`Self::with_gpu_volumes`]).
    gpu: Option<GpuMasked>,
    /// Blocker culling: bounding boxes against the shadow map.
    boxes: GraphicsPipeline,
    /// The conservative depth bounds the classification reads (`hybrid bounds N`).
    pub bounds: BoundsPass,
    depth_format: vk::Format,
    targets: Option<Targets>,
}

/// The stencil face that tests `compare` against the reference through `compare_mask`,
/// changing nothing.
pub(super) fn test_only(compare: vk::CompareOp, compare_mask: u32) -> StencilFace {
    StencilFace { compare, compare_mask, write_mask: 0, ..StencilFace::KEEP }
}

/// Step 4's two full-screen pipelines for a count in the stencil bits `count_bits`: silhouette
/// pixels get visibility 1 where the count is 0, and 0 where it is not. The stencil test alone
/// (no depth test or write): the frame's depth must reach the lighting pass untouched.
fn resolve_pipelines(
    ctx: &Context,
    layout: &PipelineLayout,
    depth_format: vk::Format,
    count_bits: u32,
) -> RenderResult<[GraphicsPipeline; 2]> {
    let target = [ColorTarget::opaque(VISIBILITY_FORMAT)];
    let pipeline = |lit: bool| -> RenderResult<GraphicsPipeline> {
        let (compare, op) = if lit { (vk::CompareOp::EQUAL, "==") } else { (vk::CompareOp::NOT_EQUAL, "!=") };
        let name = format!("hybrid visibility (stencil & {count_bits:#x} {op} 0)");
        let spec = [(0, 0), (1, u32::from(lit))];
        let mut desc = GraphicsPipelineDesc::new(&name, umbra_shaders::fullscreen::TRIANGLE_VERT);
        desc.fragment = Some(umbra_shaders::hybrid::RESOLVE_FRAG);
        desc.specialization = &spec;
        desc.cull = vk::CullModeFlags::NONE;
        desc.depth = DepthState::NONE;
        desc.depth_format = depth_format;
        desc.color_targets = &target;
        let face = test_only(compare, count_bits);
        desc.stencil = Some((face, face));
        Ok(GraphicsPipeline::new(ctx, layout, &desc)?)
    };
    Ok([pipeline(true)?, pipeline(false)?])
}

impl HybridPass {
    /// Builds every pipeline against the renderer's `layout`; `clamp` mirrors the volumes'
    /// `FarPlane::DepthClamp`.
    pub fn new(
        ctx: &Context,
        layout: &PipelineLayout,
        depth_format: vk::Format,
        scene_set_layout: &DescriptorSetLayout,
        shadow: &ShadowMapSettings,
        clamp: bool,
        input: volume_pass::VolumeInput,
    ) -> RenderResult<Self> {
        let caps = ctx.capabilities();
        // Step 2: the bounds (hybrid/bounds_lookup.glsl), outside the frustum as maps are.
        let spec = [(1, u32::from(shadow.outside_lit))];
        let mut desc =
            forward::surface_pass_desc("hybrid classify", umbra_shaders::hybrid::CLASSIFY_FRAG, depth_format, &spec);
        let targets = [ColorTarget::opaque(VISIBILITY_FORMAT), ColorTarget::opaque(crate::targets::COLOR_FORMAT)];
        desc.color_targets = &targets;
        let classify = GraphicsPipeline::new(ctx, layout, &desc)?;

        // §4: full-screen at depth 0, keeping silhouette pixels or the others.
        let keep_others = [(0, 0), (1, 0)];
        let keep_silhouettes = [(0, 0), (1, 1)];
        let mut desc = GraphicsPipelineDesc::new("hybrid mask (depth 0)", umbra_shaders::fullscreen::TRIANGLE_VERT);
        desc.fragment = Some(umbra_shaders::hybrid::MASK_FRAG);
        desc.cull = vk::CullModeFlags::NONE;
        desc.depth_format = depth_format;
        desc.specialization = &keep_others;
        desc.depth = DepthState { test: true, write: true, compare: vk::CompareOp::ALWAYS, ..DepthState::NONE };
        let mask_depth_bounds = GraphicsPipeline::new(ctx, layout, &desc)?;
        desc.name = "hybrid mask (stencil bit)";
        desc.specialization = &keep_silhouettes;
        desc.depth = DepthState::NONE;
        let mark = StencilFace {
            pass: vk::StencilOp::REPLACE,
            compare: vk::CompareOp::ALWAYS,
            write_mask: SILHOUETTE_BIT,
            ..StencilFace::KEEP
        };
        desc.stencil = Some((mark, mark));
        let mask_stencil = GraphicsPipeline::new(ctx, layout, &desc)?;
        desc.name = "hybrid silhouette count (no mask)";
        desc.stencil = None;
        let mask_none = GraphicsPipeline::new(ctx, layout, &desc)?;

        // Step 3: z-fail volumes, masked.
        let volumes = MaskedCounting::new(ctx, layout, depth_format, clamp, caps.depth_bounds, input)?;
        let fold = GraphicsPipeline::new(ctx, layout, &fold_desc("hybrid batch fold", depth_format, FULL_STENCIL))?;
        let fold_under_silhouette = GraphicsPipeline::new(
            ctx,
            layout,
            &fold_desc("hybrid batch fold (under the silhouette bit)", depth_format, UNDER_SILHOUETTE_BIT),
        )?;

        let zfail = volume_pass::zfail_desc(depth_format, clamp, input);
        let fragments = MaskedFragments::new(ctx, layout, zfail, caps.depth_bounds, input)?;

        // Step 4: the silhouette pixels' visibility, through the whole stencil or its count bits.
        let resolve = resolve_pipelines(ctx, layout, depth_format, 0xff)?;
        let resolve_count_bits = resolve_pipelines(ctx, layout, depth_format, COUNT_BITS)?;

        // §6.3: boxes from the light against its map.
        let mut desc = GraphicsPipelineDesc::new("hybrid blocker boxes", umbra_shaders::hybrid::BOX_VERT);
        desc.vertex_stride = volume_pass::VOLUME_STRIDE;
        desc.vertex_attributes = &volume_pass::VOLUME_ATTRIBUTES;
        desc.cull = vk::CullModeFlags::NONE;
        desc.depth = DepthState {
            test: true,
            write: false,
            compare: vk::CompareOp::LESS_OR_EQUAL,
            clamp: caps.depth_clamp,
            ..DepthState::NONE
        };
        desc.depth_format = shadow_map::pass::FORMAT;
        let boxes = GraphicsPipeline::new(ctx, layout, &desc)?;

        Ok(Self {
            classify,
            mask_depth_bounds,
            mask_stencil,
            mask_none,
            volumes,
            fold,
            fold_under_silhouette,
            resolve,
            resolve_count_bits,
            fragments,
            gpu: None,
            boxes,
            bounds: BoundsPass::new(ctx, scene_set_layout)?,
            depth_format,
            targets: None,
        })
    }

    /// Step 3's pipelines over the shadow volumes built on the GPU (`volumes`), for renderers
    /// that build them there; `clamp` as in [`Self::new`], `overdraw` adds the diagnostic's
    /// fragment counts.
    pub fn with_gpu_volumes(
        mut self,
        ctx: &Context,
        volumes: &GpuVolumes,
        clamp: bool,
        overdraw: bool,
    ) -> RenderResult<Self> {
        self.gpu = Some(GpuMasked::new(ctx, volumes, self.depth_format, clamp, overdraw)?);
        Ok(self)
    }

    /// Makes sure the frame-sized targets exist for a `width` × `height` frame (and the masked
    /// depth copy when some light uses `depth-bounds`).
    pub fn prepare(
        &mut self,
        ctx: &Context,
        width: u32,
        height: u32,
        masked_depth: bool,
        retired: &mut Retired,
    ) -> RenderResult<()> {
        let fits = self.targets.as_ref().is_some_and(|t| {
            t.classes.desc.width == width && t.classes.desc.height == height && t.masked_depth.is_some() >= masked_depth
        });
        if fits {
            return Ok(());
        }
        retired.take(&mut self.targets);
        let (classes, masked) = target_descs(self.depth_format, width, height);
        let classes = Image::new(ctx, "hybrid silhouette classes", classes)?;
        let masked_depth = match masked_depth {
            true => Some(Image::new(ctx, "hybrid masked depth", masked)?),
            false => None,
        };
        self.targets = Some(Targets { classes, masked_depth });
        Ok(())
    }

    /// The classes image bound at set 1, binding 3 of hybrid lights (after [`Self::prepare`]).
    pub fn classes(&self) -> Option<&Image> {
        self.targets.as_ref().map(|t| &t.classes)
    }

    /// `blocker culling`: per light of `maps`, the box of every caster in its range (36
    /// vertices each in `vertices`) from its map's view against its map, query
    /// `first_query + b` around box `b`.
    pub fn record_culling<'a>(
        &'a self,
        cx: &mut PassRecorder<'_, 'a>,
        layout: &'a PipelineLayout,
        gpu: &'a GpuScene,
        vertices: &'a Buffer,
        maps: &[CullingMap<'a>],
        first_query: QueryId,
    ) {
        for m in maps {
            let depth = DepthAttachment { image: m.map, view: None, clear: None, clear_stencil: None, read_only: true };
            cx.rec.begin_rendering(&RenderTargets { color: &[], depth: Some(depth) });
            cx.rec.bind_pipeline(&self.boxes);
            cx.rec.bind_descriptor_set(layout, 0, &gpu.frame.set);
            cx.rec.bind_vertex_buffer(vertices);
            cx.rec.push_constants(layout, &DrawPush { object: 0, view: m.view });
            for b in m.boxes.clone() {
                let query = QueryId(first_query.0 + b);
                cx.begin_query(query);
                cx.rec.draw_range(BOX_VERTICES, b * BOX_VERTICES);
                cx.end_query(query);
                cx.log.count_draw(u64::from(BOX_VERTICES / 3));
            }
            cx.rec.end_rendering();
        }
    }

    /// The depth/stencil image a light with `mask` counts in: the masked copy for
    /// `depth-bounds`, else the frame's own.
    pub fn count_target<'a>(&'a self, mask: MaskKind, depth: &'a Image) -> &'a Image {
        match (mask, self.targets.as_ref().and_then(|t| t.masked_depth.as_ref())) {
            (MaskKind::DepthBounds, Some(masked)) => masked,
            _ => depth,
        }
    }

    /// Step 2 (the visibility image and classes in ColorAttachment, the bounds readable):
    /// classify every visible pixel; the bounds decide the visibility of all but the silhouette
    /// pixels.
    pub fn record_classify<'a>(&'a self, cx: &mut PassRecorder<'_, 'a>, h: &HybridLight<'a>) {
        let Some(classes) = self.classes() else { return };
        let color = [
            ColorAttachment { image: h.visibility, view: None, clear: Some([0.0; 4]) },
            ColorAttachment { image: classes, view: None, clear: Some([0.0; 4]) },
        ];
        cx.rec.begin_rendering(&RenderTargets { color: &color, depth: Some(DepthAttachment::keep(h.depth)) });
        cx.rec.bind_pipeline(&self.classify);
        cx.rec.bind_descriptor_set(h.layout, 1, h.shadow_set);
        crate::light_surfaces::draw_objects(cx.rec, h.layout, h.gpu, h.scene, h.light as u32, cx.log);
        cx.rec.end_rendering();
    }

    /// §4: the computation mask (and the silhouette-pixel count, by occlusion query). With
    /// `depth-bounds` the pass begins with the frame's depth in TransferSrc and the masked copy
    /// in TransferDst: the depth is copied, then both become attachments again.
    pub fn record_mask<'a>(&'a self, cx: &mut PassRecorder<'_, 'a>, h: &HybridLight<'a>) {
        let target = self.count_target(h.mask, h.depth);
        if target.raw != h.depth.raw {
            cx.rec.copy_image(h.depth, target);
            cx.enter(&[(h.depth, ImageState::DepthStencilAttachment), (target, ImageState::DepthStencilAttachment)]);
        }
        let attach = DepthAttachment::clearing_stencil(target, 0);
        cx.rec.begin_rendering(&RenderTargets { color: &[], depth: Some(attach) });
        cx.rec.bind_pipeline(match h.mask {
            MaskKind::DepthBounds => &self.mask_depth_bounds,
            MaskKind::Stencil => &self.mask_stencil,
            MaskKind::None => &self.mask_none,
        });
        if h.mask == MaskKind::Stencil {
            cx.rec.set_stencil_reference(SILHOUETTE_BIT);
        }
        cx.rec.bind_descriptor_set(h.layout, 1, h.shadow_set);
        cx.begin_query(h.mask_query);
        cx.rec.draw(3);
        cx.log.count_draw(1);
        cx.end_query(h.mask_query);
        cx.rec.end_rendering();
    }

    /// Step 3: z-fail volumes, where the mask lets them through: the host's vertices, or the
    /// volumes built on the GPU (`shadow_volume/gpu_frame.rs`).
    pub fn record_volumes<'a>(&'a self, cx: &mut PassRecorder<'_, 'a>, h: &HybridLight<'a>) -> RenderResult<()> {
        if let VolumeSource::Host(None) = h.source {
            return Ok(());
        }
        let masked = self.masked(h)?;
        let target = self.count_target(h.mask, h.depth);
        cx.rec.begin_rendering(&RenderTargets { color: &[], depth: Some(DepthAttachment::keep(target)) });
        let bits = count_bits(h.mask);
        let fold = if h.mask == MaskKind::Stencil { &self.fold_under_silhouette } else { &self.fold };
        h.volume_light().draw(
            cx,
            |cx, b| {
                b.bind(cx.rec);
                let host_clipped = h.volumes.host_clipped;
                record_in_batches(cx.rec, cx.log, h.volumes, bits, fold, |rec, log, batch, batched| {
                    self.volumes.bind(rec, h.mask, batched);
                    b.draw_counting(rec, batch.iter(), host_clipped, h.light as u32, log);
                });
            },
            |cx, g, draws| {
                // Some for volumes built on the GPU (`masked` refused the frame otherwise).
                if let Some(masked) = masked {
                    masked.record_counting(cx.rec, g, draws, (h.mask, bits), fold, cx.log);
                }
            },
        );
        cx.rec.end_rendering();
        Ok(())
    }

    /// The masked pipelines over GPU-built volumes, where `h`'s volumes were built on the GPU;
    /// an error where this pass was made without them ([`HybridPass::with_gpu_volumes`]).
    fn masked(&self, h: &HybridLight<'_>) -> RenderResult<Option<&GpuMasked>> {
        match (h.source, &self.gpu) {
            (VolumeSource::Gpu(..), None) => Err(crate::RenderError::InvalidInput {
                field: format!("light {}", h.light),
                why: "its hybrid volumes were built on the GPU, but the hybrid's pipelines were made without \
                      the GPU path (shadow_volume.build)"
                    .into(),
            }),
            (VolumeSource::Gpu(..), Some(masked)) => Ok(Some(masked)),
            _ => Ok(None),
        }
    }

    /// Step 4 (the visibility image in ColorAttachment, the classes readable): the silhouette
    /// pixels' visibility, 1 where their count is zero and 0 where it is not.
    pub fn record_visibility<'a>(&'a self, cx: &mut PassRecorder<'_, 'a>, h: &HybridLight<'a>) {
        let target = self.count_target(h.mask, h.depth);
        let color = [ColorAttachment { image: h.visibility, view: None, clear: None }];
        cx.rec.begin_rendering(&RenderTargets { color: &color, depth: Some(DepthAttachment::keep(target)) });
        let pipelines = if h.mask == MaskKind::Stencil { &self.resolve_count_bits } else { &self.resolve };
        for pipeline in pipelines {
            cx.rec.bind_pipeline(pipeline);
            cx.rec.set_stencil_reference(0);
            cx.rec.bind_descriptor_set(h.layout, 1, h.shadow_set);
            cx.rec.draw(3);
            cx.log.count_draw(1);
        }
        cx.rec.end_rendering();
    }

    /// Diagnostic: the volume fragments the mask lets through (no depth test, no writes) into
    /// `query`; without a mask the query stays empty (the count is the unmasked one).
    pub fn record_fragments<'a>(
        &'a self,
        cx: &mut PassRecorder<'_, 'a>,
        h: &HybridLight<'a>,
        query: QueryId,
    ) -> RenderResult<()> {
        let masked = self.masked(h)?;
        let target = self.count_target(h.mask, h.depth);
        cx.rec.begin_rendering(&RenderTargets { color: &[], depth: Some(DepthAttachment::keep(target)) });
        cx.begin_query(query);
        h.volume_light().draw(
            cx,
            |cx, b| {
                if self.fragments.bind(cx.rec, h.mask) {
                    b.bind(cx.rec);
                    b.draw(cx.rec, &h.volumes.casters, h.light as u32, cx.log);
                }
            },
            |cx, g, draws| {
                if let Some(masked) = masked {
                    masked.record_fragments(cx.rec, g, draws, h.mask);
                }
            },
        );
        cx.end_query(query);
        cx.rec.end_rendering();
        Ok(())
    }

    /// Diagnostic (classes and count target in TransferSrc): both copied into `out`.
    pub fn record_readback<'a>(&'a self, cx: &mut PassRecorder<'_, 'a>, h: &HybridLight<'a>, out: &'a ClassReadback) {
        let Some(classes) = self.classes() else { return };
        cx.rec.copy_image_to_buffer(classes, 0, &out.classes);
        if let Some(stencil) = &out.stencil {
            cx.rec.copy_stencil_to_buffer(self.count_target(h.mask, h.depth), stencil);
        }
    }
}

/// The stencil's count layout under `mask` (`shadow_volume/batches.rs`): the whole stencil,
/// or, with the stencil mask, the seven bits under [`SILHOUETTE_BIT`].
pub(crate) fn count_bits(mask: MaskKind) -> CountBits {
    match mask {
        MaskKind::Stencil => UNDER_SILHOUETTE_BIT,
        _ => FULL_STENCIL,
    }
}

/// The stencil mask's count: seven bits at once, six in a batch, bit 6 folded.
const UNDER_SILHOUETTE_BIT: CountBits = CountBits { all: 0x7f, batch: 0x3f, fold: 0x40 };

/// What one hybrid light's passes read and write.
#[derive(Clone, Copy)]
pub(crate) struct HybridLight<'a> {
    /// Index of the light.
    pub light: usize,
    /// Its computation mask (supported by the device: checked when the renderer was built).
    pub mask: MaskKind,
    pub layout: &'a PipelineLayout,
    pub gpu: &'a GpuScene,
    pub scene: &'a Scene,
    /// Set 1: its map, the classes image at binding 3, its depth bounds at binding 4.
    pub shadow_set: &'a DescriptorSet,
    /// The visibility image and the frame's depth/stencil, as attachments.
    pub visibility: &'a Image,
    pub depth: &'a Image,
    /// Its z-fail volumes (culled casters already left out) and where they are drawn from.
    pub volumes: &'a LightVolumes,
    pub source: VolumeSource<'a>,
    /// The mask pass's samples.
    pub mask_query: QueryId,
}

impl<'a> HybridLight<'a> {
    /// Its volumes as shadow volumes draw them (the hybrid's passes are not bounded: the mask
    /// already limits them).
    fn volume_light(&self) -> VolumeLight<'a> {
        let surfaces =
            LightSurfaces { gpu: self.gpu, scene: self.scene, light: self.light as u32, bounds: PassBounds::default() };
        VolumeLight { surfaces, layout: self.layout, volumes: self.volumes, source: self.source }
    }
}

/// One light's blocker boxes, tested against its shadow map.
pub(crate) struct CullingMap<'a> {
    /// A 2D shadow map, in [`ImageState::DepthStencilReadOnly`].
    pub map: &'a Image,
    /// The light's boxes in the frame's box vertices (box `b` is queried by query `b`).
    pub boxes: std::ops::Range<u32>,
    /// The map's view in the frame's uniforms.
    pub view: u32,
}
