//! The forward lighting passes: one pass lays down depth and the ambient term, then one
//! additive pass per light applies Lambert's law, times the light's shadow visibility, where
//! the depth is EQUAL.
//!
//! Both pipelines share `forward/mesh.vert` (with `invariant gl_Position`), so the EQUAL test
//! sees bit-identical depths. Faces are not culled: open meshes show their inside, lit from
//! that side. The shadow filter and out-of-frustum policy are specialization constants.

use crate::gpu_scene::{self, DrawPush, GpuScene};
use crate::shadow_map::ShadowMapSettings;
use crate::timing::PassLog;
use crate::RenderResult;
use umbra_scene::Scene;
use umbra_vk::{
    vk, Blend, ColorTarget, Context, DepthState, DescriptorSet, GraphicsPipeline, GraphicsPipelineDesc, PipelineLayout,
    Recorder, StencilFace,
};

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

/// A pipeline and, when the device has `depthBounds` and the renderer culls, its twin with the
/// depth-bounds test on (for bounded lights).
pub(crate) struct Bounded {
    plain: GraphicsPipeline,
    bounded: Option<GraphicsPipeline>,
}

impl Bounded {
    /// Builds `desc`, and its depth-bounds twin when `depth_bounds`.
    pub fn new(
        ctx: &Context,
        layout: &PipelineLayout,
        desc: &GraphicsPipelineDesc<'_>,
        depth_bounds: bool,
    ) -> RenderResult<Self> {
        let plain = GraphicsPipeline::new(ctx, layout, desc)?;
        let bounded = if depth_bounds {
            let name = format!("{} (depth bounds)", desc.name);
            let mut twin = *desc;
            twin.name = &name;
            twin.depth.bounds_test = true;
            Some(GraphicsPipeline::new(ctx, layout, &twin)?)
        } else {
            None
        };
        Ok(Self { plain, bounded })
    }

    /// Binds the pipeline `bounds` calls for and sets its scissor and bounds.
    pub fn bind<'a>(&'a self, rec: &mut Recorder<'a>, bounds: PassBounds) {
        match (&self.bounded, bounds.depth) {
            (Some(p), Some(_)) => {
                rec.bind_pipeline(p);
                bounds.apply(rec, true);
            }
            _ => {
                rec.bind_pipeline(&self.plain);
                bounds.apply(rec, false);
            }
        }
    }

    /// The pipeline without bounds.
    pub fn plain(&self) -> &GraphicsPipeline {
        &self.plain
    }
}

/// The forward pipelines.
pub(crate) struct Forward {
    ambient: GraphicsPipeline,
    light: Bounded,
    /// The light pass of shadow-volume lights: lit only where the stencil count is 0.
    light_stenciled: Bounded,
    /// The light pass writing each pixel's class instead of light (with diagnostics).
    classes: Option<GraphicsPipeline>,
}

impl Forward {
    /// Builds both pipelines against the renderer's shared `layout` (set 0 scene, set 1 shadow).
    pub fn new(
        ctx: &Context,
        layout: &PipelineLayout,
        color_format: vk::Format,
        depth_format: vk::Format,
        shadow: &ShadowMapSettings,
        diagnostics: bool,
        depth_bounds: bool,
    ) -> RenderResult<Self> {
        let ambient_frag = umbra_shaders::forward::AMBIENT_FRAG;
        let mut desc = surface_pass_desc("forward ambient + depth", ambient_frag, depth_format, &[]);
        // The pass that lays the depth down: LESS and write.
        desc.depth = DepthState { compare: vk::CompareOp::LESS, ..DepthState::TEST_AND_WRITE };
        let opaque = [ColorTarget::opaque(color_format)];
        desc.color_targets = &opaque;
        let ambient = GraphicsPipeline::new(ctx, layout, &desc)?;

        let spec = shadow_spec(shadow);
        let mut desc =
            surface_pass_desc("forward light (additive)", umbra_shaders::forward::LIGHT_FRAG, depth_format, &spec);
        let additive = [ColorTarget { blend: Some(Blend::ADDITIVE), ..ColorTarget::opaque(color_format) }];
        desc.color_targets = &additive;
        let light = Bounded::new(ctx, layout, &desc, depth_bounds)?;
        desc.name = "forward light (additive, stencil == 0)";
        let zero = StencilFace { compare: vk::CompareOp::EQUAL, write_mask: 0, ..StencilFace::KEEP };
        desc.stencil = Some((zero, zero));
        let light_stenciled = Bounded::new(ctx, layout, &desc, depth_bounds)?;
        let classes = if diagnostics {
            let [filter, outside] = spec;
            let spec = [filter, outside, (2, 1)];
            let mut desc = surface_pass_desc(
                "light diagnostics (classes)",
                umbra_shaders::forward::LIGHT_FRAG,
                depth_format,
                &spec,
            );
            desc.color_targets = &opaque;
            Some(GraphicsPipeline::new(ctx, layout, &desc)?)
        } else {
            None
        };
        Ok(Self { ambient, light, light_stenciled, classes })
    }

    /// Draws every object with the ambient pipeline (inside an open rendering pass).
    pub fn record_ambient<'a>(
        &'a self,
        rec: &mut Recorder<'a>,
        layout: &'a PipelineLayout,
        gpu: &'a GpuScene,
        scene: &Scene,
        log: &mut PassLog,
    ) {
        rec.bind_pipeline(&self.ambient);
        draw_objects(rec, layout, gpu, scene, 0, log);
    }

    /// Draws every object lit by light `light`, whose shadow maps `shadow_set` binds (inside an
    /// open rendering pass), within `bounds`. With `stenciled`, objects that receive shadows
    /// only where the stencil holds 0 (shadow volumes); the others are lit unshadowed.
    #[allow(clippy::too_many_arguments)]
    pub fn record_light<'a>(
        &'a self,
        rec: &mut Recorder<'a>,
        layout: &'a PipelineLayout,
        gpu: &'a GpuScene,
        shadow_set: &'a DescriptorSet,
        scene: &Scene,
        light: u32,
        stenciled: bool,
        bounds: PassBounds,
        log: &mut PassLog,
    ) {
        if stenciled {
            self.light_stenciled.bind(rec, bounds);
            rec.set_stencil_reference(0);
            rec.bind_descriptor_set(layout, 1, shadow_set);
            draw_objects_where(rec, layout, gpu, scene, light, log, |o| o.receives_shadows);
            if scene.objects.iter().all(|o| o.receives_shadows) {
                return;
            }
        }
        self.light.bind(rec, bounds);
        rec.bind_descriptor_set(layout, 1, shadow_set);
        draw_objects_where(rec, layout, gpu, scene, light, log, |o| !stenciled || !o.receives_shadows);
    }

    /// Draws every object's class under light `light` (inside an open rendering pass with one
    /// RGBA8 target): the decisions `record_light` shades with, written as colours.
    /// Nothing is drawn when the pipelines were built without diagnostics.
    #[allow(clippy::too_many_arguments)]
    pub fn record_classes<'a>(
        &'a self,
        rec: &mut Recorder<'a>,
        layout: &'a PipelineLayout,
        gpu: &'a GpuScene,
        shadow_set: &'a DescriptorSet,
        scene: &Scene,
        light: u32,
        log: &mut PassLog,
    ) {
        let Some(classes) = &self.classes else { return };
        rec.bind_pipeline(classes);
        rec.bind_descriptor_set(layout, 1, shadow_set);
        draw_objects(rec, layout, gpu, scene, light, log);
    }
}

/// The lighting shaders' specialization: shadow filter (0) and out-of-frustum policy (1).
pub(crate) fn shadow_spec(shadow: &ShadowMapSettings) -> [(u32, u32); 2] {
    [(0, shadow.filter.spec_value()), (1, u32::from(shadow.outside_lit))]
}

/// A pass over the scene's surfaces with `forward/mesh.vert` (bit-identical depth between
/// passes) and `fragment`: no culling, depth EQUAL without writes (the passes after the depth
/// pass); colour targets left to the caller.
pub(crate) fn surface_pass_desc<'a>(
    name: &'a str,
    fragment: &'a [u32],
    depth_format: vk::Format,
    specialization: &'a [(u32, u32)],
) -> GraphicsPipelineDesc<'a> {
    let mut desc = GraphicsPipelineDesc::new(name, umbra_shaders::forward::MESH_VERT);
    desc.fragment = Some(fragment);
    desc.specialization = specialization;
    desc.vertex_stride = gpu_scene::VERTEX_STRIDE;
    desc.vertex_attributes = &gpu_scene::VERTEX_ATTRIBUTES;
    desc.cull = vk::CullModeFlags::NONE;
    desc.depth = DepthState { write: false, compare: vk::CompareOp::EQUAL, ..DepthState::TEST_AND_WRITE };
    desc.depth_format = depth_format;
    desc
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
    draw_objects_where(rec, layout, gpu, scene, light, log, |_| true);
}

/// Draws the objects `keep` accepts with the bound pipeline, light index `light` in the push
/// constants.
fn draw_objects_where<'a>(
    rec: &mut Recorder<'a>,
    layout: &'a PipelineLayout,
    gpu: &'a GpuScene,
    scene: &Scene,
    light: u32,
    log: &mut PassLog,
    keep: impl Fn(&umbra_scene::Object) -> bool,
) {
    rec.bind_descriptor_set(layout, 0, &gpu.frame.set);
    rec.bind_vertex_buffer(&gpu.geometry.vertices);
    rec.bind_index_buffer(&gpu.geometry.indices);
    for (i, o) in scene.objects.iter().enumerate() {
        if !keep(o) {
            continue;
        }
        let Some(m) = gpu.geometry.meshes.get(o.mesh) else { continue };
        if m.index_count == 0 {
            continue;
        }
        rec.push_constants(layout, &DrawPush { object: i as u32, view: light });
        rec.draw_indexed(m.index_count, m.first_index, m.vertex_offset);
        log.count_draw(u64::from(m.index_count / 3));
    }
}
