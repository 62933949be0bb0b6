//! `Technique::Auto`: per light and frame, the cheapest technique that delivers the accuracy
//! asked for ([`AutoPolicy`]). Two questions, in order:
//!
//! 1. **Is a shadow map accurate enough?** With [`AutoAccuracy::Texel`] (the default), yes when
//!    a texel of the light's map projects no larger than a pixel on every visible receiver
//!    (Stamminger–Drettakis' ratio, Chan–Durand §6.3). With [`AutoAccuracy::Exact`], never.
//! 2. **Which exact technique costs least?** A one-parameter cost model, measured
//!    (`docs/results.md`, "Ray-traced shadows on the plane"): shadow volumes cost their fill,
//!    which grows with the casters' triangles (every silhouette edge is a quad across the
//!    screen: 15 volume fragments per pixel on `cage`, 128 on `tree`); shadow rays cost about
//!    log(triangles) node visits per receiver pixel. Both scale with the pixels, so where one
//!    overtakes the other depends on the casters' triangles alone:
//!    [`AutoPolicy::ray_tracing_above`]. Below it the volumes, above it the rays — on a device
//!    where the map classifies first ([`AutoPolicy::classify_first`]) the hybrid and the
//!    ray-traced hybrid, which run them only at the pixels the map cannot decide.

use super::PlanInput;
use crate::reach;
use crate::shadow_map::{frustum, texels};
use glam::{Mat4, Vec4Swizzles};
use umbra_scene::{Scene, Technique};
use umbra_vk::Capabilities;

/// What `auto` must deliver.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum AutoAccuracy {
    /// A shadow map wherever its texels are no larger than the pixels they shadow, an exact
    /// technique elsewhere.
    #[default]
    Texel,
    /// Shadow volumes' accuracy or better on every light: never a shadow map.
    Exact,
}

/// How `auto` chooses ([`crate::RendererDesc::auto`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AutoPolicy {
    /// The accuracy every `auto` light must have.
    pub accuracy: AutoAccuracy,
    /// Triangles of the casters a light reaches above which its exact shadows are ray traced
    /// rather than given shadow volumes: where the model's two costs cross.
    /// [`AutoPolicy::RAY_TRACING_ABOVE`] by default.
    pub ray_tracing_above: usize,
    /// Let a shadow map classify first, and run volumes or rays only at its uncertain pixels
    /// (the hybrid, the ray-traced hybrid). Pays where fill is what costs and masked fragments
    /// are rejected before shading (Chan–Durand's premise: a GPU with `depthBounds`); on CPU
    /// rasterizers the classification is one more pass over every pixel, measured slower than
    /// plain volumes or rays on every sweep scene but one.
    pub classify_first: bool,
}

impl AutoPolicy {
    /// The crossover measured on lavapipe at 512×384 and 1024×768: shadow volumes faster on
    /// `cubes` and `cage` (11.7 k and 12.2 k triangles, 0.76× and 0.46× the rays' time), rays
    /// on `tree` and the bunnies (39 k to 1.1 M, 0.55×–0.79× the volumes'); interpolated in
    /// log(triangles) between `cubes` and `tree`, rounded. SwiftShader, whose fragment shaders
    /// walk the BVH slowly, crosses over near 250 k (four bunnies).
    pub const RAY_TRACING_ABOVE: usize = 20_000;

    /// The policy for a device: texel accuracy, the measured crossover, and classification
    /// first on a GPU (not a CPU rasterizer) with `depthBounds`.
    pub fn for_device(caps: &Capabilities) -> Self {
        Self {
            accuracy: AutoAccuracy::Texel,
            ray_tracing_above: Self::RAY_TRACING_ABOVE,
            classify_first: caps.depth_bounds && caps.device_type != "cpu",
        }
    }

    /// The exact technique for casters of `triangles` triangles, and why.
    fn exact(&self, triangles: usize) -> (Technique, String) {
        let rays = triangles > self.ray_tracing_above;
        let technique = match (rays, self.classify_first) {
            (false, false) => Technique::ShadowVolume,
            (false, true) => Technique::Hybrid,
            (true, false) => Technique::RayTraced,
            (true, true) => Technique::HybridRt,
        };
        let side = if rays { "above" } else { "at most" };
        let why = format!(
            "{}: {triangles} caster triangles in reach, {side} the {} where rays overtake volumes",
            technique.name(),
            self.ray_tracing_above
        );
        (technique, why)
    }
}

/// `auto`'s choice for light `light` under `policy`, and why. The texel ratio is taken at a
/// grid of points through each receiver's box (those in view and in the light's reach),
/// ignoring surface orientation.
pub(crate) fn choose(
    scene: &Scene,
    light: usize,
    input: &PlanInput<'_>,
    view_proj: &Mat4,
    policy: &AutoPolicy,
) -> (Technique, String) {
    let l = &scene.lights[light];
    let Some(views) = frustum::fit(l, scene, input.boxes, *view_proj) else {
        return (Technique::ShadowMap, "shadow_map: no caster can shadow a visible receiver".into());
    };
    let exact = || policy.exact(caster_triangles(scene, light, input));
    if policy.accuracy == AutoAccuracy::Exact {
        return exact();
    }
    let seen = texels::Seen { view: input.view, height: input.size.1 };
    let resolution = l
        .shadow_map_size
        .or(input.map_resolution)
        .unwrap_or_else(|| texels::resolution_from_frame(&views, seen, input.size.0));
    match worst_texel(scene, light, input, &views.views, resolution) {
        Some((ratio, o)) if ratio > 1.0 => {
            let (technique, why) = exact();
            let name = &scene.objects[o].name;
            let texel = format!("a {resolution}² map's texel covers up to {ratio:.2} pixels on {name:?} (Stamminger–Drettakis ratio > 1)");
            (technique, format!("{why}; {texel}"))
        }
        Some((ratio, _)) => (
            Technique::ShadowMap,
            format!(
                "shadow_map: a {resolution}² map's texel covers at most {ratio:.2} pixels on every visible receiver"
            ),
        ),
        None => (Technique::ShadowMap, "shadow_map: no visible receiver it reaches".into()),
    }
}

/// The largest ratio of a map texel to a pixel over the visible receivers light `light`
/// reaches, and the receiver where it is.
fn worst_texel(
    scene: &Scene,
    light: usize,
    input: &PlanInput<'_>,
    views: &[Mat4],
    resolution: u32,
) -> Option<(f32, usize)> {
    /// Grid points per box side.
    const SAMPLES: usize = 6;
    let l = &scene.lights[light];
    let seen = texels::Seen { view: input.view, height: input.size.1 };
    let reached = scene.objects.iter().enumerate().filter_map(|(o, object)| {
        let b = input.boxes.get(o).copied().flatten()?;
        (object.receives_shadows && reach::light_reaches(l, &b, 0.0).is_ok()).then_some((o, b))
    });
    let mut worst: Option<(f32, usize)> = None;
    seen.for_grid(reached, SAMPLES, |o, p| {
        let lit = l.bounded_range().is_none_or(|r| p.distance(l.position.xyz()) < r);
        let Some(texel) = texels::texel_at(views, p, resolution).filter(|_| lit) else { return };
        let ratio = texel / seen.pixel_at(p);
        if worst.is_none_or(|(w, _)| ratio > w) {
            worst = Some((ratio, o));
        }
    });
    worst
}

/// Triangles of the shadow casters light `light` reaches (in view or not: a caster outside
/// the view can shadow what is in it).
fn caster_triangles(scene: &Scene, light: usize, input: &PlanInput<'_>) -> usize {
    let l = &scene.lights[light];
    scene
        .objects
        .iter()
        .enumerate()
        .filter(|(o, object)| {
            object.casts_shadows
                && input.boxes.get(*o).copied().flatten().is_some_and(|b| reach::light_reaches(l, &b, 0.0).is_ok())
        })
        .filter_map(|(_, object)| scene.meshes.get(object.mesh))
        .map(umbra_scene::Mesh::triangle_count)
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn policy(classify_first: bool) -> AutoPolicy {
        AutoPolicy { accuracy: AutoAccuracy::Exact, ray_tracing_above: 1000, classify_first }
    }

    #[test]
    fn the_exact_choice_follows_the_triangles_and_the_device() {
        assert_eq!(policy(false).exact(1000).0, Technique::ShadowVolume);
        assert_eq!(policy(false).exact(1001).0, Technique::RayTraced);
        assert_eq!(policy(true).exact(10).0, Technique::Hybrid);
        assert_eq!(policy(true).exact(5000).0, Technique::HybridRt);
        assert!(policy(false).exact(5000).1.contains("5000 caster triangles in reach, above the 1000"));
    }

    #[test]
    fn classification_first_only_on_a_gpu_with_depth_bounds() {
        let caps = |device_type: &str, depth_bounds| Capabilities {
            device_type: device_type.into(),
            depth_bounds,
            ..Capabilities::default()
        };
        assert!(AutoPolicy::for_device(&caps("discrete", true)).classify_first);
        assert!(!AutoPolicy::for_device(&caps("discrete", false)).classify_first);
        assert!(!AutoPolicy::for_device(&caps("cpu", true)).classify_first);
        assert_eq!(AutoPolicy::for_device(&caps("cpu", true)).accuracy, AutoAccuracy::Texel);
    }
}
