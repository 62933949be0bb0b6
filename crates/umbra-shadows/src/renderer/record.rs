//! One frame, for both entry points: [`Renderer::render`] (umbra's own targets, submitted and
//! waited for) and [`crate::Shadows::record`] (an engine's command buffer, over the engine's
//! depth). Both plan, prepare, upload, bind and declare the same shadow passes through
//! [`Renderer::frame`]; the renderer's own frame adds, around the shadows, what an engine draws
//! itself — its depth and ambient term before them, its lights and readback after — and an
//! engine's frame ends with the hand-off.

use super::engine::FrameDepth;
use super::Renderer;
use crate::frame::timing::PassReport;
use crate::frame::{FrameGraph, PassId, QueryId, StageResults, Use};
use crate::gpu_scene::GpuScene;
use crate::streams::Streams;
use crate::techniques::{
    Binding, CullingPlan, FrameInputs, FrameView, LightBindings, LightFrame, LightQueries, LightSets, PrepareInputs,
};
use crate::RenderResult;
use std::sync::Arc;
use std::time::Instant;
use umbra_scene::{Adjacency, Scene};
use umbra_vk::{vk, Image, ImageState};

/// Where a frame's passes go.
pub(super) enum Output<'a> {
    /// The renderer's own targets: submitted and waited for (twice with blocker culling).
    Own,
    /// An engine's command buffer (recording): nothing submitted, nothing waited for.
    Engine { depth: FrameDepth<'a>, cmd: vk::CommandBuffer },
}

/// What a frame's passes gave back.
pub(super) struct FrameRun {
    /// The renderer's own frame: every submission's results, in order (the last holds the
    /// lighting passes' queries).
    pub stages: Vec<StageResults>,
    /// An engine's frame: the passes recorded, in order, their GPU times not read yet.
    pub recorded: Vec<PassReport>,
    /// Per light, its queries in the last stage.
    pub queries: Vec<LightQueries>,
    /// Whether a pass drew into the overdraw image.
    pub overdraw: bool,
    /// Whether the GPU-built volumes' counts were copied out (`volume counts readback`).
    pub volume_counts: bool,
}

/// A frame, recorded (and, the renderer's own, run).
pub(super) struct Recorded {
    pub lights: Vec<LightFrame>,
    pub sets: Vec<LightSets>,
    /// Welded connectivity per mesh, as the frame used it.
    pub adjacency: Vec<Arc<Adjacency>>,
    pub run: FrameRun,
    /// Bytes of mesh data uploaded for it (0 when the meshes were unchanged).
    pub geometry_uploaded: u64,
    /// When the CPU preparation ended and declaring the passes began.
    pub prepared: Instant,
    /// Host time declaring, recording and (the renderer's own) running the passes.
    pub run_ms: f64,
}

impl Renderer {
    /// The frame's table of contents, for `scene` seen through `view`:
    /// 1. plan: per light, what to record and which casters enter its passes (the slot's last
    ///    frame completed, so what it retired goes);
    /// 2. prepare each light's technique on the CPU (`Techniques::prepare`): map views and
    ///    maps, silhouette edges, volumes, the ray-tracing BVH, blocker boxes, with welded
    ///    connectivity cached per mesh revision;
    /// 3. upload what changed (`prepare.rs`) and bind each light's maps (`Techniques::bind`);
    /// 4. declare the passes into the frame graph and run or record them
    ///    ([`Renderer::declare_frame`]).
    pub(super) fn frame(&mut self, scene: &Scene, view: FrameView, out: Output<'_>) -> RenderResult<Recorded> {
        self.slot.begin();
        let mut lights = self.plan(scene, &view)?;
        let mut adjacency = self.meshes.adjacency(scene)?;
        self.techniques.deforming.substitute(&mut adjacency);
        let mut streams = std::mem::take(&mut self.slot.streams);
        let ran = self.prepare_and_run(scene, &view, &adjacency, &mut lights, &mut streams, out);
        self.slot.streams = streams;
        let (run, sets, geometry_uploaded, prepared, run_ms) = ran?;
        Ok(Recorded { lights, sets, adjacency, run, geometry_uploaded, prepared, run_ms })
    }

    /// Steps 2 to 4 of [`Renderer::frame`], with the slot's `streams` taken out of it.
    #[allow(clippy::type_complexity)]
    fn prepare_and_run(
        &mut self,
        scene: &Scene,
        view: &FrameView,
        adjacency: &[Arc<Adjacency>],
        lights: &mut [LightFrame],
        streams: &mut Streams,
        out: Output<'_>,
    ) -> RenderResult<(FrameRun, Vec<LightSets>, u64, Instant, f64)> {
        let p = PrepareInputs { ctx: &self.ctx, scene, view, adjacency };
        let (slot, retired) = (&mut self.slot.techniques, &mut self.slot.retired);
        let techniques = self.techniques.prepare(p, lights, streams, slot, retired)?;
        let gpu = self.upload(scene, view, adjacency, lights, &techniques.shadow_views)?;
        let geometry_uploaded = gpu.geometry_uploaded;
        let binding = Binding {
            ctx: &self.ctx,
            sets: &mut self.slot.sets,
            layout: &self.shadow_set_layout,
            readbacks: &mut self.readbacks,
        };
        let sets = match self.techniques.bind(binding, lights) {
            Ok(sets) => sets,
            Err(e) => {
                self.slot.retired.keep(gpu);
                return Err(e);
            }
        };
        let prepared = Instant::now();
        let mut graph = std::mem::take(&mut self.slot.graph);
        let run = self.declare_frame(&mut graph, scene, &gpu, lights, &sets, streams, techniques.culling, out);
        self.slot.graph = graph;
        let run_ms = prepared.elapsed().as_secs_f64() * 1e3;
        match run {
            // Kept for the next frame: its meshes and per-frame buffers are reused.
            Ok(_) => self.geometry = Some(self.slot.keep(gpu)),
            // Never run (an engine will not submit a recording that failed): the meshes were
            // never copied (the next frame uploads them again), and what the commands refer to
            // is retired.
            Err(_) => self.slot.retired.keep(gpu),
        }
        Ok((run?, sets, geometry_uploaded, prepared, run_ms))
    }

    /// Declares the frame's passes and runs or records them. With blocker culling (the
    /// renderer's own frames only) the views and the boxes' queries go first, in a submission
    /// of their own whose results drop the hidden casters. Then, in one stage: the mesh upload
    /// and the views (`declare_views`), the renderer's own surfaces (its depth, the ambient
    /// term, the G-buffer), every light's shadows (`declare_shadows`), and the renderer's
    /// lights and readback, or an engine's hand-off.
    #[allow(clippy::too_many_arguments)]
    fn declare_frame(
        &self,
        graph: &mut FrameGraph,
        scene: &Scene,
        gpu: &GpuScene,
        lights: &mut [LightFrame],
        sets: &[LightSets],
        streams: &Streams,
        mut culling: CullingPlan,
        out: Output<'_>,
    ) -> RenderResult<FrameRun> {
        graph.begin_frame();
        let bindings = &self.bindings(sets);
        // The depth the passes test: the renderer's own, the engine's as handed over, or
        // umbra's own, re-drawn first.
        let (depth, handed_over, rebuild) = match &out {
            Output::Own => (&self.own()?.depth, None, None),
            Output::Engine { depth: FrameDepth::Engine(d), .. } => {
                graph.import(d.image, d.state);
                (d.image, Some((d.image, d.state)), None)
            }
            Output::Engine { depth: FrameDepth::Rebuilt, .. } => {
                let rebuild = self.rebuild_ref()?;
                (rebuild.made()?, None, Some(rebuild))
            }
        };
        let base = self.inputs(scene, gpu, bindings, depth, rebuild, streams);
        let mut stages = Vec::new();
        let boxes = streams.blockers.filled().filter(|_| culling.queries() > 0);
        if let Some(boxes) = boxes {
            let f = FrameInputs { lights, ..base };
            let mut views = graph.stage("frame: views and blocker culling");
            self.declare_views(&mut views, f)?;
            let first = self.techniques.declare_culling(&mut views, f, &culling, boxes)?;
            let done = graph.run(&self.ctx, views)?;
            let visible: Vec<u64> = (0..culling.queries()).map(|i| done.samples(QueryId(first.0 + i))).collect();
            self.techniques.apply_culling(lights, &mut culling, &visible);
            stages.push(done);
        }
        self.techniques.settle_volumes(scene, lights, &culling);
        let f = FrameInputs { lights, ..base };
        let own = matches!(out, Output::Own);
        let mut stage = graph.stage(if own { "frame" } else { "umbra shadows" });
        if stages.is_empty() {
            self.declare_views(&mut stage, f)?;
        }
        if own {
            self.declare_surfaces(&mut stage, f)?;
        }
        let (queries, overdraw) = self.declare_shadows(&mut stage, f)?;
        match out {
            Output::Own => {
                let volume_counts = self.declare_lights(&mut stage, f, &queries, overdraw)?;
                stages.push(graph.run(&self.ctx, stage)?);
                Ok(FrameRun { stages, recorded: Vec::new(), queries, overdraw, volume_counts })
            }
            Output::Engine { cmd, .. } => {
                stage.pass(PassId::HandOff, &self.hand_off(f.lights, handed_over, &queries)?, |_| Ok(()));
                let mut rec = self.ctx.record_into(cmd);
                let recorded = graph.record(&self.ctx, &mut rec, stage)?.into_passes();
                Ok(FrameRun { stages, recorded, queries, overdraw, volume_counts: false })
            }
        }
    }

    /// An engine's hand-off: what the engine reads, readable by its fragment shaders (every
    /// shadowed light's visibility image, every drawn shadow map), and its depth as it was.
    fn hand_off<'a>(
        &'a self,
        lights: &[LightFrame],
        depth: Option<(&'a Image, ImageState)>,
        queries: &[LightQueries],
    ) -> RenderResult<Vec<Use<'a>>> {
        let mut uses: Vec<Use> = depth.iter().map(|&(image, state)| Use::Image(image, state)).collect();
        for light in lights.iter().filter(|l| queries[l.light()].shadowed) {
            uses.push(Use::Image(&self.visibility.light(light.light())?.image, ImageState::FragmentRead));
        }
        for light in lights.iter().filter(|l| l.map_drawn()) {
            uses.push(Use::Image(self.techniques.shadow_map_image(light.light())?, ImageState::FragmentRead));
        }
        Ok(uses)
    }

    /// What every pass of the frame reads, but its lights (`FrameInputs { lights, ..inputs }`:
    /// blocker culling changes them between its stages).
    fn inputs<'a>(
        &'a self,
        scene: &'a Scene,
        gpu: &'a GpuScene,
        bindings: &'a [LightBindings<'a>],
        depth: &'a Image,
        rebuild: Option<&'a crate::depth_rebuild::DepthRebuild>,
        streams: &'a Streams,
    ) -> FrameInputs<'a> {
        FrameInputs {
            scene,
            gpu,
            lights: &[],
            bindings,
            depth,
            rebuild,
            edges: streams.edges.filled(),
            volumes: streams.volumes.filled(),
            volume_resets: streams.volume_draws.filled(),
            layout: &self.layout,
            visibility: &self.visibility,
            slot: &self.slot.techniques,
            diagnostic_targets: self.diagnostic_targets.as_ref(),
            overdraw: self.overdraw.as_ref().map(|(image, _)| image),
        }
    }

    /// This frame's sets and readbacks of every light, resolved.
    pub(super) fn bindings(&self, sets: &[LightSets]) -> Vec<LightBindings<'_>> {
        sets.iter()
            .zip(&self.readbacks)
            .map(|(s, r)| LightBindings {
                shadow_set: s.shadow_set.and_then(|i| self.slot.sets.get(i)),
                depth_set: s.depth_set.and_then(|i| self.slot.sets.get(i)),
                silhouette_readback: r.silhouette.as_ref(),
                class_readback: r.classes.as_ref(),
                visibility_readback: r.visibility.as_ref(),
            })
            .collect()
    }
}
