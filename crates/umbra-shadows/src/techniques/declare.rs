//! Every recorded light's shadows, declared into the frame graph before any light is lit: the
//! one dispatch of its technique's visibility passes (the hybrid's own, a shadow-volume
//! light's stencil counts resolved, rays, or a map lookup), the GPU-built volumes' frame passes,
//! and the technique's diagnostics (volume overdraw, a silhouette map's classification and
//! points). Each pass names the images it uses; the graph emits the barriers, labels and
//! timestamps (`crate::frame`).

use super::inputs::FrameInputs;
use super::light::{LightFrame, LightQueries, Prepared};
use super::Techniques;
use crate::frame::{PassId, QueryId, Stage, Use};
use crate::hybrid::frame::{self as hybrid_frame, HybridQueries};
use crate::hybrid::pass::HybridLight;
use crate::hybrid::rays::RaysLight;
use crate::ray_traced::frame as ray_frame;
use crate::ray_traced::stats::RayStats;
use crate::shadow_volume::build::LightVolumes;
use crate::shadow_volume::frame::{self as volume_frame, VolumeLight, VolumeSource};
use crate::visibility;
use crate::RenderResult;
use umbra_vk::{ColorAttachment, DepthAttachment, DescriptorSet, ImageState, RenderTargets};

use ImageState::{ColorAttachment as Color, DepthStencilAttachment as Depth, FragmentRead as Read};

/// What the frame's shadows share across lights: the shadow rays' counters, when counted.
#[derive(Clone, Copy)]
pub(crate) struct ShadowPasses<'a> {
    stats: Option<&'a RayStats>,
}

impl Techniques {
    /// Before the first light's shadows: `ray stats reset` (with the rays' counters and a
    /// ray-casting light) and the GPU-built volumes' frame passes.
    pub fn begin_shadows<'a>(&'a self, stage: &mut Stage<'a>, f: FrameInputs<'a>) -> ShadowPasses<'a> {
        let stats = self.declare_ray_stats_reset(stage, f);
        if let Some(g) = self.gpu_volumes.as_ref() {
            volume_frame::declare_gpu_frame(stage, g, f.lights.iter().any(builds_on_gpu), f.volume_resets);
        }
        ShadowPasses { stats }
    }

    /// After a light's visibility: its volumes' overdraw (clearing the image when `first`), a
    /// silhouette-map light's diagnostics, its rays counted. The query counting its volume
    /// fragments, when they were drawn into the overdraw image.
    pub fn declare_light_extras<'a>(
        &'a self,
        stage: &mut Stage<'a>,
        f: FrameInputs<'a>,
        s: ShadowPasses<'a>,
        light: &'a LightFrame,
        reads: &[Use<'a>],
        first: bool,
    ) -> RenderResult<Option<QueryId>> {
        let volume_fragments = self.declare_overdraw(stage, f, light, first);
        self.declare_silhouette_diagnostics(stage, f, light, reads);
        if let (Some(stats), true) = (s.stats, light.rays()) {
            self.declare_ray_stats(stage, f, light, stats)?;
        }
        Ok(volume_fragments)
    }

    /// After the last light's shadows: `ray stats readback`.
    pub fn end_shadows<'a>(&'a self, stage: &mut Stage<'a>, s: ShadowPasses<'a>) {
        if let Some(stats) = s.stats {
            self.declare_ray_stats_readback(stage, stats);
        }
    }

    /// The technique seam's one dispatch of visibility passes (`crate::visibility`), by what
    /// the light prepared: a map lookup, a shadow-volume light's stencil counts resolved, its
    /// rays, or the hybrids' own passes. False when nothing shadows the light this frame (it
    /// is lit unshadowed).
    pub fn declare_visibility<'a>(
        &'a self,
        stage: &mut Stage<'a>,
        f: FrameInputs<'a>,
        light: &'a LightFrame,
        shadow_set: &'a DescriptorSet,
        reads: &[Use<'a>],
        queries: &mut LightQueries,
    ) -> RenderResult<bool> {
        match &light.prepared {
            Prepared::Nothing => return Ok(false),
            Prepared::Map(_) | Prepared::SilhouetteMap(..) => {
                let target = f.visibility_target(light)?;
                let (layout, surfaces) = (f.layout, f.surfaces(light));
                visibility::declare_map_light(stage, f.visibility, layout, surfaces, shadow_set, target, reads);
            }
            Prepared::Volumes(volumes) => {
                let source = match (volumes.gpu.is_some(), f.volumes) {
                    (true, _) => self.declare_gpu_stages(stage, f, light, volumes)?,
                    (false, Some(vertices)) => VolumeSource::Host(Some(vertices)),
                    // Not one volume triangle this frame: nothing shadows the light.
                    (false, None) => return Ok(false),
                };
                self.declare_volume_light(stage, f, light, volumes, source)?;
            }
            Prepared::Rays => {
                let target = f.visibility_target(light)?;
                ray_frame::declare_light(stage, &self.rays, f.slot.rays.as_ref(), f.surfaces(light), target);
            }
            Prepared::Hybrid(_, volumes) => {
                queries.hybrid = Some(self.declare_hybrid(stage, f, light, volumes, shadow_set)?);
            }
            Prepared::HybridRays(_) => self.declare_hybrid_rays(stage, f, light, shadow_set)?,
        }
        Ok(true)
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
            Some(_) => self.declare_gpu_stages(stage, f, light, volumes)?,
            None => VolumeSource::Host(f.volumes),
        };
        let h = HybridLight {
            light: l,
            mask: self.mask,
            layout: f.layout,
            gpu: f.gpu,
            scene: f.scene,
            shadow_set,
            visibility: &f.visibility.light(l)?.image,
            depth: f.depth,
            volumes,
            source,
            mask_query: QueryId(0),
        };
        let bounds = self.hybrid.bounds.image(Some(l));
        let readback = f.bindings[l].class_readback;
        Ok(hybrid_frame::declare_light(stage, &self.hybrid, h, bounds, f.overdraw.is_some(), readback))
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
        let bvh = &f.slot.rays.as_ref().ok_or_else(|| missing("the BVH"))?.set;
        let classes = self.hybrid.classes().ok_or_else(|| missing("the classes image"))?;
        let r = RaysLight {
            light: l,
            gpu: f.gpu,
            scene: f.scene,
            shadow_set,
            bvh,
            visibility: &f.visibility.light(l)?.image,
            classes,
            depth: f.depth,
        };
        let bounds = self.hybrid.bounds.image(Some(l));
        hybrid_frame::declare_rays_light(stage, rays, r, bounds, self.setup.own);
        Ok(())
    }

    /// The images a light's lighting passes sample: its shadow map and silhouette map.
    pub fn light_reads(&self, light: &LightFrame) -> RenderResult<Vec<Use<'_>>> {
        let mut reads = Vec::new();
        if light.map().is_some_and(|m| m.depth) {
            reads.push(Use::Image(self.shadow_map.image(light.light())?, Read));
        }
        if light.edges().is_some() {
            reads.push(Use::Image(self.silhouette_map.image(Some(light.light())), Read));
        }
        Ok(reads)
    }

    /// `volume counts readback` (`shadow_volume::frame::declare_gpu_counts`) over every job of
    /// the frame's lights built on the GPU. Whether it was declared.
    pub fn declare_volume_counts<'a>(&'a self, stage: &mut Stage<'a>, f: FrameInputs<'a>) -> bool {
        let Some(g) = self.gpu_volumes.as_ref() else { return false };
        let jobs = f.lights.iter().filter(|l| builds_on_gpu(l)).filter_map(|l| l.volumes()?.gpu.as_ref());
        volume_frame::declare_gpu_counts(stage, g, jobs.map(|(first, jobs)| first + jobs.len()).max())
    }

    /// The GPU's build of a light's volumes (`shadow_volume::frame::declare_gpu_stages`):
    /// where its counting draws read them.
    fn declare_gpu_stages<'a>(
        &'a self,
        stage: &mut Stage<'a>,
        f: FrameInputs<'a>,
        light: &'a LightFrame,
        volumes: &'a LightVolumes,
    ) -> RenderResult<VolumeSource<'a>> {
        let l = light.light();
        let missing = |what: &str| crate::RenderError::InvalidInput {
            field: format!("light {l}"),
            why: format!("its GPU-built volumes were declared before {what} was prepared"),
        };
        let g = self.gpu_volumes.as_ref().ok_or_else(|| missing("the GPU path"))?;
        let slot = f.slot.volumes.as_ref().ok_or_else(|| missing("the volumes' set"))?;
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
        let v = VolumeLight { surfaces: f.surfaces(light), layout: f.layout, volumes, source };
        let target = f.visibility_target(light)?;
        volume_frame::declare_light(stage, &self.shadow_volume, f.visibility, v, target);
        Ok(())
    }

    /// With `overdraw`, a light's volumes into the overdraw image (cleared by the `first`),
    /// counted by the returned query.
    fn declare_overdraw<'a>(
        &'a self,
        stage: &mut Stage<'a>,
        f: FrameInputs<'a>,
        light: &'a LightFrame,
        first: bool,
    ) -> Option<QueryId> {
        let (image, volumes) = (f.overdraw?, light.volumes()?);
        // Built on the CPU: the frame's vertices; on the GPU: the stages' draws and set.
        let source = match volumes.gpu {
            Some(_) => VolumeSource::Gpu(self.gpu_volumes.as_ref()?, f.slot.volumes.as_ref()?),
            None => VolumeSource::Host(Some(f.volumes?)),
        };
        let v = VolumeLight { surfaces: f.surfaces(light), layout: f.layout, volumes, source };
        Some(volume_frame::declare_overdraw(stage, &self.shadow_volume, v, image, first))
    }

    /// With diagnostics, a silhouette-map light's classification and silhouette points over
    /// the frame's depth, copied out with its silhouette map.
    fn declare_silhouette_diagnostics<'a>(
        &'a self,
        stage: &mut Stage<'a>,
        f: FrameInputs<'a>,
        light: &'a LightFrame,
        reads: &[Use<'a>],
    ) {
        let l = light.light();
        let (Some(targets), Some(out), Some(shadow_set)) =
            (f.diagnostic_targets, &f.bindings[l].silhouette_readback, &f.bindings[l].shadow_set)
        else {
            return;
        };
        let (class, points, depth) = (&targets.classification, &targets.points, f.depth);
        let silmap = self.silhouette_map.image(Some(l));
        let mut uses = vec![Use::Image(class, Color), Use::Image(points, Color), Use::Image(depth, Depth)];
        uses.extend_from_slice(reads);
        uses.extend([
            Use::Readback(&out.classification),
            Use::Readback(&out.points),
            Use::Readback(&out.silhouette_map),
        ]);
        let surfaces = f.surfaces(light);
        stage.pass(PassId::SilhouetteDiagnostics(l), &uses, move |cx| {
            let color = [
                ColorAttachment { image: class, view: None, clear: Some(crate::diagnostics::BACKGROUND) },
                ColorAttachment { image: points, view: None, clear: Some([0.0; 4]) },
            ];
            cx.rec.begin_rendering(&RenderTargets { color: &color, depth: Some(DepthAttachment::keep(depth)) });
            self.silhouette_map.record_diagnostics(cx, f.layout, surfaces, shadow_set);
            cx.rec.end_rendering();
            let src = ImageState::TransferSrc;
            cx.enter(&[(class, src), (points, src), (silmap, src)]);
            cx.rec.copy_image_to_buffer(class, 0, &out.classification);
            cx.rec.copy_image_to_buffer(points, 0, &out.points);
            cx.rec.copy_image_to_buffer(silmap, 0, &out.silhouette_map);
            Ok(())
        });
    }
}

/// Whether a light's volumes are built on the GPU this frame.
fn builds_on_gpu(light: &LightFrame) -> bool {
    light.plan.recorded && light.volumes().is_some_and(|v| v.gpu.is_some())
}
