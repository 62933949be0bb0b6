//! The end of a frame: the pixels and views read back, each light's counts decoded from its
//! queries and readbacks, and the frame report.

use super::record::FrameRun;
use super::{Frame, Renderer};
use crate::frame::timing::PassReport;
use crate::gbuffer::GBufferPass;
use crate::plan::{FramePlan, LightPlan};
use crate::report::{FrameReport, SceneSummary};
use crate::techniques::{FrameCounts, LightFrame, LightSets};
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
        let volume_counts = self.techniques.read_volume_counts(run.volume_counts)?;
        let counts = FrameCounts {
            passes: &passes,
            samples: &samples,
            volume_counts: &volume_counts,
            overdraw: self.overdraw.is_some(),
        };
        for light in &lights {
            let mut plan = light.plan.clone();
            let queries = run.queries[light.light()];
            self.techniques.report_light(scene, light, queries, &counts, &mut plan)?;
            if let Some(d) = self.techniques.read_diagnostics(light, &bindings[light.light()], &mut plan)? {
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
            shadow_map_settings: *self.techniques.shadow_map_settings(),
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
