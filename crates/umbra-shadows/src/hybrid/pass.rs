//! The GPU passes of a hybrid light (Chan–Durand §3–4), after its shadow map:
//! `hybrid classify N` (step 2), `computation mask N` (§4), `hybrid volumes N` (step 3, the
//! stencil pass), `light N (…) silhouettes` (step 4), plus blocker culling (§6.3) and the
//! diagnostic readbacks.

use super::cull::BOX_VERTICES;
use super::settings::{MaskKind, COUNT_BITS, DEPTH_BOUNDS_EPSILON, SILHOUETTE_BIT};
use crate::diagnostics::ClassReadback;
use crate::forward;
use crate::gpu_scene::{DrawPush, GpuScene};
use crate::shadow_map::{self, ShadowFilter, ShadowMapSettings};
use crate::shadow_volume::build::LightVolumes;
use crate::shadow_volume::pass::{self as volume_pass, VolumeBindings};
use crate::timing::{PassLog, PassTimer};
use crate::RenderResult;
use umbra_scene::Scene;
use umbra_vk::{
    vk, Blend, Buffer, ColorAttachment, ColorTarget, Context, DepthAttachment, DepthState, DescriptorSet,
    GraphicsPipeline, GraphicsPipelineDesc, Image, ImageDesc, ImageState, PipelineLayout, QueryPool, Recorder,
    RenderTargets, StencilFace,
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
    let classes = ImageDesc::new_2d(crate::COLOR_FORMAT, width, height).usage(usage);
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
    /// Z-fail volumes with the depth-bounds test (`None` without `depthBounds`).
    volumes_depth_bounds: Option<GraphicsPipeline>,
    volumes_stencil: GraphicsPipeline,
    /// Silhouette pixels lit where the whole stencil is 0 / where its count bits are 0.
    lit: GraphicsPipeline,
    lit_count_bits: GraphicsPipeline,
    /// Diagnostic: volume fragments the mask lets through (depth and stencil untouched).
    fragments_depth_bounds: Option<GraphicsPipeline>,
    fragments_stencil: GraphicsPipeline,
    /// Blocker culling: bounding boxes against the shadow map.
    boxes: GraphicsPipeline,
    depth_format: vk::Format,
    targets: Option<Targets>,
}

/// The stencil face that tests `compare` against the reference through `compare_mask`,
/// changing nothing.
fn test_only(compare: vk::CompareOp, compare_mask: u32) -> StencilFace {
    StencilFace { compare, compare_mask, write_mask: 0, ..StencilFace::KEEP }
}

/// `desc` with the depth-bounds test on, named `name`, where the device has `depthBounds`.
fn with_depth_bounds<'d>(
    ctx: &Context,
    layout: &PipelineLayout,
    mut desc: GraphicsPipelineDesc<'d>,
    name: &'d str,
    depth_bounds: bool,
) -> RenderResult<Option<GraphicsPipeline>> {
    if !depth_bounds {
        return Ok(None);
    }
    desc.name = name;
    desc.depth.bounds_test = true;
    Ok(Some(GraphicsPipeline::new(ctx, layout, &desc)?))
}

impl HybridPass {
    /// Builds every pipeline against the renderer's `layout`; `clamp` mirrors the volumes'
    /// `FarPlane::DepthClamp`.
    pub fn new(
        ctx: &Context,
        layout: &PipelineLayout,
        color_format: vk::Format,
        depth_format: vk::Format,
        shadow: &ShadowMapSettings,
        clamp: bool,
    ) -> RenderResult<Self> {
        let caps = ctx.capabilities();
        // Step 2: one hardware-PCF fetch, whatever filter plain shadow maps use.
        let spec = forward::shadow_spec(&ShadowMapSettings { filter: ShadowFilter::Pcf2x2, ..*shadow });
        let mut desc =
            forward::surface_pass_desc("hybrid classify", umbra_shaders::hybrid::CLASSIFY_FRAG, depth_format, &spec);
        // Both targets blend additively (one blend state: no `independentBlend` needed); the
        // classes target is cleared to 0 and written once per pixel, so it holds the class.
        let additive = ColorTarget { blend: Some(Blend::ADDITIVE), ..ColorTarget::opaque(color_format) };
        let targets = [additive, additive];
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
        let mut desc = volume_pass::zfail_desc(depth_format, clamp);
        let volumes_depth_bounds =
            with_depth_bounds(ctx, layout, desc, "hybrid volumes (depth-bounds mask)", caps.depth_bounds)?;
        desc.name = "hybrid volumes (stencil mask)";
        // Only where the silhouette bit is set; count in the low bits (settings::COUNT_BITS).
        desc.stencil = desc.stencil.map(|(front, back)| {
            let masked = |f: StencilFace| StencilFace {
                compare: vk::CompareOp::EQUAL,
                compare_mask: SILHOUETTE_BIT,
                write_mask: COUNT_BITS,
                ..f
            };
            (masked(front), masked(back))
        });
        let volumes_stencil = GraphicsPipeline::new(ctx, layout, &desc)?;

        // Diagnostic fragment counts: the volume draws with only the mask's test. The depth test
        // is on but ALWAYS passes: SwiftShader skips the depth-bounds test while it is off.
        desc.depth = DepthState { test: true, compare: vk::CompareOp::ALWAYS, clamp, ..DepthState::NONE };
        desc.stencil = None;
        let fragments_depth_bounds =
            with_depth_bounds(ctx, layout, desc, "hybrid volume fragments (depth-bounds mask)", caps.depth_bounds)?;
        desc.name = "hybrid volume fragments (stencil mask)";
        let bit = test_only(vk::CompareOp::EQUAL, SILHOUETTE_BIT);
        desc.stencil = Some((bit, bit));
        let fragments_stencil = GraphicsPipeline::new(ctx, layout, &desc)?;

        // Step 4: silhouette pixels lit where the count is zero.
        let lit_frag = umbra_shaders::hybrid::LIT_FRAG;
        let mut desc = forward::surface_pass_desc("hybrid lit (stencil == 0)", lit_frag, depth_format, &[]);
        let additive = [ColorTarget { blend: Some(Blend::ADDITIVE), ..ColorTarget::opaque(color_format) }];
        desc.color_targets = &additive;
        let zero = test_only(vk::CompareOp::EQUAL, 0xff);
        desc.stencil = Some((zero, zero));
        let lit = GraphicsPipeline::new(ctx, layout, &desc)?;
        desc.name = "hybrid lit (stencil & 0x7f == 0)";
        let zero = test_only(vk::CompareOp::EQUAL, COUNT_BITS);
        desc.stencil = Some((zero, zero));
        let lit_count_bits = GraphicsPipeline::new(ctx, layout, &desc)?;

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
            volumes_depth_bounds,
            volumes_stencil,
            lit,
            lit_count_bits,
            fragments_depth_bounds,
            fragments_stencil,
            boxes,
            depth_format,
            targets: None,
        })
    }

    /// Makes sure the frame-sized targets exist for a `width` × `height` frame (and the masked
    /// depth copy when some light uses `depth-bounds`).
    pub fn prepare(&mut self, ctx: &Context, width: u32, height: u32, masked_depth: bool) -> RenderResult<()> {
        let fits = self.targets.as_ref().is_some_and(|t| {
            t.classes.desc.width == width && t.classes.desc.height == height && t.masked_depth.is_some() >= masked_depth
        });
        if fits {
            return Ok(());
        }
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

    /// Records the box of every caster in `boxes` (a range of 36 vertices each in `vertices`)
    /// from view `view` against `map` (a 2D shadow map in [`ImageState::FragmentRead`]), query
    /// `first_query + i` around box `i`.
    #[allow(clippy::too_many_arguments)]
    pub fn record_culling<'a>(
        &'a self,
        rec: &mut Recorder<'a>,
        layout: &'a PipelineLayout,
        gpu: &'a GpuScene,
        map: &'a Image,
        vertices: &'a Buffer,
        boxes: std::ops::Range<u32>,
        view: u32,
        queries: &'a QueryPool,
        first_query: u32,
        log: &mut PassLog,
    ) {
        rec.transition(&[(map, ImageState::FragmentRead, ImageState::DepthStencilReadOnly)]);
        let depth = DepthAttachment { image: map, view: None, clear: None, clear_stencil: None, read_only: true };
        rec.begin_rendering(&RenderTargets { color: &[], depth: Some(depth) });
        rec.bind_pipeline(&self.boxes);
        rec.bind_descriptor_set(layout, 0, &gpu.frame.set);
        rec.bind_vertex_buffer(vertices);
        rec.push_constants(layout, &DrawPush { object: 0, view });
        for (i, b) in boxes.enumerate() {
            rec.begin_query(queries, first_query + i as u32);
            rec.draw_range(BOX_VERTICES, b * BOX_VERTICES);
            rec.end_query(queries, first_query + i as u32);
            log.count_draw(u64::from(BOX_VERTICES / 3));
        }
        rec.end_rendering();
        rec.transition(&[(map, ImageState::DepthStencilReadOnly, ImageState::FragmentRead)]);
    }

    /// Records steps 2–4 of one hybrid light, each a timed pass, and its diagnostics.
    pub fn record_light<'a>(
        &'a self,
        rec: &mut Recorder<'a>,
        timer: &'a PassTimer,
        log: &mut PassLog,
        h: HybridLight<'a>,
    ) {
        let Some(targets) = &self.targets else { return };
        let classes = &targets.classes;
        let light = h.light as u32;
        let name = |what: &str| format!("{what} {}", h.light);

        // Step 2: classify every visible pixel; shade those the map decides.
        timer.begin(rec, log, name("hybrid classify"), Some(h.light));
        let classes_was = if h.first_in_frame { ImageState::Undefined } else { ImageState::FragmentRead };
        rec.transition(&[(classes, classes_was, ImageState::ColorAttachment)]);
        let color = [
            ColorAttachment { image: h.color, clear: None },
            ColorAttachment { image: classes, clear: Some([0.0; 4]) },
        ];
        let frame_depth =
            DepthAttachment { image: h.depth, view: None, clear: None, clear_stencil: None, read_only: false };
        rec.begin_rendering(&RenderTargets { color: &color, depth: Some(frame_depth) });
        rec.bind_pipeline(&self.classify);
        rec.bind_descriptor_set(h.layout, 1, h.shadow_set);
        forward::draw_objects(rec, h.layout, h.gpu, h.scene, light, log);
        rec.end_rendering();
        rec.transition(&[(classes, ImageState::ColorAttachment, ImageState::FragmentRead)]);
        timer.end(rec, log);

        // §4: the computation mask (and the silhouette-pixel count, by occlusion query).
        timer.begin(rec, log, name("computation mask"), Some(h.light));
        let target = match (h.mask, &targets.masked_depth) {
            (MaskKind::DepthBounds, Some(masked)) => {
                let masked_was =
                    if h.first_in_frame { ImageState::Undefined } else { ImageState::DepthStencilAttachment };
                rec.transition(&[
                    (h.depth, ImageState::DepthStencilAttachment, ImageState::TransferSrc),
                    (masked, masked_was, ImageState::TransferDst),
                ]);
                rec.copy_image(h.depth, masked);
                rec.transition(&[
                    (h.depth, ImageState::TransferSrc, ImageState::DepthStencilAttachment),
                    (masked, ImageState::TransferDst, ImageState::DepthStencilAttachment),
                ]);
                masked
            }
            _ => h.depth,
        };
        let attach =
            |clear_stencil| DepthAttachment { image: target, view: None, clear: None, clear_stencil, read_only: false };
        rec.begin_rendering(&RenderTargets { color: &[], depth: Some(attach(Some(0))) });
        rec.bind_pipeline(match h.mask {
            MaskKind::DepthBounds => &self.mask_depth_bounds,
            MaskKind::Stencil => &self.mask_stencil,
            MaskKind::None => &self.mask_none,
        });
        if h.mask == MaskKind::Stencil {
            rec.set_stencil_reference(SILHOUETTE_BIT);
        }
        rec.bind_descriptor_set(h.layout, 1, h.shadow_set);
        rec.begin_query(h.queries, h.first_query);
        rec.draw(3);
        log.count_draw(1);
        rec.end_query(h.queries, h.first_query);
        rec.end_rendering();
        timer.end(rec, log);

        // Step 3: z-fail volumes, where the mask lets them through.
        timer.begin(rec, log, name("hybrid volumes"), Some(h.light));
        rec.transition(&[(target, ImageState::DepthStencilAttachment, ImageState::DepthStencilAttachment)]);
        if let Some(vertices) = h.vertices {
            rec.begin_rendering(&RenderTargets { color: &[], depth: Some(attach(None)) });
            self.bind_volumes(rec, h.mask, h.zfail);
            let b = VolumeBindings { layout: h.layout, gpu: h.gpu, vertices };
            b.bind(rec);
            b.draw(rec, &h.volumes.casters, light, log);
            rec.end_rendering();
        }
        timer.end(rec, log);

        // Step 4: silhouette pixels lit where their count is zero.
        timer.begin(rec, log, format!("light {} silhouettes", h.light), Some(h.light));
        let color = [ColorAttachment { image: h.color, clear: None }];
        rec.begin_rendering(&RenderTargets { color: &color, depth: Some(attach(None)) });
        rec.bind_pipeline(if h.mask == MaskKind::Stencil { &self.lit_count_bits } else { &self.lit });
        rec.set_stencil_reference(0);
        rec.bind_descriptor_set(h.layout, 1, h.shadow_set);
        forward::draw_objects(rec, h.layout, h.gpu, h.scene, light, log);
        rec.end_rendering();
        timer.end(rec, log);

        if let Some(q) = h.fragment_query {
            // The volume fragments the mask lets through (no depth test, no writes); without
            // a mask the query stays empty (the count is the unmasked one).
            timer.begin_diagnostic(rec, log, name("masked volume fragments"), Some(h.light));
            rec.begin_rendering(&RenderTargets { color: &[], depth: Some(attach(None)) });
            rec.begin_query(h.queries, q);
            let counting = match h.mask {
                MaskKind::DepthBounds => self.fragments_depth_bounds.as_ref(),
                MaskKind::Stencil => Some(&self.fragments_stencil),
                MaskKind::None => None,
            };
            if let (Some(p), Some(vertices)) = (counting, h.vertices) {
                rec.bind_pipeline(p);
                match h.mask {
                    MaskKind::DepthBounds => rec.set_depth_bounds(DEPTH_BOUNDS_EPSILON, 1.0),
                    _ => rec.set_stencil_reference(SILHOUETTE_BIT),
                }
                let b = VolumeBindings { layout: h.layout, gpu: h.gpu, vertices };
                b.bind(rec);
                b.draw(rec, &h.volumes.casters, light, log);
            }
            rec.end_query(h.queries, q);
            rec.end_rendering();
            timer.end(rec, log);
        }

        let Some(out) = h.readback else { return };
        timer.begin_diagnostic(rec, log, name("hybrid diagnostics"), Some(h.light));
        rec.transition(&[
            (classes, ImageState::FragmentRead, ImageState::TransferSrc),
            (target, ImageState::DepthStencilAttachment, ImageState::TransferSrc),
        ]);
        rec.copy_image_to_buffer(classes, 0, &out.classes);
        if let Some(stencil) = &out.stencil {
            rec.copy_stencil_to_buffer(target, stencil);
        }
        rec.transition(&[
            (classes, ImageState::TransferSrc, ImageState::FragmentRead),
            (target, ImageState::TransferSrc, ImageState::DepthStencilAttachment),
        ]);
        timer.end(rec, log);
    }

    /// Binds the counting pipeline of `mask` and its dynamic state.
    fn bind_volumes<'a>(&'a self, rec: &mut Recorder<'a>, mask: MaskKind, unmasked: &'a GraphicsPipeline) {
        match (mask, &self.volumes_depth_bounds) {
            (MaskKind::DepthBounds, Some(p)) => {
                rec.bind_pipeline(p);
                rec.set_depth_bounds(DEPTH_BOUNDS_EPSILON, 1.0);
                rec.set_stencil_reference(0);
            }
            (MaskKind::Stencil, _) => {
                rec.bind_pipeline(&self.volumes_stencil);
                rec.set_stencil_reference(SILHOUETTE_BIT);
            }
            _ => {
                rec.bind_pipeline(unmasked);
                rec.set_stencil_reference(0);
            }
        }
    }
}

/// What one hybrid light's passes read and write.
pub(crate) struct HybridLight<'a> {
    /// Index of the light.
    pub light: usize,
    /// Its computation mask (supported by the device: checked when the renderer was built).
    pub mask: MaskKind,
    /// Whether it is the frame's first hybrid light (the targets' content is undefined).
    pub first_in_frame: bool,
    pub layout: &'a PipelineLayout,
    pub gpu: &'a GpuScene,
    pub scene: &'a Scene,
    /// Set 1: its map through the hardware-PCF sampler, the classes image at binding 3.
    pub shadow_set: &'a DescriptorSet,
    /// The frame's colour and depth/stencil, as attachments.
    pub color: &'a Image,
    pub depth: &'a Image,
    /// Its z-fail volumes (culled casters already left out) and their vertices.
    pub volumes: &'a LightVolumes,
    pub vertices: Option<&'a Buffer>,
    /// The unmasked z-fail pipeline (`none`).
    pub zfail: &'a GraphicsPipeline,
    /// Query `first_query`: the mask pass's samples.
    pub queries: &'a QueryPool,
    pub first_query: u32,
    /// With `overdraw`: the query counting masked volume fragments (written even when empty:
    /// every query of the pool is read back). With diagnostics: the readbacks.
    pub fragment_query: Option<u32>,
    pub readback: Option<&'a ClassReadback>,
}
