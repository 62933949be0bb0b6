//! An engine's frame ([`crate::Shadows`]): the same plan, CPU preparation and shadow passes as
//! [`Renderer::render`], recorded into the engine's command buffer over the engine's depth and
//! ended by the hand-off; no submission, no wait, no readback. Blocker culling, which needs a
//! query result mid-frame, is off (`Shadows::new` refuses it), and so are the diagnostics.

use super::lights::{FrameView, LightFrame};
use super::slot::FrameSlot;
use super::Renderer;
use crate::frame::{PassId, Use};
use crate::hybrid::cull::CullingPlan;
use crate::plan::LightPlan;
use crate::timing::PassReport;
use crate::view::View;
use crate::RenderResult;
use umbra_scene::Scene;
use umbra_vk::{vk, Image, ImageState};

/// The engine's depth for one frame: the image and the state it is in (and is left in).
pub(crate) struct EngineDepth<'a> {
    pub image: &'a Image,
    pub state: ImageState,
}

/// The depth an engine's frame is recorded over.
pub(crate) enum FrameDepth<'a> {
    /// The engine's, drawn in umbra's convention and with a stencil where one is needed:
    /// umbra's passes test against it and leave it as it was.
    Engine(EngineDepth<'a>),
    /// umbra's own, re-drawn first (`crate::depth_rebuild`): the engine's depth is not touched.
    Rebuilt,
}

/// What one light got in an engine's frame.
pub(crate) struct RecordedLight {
    pub plan: LightPlan,
    /// Whether its technique wrote its visibility image (else it is lit unshadowed).
    pub shadowed: bool,
    /// Whether its shadow map was drawn (its views are in `plan.shadow_map`).
    pub map: bool,
}

/// What an engine's frame recorded.
pub(crate) struct RecordedFrame {
    pub lights: Vec<RecordedLight>,
    /// The passes recorded, in order, their GPU times not read yet.
    pub passes: Vec<PassReport>,
    /// Bytes of mesh data uploaded for it (0 when the meshes were unchanged).
    pub geometry_uploaded_bytes: u64,
}

impl Renderer {
    /// A frame slot for an engine's frames in flight.
    pub(crate) fn new_slot(&self, index: usize) -> RenderResult<FrameSlot> {
        FrameSlot::new(&self.ctx, &format!("shadow sets (frame slot {index})"), &self.shadow_set_layout)
    }

    /// Records the shadows of `scene` seen through `view` into `cmd` (an engine's command
    /// buffer, recording), over `depth`, with `slot`'s host-written buffers, sets and queries.
    pub(crate) fn record_into(
        &mut self,
        slot: &mut FrameSlot,
        scene: &Scene,
        view: View,
        depth: FrameDepth<'_>,
        cmd: vk::CommandBuffer,
    ) -> RenderResult<RecordedFrame> {
        if let FrameDepth::Rebuilt = depth {
            let ctx = self.ctx.clone();
            self.rebuild()?.image(&ctx)?;
        }
        std::mem::swap(&mut self.slot, slot);
        let recorded = self.record_slot(scene, view, depth, cmd);
        std::mem::swap(&mut self.slot, slot);
        recorded
    }

    fn record_slot(
        &mut self,
        scene: &Scene,
        view: View,
        depth: FrameDepth<'_>,
        cmd: vk::CommandBuffer,
    ) -> RenderResult<RecordedFrame> {
        // The same steps as `render` (see there), the view as the engine gave it.
        self.slot.begin();
        let view = FrameView { view, boxes: scene.object_bounds() };
        let mut lights = self.plan(scene, &view)?;
        let adjacency = self.meshes.adjacency(scene)?;
        let mut streams = std::mem::take(&mut self.slot.streams);
        let recorded = self.record_streams(scene, &view, &adjacency, &mut lights, &mut streams, depth, cmd);
        self.slot.streams = streams;
        let (passes, shadowed, geometry_uploaded_bytes) = recorded?;
        let lights = lights
            .into_iter()
            .map(|l| RecordedLight {
                shadowed: shadowed[l.light()],
                map: l.map.as_ref().is_some_and(|m| m.depth),
                plan: l.plan,
            })
            .collect();
        Ok(RecordedFrame { lights, passes, geometry_uploaded_bytes })
    }

    /// Prepares, uploads and records the frame with the slot's `streams` taken out of it.
    #[allow(clippy::too_many_arguments)]
    fn record_streams(
        &mut self,
        scene: &Scene,
        view: &FrameView,
        adjacency: &[std::sync::Arc<umbra_scene::Adjacency>],
        lights: &mut [LightFrame],
        streams: &mut crate::streams::Streams,
        depth: FrameDepth<'_>,
        cmd: vk::CommandBuffer,
    ) -> RenderResult<(Vec<PassReport>, Vec<bool>, u64)> {
        let shadow_views = self.prepare_maps(scene, view, adjacency, lights, streams)?;
        self.prepare_volumes(scene, view, adjacency, lights, streams)?;
        let gpu = self.upload(scene, view, adjacency, lights, &shadow_views)?;
        self.settle_volumes(scene, lights, &CullingPlan::default());
        let recorded = self.bind(lights).and_then(|sets| {
            let mut graph = std::mem::take(&mut self.slot.graph);
            let passes = self.record_passes(&mut graph, scene, &gpu, lights, &sets, streams, depth, cmd);
            self.slot.graph = graph;
            passes
        });
        let geometry_uploaded_bytes = gpu.geometry_uploaded;
        match recorded {
            Ok(_) => self.geometry = Some(self.slot.keep(gpu)),
            // The engine will not submit what was recorded: the meshes were never copied (the
            // next frame uploads them again), and what the recording refers to is retired.
            Err(_) => self.slot.retired.keep(gpu),
        }
        let (passes, shadowed) = recorded?;
        Ok((passes, shadowed, geometry_uploaded_bytes))
    }

    /// Declares the views and every light's shadows, then the hand-off, and records them into
    /// `cmd`; returns the passes and, per light, whether its visibility image was written.
    #[allow(clippy::too_many_arguments)]
    fn record_passes(
        &self,
        graph: &mut crate::frame::FrameGraph,
        scene: &Scene,
        gpu: &crate::gpu_scene::GpuScene,
        lights: &[LightFrame],
        sets: &[super::lights::LightSets],
        streams: &crate::streams::Streams,
        depth: FrameDepth<'_>,
        cmd: vk::CommandBuffer,
    ) -> RenderResult<(Vec<PassReport>, Vec<bool>)> {
        graph.begin_frame();
        let bindings = &self.bindings(sets);
        let (edges, volumes) = (streams.edges.filled(), streams.volumes.filled());
        let mut stage = graph.stage("umbra shadows");
        // The engine's depth as it was handed over, or umbra's own, drawn first.
        let (image, handed_over, rebuild) = match depth {
            FrameDepth::Engine(d) => {
                graph.import(d.image, d.state);
                (d.image, Some(d), None)
            }
            FrameDepth::Rebuilt => {
                let rebuild = self.rebuild_ref()?;
                (rebuild.made()?, None, Some(rebuild))
            }
        };
        let f = super::declare::FrameInputs { scene, gpu, lights, bindings, depth: image, rebuild, edges, volumes };
        self.declare_views(&mut stage, f)?;
        let (queries, _) = self.declare_shadows(&mut stage, f)?;
        let shadowed: Vec<bool> = queries.iter().map(|q| q.shadowed).collect();
        // The hand-off: what the engine reads, readable by its shaders; its depth as it was.
        let mut uses: Vec<Use> = handed_over.iter().map(|d| Use::Image(d.image, d.state)).collect();
        for light in lights.iter().filter(|l| shadowed[l.light()]) {
            uses.push(Use::Image(&self.visibility.light(light.light())?.image, ImageState::FragmentRead));
        }
        for light in lights.iter().filter(|l| l.map.as_ref().is_some_and(|m| m.depth)) {
            uses.push(Use::Image(self.shadow_map.image(light.light())?, ImageState::FragmentRead));
        }
        stage.pass(PassId::HandOff, &uses, |_| Ok(()));
        let mut rec = self.ctx.record_into(cmd);
        let passes = graph.record(&self.ctx, &mut rec, stage)?.into_passes();
        Ok((passes, shadowed))
    }

    /// The depth rebuild (engine renderers only).
    fn rebuild(&mut self) -> RenderResult<&mut crate::depth_rebuild::DepthRebuild> {
        self.depth_rebuild.as_mut().ok_or_else(not_engine)
    }

    fn rebuild_ref(&self) -> RenderResult<&crate::depth_rebuild::DepthRebuild> {
        self.depth_rebuild.as_ref().ok_or_else(not_engine)
    }

    /// Light `light`'s visibility image (while it is shadowed).
    pub(crate) fn visibility_image(&self, light: usize) -> RenderResult<&Image> {
        Ok(&self.visibility.light(light)?.image)
    }

    /// Light `light`'s shadow map (while it has one).
    pub(crate) fn shadow_map_image(&self, light: usize) -> RenderResult<&Image> {
        self.shadow_map.image(light)
    }
}

fn not_engine() -> crate::RenderError {
    crate::RenderError::InvalidInput {
        field: "Renderer".into(),
        why: "only a renderer recording into an engine's frame rebuilds depth".into(),
    }
}
