//! Step 3's counting pipelines (Chan–Durand §4): the z-fail volumes drawn only where the
//! computation mask lets them through, for one volume input (the host's vertices, or a
//! GPU-built volume's sides or caps, `shadow_volume/gpu_frame.rs`).

use super::pass::count_bits;
use super::settings::{MaskKind, COUNT_BITS, DEPTH_BOUNDS_EPSILON, SILHOUETTE_BIT};
use crate::frame::timing::PassLog;
use crate::shadow_volume::batches::{counting_in_batch, CountBits, FULL_STENCIL};
use crate::shadow_volume::gpu_frame::{GpuDraws, GpuVolumes};
use crate::shadow_volume::pass::{self as volume_pass, VolumeInput};
use crate::RenderResult;
use umbra_vk::{
    vk, Context, DepthState, GraphicsPipeline, GraphicsPipelineDesc, PipelineLayout, Recorder, StencilFace,
};

/// The debug name prefix of `input`'s pipelines.
fn prefix(input: VolumeInput) -> &'static str {
    match input {
        VolumeInput::GpuSides => "hybrid volume sides",
        VolumeInput::GpuCaps => "hybrid volume caps",
        VolumeInput::Built | VolumeInput::HostClipped => "hybrid volumes",
    }
}

/// `desc` with the depth-bounds test on, named `name`, where the device has `depthBounds`.
pub(super) fn with_depth_bounds<'d>(
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

/// The z-fail counting desc of `input` counting only where the silhouette bit is set, in the
/// count bits (`settings::COUNT_BITS`).
fn stencil_masked<'d>(mut desc: GraphicsPipelineDesc<'d>, name: &'d str) -> GraphicsPipelineDesc<'d> {
    desc.name = name;
    desc.stencil = desc.stencil.map(|(front, back)| {
        let masked = |f: StencilFace| StencilFace {
            compare: vk::CompareOp::EQUAL,
            compare_mask: SILHOUETTE_BIT,
            write_mask: COUNT_BITS,
            ..f
        };
        (masked(front), masked(back))
    });
    desc
}

/// Step 3's z-fail counting of one volume input under each computation mask, alone and in a
/// batch's bits (`hybrid::pass::count_bits`; `shadow_volume/batches.rs`).
pub(crate) struct MaskedCounting {
    none: GraphicsPipeline,
    none_batch: GraphicsPipeline,
    /// With the depth-bounds test (`None` without `depthBounds`).
    depth_bounds: Option<GraphicsPipeline>,
    depth_bounds_batch: Option<GraphicsPipeline>,
    stencil: GraphicsPipeline,
    stencil_batch: GraphicsPipeline,
}

impl MaskedCounting {
    /// The pipelines reading `input` against `layout`; `clamp` mirrors the volumes'
    /// `FarPlane::DepthClamp`, `depth_bounds` the device's `depthBounds`.
    pub fn new(
        ctx: &Context,
        layout: &PipelineLayout,
        depth_format: vk::Format,
        clamp: bool,
        depth_bounds: bool,
        input: VolumeInput,
    ) -> RenderResult<Self> {
        let name = |what: &str| format!("{} ({what})", prefix(input));
        let [n_none, n_none_batch, n_bounds, n_bounds_batch, n_stencil, n_stencil_batch] = [
            "no mask",
            "no mask, batch",
            "depth-bounds mask",
            "depth-bounds mask, batch",
            "stencil mask",
            "stencil mask, batch",
        ]
        .map(name);
        let mut desc = volume_pass::zfail_desc(depth_format, clamp, input);
        desc.name = &n_none;
        let none = GraphicsPipeline::new(ctx, layout, &desc)?;
        let none_batch_desc = counting_in_batch(&desc, &n_none_batch, FULL_STENCIL);
        let none_batch = GraphicsPipeline::new(ctx, layout, &none_batch_desc)?;
        let with_bounds = |d, name| with_depth_bounds(ctx, layout, d, name, depth_bounds);
        let depth_bounds_plain = with_bounds(desc, &n_bounds)?;
        let depth_bounds_batch = with_bounds(none_batch_desc, &n_bounds_batch)?;
        let desc = stencil_masked(desc, &n_stencil);
        let stencil = GraphicsPipeline::new(ctx, layout, &desc)?;
        let batch = counting_in_batch(&desc, &n_stencil_batch, count_bits(MaskKind::Stencil));
        let stencil_batch = GraphicsPipeline::new(ctx, layout, &batch)?;
        Ok(Self { none, none_batch, depth_bounds: depth_bounds_plain, depth_bounds_batch, stencil, stencil_batch })
    }

    /// Binds the counting pipeline of `mask` (in a batch's bits when `batched`) and its dynamic
    /// state: the depth bounds `[DEPTH_BOUNDS_EPSILON, 1]` or the silhouette bit as reference.
    pub fn bind<'a>(&'a self, rec: &mut Recorder<'a>, mask: MaskKind, batched: bool) {
        let depth_bounds = if batched { &self.depth_bounds_batch } else { &self.depth_bounds };
        match (mask, depth_bounds) {
            (MaskKind::DepthBounds, Some(p)) => {
                rec.bind_pipeline(p);
                rec.set_depth_bounds(DEPTH_BOUNDS_EPSILON, 1.0);
                rec.set_stencil_reference(0);
            }
            (MaskKind::Stencil, _) => {
                rec.bind_pipeline(if batched { &self.stencil_batch } else { &self.stencil });
                rec.set_stencil_reference(SILHOUETTE_BIT);
            }
            _ => {
                rec.bind_pipeline(if batched { &self.none_batch } else { &self.none });
                rec.set_stencil_reference(0);
            }
        }
    }
}

/// Diagnostic fragment counts of one volume input: its draws with only the computation
/// mask's test, depth and stencil untouched (the hybrid's `volume_fragments`).
pub(crate) struct MaskedFragments {
    /// With the depth-bounds test (`None` without `depthBounds`).
    depth_bounds: Option<GraphicsPipeline>,
    stencil: GraphicsPipeline,
}

impl MaskedFragments {
    /// The pipelines of `input`'s z-fail counting desc `zfail` (`volume_pass::zfail_desc`)
    /// against `layout`; `depth_bounds` the device's `depthBounds`.
    pub fn new(
        ctx: &Context,
        layout: &PipelineLayout,
        zfail: GraphicsPipelineDesc<'_>,
        depth_bounds: bool,
        input: VolumeInput,
    ) -> RenderResult<Self> {
        let mut desc = zfail;
        let names = ["depth-bounds mask", "stencil mask"].map(|what| format!("{} fragments ({what})", prefix(input)));
        // The depth test is on but ALWAYS passes: SwiftShader skips the depth-bounds test
        // while it is off.
        let clamp = desc.depth.clamp;
        desc.depth = DepthState { test: true, compare: vk::CompareOp::ALWAYS, clamp, ..DepthState::NONE };
        desc.stencil = None;
        let with_bounds = with_depth_bounds(ctx, layout, desc, &names[0], depth_bounds)?;
        desc.name = &names[1];
        let bit = super::pass::test_only(vk::CompareOp::EQUAL, SILHOUETTE_BIT);
        desc.stencil = Some((bit, bit));
        let stencil = GraphicsPipeline::new(ctx, layout, &desc)?;
        Ok(Self { depth_bounds: with_bounds, stencil })
    }

    /// Binds the pipeline of `mask` and its dynamic state; false without a mask (nothing to
    /// count: the count is the unmasked one) or without the device's depth-bounds test.
    pub fn bind<'a>(&'a self, rec: &mut Recorder<'a>, mask: MaskKind) -> bool {
        match (mask, &self.depth_bounds) {
            (MaskKind::DepthBounds, Some(p)) => {
                rec.bind_pipeline(p);
                rec.set_depth_bounds(DEPTH_BOUNDS_EPSILON, 1.0);
                true
            }
            (MaskKind::Stencil, _) => {
                rec.bind_pipeline(&self.stencil);
                rec.set_stencil_reference(SILHOUETTE_BIT);
                true
            }
            _ => false,
        }
    }
}

/// Step 3 over volumes built on the GPU (`shadow_volume/gpu_frame.rs`): the masked counting
/// and, with the overdraw diagnostic, the masked fragment counts of their sides and their
/// caps, against the GPU draws' layout.
pub(crate) struct GpuMasked {
    counting: [MaskedCounting; 2],
    fragments: Option<[MaskedFragments; 2]>,
}

impl GpuMasked {
    /// The pipelines against `volumes`' draw layout; `clamp` mirrors the volumes'
    /// `FarPlane::DepthClamp`, `overdraw` asks for the fragment counts.
    pub fn new(
        ctx: &Context,
        volumes: &GpuVolumes,
        depth_format: vk::Format,
        clamp: bool,
        overdraw: bool,
    ) -> RenderResult<Self> {
        // The mask needs the test wherever the device has it (not only for bounds).
        let depth_bounds = ctx.capabilities().depth_bounds;
        let layout = volumes.layout();
        let inputs = [VolumeInput::GpuSides, VolumeInput::GpuCaps];
        let counting = |input| MaskedCounting::new(ctx, layout, depth_format, clamp, depth_bounds, input);
        let counting = [counting(inputs[0])?, counting(inputs[1])?];
        let fragments = |input| {
            let zfail = volume_pass::zfail_desc(depth_format, clamp, input);
            MaskedFragments::new(ctx, layout, zfail, depth_bounds, input)
        };
        let fragments = match overdraw {
            true => Some([fragments(inputs[0])?, fragments(inputs[1])?]),
            false => None,
        };
        Ok(Self { counting, fragments })
    }

    /// A hybrid light's step 3 (inside its `hybrid volumes` pass): its z-fail casters' sides
    /// and caps where the computation mask `mask` lets them through, counted in `bits` with
    /// `fold` between batches.
    pub fn record_counting<'a>(
        &'a self,
        rec: &mut Recorder<'a>,
        volumes: &'a GpuVolumes,
        draws: GpuDraws<'a, '_>,
        (mask, bits): (MaskKind, CountBits),
        fold: &'a GraphicsPipeline,
        log: &mut PassLog,
    ) {
        let [sides, caps] = &self.counting;
        volumes.record_counting(rec, draws, bits, fold, log, |rec, _, batched, is_caps| {
            (if is_caps { caps } else { sides }).bind(rec, mask, batched);
        });
    }

    /// A hybrid light's volume fragments the computation mask `mask` lets through (inside a
    /// rendering pass over its count target; nothing without a mask or the diagnostic).
    pub fn record_fragments<'a>(
        &'a self,
        rec: &mut Recorder<'a>,
        volumes: &'a GpuVolumes,
        draws: GpuDraws<'a, '_>,
        mask: MaskKind,
    ) {
        let Some(fragments) = &self.fragments else { return };
        volumes.record_every_draw(rec, draws, |rec, caps| fragments[usize::from(caps)].bind(rec, mask));
    }
}
