//! What a light's passes over the frame's surfaces share: the scene as drawn on the GPU, the
//! light's index (its view in the frame's uniforms) and where its passes may draw
//! ([`PassBounds`]). Every technique's visibility pass, the lighting and the diagnostics draw
//! the scene's objects through [`LightSurfaces::draw`]; the passes of no light (ambient,
//! G-buffer, depth rebuild) through [`draw_objects`] itself.

use crate::frame::timing::PassLog;
use crate::frame::PassRecorder;
use crate::gpu_scene::{Bound, DrawPush, GpuScene};
use umbra_scene::Scene;
use umbra_vk::{ColorAttachment, DepthAttachment, Image, PipelineLayout, Recorder, RenderTargets};

/// Where a bounded light's passes may draw (`LightPlan::scissor`, `LightPlan::depth_bounds`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct PassBounds {
    pub scissor: Option<[u32; 4]>,
    pub depth: Option<[f32; 2]>,
}

impl PassBounds {
    /// Sets the scissor and, for a pipeline with the depth-bounds test, the bounds.
    pub fn apply(&self, rec: &mut Recorder<'_>, depth_tested: bool) {
        if let Some(rect) = self.scissor {
            rec.set_scissor(rect);
        }
        if let (Some([min, max]), true) = (self.depth, depth_tested) {
            rec.set_depth_bounds(min, max);
        }
    }
}

/// One light's pass over the frame's surfaces: what it draws and where it may draw.
#[derive(Clone, Copy)]
pub(crate) struct LightSurfaces<'a, 's> {
    /// The frame's scene on the GPU (set 0 of every surface pass).
    pub gpu: &'a GpuScene,
    pub scene: &'s Scene,
    /// The light's index: its view in the frame's uniforms.
    pub light: u32,
    /// Where the light's passes may draw (applied by the pipelines that honour bounds).
    pub bounds: PassBounds,
}

impl<'a> LightSurfaces<'a, '_> {
    /// Draws every object with the bound pipeline, the scene's set bound at set 0 of `layout`
    /// and the light as the push constants' view.
    pub fn draw(&self, cx: &mut PassRecorder<'_, 'a>, layout: &'a PipelineLayout) {
        draw_objects(cx.rec, layout, self.gpu, self.scene, self.light, cx.log);
    }
}

/// Begins a pass over the frame's surfaces: one colour target (`clear`ed or kept) and the
/// frame's depth, kept, for the EQUAL test.
pub(crate) fn over_surfaces<'a>(rec: &mut Recorder<'a>, image: &'a Image, clear: Option<[f32; 4]>, depth: &'a Image) {
    let color = [ColorAttachment { image, view: None, clear }];
    rec.begin_rendering(&RenderTargets { color: &color, depth: Some(DepthAttachment::keep(depth)) });
}

/// Draws every object with the bound pipeline, light index `light` in the push constants.
pub(crate) fn draw_objects<'a>(
    rec: &mut Recorder<'a>,
    layout: &'a PipelineLayout,
    gpu: &'a GpuScene,
    scene: &Scene,
    light: u32,
    log: &mut PassLog,
) {
    rec.bind_descriptor_set(layout, 0, &gpu.frame.set);
    let mut bound = Bound::Nothing;
    for (i, o) in scene.objects.iter().enumerate() {
        if gpu.geometry.drawable(o.mesh).is_none() {
            continue;
        }
        rec.push_constants(layout, &DrawPush { object: i as u32, view: light });
        log.count_draw(gpu.geometry.draw(rec, o.mesh, 2, &mut bound));
    }
}
