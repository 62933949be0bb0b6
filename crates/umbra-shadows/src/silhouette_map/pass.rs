//! Pass 2 of the silhouette map (§3.1): per light, an RG32F map on the depth map's dual grid,
//! cleared to the default point and written by the silhouette edges' quads; and the
//! diagnostic views drawn from it.

use super::edges::{EdgeInstance, LightEdges};
use super::geometry::DEFAULT_POINT;
use crate::forward;
use crate::frame::timing::PassLog;
use crate::frame::PassRecorder;
use crate::gpu_scene::{DrawPush, GpuScene};
use crate::light_surfaces::LightSurfaces;
use crate::retired::Retired;
use crate::shadow_map::atlas;
use crate::shadow_map::frustum::MapKind;
use crate::shadow_map::ShadowMapSettings;
use crate::{RenderError, RenderResult};
use umbra_vk::{
    vk, Buffer, ColorAttachment, ColorTarget, Context, DepthState, DescriptorSet, GraphicsPipeline,
    GraphicsPipelineDesc, Image, ImageDesc, ImageState, PipelineLayout, Recorder, RenderTargets, VertexAttribute,
};

/// Texel-local silhouette points, two floats per texel.
pub(crate) const FORMAT: vk::Format = vk::Format::R32G32_SFLOAT;

/// The silhouette map over a depth map of `resolution` and `kind` (a `resolution`² map, or a
/// face atlas): rendered to, sampled, and copied out for diagnostics.
fn map_desc(resolution: u32, kind: MapKind) -> ImageDesc {
    let usage =
        vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_SRC;
    let (width, height) = kind.extent(resolution);
    ImageDesc::new_2d(FORMAT, width, height).usage(usage)
}

/// Vertices of one edge's quad: two triangles (`edges.vert`).
const VERTICES_PER_EDGE: u32 = 6;

/// Per-instance edge layout: endpoint a at location 0, b at location 1.
const EDGE_ATTRIBUTES: [VertexAttribute; 2] = [
    VertexAttribute { location: 0, format: vk::Format::R32G32B32_SFLOAT, offset: 0 },
    VertexAttribute { location: 1, format: vk::Format::R32G32B32_SFLOAT, offset: 12 },
];

/// Pipelines, placeholder and per-light targets of the silhouette map.
pub(crate) struct SilhouetteMapPass {
    points: GraphicsPipeline,
    diagnostics: GraphicsPipeline,
    placeholder: Image,
    targets: Vec<Option<Image>>,
}

impl SilhouetteMapPass {
    /// Builds the point pipeline and the diagnostic-view pipeline (drawn over a
    /// `depth_format` frame into two `color_format` targets).
    pub fn new(
        ctx: &Context,
        layout: &PipelineLayout,
        color_format: vk::Format,
        depth_format: vk::Format,
        shadow: &ShadowMapSettings,
    ) -> RenderResult<Self> {
        let mut desc = GraphicsPipelineDesc::new("silhouette map points", umbra_shaders::silhouette_map::EDGES_VERT);
        desc.fragment = Some(umbra_shaders::silhouette_map::POINTS_FRAG);
        desc.vertex_stride = std::mem::size_of::<EdgeInstance>() as u32;
        desc.vertex_attributes = &EDGE_ATTRIBUTES;
        desc.vertex_input_rate = vk::VertexInputRate::INSTANCE;
        let bits = ctx.capabilities().sub_pixel_precision_bits.min(16);
        let snap = [(2, bits)];
        desc.specialization = &snap;
        // The quad's winding follows the edge's direction.
        desc.cull = vk::CullModeFlags::NONE;
        desc.depth = DepthState::NONE;
        let target = [ColorTarget::opaque(FORMAT)];
        desc.color_targets = &target;
        let points = GraphicsPipeline::new(ctx, layout, &desc)?;

        let spec = shadow.lookup_spec();
        let diagnostics_frag = umbra_shaders::silhouette_map::DIAGNOSTICS_FRAG;
        let mut desc = forward::surface_pass_desc("silhouette map diagnostics", diagnostics_frag, depth_format, &spec);
        let targets = [ColorTarget::opaque(color_format), ColorTarget::opaque(color_format)];
        desc.color_targets = &targets;
        let diagnostics = GraphicsPipeline::new(ctx, layout, &desc)?;

        let placeholder = Image::new(
            ctx,
            "no silhouette map",
            ImageDesc::new_2d(FORMAT, 1, 1).usage(vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::COLOR_ATTACHMENT),
        )?;
        let mut rec = ctx.begin_commands("clear silhouette placeholder")?;
        rec.transition(&[(&placeholder, ImageState::Undefined, ImageState::ColorAttachment)]);
        let clear = [ColorAttachment { image: &placeholder, view: None, clear: Some(default_clear()) }];
        rec.begin_rendering(&RenderTargets { color: &clear, depth: None });
        rec.end_rendering();
        rec.transition(&[(&placeholder, ImageState::ColorAttachment, ImageState::FragmentRead)]);
        ctx.submit_and_wait(rec)?;
        Ok(Self { points, diagnostics, placeholder, targets: Vec::new() })
    }

    /// Checks that light `light` can have a silhouette map over its `resolution` depth map of
    /// `kind` on this device (every limit of an RG32F attachment, [`Context::image_limits`]);
    /// returns the bytes it takes.
    pub fn check(&self, ctx: &Context, light: usize, resolution: u32, kind: MapKind) -> RenderResult<u64> {
        let desc = map_desc(resolution, kind);
        if let Some((_, limit)) = ctx.image_limits(&desc)?.broken_by(&desc) {
            let device = &ctx.capabilities().device_name;
            return Err(RenderError::InvalidShadowMap {
                light,
                resolution,
                why: format!("its silhouette map ({FORMAT:?}) must fit {limit} on {device}"),
                limit: Some(limit),
            });
        }
        Ok(crate::budget::desc_bytes(&desc, 8))
    }

    /// Makes sure light `light` has a silhouette map over its `resolution` depth map of
    /// `kind`; a new map is checked first ([`Self::check`]), a kept one was when it was made.
    pub fn prepare(
        &mut self,
        ctx: &Context,
        light: usize,
        resolution: u32,
        kind: MapKind,
        retired: &mut Retired,
    ) -> RenderResult<()> {
        if self.targets.len() <= light {
            self.targets.resize_with(light + 1, || None);
        }
        let desc = map_desc(resolution, kind);
        let same = |t: &Image| (t.desc.width, t.desc.height) == (desc.width, desc.height);
        if self.targets[light].as_ref().is_some_and(same) {
            return Ok(());
        }
        self.check(ctx, light, resolution, kind)?;
        retired.take(&mut self.targets[light]);
        self.targets[light] = Some(Image::new(ctx, &format!("silhouette map light {light}"), desc)?);
        Ok(())
    }

    /// Frees the silhouette maps of every light for which `keep` is false (or beyond it).
    pub fn keep_only(&mut self, keep: &[bool], retired: &mut Retired) {
        crate::budget::release_unused(&mut self.targets, keep, retired);
    }

    /// Light `light`'s silhouette map (after [`Self::prepare`]), or the 1×1 placeholder.
    pub fn image(&self, light: Option<usize>) -> &Image {
        light.and_then(|l| self.targets.get(l)).and_then(Option::as_ref).unwrap_or(&self.placeholder)
    }

    /// Records pass 2 for light `light` (its silhouette map in
    /// [`ImageState::ColorAttachment`]): clear to the default point, draw its `edges` (a range
    /// of `instances`) as quads reading the depth map through `depth_set`; into each face of a
    /// face atlas (`map`: its kind and resolution) in turn, its edges clipped to the face.
    #[allow(clippy::too_many_arguments)]
    pub fn record_points<'a>(
        &'a self,
        rec: &mut Recorder<'a>,
        layout: &'a PipelineLayout,
        gpu: &'a GpuScene,
        depth_set: &'a DescriptorSet,
        light: usize,
        instances: Option<&'a Buffer>,
        edges: LightEdges,
        map: (MapKind, u32),
        log: &mut PassLog,
    ) -> RenderResult<()> {
        let target = self.targets.get(light).and_then(Option::as_ref).ok_or(RenderError::InvalidShadowMap {
            light,
            resolution: 0,
            why: "silhouette map recorded before `prepare`".into(),
            limit: None,
        })?;
        let color = [ColorAttachment { image: target, view: None, clear: Some(default_clear()) }];
        rec.begin_rendering(&RenderTargets { color: &color, depth: None });
        if let (Some(buffer), true) = (instances, edges.count > 0) {
            rec.bind_pipeline(&self.points);
            rec.bind_descriptor_set(layout, 0, &gpu.frame.set);
            rec.bind_descriptor_set(layout, 1, depth_set);
            rec.bind_vertex_buffer(buffer);
            let (kind, resolution) = map;
            for face in 0..kind.views() {
                if kind == MapKind::FaceAtlas {
                    rec.set_viewport_rect(atlas::face_rect(face, resolution));
                }
                // `object` names the face (edges.vert): the edges are the light's, not an object's.
                rec.push_constants(layout, &DrawPush { object: face, view: light as u32 });
                rec.draw_instanced(VERTICES_PER_EDGE, edges.count, edges.first);
                log.count_draw(u64::from(VERTICES_PER_EDGE / 3 * edges.count));
            }
        }
        rec.end_rendering();
        Ok(())
    }

    /// Draws the diagnostic views of the light of `s` (inside a rendering pass with the two
    /// diagnostic targets and the frame's depth), its maps bound through `shadow_set`.
    pub fn record_diagnostics<'a>(
        &'a self,
        cx: &mut PassRecorder<'_, 'a>,
        layout: &'a PipelineLayout,
        s: LightSurfaces<'a, '_>,
        shadow_set: &'a DescriptorSet,
    ) {
        cx.rec.bind_pipeline(&self.diagnostics);
        cx.rec.bind_descriptor_set(layout, 1, shadow_set);
        s.draw(cx, layout);
    }
}

fn default_clear() -> [f32; 4] {
    [DEFAULT_POINT.x, DEFAULT_POINT.y, 0.0, 0.0]
}
