//! What a light's technique reports once its frame ran: its volumes as the GPU counted them,
//! the hybrid's mask and rays, the rays' walk, and its diagnostic views decoded.

use super::light::{LightBindings, LightFrame, LightQueries};
use super::Techniques;
use crate::diagnostics::{LightDiagnostics, PixelClass};
use crate::frame::timing::PassReport;
use crate::frame::{PassId, QueryId};
use crate::hybrid::rays::HybridRays;
use crate::hybrid::{MaskKind, DEPTH_BOUNDS_EPSILON};
use crate::plan::{HybridReport, HybridRtReport, LightPlan};
use crate::RenderResult;
use umbra_scene::Scene;

/// What a frame's run gave back that every light's report reads.
pub(crate) struct FrameCounts<'a> {
    /// The passes run, in order, with their GPU times.
    pub passes: &'a [PassReport],
    /// The samples of a query in the frame's last stage.
    pub samples: &'a dyn Fn(QueryId) -> u64,
    /// The GPU-built volumes' counts (empty when none were read back).
    pub volume_counts: &'a [u32],
    /// Whether volume fragments are counted (`shadow_volume.overdraw`, umbra's own frames).
    pub overdraw: bool,
}

impl Techniques {
    /// The GPU-built volumes' counts, when `read` (the frame copied them out).
    pub fn read_volume_counts(&self, read: bool) -> RenderResult<Vec<u32>> {
        match (&self.gpu_volumes, read) {
            (Some(g), true) => g.read_counts(),
            _ => Ok(Vec::new()),
        }
    }

    /// `light`'s technique's figures into `plan`, from its `queries` and the frame's counts.
    pub fn report_light(
        &self,
        scene: &Scene,
        light: &LightFrame,
        queries: LightQueries,
        c: &FrameCounts<'_>,
        plan: &mut LightPlan,
    ) -> RenderResult<()> {
        if let (Some(v), false) = (light.volumes(), c.volume_counts.is_empty()) {
            plan.shadow_volume = Some(v.counted_report(scene, c.volume_counts));
        }
        if let (Some(r), true) = (plan.shadow_volume.as_mut(), c.overdraw) {
            // Volumes built, none with a triangle: nothing was rasterized.
            r.volume_fragments = Some(queries.volume_fragments.map_or(0, c.samples));
        }
        if let Some(h) = queries.hybrid {
            let (kept, masked) = ((c.samples)(h.mask), h.fragments.map(c.samples));
            plan.hybrid = Some(self.hybrid_report(plan, light, c.passes, kept, masked));
        }
        if light.hybrid_rays() {
            plan.hybrid_rt = Some(self.hybrid_rt_report(light, c.passes)?);
        }
        if let (Some(r), Some(stats)) = (plan.ray_traced.as_mut(), &self.ray_stats) {
            r.traversal = stats.read(light.light())?;
        }
        Ok(())
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
        let image_pixels = u64::from(self.setup.width) * u64::from(self.setup.height);
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
        let image_pixels = u64::from(self.setup.width) * u64::from(self.setup.height);
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
            volume_casters: light.volumes().map_or(0, |v| v.casters.len()),
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
    pub fn read_diagnostics(
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
                    Some(n as f64 / (u64::from(self.setup.width) * u64::from(self.setup.height)) as f64);
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
}
