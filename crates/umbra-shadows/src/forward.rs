//! The forward lighting passes: one pass lays down depth and the ambient term, then one
//! additive pass per light applies Lambert's law, times the light's visibility image
//! (`crate::visibility`), where the depth is EQUAL.
//!
//! Both pipelines share `forward/mesh.vert` (with `invariant gl_Position`), so the EQUAL test
//! sees bit-identical depths. Faces are not culled: open meshes show their inside, lit from
//! that side. The shadow filter and out-of-frustum policy are specialization constants.

use crate::frame::timing::PassLog;
use crate::frame::PassRecorder;
use crate::gpu_scene::{self, GpuScene};
use crate::light_surfaces::{LightSurfaces, PassBounds};
use crate::RenderResult;
use umbra_scene::Scene;
use umbra_vk::{
    vk, Blend, ColorTarget, Context, DepthState, DescriptorSet, GraphicsPipeline, GraphicsPipelineDesc, PipelineLayout,
    Recorder,
};

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
}

/// The forward pipelines.
pub(crate) struct Forward {
    ambient: GraphicsPipeline,
    /// The light pass of a shadowed light: times its visibility image (set 2).
    light: Bounded,
    /// The light pass of a light that casts no shadow here.
    unshadowed: Bounded,
    /// The light pass's decisions written as each pixel's class (with diagnostics).
    classes: Option<GraphicsPipeline>,
}

impl Forward {
    /// Builds the pipelines against the renderer's shared `layout` (set 0 scene, set 1 shadow,
    /// set 2 visibility).
    pub fn new(
        ctx: &Context,
        layout: &PipelineLayout,
        color_format: vk::Format,
        depth_format: vk::Format,
        lookup: [(u32, u32); 2],
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

        let additive = [ColorTarget { blend: Some(Blend::ADDITIVE), ..ColorTarget::opaque(color_format) }];
        let light_pass = |name, shadowed: bool| {
            let spec = [(0, u32::from(shadowed))];
            let mut desc = surface_pass_desc(name, umbra_shaders::forward::LIGHT_FRAG, depth_format, &spec);
            desc.color_targets = &additive;
            Bounded::new(ctx, layout, &desc, depth_bounds)
        };
        let light = light_pass("forward light (additive, visibility image)", true)?;
        let unshadowed = light_pass("forward light (additive, unshadowed)", false)?;
        let classes = if diagnostics {
            let frag = umbra_shaders::debug::LIGHT_CLASSES_FRAG;
            let mut desc = surface_pass_desc("light diagnostics (classes)", frag, depth_format, &lookup);
            desc.color_targets = &opaque;
            Some(GraphicsPipeline::new(ctx, layout, &desc)?)
        } else {
            None
        };
        Ok(Self { ambient, light, unshadowed, classes })
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
        crate::light_surfaces::draw_objects(rec, layout, gpu, scene, 0, log);
    }

    /// Draws every object lit by the light of `s` (inside an open rendering pass), within its
    /// bounds: with `shadowed`, times the visibility image `visibility` binds (in
    /// [`umbra_vk::ImageState::FragmentRead`]); without, unshadowed (`visibility` then binds a
    /// placeholder).
    pub fn record_light<'a>(
        &'a self,
        cx: &mut PassRecorder<'_, 'a>,
        layout: &'a PipelineLayout,
        s: LightSurfaces<'a, '_>,
        (visibility, shadowed): (&'a DescriptorSet, bool),
    ) {
        (if shadowed { &self.light } else { &self.unshadowed }).bind(cx.rec, s.bounds);
        cx.rec.bind_descriptor_set(layout, 2, visibility);
        s.draw(cx, layout);
    }

    /// Draws every object's class under the light of `s` (inside an open rendering pass with
    /// one RGBA8 target, over the whole frame: its bounds are not applied): the decisions its
    /// visibility pass makes, written as colours. Nothing is drawn when the pipelines were
    /// built without diagnostics.
    pub fn record_classes<'a>(
        &'a self,
        cx: &mut PassRecorder<'_, 'a>,
        layout: &'a PipelineLayout,
        s: LightSurfaces<'a, '_>,
        shadow_set: &'a DescriptorSet,
    ) {
        let Some(classes) = &self.classes else { return };
        cx.rec.bind_pipeline(classes);
        cx.rec.bind_descriptor_set(layout, 1, shadow_set);
        s.draw(cx, layout);
    }
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
    desc.vertex_streams = true;
    desc.cull = vk::CullModeFlags::NONE;
    desc.depth = DepthState { write: false, compare: vk::CompareOp::EQUAL, ..DepthState::TEST_AND_WRITE };
    desc.depth_format = depth_format;
    desc
}
