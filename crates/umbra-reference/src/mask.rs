//! Per-light shadow masks: for every pixel, whether the light's contribution is shadowed, lit,
//! or not in question (no surface, a surface that does not receive shadows, a surface facing
//! away from the light or outside a spot's cone). The exact one comes from shadow rays; a
//! technique's comes from its classification view (`umbra_shadows::LightDiagnostics`).

use crate::bvh::SceneBvh;
use crate::surfaces::{Surface, SurfaceImage};
use crate::{ReferenceError, ReferenceResult};
use glam::{Vec3, Vec4};
use rayon::prelude::*;
use std::path::Path;
use umbra_scene::{Light, Scene};

/// Shadow-ray origins move off the surface by this much per unit of the position's largest
/// coordinate (at least this much in absolute terms): f32 positions carry a relative error of
/// about 6e-8, so 1e-5 clears it by two orders of magnitude while staying far below a pixel.
pub const RAY_OFFSET_SCALE: f32 = 1e-5;

/// One light's shadow decision per pixel, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct ShadowMask {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `Some(true)` shadowed, `Some(false)` lit, `None` where the light's shadow is not in
    /// question.
    pub shadowed: Vec<Option<bool>>,
}

impl ShadowMask {
    /// A mask from its values; `shadowed.len()` must be `width * height`.
    pub fn new(width: u32, height: u32, shadowed: Vec<Option<bool>>) -> ReferenceResult<Self> {
        let n = width as usize * height as usize;
        if shadowed.len() != n {
            return Err(ReferenceError::SizeMismatch {
                what: "shadow mask",
                got: (shadowed.len(), 1),
                expected: (n, 1),
            });
        }
        Ok(Self { width, height, shadowed })
    }

    /// The exact mask of light `light`: a shadow ray from every pixel's surface towards the
    /// light (to infinity for a directional light, w = 0), blocked by any triangle of a
    /// shadow-casting object. Rays leave from the surface moved along its normal by
    /// [`RAY_OFFSET_SCALE`] times the position's magnitude. Computed on every rayon thread.
    pub fn reference(scene: &Scene, bvh: &SceneBvh, light: usize, surfaces: &SurfaceImage) -> ReferenceResult<Self> {
        let l = scene.lights.get(light).ok_or(ReferenceError::NoSuchLight { light, lights: scene.lights.len() })?;
        let shadowed = surfaces
            .pixels
            .par_iter()
            .map(|s| {
                let s = s.as_ref()?;
                let receives = scene.objects.get(s.object).is_some_and(|o| o.receives_shadows);
                if !receives {
                    return None;
                }
                shadow_state(l, bvh, s)
            })
            .collect();
        Ok(Self { width: surfaces.width, height: surfaces.height, shadowed })
    }

    /// The value at `(x, y)`.
    pub fn get(&self, x: u32, y: u32) -> Option<bool> {
        self.shadowed[(y * self.width + x) as usize]
    }

    /// Pixels shadowed, lit.
    pub fn counts(&self) -> (u64, u64) {
        let shadowed = self.shadowed.iter().filter(|s| **s == Some(true)).count() as u64;
        let lit = self.shadowed.iter().filter(|s| **s == Some(false)).count() as u64;
        (shadowed, lit)
    }

    /// Writes the mask as a float EXR: R = G = B = 1 lit, 0 shadowed; A = 1 where the pixel
    /// is in question, 0 elsewhere.
    pub fn save_exr(&self, path: &Path) -> ReferenceResult<()> {
        exr::prelude::write_rgba_file(path, self.width as usize, self.height as usize, |x, y| {
            match self.get(x as u32, y as u32) {
                Some(s) => {
                    let v = if s { 0.0 } else { 1.0 };
                    (v, v, v, 1.0)
                }
                None => (0.0, 0.0, 0.0, 0.0),
            }
        })
        .map_err(|e| ReferenceError::Output { path: path.to_owned(), message: e.to_string() })
    }
}

/// The exact state of one surface point for `light`: `None` where the light does not reach it
/// (the surface faces away, or lies outside a spot's cone), else whether the shadow ray from
/// it (offset by [`RAY_OFFSET_SCALE`]·|p| along the normal) meets a caster before the light.
pub fn shadow_state(light: &Light, bvh: &SceneBvh, s: &Surface) -> Option<bool> {
    let (origin, dir, t_max) = shadow_ray(light, s)?;
    Some(bvh.occluded(origin, dir, t_max))
}

/// The shadow-casting triangles (indices into [`SceneBvh::triangles`]) the shadow ray of
/// [`shadow_state`] meets, or `None` where `light` does not reach `s`: empty exactly when
/// `shadow_state` says lit.
pub fn shadow_blockers(light: &Light, bvh: &SceneBvh, s: &Surface) -> Option<Vec<usize>> {
    let (origin, dir, t_max) = shadow_ray(light, s)?;
    Some(bvh.blockers(origin, dir, t_max))
}

/// The shadow ray of `s` (origin offset along the normal by [`RAY_OFFSET_SCALE`]·|p|, unit
/// direction, length: infinite for a directional light), or `None` where `light` does not
/// reach it.
pub fn shadow_ray(light: &Light, s: &Surface) -> Option<(Vec3, Vec3, f32)> {
    let (dir, distance) = towards(light.position, s.position);
    if !reaches(light, s, dir) {
        return None;
    }
    let offset = RAY_OFFSET_SCALE * s.position.abs().max_element().max(1.0);
    let t_max = if light.position.w == 0.0 { f32::INFINITY } else { distance - offset };
    Some((s.position + s.normal * offset, dir, t_max))
}

/// The unit direction from `p` towards a homogeneous light position, and the distance (infinite
/// for w = 0).
pub fn towards(light: Vec4, p: Vec3) -> (Vec3, f32) {
    if light.w == 0.0 {
        (light.truncate().normalize(), f32::INFINITY)
    } else {
        let to = light.truncate() / light.w - p;
        let d = to.length();
        (to / d, d)
    }
}

/// Whether `light` reaches surface `s` at all: it faces the light, lies within its range and
/// inside a spot's outer cone. The lighting passes decide the same with the interpolated normal; the comparison
/// only counts pixels both call reached.
fn reaches(light: &Light, s: &Surface, dir: Vec3) -> bool {
    if s.normal.dot(dir) <= 0.0 {
        return false;
    }
    if light.bounded_range().is_some_and(|r| s.position.distance(light.position.truncate()) >= r) {
        return false;
    }
    match light.spot {
        Some(spot) => (-dir).dot(spot.direction.normalize()) > spot.outer_deg.to_radians().cos(),
        None => true,
    }
}

/// Inverse-square falloff for point and spot lights, the range window and a spot's smooth cone
/// (as `shaders-glsl/forward/lambert.glsl`).
fn falloff(light: &Light, dir: Vec3, distance: f32) -> f32 {
    let mut f = if light.position.w == 0.0 { 1.0 } else { 1.0 / (distance * distance) };
    if let Some(range) = light.bounded_range() {
        let q = (distance / range).powi(4);
        f *= (1.0 - q).clamp(0.0, 1.0).powi(2);
    }
    if let Some(spot) = light.spot {
        let (outer, inner) = (spot.outer_deg.to_radians().cos(), spot.inner_deg.to_radians().cos());
        let t = (((-dir).dot(spot.direction.normalize()) - outer) / (inner - outer)).clamp(0.0, 1.0);
        f *= t * t * (3.0 - 2.0 * t);
    }
    f
}

/// The pure ray-cast render, for sanity checks: ambient plus every light's Lambert term
/// (falloff as the renderer's) where its shadow ray is free, as RGBA8 row 0 at the top.
pub fn ray_cast_image(scene: &Scene, bvh: &SceneBvh, width: u32, height: u32) -> Vec<u8> {
    let surfaces = SurfaceImage::ray_cast(scene, bvh, width, height);
    let masks: Vec<Option<ShadowMask>> =
        (0..scene.lights.len()).map(|l| ShadowMask::reference(scene, bvh, l, &surfaces).ok()).collect();
    let bg = scene.background;
    surfaces
        .pixels
        .iter()
        .enumerate()
        .flat_map(|(i, s)| {
            let colour = match s {
                None => bg,
                Some(s) => {
                    let albedo = scene.objects.get(s.object).map_or(Vec3::ONE, |o| o.albedo);
                    let mut c = albedo * scene.ambient;
                    for (l, mask) in scene.lights.iter().zip(&masks) {
                        let Some(mask) = mask else { continue };
                        let (dir, distance) = towards(l.position, s.position);
                        let reached = reaches(l, s, dir);
                        let blocked = mask.shadowed[i] == Some(true);
                        if reached && !blocked {
                            c += albedo * l.radiance() * s.normal.dot(dir) * falloff(l, dir, distance);
                        }
                    }
                    c
                }
            };
            let byte = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
            [byte(colour.x), byte(colour.y), byte(colour.z), 255]
        })
        .collect()
}
