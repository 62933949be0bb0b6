//! Each light's descriptor sets (its maps as the lighting passes sample them) and, with
//! diagnostics, its readbacks.

use super::lights::{LightBindings, LightFrame};
use super::Renderer;
use crate::diagnostics::{ClassReadback, DiagnosticReadback};
use crate::technique::needs;
use crate::RenderResult;

impl Renderer {
    /// Binds every light of `lights` (after their maps were prepared).
    pub(super) fn bind(&self, lights: &[LightFrame]) -> RenderResult<Vec<LightBindings>> {
        lights.iter().map(|light| self.bind_light(light)).collect()
    }

    fn bind_light(&self, light: &LightFrame) -> RenderResult<LightBindings> {
        let (l, plan) = (light.light(), &light.plan);
        let (ctx, layout) = (&self.ctx, &self.shadow_set_layout);
        let (width, height) = (self.desc.width, self.desc.height);
        let mut out = LightBindings::default();
        let has_map = light.map.is_some().then_some(l);
        if plan.recorded {
            let technique_image = match (light.hybrid(), self.hybrid.classes()) {
                (true, Some(classes)) => classes,
                _ => self.silhouette_map.image(light.edges.map(|_| l)),
            };
            let set = self.shadow_map.descriptor_set(ctx, layout, has_map, light.hybrid(), technique_image)?;
            out.shadow_set = Some(set);
        }
        if light.edges.is_some() {
            // Pass 2 reads the depth map raw while it writes the silhouette map, which its set
            // must not bind: the placeholder stands in.
            let placeholder = self.silhouette_map.image(None);
            out.depth_set = Some(self.shadow_map.descriptor_set(ctx, layout, Some(l), false, placeholder)?);
            if self.desc.diagnostics {
                let map = self.silhouette_map.image(Some(l));
                out.silhouette_readback = Some(DiagnosticReadback::new(ctx, width, height, map)?);
            }
        }
        let classified = plan.recorded && needs(plan.technique).classified;
        if self.desc.diagnostics && (light.hybrid() || classified) {
            // The stencil too where it decides pixels: the hybrid's, a shadow-volume light's.
            let stencil = light.volumes.is_some();
            out.class_readback = Some(ClassReadback::new(ctx, width, height, stencil)?);
        }
        Ok(out)
    }
}
