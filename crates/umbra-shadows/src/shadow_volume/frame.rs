//! The passes of shadow volumes in the frame graph (Everitt–Kilgard), each declaring what it
//! reads and writes:
//! - once a frame, when a light builds its volumes on the GPU: `volume positions` (meshes an
//!   engine deforms on the GPU) and `volume draws reset`; after every light, `volume counts
//!   readback` for the report;
//! - per light built on the GPU: `volume classify N` and `volume silhouettes N`;
//! - per light: `shadow_volume N`, the stencil counts, then `visibility N (stencil)` resolving
//!   them into the light's visibility image, which the lighting pass reads;
//! - with the overdraw diagnostic, per light: `volume overdraw N`, every volume fragment
//!   counted into the overdraw image.

use super::build::LightVolumes;
use super::gpu_frame::{GpuDraws, GpuVolumes, SlotVolumes};
use super::pass::{ShadowVolumePass, VolumeBindings};
use crate::frame::{PassId, PassRecorder, QueryId, Stage, Use};
use crate::light_surfaces::LightSurfaces;
use crate::visibility::{VisibilityPass, VisibilityTarget};
use umbra_vk::{
    Buffer, BufferState, ColorAttachment, DepthAttachment, Image, ImageState, PipelineLayout, RenderTargets,
};

/// Where a light's volumes are drawn from.
#[derive(Clone, Copy)]
pub(crate) enum VolumeSource<'a> {
    /// Built on the host: the frame's volume vertices (none when the frame has none).
    Host(Option<&'a Buffer>),
    /// Built on the GPU (`VolumeBuild::Gpu`): the stages' buffers and the frame slot's set.
    Gpu(&'a GpuVolumes, &'a SlotVolumes),
}

impl<'a> VolumeSource<'a> {
    /// What the counting draws read besides the depth/stencil: the GPU-built volumes' facing,
    /// lists and indirect draws, and the positions where a mesh deforms on the GPU, as vertex
    /// input.
    pub fn reads(&self) -> Vec<Use<'a>> {
        let VolumeSource::Gpu(g, _) = self else { return Vec::new() };
        let read = |b| Use::Buffer(b, BufferState::VertexRead);
        let mut reads =
            g.written().map_or_else(Vec::new, |(facing, list, draws)| vec![read(facing), read(list), read(draws)]);
        reads.extend(g.deformed_positions().map(read));
        reads
    }
}

/// One shadow-volume light's volumes, as its passes draw them.
#[derive(Clone, Copy)]
pub(crate) struct VolumeLight<'a> {
    /// The light's passes over the frame's surfaces.
    pub surfaces: LightSurfaces<'a, 'a>,
    /// The renderer's scene layout.
    pub layout: &'a PipelineLayout,
    /// Its volumes and where they are drawn from.
    pub volumes: &'a LightVolumes,
    pub source: VolumeSource<'a>,
}

impl<'a> VolumeLight<'a> {
    /// Draws the light's volumes inside `cx`'s open rendering pass: `host` with the frame's
    /// vertices bound, or `gpu` with the draws the GPU built; nothing without volume vertices.
    pub fn draw(
        &self,
        cx: &mut PassRecorder<'_, 'a>,
        host: impl FnOnce(&mut PassRecorder<'_, 'a>, VolumeBindings<'a>),
        gpu: impl FnOnce(&mut PassRecorder<'_, 'a>, &'a GpuVolumes, GpuDraws<'a, 'a>),
    ) {
        let s = self.surfaces;
        match self.source {
            VolumeSource::Host(Some(vertices)) => {
                host(cx, VolumeBindings { layout: self.layout, gpu: s.gpu, vertices })
            }
            VolumeSource::Gpu(g, slot) => {
                gpu(cx, g, GpuDraws { gpu: s.gpu, slot, volumes: self.volumes, light: s.light })
            }
            VolumeSource::Host(None) => {}
        }
    }
}

/// The frame's passes before any light's volumes are built on the GPU, when `any_light` builds
/// them: `volume positions`, the meshes an engine deforms on the GPU copied into the volumes'
/// positions (`deform.rs`), and `volume draws reset`, every job's draw and counts set from
/// their initial values `resets`.
pub(crate) fn declare_gpu_frame<'a>(
    stage: &mut Stage<'a>,
    g: &'a GpuVolumes,
    any_light: bool,
    resets: Option<&'a Buffer>,
) {
    if !any_light {
        return;
    }
    if let Some(positions) = g.deformed_positions() {
        stage.pass(PassId::VolumePositions, &[Use::Buffer(positions, BufferState::ComputeStorage)], move |cx| {
            g.record_deform(cx.rec);
            Ok(())
        });
    }
    if let (Some(init), Some((_, _, draws))) = (resets, g.written()) {
        stage.pass(PassId::VolumeDrawsReset, &[Use::Buffer(draws, BufferState::TransferDst)], move |cx| {
            g.record_reset(cx.rec, init);
            Ok(())
        });
    }
}

/// `volume counts readback` (the renderer's own frames, after every light's shadows): the
/// first `jobs` draws and counts of the volumes built on the GPU copied out for the report.
/// Whether it was declared.
pub(crate) fn declare_gpu_counts<'a>(stage: &mut Stage<'a>, g: &'a GpuVolumes, jobs: Option<usize>) -> bool {
    let (Some((_, _, draws)), Some(out), Some(count)) = (g.written(), g.counts_readback(), jobs) else {
        return false;
    };
    stage.pass(PassId::VolumeCounts, &[Use::Buffer(draws, BufferState::TransferSrc), Use::Readback(out)], move |cx| {
        g.record_counts_readback(cx.rec, count);
        Ok(())
    });
    true
}

/// The GPU's build of light `l`'s volumes: `volume classify N` and `volume silhouettes N`,
/// through the frame slot's set `slot`; `None` when the stages' buffers are not prepared.
pub(crate) fn declare_gpu_stages<'a>(
    stage: &mut Stage<'a>,
    l: usize,
    g: &'a GpuVolumes,
    slot: &'a SlotVolumes,
    volumes: &'a LightVolumes,
) -> Option<VolumeSource<'a>> {
    let (facing, list, draws) = g.written()?;
    let storage = BufferState::ComputeStorage;
    let mut uses = vec![Use::Buffer(facing, storage), Use::Buffer(draws, storage)];
    uses.extend(g.deformed_positions().map(|p| Use::Buffer(p, BufferState::ComputeRead)));
    stage.pass(PassId::VolumeClassify(l), &uses, move |cx| {
        g.record_classify(cx.rec, slot, volumes);
        Ok(())
    });
    let uses = [Use::Buffer(facing, storage), Use::Buffer(list, storage), Use::Buffer(draws, storage)];
    stage.pass(PassId::VolumeSilhouettes(l), &uses, move |cx| {
        g.record_silhouettes(cx.rec, slot, volumes);
        Ok(())
    });
    Some(VolumeSource::Gpu(g, slot))
}

/// Light `v`'s `shadow_volume N`, the stencil counts of its volumes in the frame's depth (the
/// stencil cleared, the depth kept), then `visibility N (stencil)` resolving them into its
/// visibility image. The counts are empty without volume vertices.
pub(crate) fn declare_light<'a>(
    stage: &mut Stage<'a>,
    pass: &'a ShadowVolumePass,
    resolve: &'a VisibilityPass,
    v: VolumeLight<'a>,
    target: VisibilityTarget<'a>,
) {
    let (s, l, depth) = (v.surfaces, v.surfaces.light as usize, target.depth);
    let uses = [vec![Use::Image(depth, ImageState::DepthStencilAttachment)], v.source.reads()].concat();
    stage.pass(PassId::ShadowVolume(l), &uses, move |cx| {
        let stencil = DepthAttachment::clearing_stencil(depth, 0);
        cx.rec.begin_rendering(&RenderTargets { color: &[], depth: Some(stencil) });
        v.draw(
            cx,
            |cx, b| pass.record_stencil(cx.rec, b, v.volumes, s.light, s.bounds, cx.log),
            |cx, g, draws| g.record_stencil(cx.rec, draws, s.bounds, pass.fold(), cx.log),
        );
        cx.rec.end_rendering();
        Ok(())
    });
    stage.pass(PassId::StencilVisibility(l), &target.uses(), move |cx| {
        target.begin(cx.rec);
        resolve.record_stencil(cx, v.layout, s);
        cx.rec.end_rendering();
        Ok(())
    });
}

/// With the overdraw diagnostic, light `v`'s volumes drawn into the overdraw image `image`
/// (cleared by the `first` light), counted by the returned query: every fragment of every
/// volume, as rasterised.
pub(crate) fn declare_overdraw<'a>(
    stage: &mut Stage<'a>,
    pass: &'a ShadowVolumePass,
    v: VolumeLight<'a>,
    image: &'a Image,
    first: bool,
) -> QueryId {
    let (s, l) = (v.surfaces, v.surfaces.light as usize);
    let query = stage.queries(1);
    let uses = [vec![Use::Image(image, ImageState::ColorAttachment)], v.source.reads()].concat();
    stage.pass(PassId::VolumeOverdraw(l), &uses, move |cx| {
        let clear = first.then_some([0.0; 4]);
        cx.rec.begin_rendering(&RenderTargets { color: &[ColorAttachment { image, view: None, clear }], depth: None });
        cx.begin_query(query);
        v.draw(
            cx,
            |cx, b| pass.record_overdraw(cx.rec, b, v.volumes, s.light, cx.log),
            |cx, g, draws| g.record_overdraw(cx.rec, draws),
        );
        cx.end_query(query);
        cx.rec.end_rendering();
        Ok(())
    });
    query
}
