//! The frame plan: what each light needs this frame, decided from the scene before anything
//! is recorded. Work that cannot change the image (a light with zero radiance, a scene with
//! nothing to light) is not recorded, and the report says why.
//!
//! This is the seam where shadow techniques plug in: each light carries the technique the
//! scene asked for, and the renderer records that technique's passes for it.

use crate::hybrid::MaskKind;
use crate::{RenderError, RenderResult};
use serde::Serialize;
use umbra_scene::{LightKind, Scene, Technique};

/// The decision for one light.
#[derive(Clone, Debug, Serialize)]
pub struct LightPlan {
    /// Index in `Scene::lights`.
    pub light: usize,
    /// Name from the scene.
    pub name: String,
    /// Directional, point or spot.
    pub kind: LightKind,
    /// The technique its shadows use.
    pub technique: Technique,
    /// Whether any pass is recorded for it.
    pub recorded: bool,
    /// Why not, when `recorded` is false.
    pub skipped_because: Option<String>,
    /// The shadow map rendered for it this frame, if any.
    pub shadow_map: Option<ShadowMapReport>,
    /// Its shadow volumes this frame, if any.
    pub shadow_volume: Option<ShadowVolumeReport>,
    /// Its silhouette map this frame, if any (its depth map is `shadow_map`).
    pub silhouette_map: Option<SilhouetteMapReport>,
    /// The hybrid's figures this frame, if it used one (its map is `shadow_map`, its volumes
    /// `shadow_volume`).
    pub hybrid: Option<HybridReport>,
    /// What the renderer decided beyond the plan (e.g. a shadow map not needed this frame).
    pub note: Option<String>,
}

/// A light's shadow map as rendered in one frame.
#[derive(Clone, Debug, Serialize)]
pub struct ShadowMapReport {
    /// Texels per side (per face for cube maps).
    pub resolution: u32,
    /// Whether it is a cube map (six faces).
    pub cube: bool,
    /// Near distance of its frustum.
    pub near: f32,
    /// Far distance of its frustum.
    pub far: f32,
    /// Objects drawn into it.
    pub casters: usize,
    /// World units per texel along the map's x and y (orthographic maps: directional lights).
    pub texel_size: Option<[f32; 2]>,
    /// World-to-clip matrix of each view (one, or six cube faces in +x, −x, +y, −y, +z, −z
    /// order; Vulkan clip space, depth 0..1): where a world point falls in the map, and how
    /// large a texel is there.
    pub view_proj: Vec<glam::Mat4>,
}

/// A light's silhouette map as rendered in one frame (Sen et al. Table 1's statistics).
#[derive(Clone, Debug, Serialize)]
pub struct SilhouetteMapReport {
    /// Texels per side (the depth map's resolution).
    pub resolution: u32,
    /// Silhouette edges drawn into it.
    pub silhouette_edges: usize,
    /// CPU time to find them (facing and silhouettes of every caster).
    pub cpu_extract_ms: f64,
    /// Pixels of the image whose four depth comparisons disagreed, so the silhouette points
    /// decided them (counted by the diagnostics pass: `RendererDesc::diagnostics`).
    pub silhouette_pixels: Option<u64>,
    /// `silhouette_pixels` over the image's pixel count (Chan–Durand's P).
    pub silhouette_fraction: Option<f64>,
}

/// A hybrid light in one frame (Chan–Durand §5's figures).
#[derive(Clone, Debug, Serialize)]
pub struct HybridReport {
    /// The computation mask used: `depth-bounds`, `stencil` or `none`.
    pub mask: MaskKind,
    /// The lower depth bound with `depth-bounds` (the upper is 1).
    pub depth_bounds_epsilon: Option<f32>,
    /// Pixels whose hardware-PCF result lay strictly between 0 and 1 on a surface facing the
    /// light: the only pixels the volumes decide (an occlusion query on the mask pass).
    pub silhouette_pixels: u64,
    /// `silhouette_pixels` over the image's pixel count (P).
    pub silhouette_fraction: f64,
    /// Casters whose volumes were drawn.
    pub volume_casters: usize,
    /// Casters dropped by blocker culling (§6.3), when it ran.
    pub culled_casters: Option<usize>,
    /// Volume fragments rasterized without any mask (O; with `ShadowVolumeSettings::overdraw`).
    pub volume_fragments: Option<u64>,
    /// Volume fragments the mask let through to the stencil test (with `overdraw`).
    pub masked_volume_fragments: Option<u64>,
    /// GPU time of the masked stencil pass (`hybrid volumes N`).
    pub stencil_gpu_ms: Option<f64>,
}

/// A light's shadow volumes as built and counted in one frame.
#[derive(Clone, Debug, Serialize)]
pub struct ShadowVolumeReport {
    /// Casters with a non-empty volume.
    pub casters: usize,
    /// Casters counted with z-pass.
    pub zpass_casters: usize,
    /// Casters counted with z-fail.
    pub zfail_casters: usize,
    /// Silhouette edges extruded (with multiplicity).
    pub silhouette_edges: usize,
    /// Volume triangles drawn (sides, plus caps for z-fail casters).
    pub volume_triangles: usize,
    /// CPU time to build every caster's volume (facing, silhouettes, caps).
    pub cpu_build_ms: f64,
    /// Rasterized volume fragments (from the overdraw pass's occlusion query), when the
    /// renderer was built with `overdraw`.
    pub volume_fragments: Option<u64>,
    /// Per caster: object index, name and the mode it was counted with.
    pub caster_modes: Vec<CasterMode>,
}

/// The counting mode one caster used.
#[derive(Clone, Debug, Serialize)]
pub struct CasterMode {
    /// Object index.
    pub object: usize,
    /// Object name.
    pub name: String,
    /// `zpass` or `zfail`.
    pub mode: &'static str,
    /// Volume triangles drawn for it.
    pub triangles: usize,
}

/// Why silhouette maps refuse lights that need a cube map.
pub(crate) const SILHOUETTE_CUBE_UNSUPPORTED: &str =
    "silhouette maps need one 2D depth map, and point lights (and spots \
     wider than 80°) use cube maps, whose silhouette texels would need neighbours across faces; use a spot or \
     directional light, or shadow_map / shadow_volume for this light";

/// Decides, per light, what to record.
pub fn plan_lights(scene: &Scene) -> RenderResult<Vec<LightPlan>> {
    scene
        .lights
        .iter()
        .enumerate()
        .map(|(i, l)| {
            let skip = if !l.contributes() {
                Some("zero radiance: cannot change the image")
            } else if scene.objects.is_empty() {
                Some("no objects to light")
            } else {
                None
            };
            if skip.is_none() && l.technique == Technique::SilhouetteMap && l.kind() == LightKind::Point {
                return Err(RenderError::UnsupportedLight {
                    light: i,
                    technique: l.technique,
                    why: SILHOUETTE_CUBE_UNSUPPORTED.into(),
                });
            }
            Ok(LightPlan {
                light: i,
                name: l.name.clone(),
                kind: l.kind(),
                technique: l.technique,
                recorded: skip.is_none(),
                skipped_because: skip.map(str::to_owned),
                shadow_map: None,
                shadow_volume: None,
                silhouette_map: None,
                hybrid: None,
                note: None,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    use umbra_scene::Light;

    #[test]
    fn dark_lights_are_planned_out_with_a_reason() {
        let mut s = umbra_scene::procedural::build("ball").unwrap();
        s.lights.push(Light::point(Vec3::ONE, 0.0));
        let plan = plan_lights(&s).unwrap();
        assert!(plan[0].recorded);
        assert!(!plan[1].recorded);
        assert!(plan[1].skipped_because.as_deref().unwrap().contains("zero radiance"));
    }

    #[test]
    fn silhouette_maps_refuse_point_lights_with_a_reason() {
        let mut s = umbra_scene::procedural::build("ball").unwrap();
        s.lights = vec![Light::point(Vec3::new(0.0, 4.0, 0.0), 10.0)];
        s.lights[0].technique = Technique::SilhouetteMap;
        let err = plan_lights(&s).unwrap_err();
        assert!(matches!(err, RenderError::UnsupportedLight { light: 0, technique: Technique::SilhouetteMap, .. }));
        assert!(err.to_string().contains("cube map"), "{err}");
        s.lights[0] = Light::spot(Vec3::new(0.0, 4.0, 0.0), -Vec3::Y, 20.0, 30.0, 10.0);
        s.lights[0].technique = Technique::SilhouetteMap;
        assert!(plan_lights(&s).is_ok());
    }
}
