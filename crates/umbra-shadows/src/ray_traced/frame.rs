//! The pass of a ray-traced light in the frame graph: `visibility N (rays)`, one shadow ray
//! per receiver pixel through the scene's BVH, written into the light's visibility image.

use super::pass::{RayPass, SlotRays};
use crate::frame::{PassId, Stage};
use crate::light_surfaces::LightSurfaces;
use crate::visibility::VisibilityTarget;

/// Light `s`'s `visibility N (rays)` through the frame slot's BVH set `rays` (an error when the
/// pass records without it).
pub(crate) fn declare_light<'a>(
    stage: &mut Stage<'a>,
    pass: &'a RayPass,
    rays: Option<&'a SlotRays>,
    s: LightSurfaces<'a, 'a>,
    target: VisibilityTarget<'a>,
) {
    stage.pass(PassId::RayVisibility(s.light as usize), &target.uses(), move |cx| {
        target.begin(cx.rec);
        pass.record(cx, rays, s)?;
        cx.rec.end_rendering();
        Ok(())
    });
}
