//! The frame's passes, each declared into the frame graph (`record.rs` puts them in order):
//! the mesh upload (when a mesh changed) and the lights' views (shadow maps, silhouette points,
//! blocker culling); the renderer's own surfaces (`ambient`, the optional `g-buffer`); every
//! recorded light's shadows (its technique's passes writing its visibility image, from the
//! technique's own `frame.rs` or `visibility::declare_map_light`; the diagnostics asked for
//! are `diagnostics.rs`'s); the renderer's own lights. Each pass names the images it uses; the
//! graph emits the barriers, labels and timestamps (`crate::frame`).

use super::lights::{LightBindings, LightFrame, LightQueries};
use super::Renderer;
use crate::frame::{PassId, QueryId, Stage, Use};
use crate::gpu_scene::GpuScene;
use crate::hybrid::cull::CullingPlan;
use crate::hybrid::frame::{self as hybrid_frame, HybridQueries};
use crate::hybrid::pass::{CullingMap, HybridLight};
use crate::hybrid::rays::RaysLight;
use crate::light_surfaces::{over_surfaces, LightSurfaces, PassBounds};
use crate::plan::{tally, CullReason};
use crate::ray_traced::frame as ray_frame;
use crate::shadow_volume::build::LightVolumes;
use crate::shadow_volume::frame::{self as volume_frame, VolumeLight, VolumeSource};
use crate::visibility::{self, VisibilityTarget};
use crate::RenderResult;
use umbra_scene::Scene;
use umbra_vk::{Buffer, ColorAttachment, DepthAttachment, DescriptorSet, Image, ImageState, RenderTargets};

use ImageState::{ColorAttachment as Color, DepthStencilAttachment as Depth, FragmentRead as Read};

/// What every pass of a frame reads.
#[derive(Clone, Copy)]
pub(super) struct FrameInputs<'a> {
    pub scene: &'a Scene,
    pub gpu: &'a GpuScene,
    pub lights: &'a [LightFrame],
    pub bindings: &'a [LightBindings<'a>],
    /// The frame's depth (and stencil): the renderer's own, the engine's, or umbra's rebuilt
    /// one for an engine's frame.
    pub depth: &'a Image,
    /// An engine's frame whose depth umbra re-draws into `depth` before anything tests it.
    pub rebuild: Option<&'a crate::depth_rebuild::DepthRebuild>,
    /// The frame's silhouette edges and shadow-volume vertices (none when empty).
    pub edges: Option<&'a Buffer>,
    pub volumes: Option<&'a Buffer>,
    /// The draws' initial values of the shadow volumes built on the GPU (when any).
    pub volume_resets: Option<&'a Buffer>,
}

impl<'a> FrameInputs<'a> {
    /// `light`'s passes over the frame's surfaces: this frame's scene, the light, its bounds.
    pub fn surfaces(&self, light: &LightFrame) -> LightSurfaces<'a, 'a> {
        LightSurfaces { gpu: self.gpu, scene: self.scene, light: light.light() as u32, bounds: light_bounds(light) }
    }
}

impl Renderer {
    /// Every light's volumes once blocker culling (if any) dropped casters: their stencil
    /// batches and report.
    pub(super) fn settle_volumes(&self, scene: &Scene, lights: &mut [LightFrame], culling: &CullingPlan) {
        for light in lights.iter_mut() {
            if let Some(v) = light.volumes.as_mut() {
                v.plan_batches(match light.plan.technique {
                    umbra_scene::Technique::Hybrid => crate::hybrid::pass::count_bits(self.mask),
                    _ => crate::shadow_volume::batches::FULL_STENCIL,
                });
                light.plan.shadow_volume = Some(v.report(scene));
            }
            light.culled_blockers = culling.culled(light.light());
            if let Some(n) = light.culled_blockers {
                tally(&mut light.plan.culled, CullReason::HiddenBlocker, n);
            }
        }
    }

    /// The frame's first passes: the meshes' upload when they changed, an engine's depth re-drawn
    /// where umbra rebuilds it, then the lights' views: per recorded light its shadow map and
    /// silhouette points.
    pub(super) fn declare_views<'a>(&'a self, stage: &mut Stage<'a>, f: FrameInputs<'a>) -> RenderResult<()> {
        if let Some(upload) = &f.gpu.upload {
            stage.pass(PassId::MeshUpload, &[], move |cx| {
                upload.record(cx.rec, &f.gpu.geometry);
                Ok(())
            });
        }
        if let Some(rebuild) = f.rebuild {
            stage.pass(PassId::DepthRebuild, &[Use::Image(f.depth, Depth)], move |cx| {
                rebuild.record(cx.rec, &self.layout, f.gpu, f.scene, cx.log)
            });
        }
        for light in f.lights.iter().filter(|l| l.plan.recorded) {
            let l = light.light();
            let Some(map) = &light.map else { continue };
            if map.depth {
                let image = self.shadow_map.image(l)?;
                stage.pass(PassId::ShadowMap(l), &[Use::Image(image, Depth)], move |cx| {
                    self.shadow_map.record(cx, &self.layout, f.gpu, f.scene, l, map)
                });
            }
            if light.hybrid() {
                let bounds = self.hybrid.bounds.image(Some(l));
                stage.pass(PassId::HybridBounds(l), &[Use::Image(bounds, Depth)], move |cx| {
                    self.hybrid.bounds.record(cx, f.gpu, f.scene, l, &map.views);
                    Ok(())
                });
            }
            let (Some(e), Some(depth_set)) = (light.edges, &f.bindings[l].depth_set) else { continue };
            let (target, image) = (self.silhouette_map.image(Some(l)), self.shadow_map.image(l)?);
            stage.pass(PassId::SilhouetteMap(l), &[Use::Image(target, Color), Use::Image(image, Read)], move |cx| {
                let map_kind = (map.views.kind, map.resolution);
                self.silhouette_map.record_points(
                    cx.rec,
                    &self.layout,
                    f.gpu,
                    depth_set,
                    l,
                    f.edges,
                    e,
                    map_kind,
                    cx.log,
                )
            });
        }
        Ok(())
    }

    /// Blocker culling: every hybrid light's boxes against its map, a query per box (in
    /// `culling.boxes` order, from the returned query on).
    pub(super) fn declare_culling<'a>(
        &'a self,
        stage: &mut Stage<'a>,
        f: FrameInputs<'a>,
        culling: &CullingPlan,
        boxes: &'a Buffer,
    ) -> RenderResult<QueryId> {
        let first = stage.queries(culling.boxes.len() as u32);
        let mut ranges = Vec::new();
        let mut start = 0;
        for light in f.lights.iter().filter(|l| l.hybrid()) {
            let l = light.light();
            let n = culling.boxes.iter().filter(|(b, _)| *b == l).count() as u32;
            if let (Some(map), true) = (&light.map, n > 0) {
                let (image, view) = (self.shadow_map.image(l)?, map.shadow.first_view);
                ranges.push(CullingMap { map: image, boxes: start..start + n, view });
                start += n;
            }
        }
        let uses: Vec<Use> = ranges.iter().map(|m| Use::Image(m.map, ImageState::DepthStencilReadOnly)).collect();
        stage.pass(PassId::BlockerCulling, &uses, move |cx| {
            self.hybrid.record_culling(cx, &self.layout, f.gpu, boxes, &ranges, first);
            Ok(())
        });
        Ok(first)
    }

    /// The renderer's own surfaces, before any light's shadows test them: `ambient` (its
    /// depth and the ambient term) and the optional `g-buffer`. An engine draws its own.
    pub(super) fn declare_surfaces<'a>(&'a self, stage: &mut Stage<'a>, f: FrameInputs<'a>) -> RenderResult<()> {
        let (color, depth) = (&self.own()?.color, f.depth);
        stage.pass(PassId::Ambient, &[Use::Image(color, Color), Use::Image(depth, Depth)], move |cx| {
            let bg = f.scene.background;
            let clear = [ColorAttachment { image: color, clear: Some([bg.x, bg.y, bg.z, 1.0]) }];
            let depth = DepthAttachment::cleared(depth, 1.0, 0);
            cx.rec.begin_rendering(&RenderTargets { color: &clear, depth: Some(depth) });
            self.forward.record_ambient(cx.rec, &self.layout, f.gpu, f.scene, cx.log);
            cx.rec.end_rendering();
            Ok(())
        });
        if let Some(g) = &self.gbuffer {
            stage.pass(PassId::GBuffer, &[&g.uses()[..], &[Use::Image(depth, Depth)]].concat(), move |cx| {
                g.record(cx, &self.layout, f.gpu, f.scene, depth);
                Ok(())
            });
        }
        Ok(())
    }

    /// The renderer's own lights, after every light's shadows (`queries`, from
    /// `declare_shadows`): the volume counts read back, every recorded light's lighting, then
    /// `readback`. Whether the volume counts are read back.
    pub(super) fn declare_lights<'a>(
        &'a self,
        stage: &mut Stage<'a>,
        f: FrameInputs<'a>,
        queries: &[LightQueries],
        overdraw: bool,
    ) -> RenderResult<bool> {
        let counted = self.declare_volume_counts(stage, f);
        for light in f.lights.iter().filter(|l| l.plan.recorded && f.bindings[l.light()].shadow_set.is_some()) {
            self.declare_light(stage, f, light, queries[light.light()].shadowed)?;
        }
        self.declare_readback(stage, overdraw)?;
        Ok(counted)
    }

    /// Every recorded light's shadows, before any light is lit: its visibility image (and its
    /// copy), then the diagnostics asked for. Returns each light's queries and whether the
    /// overdraw image was drawn.
    pub(super) fn declare_shadows<'a>(
        &'a self,
        stage: &mut Stage<'a>,
        f: FrameInputs<'a>,
    ) -> RenderResult<(Vec<LightQueries>, bool)> {
        let mut queries = vec![LightQueries::default(); f.lights.len()];
        let mut overdraw = false;
        let stats = self.declare_ray_stats_reset(stage, f);
        self.declare_volume_frame(stage, f);
        for light in f.lights.iter().filter(|l| l.plan.recorded) {
            let l = light.light();
            let Some(shadow_set) = &f.bindings[l].shadow_set else { continue };
            let reads = self.light_reads(light)?;
            let shadowed = self.declare_visibility(stage, f, light, shadow_set, &reads, &mut queries[l])?;
            queries[l].shadowed = shadowed;
            if let (true, Some(out)) = (shadowed, f.bindings[l].visibility_readback) {
                let (image, src) = (&self.visibility.light(l)?.image, ImageState::TransferSrc);
                stage.pass(
                    PassId::VisibilityReadback(l),
                    &[Use::Image(image, src), Use::Readback(&out.buffer)],
                    |cx| {
                        cx.rec.copy_image_to_buffer(image, 0, &out.buffer);
                        Ok(())
                    },
                );
            }
            self.declare_light_diagnostics(stage, f, light, &reads);
            queries[l].volume_fragments = self.declare_overdraw(stage, f, light, !overdraw);
            overdraw |= queries[l].volume_fragments.is_some();
            self.declare_silhouette_diagnostics(stage, f, light, &reads);
            if let (Some(stats), true) = (stats, light.rays) {
                self.declare_ray_stats(stage, f, light, stats)?;
            }
        }
        if let Some(stats) = stats {
            self.declare_ray_stats_readback(stage, stats);
        }
        Ok((queries, overdraw))
    }

    /// The technique seam's one dispatch of visibility passes (`crate::visibility`): the
    /// hybrid's own passes, a shadow-volume light's stencil counts resolved, or a map lookup.
    /// False when nothing shadows the light this frame (it is lit unshadowed).
    fn declare_visibility<'a>(
        &'a self,
        stage: &mut Stage<'a>,
        f: FrameInputs<'a>,
        light: &'a LightFrame,
        shadow_set: &'a DescriptorSet,
        reads: &[Use<'a>],
        queries: &mut LightQueries,
    ) -> RenderResult<bool> {
        match (&light.volumes, f.volumes) {
            _ if light.hybrid_rays() => {
                self.declare_hybrid_rays(stage, f, light, shadow_set)?;
                Ok(true)
            }
            (Some(volumes), _) if light.hybrid() => {
                queries.hybrid = Some(self.declare_hybrid(stage, f, light, volumes, shadow_set)?);
                Ok(true)
            }
            (Some(volumes), _) if volumes.gpu.is_some() => {
                let source = self.declare_gpu_stages(stage, light, volumes)?;
                self.declare_volume_light(stage, f, light, volumes, source)?;
                Ok(true)
            }
            // A hybrid light without a map this frame is shadowed by its volumes alone.
            (Some(volumes), Some(vertices)) => {
                self.declare_volume_light(stage, f, light, volumes, VolumeSource::Host(Some(vertices)))?;
                Ok(true)
            }
            _ if light.rays => {
                let target = self.visibility_target(f, light)?;
                ray_frame::declare_light(stage, &self.rays, self.slot.rays.as_ref(), f.surfaces(light), target);
                Ok(true)
            }
            _ if light.map.is_some() => {
                let target = self.visibility_target(f, light)?;
                let (layout, surfaces) = (&self.layout, f.surfaces(light));
                visibility::declare_map_light(stage, &self.visibility, layout, surfaces, shadow_set, target, reads);
                Ok(true)
            }
            _ => Ok(false),
        }
    }

    /// A hybrid light's own passes (`hybrid::frame`), after its map.
    fn declare_hybrid<'a>(
        &'a self,
        stage: &mut Stage<'a>,
        f: FrameInputs<'a>,
        light: &'a LightFrame,
        volumes: &'a LightVolumes,
        shadow_set: &'a DescriptorSet,
    ) -> RenderResult<HybridQueries> {
        let l = light.light();
        let source = match volumes.gpu {
            Some(_) => self.declare_gpu_stages(stage, light, volumes)?,
            None => VolumeSource::Host(f.volumes),
        };
        let h = HybridLight {
            light: l,
            mask: self.mask,
            layout: &self.layout,
            gpu: f.gpu,
            scene: f.scene,
            shadow_set,
            visibility: &self.visibility.light(l)?.image,
            depth: f.depth,
            volumes,
            source,
            mask_query: QueryId(0),
        };
        let bounds = self.hybrid.bounds.image(Some(l));
        let readback = f.bindings[l].class_readback;
        Ok(hybrid_frame::declare_light(stage, &self.hybrid, h, bounds, self.overdraw.is_some(), readback))
    }

    /// A ray-traced hybrid light's own passes (`hybrid::rays`), after its map's depth bounds.
    fn declare_hybrid_rays<'a>(
        &'a self,
        stage: &mut Stage<'a>,
        f: FrameInputs<'a>,
        light: &'a LightFrame,
        shadow_set: &'a DescriptorSet,
    ) -> RenderResult<()> {
        let l = light.light();
        let missing = |what: &str| crate::RenderError::InvalidInput {
            field: format!("light {l}"),
            why: format!("its ray-traced hybrid passes were declared before {what} was prepared"),
        };
        let rays = self.hybrid_rays.as_ref().ok_or_else(|| missing("the ray list"))?;
        let bvh = &self.slot.rays.as_ref().ok_or_else(|| missing("the BVH"))?.set;
        let classes = self.hybrid.classes().ok_or_else(|| missing("the classes image"))?;
        let r = RaysLight {
            light: l,
            gpu: f.gpu,
            scene: f.scene,
            shadow_set,
            bvh,
            visibility: &self.visibility.light(l)?.image,
            classes,
            depth: f.depth,
        };
        let bounds = self.hybrid.bounds.image(Some(l));
        hybrid_frame::declare_rays_light(stage, rays, r, bounds, self.own.is_some());
        Ok(())
    }

    /// The images a light's lighting passes sample: its shadow map and silhouette map.
    fn light_reads(&self, light: &LightFrame) -> RenderResult<Vec<Use<'_>>> {
        let mut reads = Vec::new();
        if light.map.as_ref().is_some_and(|m| m.depth) {
            reads.push(Use::Image(self.shadow_map.image(light.light())?, Read));
        }
        if light.edges.is_some() {
            reads.push(Use::Image(self.silhouette_map.image(Some(light.light())), Read));
        }
        Ok(reads)
    }

    /// The volumes' frame passes (`shadow_volume::frame::declare_gpu_frame`) when a light
    /// builds its volumes on the GPU.
    fn declare_volume_frame<'a>(&'a self, stage: &mut Stage<'a>, f: FrameInputs<'a>) {
        let Some(g) = self.gpu_volumes.as_ref() else { return };
        volume_frame::declare_gpu_frame(stage, g, f.lights.iter().any(builds_on_gpu), f.volume_resets);
    }

    /// `volume counts readback` (`shadow_volume::frame::declare_gpu_counts`) over every job of
    /// the frame's lights built on the GPU. Whether it was declared.
    fn declare_volume_counts<'a>(&'a self, stage: &mut Stage<'a>, f: FrameInputs<'a>) -> bool {
        let Some(g) = self.gpu_volumes.as_ref() else { return false };
        let jobs = f.lights.iter().filter(|l| builds_on_gpu(l)).filter_map(|l| l.volumes.as_ref()?.gpu.as_ref());
        volume_frame::declare_gpu_counts(stage, g, jobs.map(|(first, jobs)| first + jobs.len()).max())
    }

    /// The GPU's build of a light's volumes (`shadow_volume::frame::declare_gpu_stages`):
    /// where its counting draws read them.
    fn declare_gpu_stages<'a>(
        &'a self,
        stage: &mut Stage<'a>,
        light: &'a LightFrame,
        volumes: &'a LightVolumes,
    ) -> RenderResult<VolumeSource<'a>> {
        let l = light.light();
        let missing = |what: &str| crate::RenderError::InvalidInput {
            field: format!("light {l}"),
            why: format!("its GPU-built volumes were declared before {what} was prepared"),
        };
        let g = self.gpu_volumes.as_ref().ok_or_else(|| missing("the GPU path"))?;
        let slot = self.slot.volumes.as_ref().ok_or_else(|| missing("the volumes' set"))?;
        volume_frame::declare_gpu_stages(stage, l, g, slot, volumes).ok_or_else(|| missing("the volumes' buffers"))
    }

    /// A shadow-volume light (`shadow_volume::frame::declare_light`): its stencil counts from
    /// `source`, resolved into its visibility image.
    fn declare_volume_light<'a>(
        &'a self,
        stage: &mut Stage<'a>,
        f: FrameInputs<'a>,
        light: &'a LightFrame,
        volumes: &'a LightVolumes,
        source: VolumeSource<'a>,
    ) -> RenderResult<()> {
        let v = VolumeLight { surfaces: f.surfaces(light), layout: &self.layout, volumes, source };
        let target = self.visibility_target(f, light)?;
        volume_frame::declare_light(stage, &self.shadow_volume, &self.visibility, v, target);
        Ok(())
    }

    /// What `light`'s visibility pass writes: its visibility image over the frame's depth.
    fn visibility_target<'a>(&'a self, f: FrameInputs<'a>, light: &LightFrame) -> RenderResult<VisibilityTarget<'a>> {
        Ok(VisibilityTarget { image: &self.visibility.light(light.light())?.image, depth: f.depth })
    }

    /// `light N (kind)`: the light's Lambert term times its visibility image (`shadowed`), or
    /// unshadowed.
    fn declare_light<'a>(
        &'a self,
        stage: &mut Stage<'a>,
        f: FrameInputs<'a>,
        light: &'a LightFrame,
        shadowed: bool,
    ) -> RenderResult<()> {
        let (l, depth) = (light.light(), f.depth);
        let color = &self.own()?.color;
        let mut uses = vec![Use::Image(color, Color), Use::Image(depth, Depth)];
        let set = match shadowed {
            true => {
                let own = self.visibility.light(l)?;
                uses.push(Use::Image(&own.image, Read));
                &own.set
            }
            false => &self.visibility.unshadowed_set,
        };
        let visibility = (set, shadowed);
        let surfaces = f.surfaces(light);
        stage.pass(PassId::Light(l, light.plan.kind), &uses, move |cx| {
            over_surfaces(cx.rec, color, None, depth);
            self.forward.record_light(cx, &self.layout, surfaces, visibility);
            cx.rec.end_rendering();
            Ok(())
        });
        Ok(())
    }
}

/// Where a bounded light's passes may draw (its plan's scissor and depth bounds).
fn light_bounds(light: &LightFrame) -> PassBounds {
    PassBounds { scissor: light.plan.scissor, depth: light.plan.depth_bounds }
}

/// Whether a light's volumes are built on the GPU this frame.
fn builds_on_gpu(light: &LightFrame) -> bool {
    light.plan.recorded && light.volumes.as_ref().is_some_and(|v| v.gpu.is_some())
}
