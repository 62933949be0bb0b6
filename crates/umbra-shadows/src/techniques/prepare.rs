//! The CPU half of a frame, per light and per technique: fit and size the shadow maps (checked
//! against the device and the budget before any is made), extract silhouette edges, build
//! shadow volumes, prepare the BVH, list blocker boxes, and make the lights' targets; each
//! stage adds its part of a light, assembled into its `Prepared` at the end.

use super::light::{FrameView, LightFrame, Parts};
use super::{TechniqueSlot, Techniques};
use crate::budget;
use crate::error::ShadowStorage;
use crate::gpu_scene::{GpuScene, GpuShadow};
use crate::hybrid::cull::{self, CullingPlan};
use crate::hybrid::MaskKind;
use crate::plan::{tally, CullReason, RayTracedReport, ShadowMapReport, SilhouetteMapReport};
use crate::retired::Retired;
use crate::shadow_map::texels;
use crate::shadow_map::DepthBias;
use crate::shadow_map::MapFrame;
use crate::shadow_volume::build::{self as volumes};
use crate::shadow_volume::clip;
use crate::shadow_volume::pass::VolumeInput;
use crate::shadow_volume::FarPlane;
use crate::silhouette_map::edges;
use crate::streams::Streams;
use crate::technique::{needs, MapSize, Volumes};
use crate::visibility::VisibilityPass;
use crate::{RenderError, RenderResult};
use glam::Mat4;
use std::sync::Arc;
use umbra_scene::{Adjacency, Camera, Scene};
use umbra_vk::{Context, Image};

/// What every step of a frame's preparation reads.
#[derive(Clone, Copy)]
pub(crate) struct PrepareInputs<'a> {
    pub ctx: &'a Context,
    pub scene: &'a Scene,
    pub view: &'a FrameView,
    /// Welded connectivity per mesh.
    pub adjacency: &'a [Arc<Adjacency>],
}

/// What a frame's preparation gave the passes besides each light's `Prepared`: every
/// map's views, in light order (the shadow-view buffer), and the boxes blocker culling queries.
pub(crate) struct PreparedFrame {
    pub shadow_views: Vec<Mat4>,
    pub culling: CullingPlan,
}

impl Techniques {
    /// The camera a frame of `scene` is drawn with. Shadow volumes reach infinity: the frame
    /// uses `P_inf` unless depth clamp does the job, decided from what the scene asks for
    /// (`auto` may pick the hybrid), not from the plan, so that culling never changes the depth.
    pub fn camera(&self, scene: &Scene) -> Camera {
        let asks_volumes = scene.lights.iter().any(|l| needs(l.technique).infinite_camera);
        match asks_volumes {
            true => volumes::volume_camera(&scene.camera, self.setup.shadow_volume.far_plane == FarPlane::Infinite),
            false => scene.camera,
        }
    }

    /// Every planned light's technique on the CPU, in the frame's order: its shadow map (views,
    /// size, edges), its volumes, the BVH its rays walk, the boxes blocker culling queries.
    pub fn prepare(
        &mut self,
        p: PrepareInputs<'_>,
        lights: &mut [LightFrame],
        streams: &mut Streams,
        slot: &mut TechniqueSlot,
        retired: &mut Retired,
    ) -> RenderResult<PreparedFrame> {
        let mut parts: Vec<Parts> = lights.iter().map(|_| Parts::default()).collect();
        let shadow_views = self.prepare_maps(p, lights, &mut parts, streams, retired)?;
        self.prepare_volumes(p, lights, &mut parts, streams, slot, retired)?;
        self.prepare_rays(p, lights, &mut parts, streams, slot, retired)?;
        for (light, parts) in lights.iter_mut().zip(parts) {
            light.prepared = parts.assemble(light.plan.technique);
        }
        let culling = self.plan_culling(p, lights, streams)?;
        Ok(PreparedFrame { shadow_views, culling })
    }

    /// Shadow maps (also the depth maps of silhouette maps and the hybrid): every light's views
    /// and map size, each checked against the device and all together against the budget, then
    /// the maps themselves and, for silhouette maps, the edges. Returns every map's views, in
    /// light order (the shadow-view buffer).
    fn prepare_maps(
        &mut self,
        p: PrepareInputs<'_>,
        lights: &mut [LightFrame],
        parts: &mut [Parts],
        streams: &mut Streams,
        retired: &mut Retired,
    ) -> RenderResult<Vec<Mat4>> {
        let PrepareInputs { ctx, scene, view, adjacency } = p;
        let mut fitted = self.fit_maps(ctx, scene, view, lights)?;
        let keep: Vec<bool> = fitted.iter().map(|m| m.as_ref().is_some_and(|m| m.depth)).collect();
        self.shadow_map.keep_only(&keep, retired);
        let silhouette: Vec<bool> = fitted.iter().map(|m| m.as_ref().is_some_and(|m| m.silhouette)).collect();
        self.silhouette_map.keep_only(&silhouette, retired);
        let settings = *self.shadow_map.settings();
        let mut shadow_views = Vec::new();
        let mut edge_instances = Vec::new();
        for ((light, map), parts) in lights.iter_mut().zip(&mut fitted).zip(parts.iter_mut()) {
            let Some(mut map) = map.take() else { continue };
            let (l, resolution, views) = (light.light(), map.resolution, &map.views);
            let seen = view.seen(self.setup.height);
            let source = &scene.lights[l];
            if map.depth {
                self.shadow_map.prepare(ctx, l, resolution, views.kind, retired)?;
            }
            // Texels per side of one view: a face atlas's faces have their borders too.
            let side = views.kind.view_side(resolution);
            map.shadow = GpuShadow {
                kind: views.kind.shader_kind(map.silhouette),
                first_view: shadow_views.len() as u32,
                normal_offset: settings.normal_offset,
                texel: 1.0 / side as f32,
                near: views.near,
                far: views.far,
            };
            light.plan.shadow_map = Some(ShadowMapReport {
                resolution,
                cube: views.kind.is_cube(),
                near: views.near,
                far: views.far,
                casters: views.casters.len(),
                texel_size: (source.position.w == 0.0).then(|| texels::texel_size(views.views[0], resolution)),
                receiver_texel_size: self.grid_samples.receiver_texel_size(l, views, side, seen),
                view_proj: views.views.clone(),
                view_texels: side,
            });
            if map.silhouette {
                self.silhouette_map.prepare(ctx, l, resolution, views.kind, retired)?;
                let e = edges::extract(scene, adjacency, &views.casters, source, &mut edge_instances);
                light.plan.silhouette_map = Some(SilhouetteMapReport {
                    resolution,
                    silhouette_edges: e.count as usize,
                    cpu_extract_ms: e.cpu_ms,
                    silhouette_pixels: None,
                    silhouette_fraction: None,
                });
                parts.edges = Some(e);
            }
            let clamp_texels = match (settings.bias.clamp_texels, map.silhouette) {
                (Some(t), _) => Some(t),
                (None, true) => Some(DepthBias::SILHOUETTE_CLAMP_TEXELS),
                (None, false) => None,
            };
            if let (Some(texels), true) = (clamp_texels, ctx.capabilities().depth_bias_clamp) {
                map.bias_clamp = texels::bias_clamp(views.views[0], side, texels);
            }
            shadow_views.extend_from_slice(&views.views);
            parts.map = Some(map);
        }
        streams.edges.fill(ctx, &edge_instances)?;
        Ok(shadow_views)
    }

    /// Every map-using light's views and map size, checked against the device, and what they
    /// take together against the budget; nothing is allocated here.
    fn fit_maps(
        &mut self,
        ctx: &Context,
        scene: &Scene,
        view: &FrameView,
        lights: &mut [LightFrame],
    ) -> RenderResult<Vec<Option<MapFrame>>> {
        let settings = *self.shadow_map.settings();
        let uses_map = |l: &LightFrame| l.plan.recorded && l.plan.shadowed && needs(l.plan.technique).map.is_some();
        let mut fitted: Vec<Option<MapFrame>> = (0..lights.len()).map(|_| None).collect();
        let mut storage = Vec::new();
        for light in lights.iter_mut().filter(|l| uses_map(l)) {
            let plan = &mut light.plan;
            let source = &scene.lights[plan.light];
            let Some(mut views) = self.fits.fit(plan.light, source, scene, &view.boxes, view.view.view_proj) else {
                plan.note = Some("no caster can shadow a visible receiver: no shadow map rendered".into());
                continue;
            };
            let silhouette = needs(plan.technique).silhouette;
            let (set, coarser) = match needs(plan.technique).map {
                Some(MapSize::Hybrid { coarser }) => (self.setup.hybrid.resolution, coarser),
                Some(MapSize::Settings) | None => (settings.resolution, 1),
            };
            let resolution = source.shadow_map_size.or(set).unwrap_or_else(|| {
                let seen = view.seen(self.setup.height);
                let fine = self.grid_samples.resolution_from_frame(plan.light, &views, seen, self.setup.width);
                (fine / coarser).max(crate::ShadowMapSettings::MIN_RESOLUTION)
            });
            if silhouette {
                // A cube's silhouette map: six faces with borders in one atlas (`atlas.rs`).
                views.widen_to_face_atlas(resolution);
            }
            if self.setup.cull {
                // The fit saw every caster (so the map's frustum is the same either way); only
                // the planned ones are drawn, each into the views it may touch.
                views.casters.retain(|c| plan.map_casters.contains(c));
                let out = views.cull_per_view(&view.boxes);
                tally(&mut plan.culled, CullReason::OutsideMapView, out);
            }
            let map_bytes = self.shadow_map.check(ctx, plan.light, resolution, views.kind)?;
            // The hybrid's depth bounds: two floats per texel of the map's faces; its depth map
            // only where blocker culling queries it.
            let bounds = matches!(needs(plan.technique).map, Some(MapSize::Hybrid { .. }));
            let volumes = needs(plan.technique).volumes.is_some();
            let depth = !bounds || (self.setup.hybrid.cull_blockers && volumes);
            let mut bytes = if depth { map_bytes } else { 0 };
            if silhouette {
                let map = self.silhouette_map.check(ctx, plan.light, resolution, views.kind)?;
                // With diagnostics the map is also read back, as many bytes again.
                bytes += if self.setup.diagnostics { 2 * map } else { map };
            }
            if bounds {
                bytes += crate::hybrid::bounds::bytes(map_bytes);
            }
            let cube = views.kind.is_cube();
            // A silhouette map's cube faces carry borders in its atlas.
            let face_side =
                if cube && silhouette { crate::shadow_map::atlas::face_side(resolution) } else { resolution };
            storage.push(ShadowStorage {
                light: plan.light,
                resolution,
                face_side,
                cube,
                depth,
                silhouette,
                bounds,
                bytes,
            });
            fitted[plan.light] = Some(MapFrame::new(views, resolution, silhouette, depth));
        }
        budget::check(&storage, self.setup.budget_bytes)?;
        Ok(fitted)
    }

    /// Shadow volumes: every caster's volume per light (z-fail only for hybrid lights,
    /// Chan–Durand §3 step 3; none for a hybrid light without a map), built on the CPU, or with
    /// `VolumeBuild::Gpu` named as jobs of the GPU path.
    fn prepare_volumes(
        &mut self,
        p: PrepareInputs<'_>,
        lights: &[LightFrame],
        parts: &mut [Parts],
        streams: &mut Streams,
        slot: &mut TechniqueSlot,
        retired: &mut Retired,
    ) -> RenderResult<()> {
        let PrepareInputs { ctx, scene, view, adjacency } = p;
        let mut vertices = Vec::new();
        let mut jobs = Vec::new();
        let mut next = (0u32, 0u32);
        let depth_precision =
            lights.iter().any(|l| needs(l.plan.technique).volumes.is_some()).then(|| view.depth_precision()).flatten();
        for (light, parts) in lights.iter().zip(parts.iter_mut()) {
            let plan = &light.plan;
            let shadowed = plan.recorded && plan.shadowed;
            let wanted = match needs(plan.technique).volumes {
                Some(Volumes::Settings) if shadowed => Volumes::Settings,
                Some(Volumes::ZFailWithMap) if shadowed && parts.map.is_some() => Volumes::ZFailWithMap,
                _ => continue,
            };
            let mode = wanted.mode(self.setup.shadow_volume.mode);
            let casters = volumes::LightCasters {
                scene,
                casters: &plan.volume_casters,
                adjacency,
                boxes: &view.boxes,
                light: &scene.lights[plan.light],
                view: &view.view,
                mode,
            };
            if let Some(g) = self.gpu_volumes.as_mut() {
                g.prepare_arrays(ctx, adjacency, self.deforming.streams(), retired)?;
                let v = volumes::jobs_for_light(casters, g.ranges(), &mut jobs, &mut next);
                parts.volumes = Some(volumes::LightVolumes { depth_precision, ..v });
                continue;
            }
            let v = volumes::build_light(casters, &mut vertices);
            parts.volumes = Some(volumes::LightVolumes { depth_precision, ..v });
        }
        if let (Some(g), false) = (self.gpu_volumes.as_mut(), jobs.is_empty()) {
            streams.volume_draws.fill(ctx, &crate::shadow_volume::gpu::draw_resets(&jobs))?;
            g.prepare_written(ctx, u64::from(next.0), u64::from(next.1), jobs.len() as u64, retired)?;
            streams.volume_jobs.fill(ctx, &jobs)?;
            if let Some(buffer) = streams.volume_jobs.buffer() {
                let generation = streams.volume_jobs.generation();
                g.prepare_slot(ctx, &mut slot.volumes, buffer, generation, retired)?;
            }
        }
        if self.volume_input == VolumeInput::Built {
            streams.volumes.fill(ctx, &vertices)?;
            return Ok(());
        }
        // Drivers whose clipping is not watertight: every light's volumes cut to the view here.
        let (mut clipped, mut cut_caps) = (Vec::new(), Vec::new());
        for (light, parts) in lights.iter().zip(parts.iter_mut()) {
            let position = scene.lights[light.light()].position;
            if let Some(v) = parts.volumes.as_mut() {
                let started = std::time::Instant::now();
                clip::clip_light(
                    scene,
                    position,
                    view.view.view_proj,
                    &vertices,
                    &mut v.casters,
                    &mut clipped,
                    &mut cut_caps,
                );
                v.cpu_ms += started.elapsed().as_secs_f64() * 1e3;
                v.host_clipped = true;
            }
        }
        streams.volumes.fill(ctx, &clipped)?;
        Ok(())
    }

    /// Ray-traced lights (`crate::ray_traced`): every shadowed one casts rays, through the
    /// scene's BVH brought up to date (meshes built again only when their revision changed, the
    /// top level when a caster moved) and uploaded when it changed.
    fn prepare_rays(
        &mut self,
        p: PrepareInputs<'_>,
        lights: &mut [LightFrame],
        parts: &mut [Parts],
        streams: &mut Streams,
        slot: &mut TechniqueSlot,
        retired: &mut Retired,
    ) -> RenderResult<()> {
        let PrepareInputs { ctx, scene, .. } = p;
        let mut any = false;
        for (light, parts) in lights.iter().zip(parts.iter_mut()) {
            parts.rays = needs(light.plan.technique).rays && light.plan.recorded && light.plan.shadowed;
            any |= parts.rays;
            if parts.hybrid_rays(light.plan.technique) && self.hybrid_rays.is_none() {
                return Err(RenderError::UnsupportedLight {
                    light: light.light(),
                    technique: light.plan.technique,
                    why: crate::hybrid::rays::UNSUPPORTED.into(),
                });
            }
        }
        if !any {
            return Ok(());
        }
        self.rays.prepare(ctx, scene, streams, &mut slot.rays, retired)?;
        if let Some(stats) = self.ray_stats.as_mut() {
            stats.prepare(ctx, lights.len(), retired)?;
        }
        let report = RayTracedReport::of(self.rays.scene(), ctx.capabilities().ray_query);
        for (light, _) in lights.iter_mut().zip(parts.iter()).filter(|(_, parts)| parts.rays) {
            light.plan.ray_traced = Some(report);
        }
        Ok(())
    }

    /// Blocker culling (Chan–Durand §6.3, with `hybrid.cull_blockers`): one box per caster of
    /// every hybrid light with a 2D map.
    fn plan_culling(
        &self,
        p: PrepareInputs<'_>,
        lights: &[LightFrame],
        streams: &mut Streams,
    ) -> RenderResult<CullingPlan> {
        let PrepareInputs { ctx, scene, view, .. } = p;
        let mut culling = CullingPlan::default();
        if self.setup.hybrid.cull_blockers && self.setup.cull {
            for light in lights.iter().filter(|l| l.hybrid()) {
                let (Some(v), Some(map)) = (light.volumes(), light.map()) else { continue };
                if map.views.kind.is_cube() {
                    continue;
                }
                for (i, c) in v.casters.iter().enumerate() {
                    if let Some(b) = view.boxes.get(c.object).copied().flatten() {
                        if cull::queryable(&scene.lights[light.light()], &b) {
                            cull::box_triangles(&b, &mut culling.vertices);
                            culling.boxes.push((light.light(), i));
                        }
                    }
                }
            }
        }
        streams.blockers.fill(ctx, &culling.vertices)?;
        Ok(culling)
    }

    /// The frame-sized targets and per-light images the lights' passes need, before the scene
    /// is uploaded: the hybrid's targets, every shadowed light's visibility image, the
    /// ray-traced hybrid's ray list and each hybrid light's depth bounds.
    pub fn prepare_targets(
        &mut self,
        ctx: &Context,
        lights: &[LightFrame],
        visibility: &mut VisibilityPass,
        retired: &mut Retired,
    ) -> RenderResult<()> {
        if lights.iter().any(LightFrame::hybrid) {
            let masked_depth = self.mask == MaskKind::DepthBounds;
            let (width, height) = (self.setup.width, self.setup.height);
            self.hybrid.prepare(ctx, width, height, masked_depth, retired)?;
        }
        let shadowed: Vec<bool> = lights.iter().map(LightFrame::may_shadow).collect();
        visibility.keep(ctx, &shadowed, retired)?;
        let rays: Vec<(usize, &Image)> = lights
            .iter()
            .filter(|l| l.hybrid_rays())
            .map(|l| Ok((l.light(), &visibility.light(l.light())?.image)))
            .collect::<RenderResult<_>>()?;
        if let (Some(h), false) = (&mut self.hybrid_rays, rays.is_empty()) {
            let (width, height, counted) = (self.setup.width, self.setup.height, self.setup.own);
            h.prepare(ctx, width, height, &rays, counted, retired)?;
        }
        let keep: Vec<bool> = lights.iter().map(LightFrame::hybrid).collect();
        self.hybrid.bounds.keep_only(&keep, retired);
        for light in lights.iter().filter(|l| l.hybrid()) {
            if let Some(map) = light.map() {
                self.hybrid.bounds.prepare(ctx, light.light(), map.resolution, map.views.kind, retired)?;
            }
        }
        Ok(())
    }

    /// What the scene's upload tells the techniques: the hybrid's bounds read its meshes.
    pub fn bind_geometry(
        &mut self,
        ctx: &Context,
        gpu: &GpuScene,
        adjacency: &[Arc<Adjacency>],
        lights: &[LightFrame],
        retired: &mut Retired,
    ) -> RenderResult<()> {
        if lights.iter().any(LightFrame::hybrid) {
            self.hybrid.bounds.bind_geometry(ctx, gpu, adjacency, retired)?;
        }
        Ok(())
    }

    /// Each light's shadow parameters as the scene's light buffer carries them (its map's kind,
    /// first view and bias; zero without a map).
    pub fn gpu_shadows(lights: &[LightFrame]) -> Vec<GpuShadow> {
        lights.iter().map(|l| l.map().map_or_else(GpuShadow::default, |m| m.shadow)).collect()
    }
}
