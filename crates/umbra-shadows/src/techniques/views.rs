//! A frame's views, before any light's shadows: per recorded light its shadow map, the
//! hybrid's depth bounds and a silhouette map's points; blocker culling's queries against the
//! hybrid's maps; and every light's volumes settled once culling dropped casters.

use super::inputs::FrameInputs;
use super::light::{LightFrame, Prepared};
use super::Techniques;
use crate::frame::{PassId, QueryId, Stage, Use};
use crate::hybrid::cull::CullingPlan;
use crate::hybrid::pass::CullingMap;
use crate::plan::{tally, CullReason};
use crate::RenderResult;
use umbra_scene::Scene;
use umbra_vk::{Buffer, ImageState};

use ImageState::{ColorAttachment as Color, DepthStencilAttachment as Depth, FragmentRead as Read};

impl Techniques {
    /// Per recorded light with a map: its shadow map, the hybrid's depth bounds, and a
    /// silhouette map's points.
    pub fn declare_views<'a>(&'a self, stage: &mut Stage<'a>, f: FrameInputs<'a>) -> RenderResult<()> {
        for light in f.lights.iter().filter(|l| l.plan.recorded) {
            let l = light.light();
            let Some(map) = light.map() else { continue };
            if map.depth {
                let image = self.shadow_map.image(l)?;
                stage.pass(PassId::ShadowMap(l), &[Use::Image(image, Depth)], move |cx| {
                    self.shadow_map.record(cx, f.layout, f.gpu, f.scene, l, map)
                });
            }
            if light.hybrid() {
                let bounds = self.hybrid.bounds.image(Some(l));
                stage.pass(PassId::HybridBounds(l), &[Use::Image(bounds, Color)], move |cx| {
                    self.hybrid.bounds.record(cx, f.gpu, f.scene, l, &map.views);
                    Ok(())
                });
            }
            let (Some(e), Some(depth_set)) = (light.edges(), &f.bindings[l].depth_set) else { continue };
            let (target, image) = (self.silhouette_map.image(Some(l)), self.shadow_map.image(l)?);
            stage.pass(PassId::SilhouetteMap(l), &[Use::Image(target, Color), Use::Image(image, Read)], move |cx| {
                let map_kind = (map.views.kind, map.resolution);
                self.silhouette_map.record_points(cx.rec, f.layout, f.gpu, depth_set, l, f.edges, e, map_kind, cx.log)
            });
        }
        Ok(())
    }

    /// Blocker culling: every hybrid light's boxes against its map, a query per box (in
    /// `culling.boxes` order, from the returned query on).
    pub fn declare_culling<'a>(
        &'a self,
        stage: &mut Stage<'a>,
        f: FrameInputs<'a>,
        culling: &CullingPlan,
        boxes: &'a Buffer,
    ) -> RenderResult<QueryId> {
        let first = stage.queries(culling.queries());
        let mut ranges = Vec::new();
        let mut start = 0;
        for light in f.lights.iter().filter(|l| l.hybrid()) {
            let l = light.light();
            let n = culling.boxes.iter().filter(|(b, _)| *b == l).count() as u32;
            if let (Some(map), true) = (light.map(), n > 0) {
                let (image, view) = (self.shadow_map.image(l)?, map.shadow.first_view);
                ranges.push(CullingMap { map: image, boxes: start..start + n, view });
                start += n;
            }
        }
        let uses: Vec<Use> = ranges.iter().map(|m| Use::Image(m.map, ImageState::DepthStencilReadOnly)).collect();
        stage.pass(PassId::BlockerCulling, &uses, move |cx| {
            self.hybrid.record_culling(cx, f.layout, f.gpu, boxes, &ranges, first);
            Ok(())
        });
        Ok(first)
    }

    /// Drops the casters blocker culling found hidden (`visible`: each box's samples, in
    /// `culling.boxes` order) from their lights' volumes.
    pub fn apply_culling(&self, lights: &mut [LightFrame], culling: &mut CullingPlan, visible: &[u64]) {
        for (l, caster) in culling.apply(visible) {
            if let Some(v) = lights[l].volumes_mut() {
                v.casters.remove(caster);
            }
        }
    }

    /// Every light's volumes once blocker culling (if any) dropped casters: their stencil
    /// batches and report.
    pub fn settle_volumes(&self, scene: &Scene, lights: &mut [LightFrame], culling: &CullingPlan) {
        for light in lights.iter_mut() {
            // Every count at once for a shadow-volume light; the hybrid's under its mask.
            let bits = match &light.prepared {
                Prepared::Hybrid(..) => Some(crate::hybrid::pass::count_bits(self.mask)),
                Prepared::Volumes(_) => Some(crate::shadow_volume::batches::FULL_STENCIL),
                Prepared::Nothing
                | Prepared::Map(_)
                | Prepared::SilhouetteMap(..)
                | Prepared::Rays
                | Prepared::HybridRays(_) => None,
            };
            if let (Some(bits), Some(v)) = (bits, light.volumes_mut()) {
                v.plan_batches(bits);
                let report = v.report(scene);
                light.plan.shadow_volume = Some(report);
            }
            light.culled_blockers = culling.culled(light.light());
            if let Some(n) = light.culled_blockers {
                tally(&mut light.plan.culled, CullReason::HiddenBlocker, n);
            }
        }
    }
}
