//! The diagnostics' shadow-ray counters in a frame (`crate::ray_traced::stats`, with
//! `RendererDesc::diagnostics` in umbra's own frames): `ray stats reset` before the first
//! ray-casting light's shadows, `ray stats N` after each one's visibility, `ray stats readback`
//! after the last.

use super::inputs::FrameInputs;
use super::light::LightFrame;
use super::Techniques;
use crate::frame::{PassId, Stage, Use};
use crate::light_surfaces::over_surfaces;
use crate::ray_traced::stats::RayStats;
use crate::RenderResult;
use umbra_vk::{BufferState, ImageState};

use ImageState::{ColorAttachment as Color, DepthStencilAttachment as Depth};

impl Techniques {
    /// With the shadow rays' counters (`ray_traced::stats`) and a ray-casting light this frame,
    /// `ray stats reset`; the counters to use, if so.
    pub(super) fn declare_ray_stats_reset<'a>(
        &'a self,
        stage: &mut Stage<'a>,
        f: FrameInputs<'a>,
    ) -> Option<&'a RayStats> {
        let stats = self.ray_stats.as_ref().filter(|_| f.lights.iter().any(|l| l.plan.recorded && l.rays()))?;
        let (counters, _) = stats.buffers()?;
        stage.pass(PassId::RayStatsReset, &[Use::Buffer(counters, BufferState::TransferDst)], move |cx| {
            stats.record_reset(cx.rec);
            Ok(())
        });
        Some(stats)
    }

    /// `ray stats N`: a ray-traced light's rays over the frame's surfaces, or a hybrid-RT
    /// light's listed rays, cast again with counters on.
    pub(super) fn declare_ray_stats<'a>(
        &'a self,
        stage: &mut Stage<'a>,
        f: FrameInputs<'a>,
        light: &'a LightFrame,
        stats: &'a RayStats,
    ) -> RenderResult<()> {
        let l = light.light();
        let (Some((counters, _)), Some(bvh)) = (stats.buffers(), f.slot.rays.as_ref().map(|r| &r.set)) else {
            return Ok(());
        };
        let image = &f.visibility.light(l)?.image;
        if !light.hybrid_rays() {
            let (surfaces, depth) = (f.surfaces(light), f.depth);
            let uses = [
                Use::Image(image, Color),
                Use::Image(depth, Depth),
                Use::Buffer(counters, BufferState::FragmentStorage),
            ];
            stage.pass(PassId::RayStats(l), &uses, move |cx| {
                over_surfaces(cx.rec, image, None, depth);
                stats.record_surfaces(cx, bvh, surfaces);
                cx.rec.end_rendering();
                Ok(())
            });
            return Ok(());
        }
        let Some(rays) = &self.hybrid_rays else { return Ok(()) };
        let (Some((header, entries, pixel_rays)), Some((list, output))) = (rays.list(), rays.sets(l)) else {
            return Ok(());
        };
        let uses = [
            Use::Image(image, ImageState::ComputeWrite),
            Use::Image(pixel_rays, ImageState::ComputeRead),
            Use::Buffer(header, BufferState::ComputeRead),
            Use::Buffer(entries, BufferState::ComputeRead),
            Use::Buffer(counters, BufferState::ComputeStorage),
        ];
        stage.pass(PassId::RayStats(l), &uses, move |cx| {
            stats.record_listed(cx.rec, [bvh, list, output], header, l as u32);
            Ok(())
        });
        Ok(())
    }

    /// `ray stats readback`: every light's counters copied out.
    pub(super) fn declare_ray_stats_readback<'a>(&'a self, stage: &mut Stage<'a>, stats: &'a RayStats) {
        let Some((counters, readback)) = stats.buffers() else { return };
        let uses = [Use::Buffer(counters, BufferState::TransferSrc), Use::Readback(readback)];
        stage.pass(PassId::RayStatsReadback, &uses, move |cx| {
            stats.record_readback(cx.rec);
            Ok(())
        });
    }
}
