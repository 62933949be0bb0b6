//! The end of a frame: the pixels and views read back, each light's counts decoded from its
//! queries and readbacks, and the frame report.

use super::lights::{LightBindings, LightFrame, LightSets};
use super::record::FrameRun;
use super::{Frame, Renderer};
use crate::diagnostics::{LightDiagnostics, PixelClass};
use crate::frame::timing::PassReport;
use crate::frame::PassId;
use crate::gbuffer::GBufferPass;
use crate::hybrid::rays::HybridRays;
use crate::hybrid::{MaskKind, DEPTH_BOUNDS_EPSILON};
use crate::plan::{FramePlan, HybridReport, HybridRtReport, LightPlan};
use crate::report::{FrameReport, SceneSummary};
use crate::RenderResult;
use std::sync::Arc;
use umbra_scene::{Adjacency, Scene};

impl Renderer {
    /// Reads the frame back and reports it (`cpu_frame_ms` and `memory_allocations` are the
    /// caller's to fill in).
    pub(super) fn finish(
        &self,
        scene: &Scene,
        adjacency: &[Arc<Adjacency>],
        lights: Vec<LightFrame>,
        sets: &[LightSets],
        run: FrameRun,
    ) -> RenderResult<Frame> {
        let bindings = self.bindings(sets);
        let rgba = match &self.own()?.readback {
            Some(readback) => readback.read()?,
            None => Vec::new(),
        };
        let overdraw = match (&self.overdraw, run.overdraw) {
            (Some((_, readback)), true) => Some(readback.read()?),
            _ => None,
        };
        let last = run.stages.last();
        let samples = |q| last.map_or(0, |s| s.samples(q));
        let passes: Vec<PassReport> = run.stages.iter().flat_map(|s| s.passes.iter().cloned()).collect();
        let mut diagnostics = Vec::new();
        let mut visibility = Vec::new();
        let mut plans = Vec::with_capacity(lights.len());
        let volume_counts = match (&self.gpu_volumes, run.volume_counts) {
            (Some(g), true) => g.read_counts()?,
            _ => Vec::new(),
        };
        for light in &lights {
            let mut plan = light.plan.clone();
            let queries = run.queries[light.light()];
            if let (Some(v), false) = (&light.volumes, volume_counts.is_empty()) {
                plan.shadow_volume = Some(v.counted_report(scene, &volume_counts));
            }
            if let (Some(r), Some(_)) = (plan.shadow_volume.as_mut(), &self.overdraw) {
                // Volumes built, none with a triangle: nothing was rasterized.
                r.volume_fragments = Some(queries.volume_fragments.map_or(0, samples));
            }
            if let Some(h) = queries.hybrid {
                plan.hybrid =
                    Some(self.hybrid_report(&plan, light, &passes, samples(h.mask), h.fragments.map(samples)));
            }
            if light.hybrid_rays() {
                plan.hybrid_rt = Some(self.hybrid_rt_report(light, &passes)?);
            }
            if let (Some(r), Some(stats)) = (plan.ray_traced.as_mut(), &self.ray_stats) {
                r.traversal = stats.read(light.light())?;
            }
            if let Some(d) = self.read_diagnostics(light, &bindings[light.light()], &mut plan)? {
                diagnostics.push(d);
            }
            if let (true, Some(out)) = (queries.shadowed, bindings[light.light()].visibility_readback) {
                visibility.push(out.read(light.light(), self.desc.width, self.desc.height)?);
            }
            plan.passes = passes.iter().filter(|p| p.light == Some(plan.light)).map(|p| p.name.clone()).collect();
            plans.push(plan);
        }
        let gbuffer = self.gbuffer.as_ref().map(GBufferPass::read).transpose()?;
        let report = self.report(scene, adjacency, plans, passes);
        let (width, height) = (self.desc.width, self.desc.height);
        Ok(Frame { width, height, rgba, report, overdraw, diagnostics, gbuffer, visibility })
    }

    /// A ray-traced hybrid light's figures: its rays, counted by its classification and read
    /// back (umbra's own frames).
    fn hybrid_rt_report(&self, light: &LightFrame, passes: &[PassReport]) -> RenderResult<HybridRtReport> {
        let l = light.light();
        let rays = self.hybrid_rays.as_ref();
        let list_capacity = rays.map_or(0, HybridRays::capacity);
        let count = match rays.and_then(|r| r.count_readback(l)) {
            Some(readback) => Some(crate::hybrid::rays::read_count(readback)?),
            None => None,
        };
        let image_pixels = u64::from(self.desc.width) * u64::from(self.desc.height);
        Ok(HybridRtReport {
            rays: count,
            ray_fraction: count.map(|n| n as f64 / image_pixels as f64),
            rays_dropped: count.map(|n| n.saturating_sub(list_capacity)),
            list_capacity,
            rays_gpu_ms: passes.iter().find(|p| p.id == PassId::HybridRays(l)).and_then(|p| p.gpu_ms),
        })
    }

    /// A hybrid light's figures: `kept` samples passed its mask pass, `masked` volume
    /// fragments passed the mask (with `overdraw`).
    fn hybrid_report(
        &self,
        plan: &LightPlan,
        light: &LightFrame,
        passes: &[PassReport],
        kept: u64,
        masked: Option<u64>,
    ) -> HybridReport {
        let image_pixels = u64::from(self.desc.width) * u64::from(self.desc.height);
        // The depth-bounds mask pass keeps the other pixels; the others keep silhouettes.
        let silhouette_pixels = match self.mask {
            MaskKind::DepthBounds => image_pixels.saturating_sub(kept),
            _ => kept,
        };
        let volume_fragments = plan.shadow_volume.as_ref().and_then(|r| r.volume_fragments);
        HybridReport {
            mask: self.mask,
            depth_bounds_epsilon: (self.mask == MaskKind::DepthBounds).then_some(DEPTH_BOUNDS_EPSILON),
            silhouette_pixels,
            silhouette_fraction: silhouette_pixels as f64 / image_pixels as f64,
            volume_casters: light.volumes.as_ref().map_or(0, |v| v.casters.len()),
            culled_casters: light.culled_blockers,
            volume_fragments,
            masked_volume_fragments: match self.mask {
                MaskKind::None => volume_fragments,
                _ => masked,
            },
            stencil_gpu_ms: passes.iter().find(|p| p.id == PassId::HybridVolumes(light.light())).and_then(|p| p.gpu_ms),
        }
    }

    /// A light's diagnostic views, read back (silhouette-map lights also count their
    /// silhouette pixels into `plan`).
    fn read_diagnostics(
        &self,
        light: &LightFrame,
        bindings: &LightBindings<'_>,
        plan: &mut LightPlan,
    ) -> RenderResult<Option<LightDiagnostics>> {
        let l = light.light();
        if let Some(out) = &bindings.silhouette_readback {
            let d = out.read(l)?;
            if let Some(r) = plan.silhouette_map.as_mut() {
                let n = d.silhouette_pixels();
                r.silhouette_pixels = Some(n);
                r.silhouette_fraction =
                    Some(n as f64 / (u64::from(self.desc.width) * u64::from(self.desc.height)) as f64);
            }
            return Ok(Some(d));
        }
        let Some(out) = &bindings.class_readback else { return Ok(None) };
        Ok(Some(match light.hybrid() {
            true => out.read(l, Some((PixelClass::SilhouetteLit, self.mask.count_bits())))?,
            // A shadow-volume light's shader saw no shadow: its stencil decides every lit pixel.
            false => out.read(l, out.stencil.as_ref().map(|_| (PixelClass::MapLit, 0xff)))?,
        }))
    }

    fn report(
        &self,
        scene: &Scene,
        adjacency: &[Arc<Adjacency>],
        lights: Vec<LightPlan>,
        passes: Vec<PassReport>,
    ) -> FrameReport {
        let caps = self.ctx.capabilities();
        let sum = |diagnostic: bool| {
            passes.iter().filter(|p| p.diagnostic == diagnostic).map(|p| p.gpu_ms).sum::<Option<f64>>()
        };
        FrameReport {
            device: caps.device_name.clone(),
            driver: caps.driver(),
            capabilities: caps.clone(),
            scene: SceneSummary::of(scene, adjacency),
            width: self.desc.width,
            height: self.desc.height,
            shadow_map_settings: *self.shadow_map.settings(),
            shadow_volume_settings: self.desc.shadow_volume,
            plan: FramePlan::of(self.desc.cull, &lights),
            lights,
            total_gpu_ms: sum(false),
            diagnostic_gpu_ms: sum(true),
            passes,
            cpu_frame_ms: 0.0,
            cpu_prepare_ms: 0.0,
            cpu_record_ms: 0.0,
            cpu_submit_wait_ms: 0.0,
            submissions: 0,
            geometry_uploaded_bytes: 0,
            memory_allocations: 0,
        }
    }
}
