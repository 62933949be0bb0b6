//! Each light's descriptor sets (its maps as the lighting passes sample them), from the
//! renderer's per-frame arena, and, with diagnostics or `read_visibility`, its readbacks, kept
//! while they fit.

use super::lights::{LightBindings, LightFrame, LightReadbacks, LightSets};
use super::Renderer;
use crate::diagnostics::{ClassReadback, DiagnosticReadback};
use crate::technique::needs;
use crate::visibility::VisibilityReadback;
use crate::RenderResult;

impl Renderer {
    /// Binds every light of `lights` (after their maps were prepared): the arena is reset, so
    /// the sets of the frame before are gone.
    pub(super) fn bind(&mut self, lights: &[LightFrame]) -> RenderResult<Vec<LightSets>> {
        let count = lights.iter().map(|l| u32::from(l.plan.recorded) + u32::from(l.edges.is_some())).sum();
        self.slot.sets.reset(&self.shadow_set_layout, count)?;
        self.readbacks.resize_with(lights.len(), LightReadbacks::default);
        self.readbacks.truncate(lights.len());
        lights.iter().map(|light| self.bind_light(light)).collect()
    }

    fn bind_light(&mut self, light: &LightFrame) -> RenderResult<LightSets> {
        let (l, plan) = (light.light(), &light.plan);
        let layout = &self.shadow_set_layout;
        let mut out = LightSets::default();
        let has_map = light.map.as_ref().is_some_and(|m| m.depth).then_some(l);
        if plan.recorded {
            let technique_image = match (light.hybrid(), self.hybrid.classes()) {
                (true, Some(classes)) => classes,
                _ => self.silhouette_map.image(light.edges.map(|_| l)),
            };
            let bounds = self.hybrid.bounds.image(light.hybrid().then_some(l));
            let set = self.shadow_map.descriptor_set(&mut self.slot.sets, layout, has_map, technique_image, bounds)?;
            out.shadow_set = Some(set);
        }
        if light.edges.is_some() {
            // Pass 2 reads the depth map raw while it writes the silhouette map, which its set
            // must not bind: the placeholder stands in.
            let (placeholder, bounds) = (self.silhouette_map.image(None), self.hybrid.bounds.image(None));
            out.depth_set =
                Some(self.shadow_map.descriptor_set(&mut self.slot.sets, layout, Some(l), placeholder, bounds)?);
        }
        self.keep_readbacks(light)?;
        Ok(out)
    }

    /// Light `light`'s diagnostic readbacks, made only when missing or no longer fitting.
    fn keep_readbacks(&mut self, light: &LightFrame) -> RenderResult<()> {
        let (ctx, l) = (&self.ctx, light.light());
        let (width, height) = (self.desc.width, self.desc.height);
        let kept = &mut self.readbacks[l];
        let silhouette = self.desc.diagnostics && light.edges.is_some();
        let map = self.silhouette_map.image(Some(l));
        match (silhouette, &kept.silhouette) {
            (true, Some(r)) if r.fits(map) => {}
            (true, _) => kept.silhouette = Some(DiagnosticReadback::new(ctx, width, height, map)?),
            (false, _) => kept.silhouette = None,
        }
        let classified = light.plan.recorded && needs(light.plan.technique).classified;
        // The stencil too where it decides pixels: the hybrid's, a shadow-volume light's.
        let stencil = light.volumes.is_some();
        // The ray-traced hybrid's silhouette pixels are decided by rays, which leave no
        // classification to read back (as ray-traced lights).
        let hybrid = light.hybrid() && !light.rays;
        match (self.desc.diagnostics && (hybrid || classified), &kept.classes) {
            (true, Some(r)) if r.stencil.is_some() == stencil => {}
            (true, _) => kept.classes = Some(ClassReadback::new(ctx, width, height, stencil)?),
            (false, _) => kept.classes = None,
        }
        match (self.desc.read_visibility && light.may_shadow(), &kept.visibility) {
            (true, Some(_)) => {}
            (true, None) => kept.visibility = Some(VisibilityReadback::new(ctx, width, height)?),
            (false, _) => kept.visibility = None,
        }
        Ok(())
    }

    /// This frame's sets and readbacks of every light, resolved.
    pub(super) fn bindings(&self, sets: &[LightSets]) -> Vec<LightBindings<'_>> {
        sets.iter()
            .zip(&self.readbacks)
            .map(|(s, r)| LightBindings {
                shadow_set: s.shadow_set.and_then(|i| self.slot.sets.get(i)),
                depth_set: s.depth_set.and_then(|i| self.slot.sets.get(i)),
                silhouette_readback: r.silhouette.as_ref(),
                class_readback: r.classes.as_ref(),
                visibility_readback: r.visibility.as_ref(),
            })
            .collect()
    }
}
