//! Each light's descriptor sets (its maps as the lighting passes sample them), from the
//! frame slot's arena, and, with diagnostics or `read_visibility`, its readbacks, kept while
//! they fit.

use super::light::{LightFrame, LightReadbacks, LightSets, Prepared};
use super::Techniques;
use crate::diagnostics::{ClassReadback, DiagnosticReadback};
use crate::technique::needs;
use crate::visibility::VisibilityReadback;
use crate::RenderResult;
use umbra_vk::{Context, DescriptorArena, DescriptorSetLayout};

/// Where a frame's sets and readbacks go.
pub(crate) struct Binding<'a> {
    pub ctx: &'a Context,
    /// The frame slot's arena, reset here, and the layout of its sets.
    pub sets: &'a mut DescriptorArena,
    pub layout: &'a DescriptorSetLayout,
    /// Per light, its readbacks as the frames before left them.
    pub readbacks: &'a mut Vec<LightReadbacks>,
}

impl Techniques {
    /// Binds every light of `lights` (after their maps were prepared): the arena is reset, so
    /// the sets of the frame before are gone.
    pub fn bind(&self, b: Binding<'_>, lights: &[LightFrame]) -> RenderResult<Vec<LightSets>> {
        let count = lights.iter().map(|l| u32::from(l.plan.recorded) + u32::from(l.edges().is_some())).sum();
        b.sets.reset(b.layout, count)?;
        b.readbacks.resize_with(lights.len(), LightReadbacks::default);
        b.readbacks.truncate(lights.len());
        let (ctx, arena, layout) = (b.ctx, b.sets, b.layout);
        let readbacks = b.readbacks;
        lights.iter().map(|light| self.bind_light(ctx, arena, layout, &mut readbacks[light.light()], light)).collect()
    }

    fn bind_light(
        &self,
        ctx: &Context,
        arena: &mut DescriptorArena,
        layout: &DescriptorSetLayout,
        kept: &mut LightReadbacks,
        light: &LightFrame,
    ) -> RenderResult<LightSets> {
        let (l, plan) = (light.light(), &light.plan);
        let mut out = LightSets::default();
        let has_map = light.map_drawn().then_some(l);
        if plan.recorded {
            // Binding 3: the hybrids' classes, a silhouette map, or its placeholder; binding 4:
            // the hybrids' depth bounds, or their placeholder.
            let (technique_image, bounds) = match (&light.prepared, self.hybrid.classes()) {
                (Prepared::Hybrid(..) | Prepared::HybridRays(_), classes) => {
                    let image = classes.unwrap_or_else(|| self.silhouette_map.image(None));
                    (image, self.hybrid.bounds.sampled(Some(l)))
                }
                (Prepared::SilhouetteMap(..), _) => {
                    (self.silhouette_map.image(Some(l)), self.hybrid.bounds.sampled(None))
                }
                (Prepared::Nothing | Prepared::Map(_) | Prepared::Volumes(_) | Prepared::Rays, _) => {
                    (self.silhouette_map.image(None), self.hybrid.bounds.sampled(None))
                }
            };
            let set = self.shadow_map.descriptor_set(arena, layout, has_map, technique_image, bounds)?;
            out.shadow_set = Some(set);
        }
        if light.edges().is_some() {
            // Pass 2 reads the depth map raw while it writes the silhouette map, which its set
            // must not bind: the placeholder stands in.
            let (placeholder, bounds) = (self.silhouette_map.image(None), self.hybrid.bounds.sampled(None));
            out.depth_set = Some(self.shadow_map.descriptor_set(arena, layout, Some(l), placeholder, bounds)?);
        }
        self.keep_readbacks(ctx, kept, light)?;
        Ok(out)
    }

    /// Light `light`'s diagnostic readbacks, made only when missing or no longer fitting.
    fn keep_readbacks(&self, ctx: &Context, kept: &mut LightReadbacks, light: &LightFrame) -> RenderResult<()> {
        let l = light.light();
        let (width, height) = (self.setup.width, self.setup.height);
        let silhouette = self.setup.diagnostics && light.edges().is_some();
        let map = self.silhouette_map.image(Some(l));
        match (silhouette, &kept.silhouette) {
            (true, Some(r)) if r.fits(map) => {}
            (true, _) => kept.silhouette = Some(DiagnosticReadback::new(ctx, width, height, map)?),
            (false, _) => kept.silhouette = None,
        }
        let classified = light.plan.recorded && needs(light.plan.technique).classified;
        // The stencil too where it decides pixels: the hybrid's, a shadow-volume light's.
        let stencil = light.volumes().is_some();
        // The ray-traced hybrid's silhouette pixels are decided by rays, which leave no
        // classification to read back (as ray-traced lights).
        let hybrid = light.hybrid() && !light.rays();
        match (self.setup.diagnostics && (hybrid || classified), &kept.classes) {
            (true, Some(r)) if r.stencil.is_some() == stencil => {}
            (true, _) => kept.classes = Some(ClassReadback::new(ctx, width, height, stencil)?),
            (false, _) => kept.classes = None,
        }
        match (self.setup.read_visibility && light.may_shadow(), &kept.visibility) {
            (true, Some(_)) => {}
            (true, None) => kept.visibility = Some(VisibilityReadback::new(ctx, width, height)?),
            (false, _) => kept.visibility = None,
        }
        Ok(())
    }
}
