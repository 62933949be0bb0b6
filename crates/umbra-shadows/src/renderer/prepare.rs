//! The CPU half of a frame: its view, the plan, each light's technique prepared
//! (`crate::techniques`), and the scene uploaded where it changed.

use super::Renderer;
use crate::gpu_scene::GpuScene;
use crate::plan::{plan_frame, PlanInput};
use crate::techniques::{FrameView, LightFrame, Techniques};
use crate::view::View;
use crate::RenderResult;
use glam::Mat4;
use std::sync::Arc;
use umbra_scene::{Adjacency, Scene};

impl Renderer {
    /// The camera and bounds of a frame of `scene`: the camera its techniques ask for
    /// ([`Techniques::camera`]).
    pub(super) fn frame_view(&self, scene: &Scene) -> FrameView {
        let aspect = self.desc.width as f32 / self.desc.height as f32;
        let camera = self.techniques.camera(scene);
        FrameView { view: View::of_camera(&camera, aspect), boxes: scene.object_bounds_with(&self.checked) }
    }

    /// Per light, what to record and which casters enter its passes (`crate::plan`).
    pub(super) fn plan(&self, scene: &Scene, view: &FrameView) -> RenderResult<Vec<LightFrame>> {
        let plans = plan_frame(
            scene,
            &PlanInput {
                boxes: &view.boxes,
                view: &view.view,
                size: (self.desc.width, self.desc.height),
                cull: self.desc.cull,
                depth_bounds: self.desc.cull && self.ctx.capabilities().depth_bounds,
                map_resolution: self.techniques.shadow_map_settings().resolution,
                auto: self.auto_policy(),
            },
        )?;
        Ok(plans.into_iter().map(LightFrame::new).collect())
    }

    /// The scene on the GPU: meshes uploaded again only when one changed, per-frame buffers
    /// rewritten in place; the lights' targets first ([`Techniques::prepare_targets`]).
    pub(super) fn upload(
        &mut self,
        scene: &Scene,
        view: &FrameView,
        adjacency: &[Arc<Adjacency>],
        lights: &[LightFrame],
        shadow_views: &[Mat4],
    ) -> RenderResult<GpuScene> {
        let retired = &mut self.slot.retired;
        self.techniques.prepare_targets(&self.ctx, lights, &mut self.visibility, retired)?;
        let gpu = GpuScene::upload(
            &self.ctx,
            &self.scene_set_layout,
            scene,
            &self.engine_meshes,
            &view.view,
            &Techniques::gpu_shadows(lights),
            shadow_views,
            self.geometry.take(),
            self.slot.frame.take(),
        )?;
        self.techniques.bind_geometry(&self.ctx, &gpu, adjacency, lights, &mut self.slot.retired)?;
        Ok(gpu)
    }
}
