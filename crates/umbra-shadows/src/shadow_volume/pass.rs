//! The stencil pass (Everitt–Kilgard §2.1): each caster's volume drawn once with two-sided
//! stencil and wrap ops, colour and depth writes off, then (optionally) the overdraw image.

//! Counted in batches where the casters' bounds call for it (`batches.rs`).

use super::batches::{counting_in_batch, fold_desc, record_in_batches, FULL_STENCIL};
use super::build::{CasterVolume, Counting, LightVolumes};
use super::settings::{FarPlane, ShadowVolumeSettings};
use crate::forward::Bounded;
use crate::frame::timing::PassLog;
use crate::gpu_scene::{DrawPush, GpuScene};
use crate::light_surfaces::PassBounds;
use crate::RenderResult;
use umbra_vk::{
    vk, Blend, Buffer, ColorTarget, Context, DepthState, GraphicsPipeline, GraphicsPipelineDesc, PipelineLayout,
    Recorder, StencilFace, VertexAttribute,
};

/// Volume vertices are `vec4`: object-space xyz, w = 0 for vertices at infinity.
pub(crate) const VOLUME_ATTRIBUTES: [VertexAttribute; 1] =
    [VertexAttribute { location: 0, format: vk::Format::R32G32B32A32_SFLOAT, offset: 0 }];
pub(crate) const VOLUME_STRIDE: u32 = 16;

/// What the volume pipelines read: the volume vertices as built, or clipped on the host
/// ([`crate::HostClip`], `clip.rs`); or, for volumes built on the GPU (`gpu.rs`), a caster's
/// silhouette list (its sides) or its mesh's triangles and their facing (its caps).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum VolumeInput {
    Built,
    HostClipped,
    GpuSides,
    GpuCaps,
}

impl VolumeInput {
    /// `desc` reading this input: its vertex shader and layout.
    fn apply(self, desc: &mut GraphicsPipelineDesc<'static>) {
        match self {
            VolumeInput::Built => {
                desc.vertex = umbra_shaders::shadow_volume::EXTRUDE_VERT;
                desc.vertex_stride = VOLUME_STRIDE;
                desc.vertex_attributes = &VOLUME_ATTRIBUTES;
            }
            VolumeInput::HostClipped => {
                desc.vertex = umbra_shaders::shadow_volume::EXTRUDE_CLIPPED_VERT;
                desc.vertex_stride = super::clip::CLIPPED_STRIDE;
                desc.vertex_attributes = &super::clip::CLIPPED_ATTRIBUTES;
            }
            VolumeInput::GpuSides | VolumeInput::GpuCaps => {
                desc.vertex = match self {
                    VolumeInput::GpuSides => umbra_shaders::shadow_volume::GPU_SIDES_VERT,
                    _ => umbra_shaders::shadow_volume::GPU_CAPS_VERT,
                };
                desc.vertex_stride = 0;
                desc.vertex_attributes = &[];
            }
        }
    }
}

/// The depth comparison of front caps cut on the host (`clip.rs`): `NEVER`, so each of their
/// fragments counts as behind the visible surface. A front cap lies on its caster, which the
/// frame's depth holds, so nothing visible is ever behind it: the nearest surface at a cap's
/// pixel is the caster there or something in front of it. Uncut caps find that out exactly
/// (`LESS` against the caster's own depth, from the same vertices); cut caps no longer share
/// the caster's vertices, and their depth drifted from the caster's by more than two pixels'
/// depth change where the driver clipped the caster itself far off screen (hard case 31: a
/// bias of a quarter pixel's slope left a false-shadow wedge of 1 265 pixels, one pixel's 833
/// at another eye). Counted without a depth test they need no bias, whatever the drift.
pub(crate) const CUT_CAP_COMPARE: vk::CompareOp = vk::CompareOp::NEVER;

/// Stencil ops of one face: `op` on `when` (pass or depth-fail), KEEP otherwise.
fn face(op: vk::StencilOp, on_depth_fail: bool) -> StencilFace {
    StencilFace {
        pass: if on_depth_fail { vk::StencilOp::KEEP } else { op },
        depth_fail: if on_depth_fail { op } else { vk::StencilOp::KEEP },
        ..StencilFace::KEEP
    }
}

/// The overdraw image's pipeline for volumes from `input` (Chan–Durand Fig. 3, 10a): every
/// volume fragment adds 1/255 to red, additively, with no depth or stencil test.
pub(crate) fn overdraw_pipeline(
    ctx: &Context,
    layout: &PipelineLayout,
    name: &str,
    clamp: bool,
    input: VolumeInput,
) -> RenderResult<GraphicsPipeline> {
    let mut desc: GraphicsPipelineDesc<'_> = zfail_desc(vk::Format::UNDEFINED, clamp, input);
    desc.name = name;
    desc.fragment = Some(umbra_shaders::shadow_volume::OVERDRAW_FRAG);
    desc.stencil = None;
    desc.depth = DepthState { clamp, ..DepthState::NONE };
    let additive = [ColorTarget { blend: Some(Blend::ADDITIVE), ..ColorTarget::opaque(crate::targets::COLOR_FORMAT) }];
    desc.color_targets = &additive;
    Ok(GraphicsPipeline::new(ctx, layout, &desc)?)
}

/// The z-fail counting pipeline (§2.1): volumes (`input`) tested against the scene's depth
/// (`clamp`: depth clamp on), two-sided stencil with wrap ops, no colour, no depth writes.
pub(crate) fn zfail_desc(depth_format: vk::Format, clamp: bool, input: VolumeInput) -> GraphicsPipelineDesc<'static> {
    let mut desc = GraphicsPipelineDesc::new("shadow volume z-fail", umbra_shaders::shadow_volume::EXTRUDE_VERT);
    input.apply(&mut desc);
    desc.cull = vk::CullModeFlags::NONE;
    desc.depth_format = depth_format;
    // Test against the scene's depth, never write it; LESS, so a front cap lying on its
    // caster's surface fails the test and counts as behind it (z-fail). Host-clipped volumes
    // set the comparison per draw: LESS for most triangles, CUT_CAP_COMPARE for cut front caps.
    let compare_dynamic = input == VolumeInput::HostClipped;
    let compare = vk::CompareOp::LESS;
    desc.depth = DepthState { test: true, write: false, compare, clamp, compare_dynamic, ..DepthState::NONE };
    // Two-sided stencil in one draw: z-fail decrements on front faces and increments on
    // back faces where the depth test fails; *_AND_WRAP because counts interleave.
    desc.stencil = Some((face(vk::StencilOp::DECREMENT_AND_WRAP, true), face(vk::StencilOp::INCREMENT_AND_WRAP, true)));
    desc
}

/// What every volume draw binds: the shared layout, the scene set and the volume vertices.
#[derive(Clone, Copy)]
pub(crate) struct VolumeBindings<'a> {
    pub layout: &'a PipelineLayout,
    pub gpu: &'a GpuScene,
    pub vertices: &'a Buffer,
}

impl<'a> VolumeBindings<'a> {
    /// Binds the scene set and the volume vertices.
    pub fn bind(&self, rec: &mut Recorder<'a>) {
        rec.bind_descriptor_set(self.layout, 0, &self.gpu.frame.set);
        rec.bind_vertex_buffer(self.vertices);
    }

    /// The counting draws (z-fail or z-pass, bound), one per caster: its range without the
    /// cut front caps, tested `LESS`, then (when `volumes` were host-clipped) every caster's
    /// cut caps, compared with [`CUT_CAP_COMPARE`].
    pub fn draw_counting<'c>(
        &self,
        rec: &mut Recorder<'a>,
        casters: impl Iterator<Item = &'c CasterVolume> + Clone,
        host_clipped: bool,
        light: u32,
        log: &mut PassLog,
    ) {
        if host_clipped {
            rec.set_depth_compare_op(vk::CompareOp::LESS);
        }
        let ranges = |cut: bool| {
            casters.clone().map(move |c| match cut {
                false => (c.object, c.first, c.count - c.cut_caps),
                true => (c.object, c.first + c.count - c.cut_caps, c.cut_caps),
            })
        };
        self.draw_ranges(rec, ranges(false), light, log);
        if casters.clone().any(|c| c.cut_caps > 0) {
            rec.set_depth_compare_op(CUT_CAP_COMPARE);
            self.draw_ranges(rec, ranges(true), light, log);
        }
    }

    /// Draws `(object, first, count)` vertex ranges, skipping empty ones.
    fn draw_ranges(
        &self,
        rec: &mut Recorder<'a>,
        ranges: impl Iterator<Item = (usize, u32, u32)>,
        light: u32,
        log: &mut PassLog,
    ) {
        for (object, first, count) in ranges.filter(|r| r.2 > 0) {
            rec.push_constants(self.layout, &DrawPush { object: object as u32, view: light });
            rec.draw_range(count, first);
            log.count_draw(u64::from(count / 3));
        }
    }

    /// One draw per caster, its whole range, with the bound pipeline (no depth test: overdraw
    /// and fragment counts).
    pub fn draw<'c>(
        &self,
        rec: &mut Recorder<'a>,
        casters: impl IntoIterator<Item = &'c CasterVolume>,
        light: u32,
        log: &mut PassLog,
    ) {
        // A caster clipped away entirely on the host (`clip.rs`) draws nothing.
        self.draw_ranges(rec, casters.into_iter().map(|c| (c.object, c.first, c.count)), light, log);
    }
}

/// A counting pipeline (with its depth-bounds twin when `depth_bounds`) and the same counting
/// in a batch's bits, named `batch`.
fn counting_pair(
    ctx: &Context,
    layout: &PipelineLayout,
    desc: &GraphicsPipelineDesc<'_>,
    batch: &'static str,
    depth_bounds: bool,
) -> RenderResult<(Bounded, Bounded)> {
    let twin = counting_in_batch(desc, batch, FULL_STENCIL);
    Ok((Bounded::new(ctx, layout, desc, depth_bounds)?, Bounded::new(ctx, layout, &twin, depth_bounds)?))
}

/// The four counting pipelines of one volume input: z-fail and z-pass, each alone and in a
/// batch's bits (`batches.rs`), each with its depth-bounds twin where the device has them.
pub(crate) struct Counting4 {
    zfail: Bounded,
    zpass: Bounded,
    zfail_batch: Bounded,
    zpass_batch: Bounded,
}

impl Counting4 {
    /// The pipelines reading `input` against `layout`.
    pub fn new(
        ctx: &Context,
        layout: &PipelineLayout,
        depth_format: vk::Format,
        clamp: bool,
        depth_bounds: bool,
        input: VolumeInput,
    ) -> RenderResult<Self> {
        let counting = |desc: &GraphicsPipelineDesc<'_>, batch| counting_pair(ctx, layout, desc, batch, depth_bounds);
        let mut desc = zfail_desc(depth_format, clamp, input);
        let (zfail, zfail_batch) = counting(&desc, "shadow volume z-fail (batch)")?;
        desc.name = "shadow volume z-pass";
        desc.stencil = Some(zpass_faces());
        let (zpass, zpass_batch) = counting(&desc, "shadow volume z-pass (batch)")?;
        Ok(Self { zfail, zpass, zfail_batch, zpass_batch })
    }

    /// The pipeline counting `counting`, in a batch's bits when `batched`.
    pub fn pick(&self, counting: Counting, batched: bool) -> &Bounded {
        match (counting, batched) {
            (Counting::ZFail, false) => &self.zfail,
            (Counting::ZPass, false) => &self.zpass,
            (Counting::ZFail, true) => &self.zfail_batch,
            (Counting::ZPass, true) => &self.zpass_batch,
        }
    }
}

/// z-pass: front faces increment, back faces decrement where the depth test passes.
fn zpass_faces() -> (StencilFace, StencilFace) {
    (face(vk::StencilOp::INCREMENT_AND_WRAP, false), face(vk::StencilOp::DECREMENT_AND_WRAP, false))
}

/// Pipelines of the shadow-volume technique.
pub(crate) struct ShadowVolumePass {
    counting: Counting4,
    /// Between batches: the batch's "count ≠ 0" kept in the fold bit, the count cleared.
    fold: GraphicsPipeline,
    overdraw: Option<GraphicsPipeline>,
}

impl ShadowVolumePass {
    /// Builds the counting pipelines (with depth-bounds twins when `depth_bounds`, and the
    /// overdraw one when asked) against `layout`.
    pub fn new(
        ctx: &Context,
        layout: &PipelineLayout,
        depth_format: vk::Format,
        settings: &ShadowVolumeSettings,
        depth_bounds: bool,
        input: VolumeInput,
    ) -> RenderResult<Self> {
        let clamp = settings.far_plane == FarPlane::DepthClamp;
        let counting = Counting4::new(ctx, layout, depth_format, clamp, depth_bounds, input)?;
        let fold =
            GraphicsPipeline::new(ctx, layout, &fold_desc("shadow volume batch fold", depth_format, FULL_STENCIL))?;
        let overdraw = match settings.overdraw {
            true => Some(overdraw_pipeline(ctx, layout, "shadow volume overdraw", clamp, input)?),
            false => None,
        };
        Ok(Self { counting, fold, overdraw })
    }

    /// Records light `light`'s volumes into the stencil buffer (inside a rendering pass with
    /// the scene's depth loaded and the stencil cleared to 0), within `bounds`: outside them
    /// the light adds nothing, so its lighting pass never reads the stencil there.
    pub fn record_stencil<'a>(
        &'a self,
        rec: &mut Recorder<'a>,
        b: VolumeBindings<'a>,
        volumes: &LightVolumes,
        light: u32,
        bounds: PassBounds,
        log: &mut PassLog,
    ) {
        b.bind(rec);
        record_in_batches(rec, log, volumes, FULL_STENCIL, &self.fold, |rec, log, batch, batched| {
            for counting in [Counting::ZFail, Counting::ZPass] {
                let casters = batch.iter().filter(move |c| c.counting == Some(counting));
                if casters.clone().next().is_none() {
                    continue;
                }
                self.counting.pick(counting, batched).bind(rec, bounds);
                rec.set_stencil_reference(0);
                b.draw_counting(rec, casters, volumes.host_clipped, light, log);
            }
        });
    }

    /// The fold between batches (`batches.rs`).
    pub fn fold(&self) -> &GraphicsPipeline {
        &self.fold
    }

    /// Records the overdraw image's draws for light `light` (inside a rendering pass over the
    /// overdraw target), when built with `overdraw`.
    pub fn record_overdraw<'a>(
        &'a self,
        rec: &mut Recorder<'a>,
        b: VolumeBindings<'a>,
        volumes: &LightVolumes,
        light: u32,
        log: &mut PassLog,
    ) {
        let Some(p) = &self.overdraw else { return };
        rec.bind_pipeline(p);
        b.bind(rec);
        b.draw(rec, &volumes.casters, light, log);
    }
}
