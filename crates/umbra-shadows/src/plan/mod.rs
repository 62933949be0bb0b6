//! The frame plan (issue #9): what each light needs this frame, decided from the scene and
//! the camera before anything is recorded. Nothing that cannot change the image is recorded,
//! and the report says what was left out and why:
//!
//! 1. a light with zero radiance, whose range misses the view frustum, or that reaches no
//!    visible object records no pass at all;
//! 2. a light whose technique is `unshadowed`, with no visible receiver that receives shadows,
//!    or with no caster able to shadow one, records its lighting pass only;
//! 3. per caster: objects that do not cast never enter a shadow pass; casters out of the light's
//!    range or cone cannot shadow anything it lights; a caster whose shadow volume misses the
//!    view frustum draws nothing (shadow volumes and the hybrid); the renderer then culls map
//!    casters per view (cube faces) and, with `HybridSettings::cull_blockers`, the hybrid's
//!    hidden blockers (Chan–Durand §6.3);
//! 4. a bounded light's scissor rectangle and depth bounds (Lengyel; Everitt & Kilgard 2003;
//!    McGuire et al., cited in Chan–Durand §2) limit its lighting and stencil passes;
//! 5. `auto` lights get the shadow map when its texels project no larger than a pixel on every
//!    visible receiver (Stamminger–Drettakis' ratio, Chan–Durand §6.3) and the renderer accepts
//!    a map's accuracy, otherwise the exact technique a measured cost model finds cheapest
//!    (`crate::plan::auto`).
//!
//! With `RendererDesc::cull` off every light records every pass of its technique over every
//! caster: the same image, for comparison.
//!
//! This is also the seam where shadow techniques plug in: each light carries the technique it
//! uses, and the renderer records that technique's passes for it.

pub(crate) mod auto;

use crate::hybrid::MaskKind;
use crate::reach::{self, Clip, Planes, Unreached};
pub use crate::shadow_volume::{CasterMode, ShadowVolumeReport};
use crate::technique::{needs, Casters};
pub use crate::view::DepthPrecision;
use crate::view::View;
use crate::RenderResult;
use serde::Serialize;
use umbra_scene::{Aabb, LightKind, Scene, Technique};

/// Why casters were left out of a light's shadow passes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum CullReason {
    /// The object has `casts_shadows = false`.
    NotACaster,
    /// Beyond the light's range: its shadow lies where the light adds nothing.
    OutsideRange,
    /// Outside the spot's cone: its shadow lies outside the cone too.
    OutsideCone,
    /// Its shadow volume cannot reach the view frustum (shadow volumes, hybrid).
    VolumeOutsideView,
    /// Outside one view of the light's shadow map (counted per caster and cube face).
    OutsideMapView,
    /// No texel of the hybrid's shadow map sees its bounding box (blocker culling).
    HiddenBlocker,
}

/// How many casters one reason left out.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Culled {
    /// Why.
    pub reason: CullReason,
    /// How many (casters, or caster × view pairs for `OutsideMapView`).
    pub count: usize,
}

/// Adds `count` under `reason` to a tally.
pub(crate) fn tally(culled: &mut Vec<Culled>, reason: CullReason, count: usize) {
    if count == 0 {
        return;
    }
    match culled.iter_mut().find(|c| c.reason == reason) {
        Some(c) => c.count += count,
        None => {
            culled.push(Culled { reason, count });
            culled.sort_by_key(|c| c.reason);
        }
    }
}

/// The frame's plan in numbers (`FrameReport::plan`); per-light detail is in
/// `FrameReport::lights`.
#[derive(Clone, Debug, Serialize)]
pub struct FramePlan {
    /// Whether the planner culled (`RendererDesc::cull`).
    pub culling: bool,
    /// Lights with at least one pass recorded.
    pub lights_recorded: usize,
    /// Lights with no pass at all.
    pub lights_skipped: usize,
    /// Lights whose shadow passes were recorded.
    pub lights_shadowed: usize,
    /// Casters left out, summed over lights, per reason.
    pub culled: Vec<Culled>,
}

impl FramePlan {
    /// Sums the per-light plans.
    pub fn of(culling: bool, lights: &[LightPlan]) -> Self {
        let mut culled = Vec::new();
        for c in lights.iter().flat_map(|l| &l.culled) {
            tally(&mut culled, c.reason, c.count);
        }
        Self {
            culling,
            lights_recorded: lights.iter().filter(|l| l.recorded).count(),
            lights_skipped: lights.iter().filter(|l| !l.recorded).count(),
            lights_shadowed: lights.iter().filter(|l| l.shadowed).count(),
            culled,
        }
    }
}

/// The decision for one light.
#[derive(Clone, Debug, Serialize)]
pub struct LightPlan {
    /// Index in `Scene::lights`.
    pub light: usize,
    /// Name from the scene.
    pub name: String,
    /// Directional, point or spot.
    pub kind: LightKind,
    /// The technique the scene asked for.
    pub requested: Technique,
    /// The technique its shadows use this frame (`auto` resolved).
    pub technique: Technique,
    /// Why `auto` chose `technique`.
    pub auto_choice: Option<String>,
    /// Whether any pass is recorded for it.
    pub recorded: bool,
    /// Why not, when `recorded` is false.
    pub skipped_because: Option<String>,
    /// Whether its shadow passes are recorded (else it is lit unshadowed, or not at all).
    pub shadowed: bool,
    /// Why not, when it is recorded but `shadowed` is false.
    pub unshadowed_because: Option<String>,
    /// Casters left out of its shadow passes, per reason.
    pub culled: Vec<Culled>,
    /// Scissor rectangle (x, y, width, height; y down) of its lighting and stencil passes,
    /// when it is bounded and its range sphere stays in front of the camera.
    pub scissor: Option<[u32; 4]>,
    /// Depth bounds of its lighting and stencil passes (window depth), with `scissor`, on
    /// devices with `depthBounds`.
    pub depth_bounds: Option<[f32; 2]>,
    /// The passes recorded for it, in order.
    pub passes: Vec<String>,
    /// The shadow map rendered for it this frame, if any.
    pub shadow_map: Option<ShadowMapReport>,
    /// Its shadow volumes this frame, if any.
    pub shadow_volume: Option<ShadowVolumeReport>,
    /// Its silhouette map this frame, if any (its depth map is `shadow_map`).
    pub silhouette_map: Option<SilhouetteMapReport>,
    /// The hybrid's figures this frame, if it used one (its map is `shadow_map`, its volumes
    /// `shadow_volume`).
    pub hybrid: Option<HybridReport>,
    /// Its ray-tracing BVH (ray-traced lights; left out of the JSON otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ray_traced: Option<RayTracedReport>,
    /// The ray-traced hybrid's rays (its map is `shadow_map`, its BVH `ray_traced`; left out of
    /// the JSON for other lights).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub hybrid_rt: Option<HybridRtReport>,
    /// What the renderer decided beyond the plan (e.g. a shadow map not needed this frame).
    pub note: Option<String>,
    /// Objects that enter its shadow map (nearest-first order is the fitting's).
    #[serde(skip)]
    pub(crate) map_casters: Vec<usize>,
    /// Objects whose shadow volumes it draws.
    #[serde(skip)]
    pub(crate) volume_casters: Vec<usize>,
}

/// A light's shadow map as rendered in one frame.
#[derive(Clone, Debug, Serialize)]
pub struct ShadowMapReport {
    /// Texels per side (per face for cube maps).
    pub resolution: u32,
    /// Whether it has six faces: a cube map, or a silhouette-map light's face atlas.
    pub cube: bool,
    /// Near distance of its frustum.
    pub near: f32,
    /// Far distance of its frustum.
    pub far: f32,
    /// Objects drawn into it.
    pub casters: usize,
    /// World units per texel along the map's x and y (orthographic maps: directional lights).
    pub texel_size: Option<[f32; 2]>,
    /// The least and the largest world size of one texel (across the light's rays) where the
    /// map lands on what the camera sees of the receivers (the points of an 8³ grid through
    /// each visible receiver's box that lie in the camera's frustum); `None` when no such point
    /// lies in a view.
    pub receiver_texel_size: Option<[f32; 2]>,
    /// World-to-clip matrix of each view (one, or six cube faces in +x, −x, +y, −y, +z, −z
    /// order; Vulkan clip space, depth 0..1): where a world point falls in the map, and how
    /// large a texel is there.
    pub view_proj: Vec<glam::Mat4>,
    /// Texels per side of each view's clip square: `resolution`, or more for a silhouette
    /// map's cube, whose faces are widened by a border beyond their 90° (a point on a seam
    /// then lies in two views; the lookup uses the one where it lies furthest inside).
    pub view_texels: u32,
}

/// A light's silhouette map as rendered in one frame (Sen et al. Table 1's statistics).
#[derive(Clone, Debug, Serialize)]
pub struct SilhouetteMapReport {
    /// Texels per side (the depth map's resolution; per face, borders left out, where
    /// [`ShadowMapReport::cube`] says the light has six faces).
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
    /// Pixels facing the light that its depth bounds could not decide (neither certainly lit
    /// nor certainly shadowed): the only pixels the volumes decide (an occlusion query on the
    /// mask pass).
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

/// A ray-traced hybrid light's rays in one frame (`crate::hybrid::rays`).
#[derive(Clone, Copy, Debug, Serialize)]
pub struct HybridRtReport {
    /// Shadow rays its classification appended: the pixels facing the light that its depth
    /// bounds could not decide (silhouette pixels; read back in umbra's own frames, `None` in an
    /// engine's, which umbra never waits for).
    pub rays: Option<u64>,
    /// `rays` over the image's pixel count (P).
    pub ray_fraction: Option<f64>,
    /// Rays beyond the list's capacity, not cast (their pixels stay undecided): 0 unless two
    /// fragments at one pixel both appended, or the list was cut to `maxStorageBufferRange`.
    pub rays_dropped: Option<u64>,
    /// Rays the list holds.
    pub list_capacity: u64,
    /// GPU time of its rays (`hybrid rays N`).
    pub rays_gpu_ms: Option<f64>,
}

/// The BVH a ray-traced light's shadow rays walked in one frame (`crate::ray_traced`).
#[derive(Clone, Copy, Debug, Serialize)]
pub struct RayTracedReport {
    /// Shadow-casting instances in the top level.
    pub instances: usize,
    /// Triangles of every mesh's BVH.
    pub triangles: usize,
    /// Bytes of nodes, instances and triangles on the GPU.
    pub bvh_bytes: u64,
    /// The top level's depth plus the deepest mesh's, in nodes.
    pub depth: u32,
    /// Mesh BVHs built so far (once per mesh revision).
    pub mesh_builds: u64,
    /// Top levels built so far (when a caster moved, came or went).
    pub top_builds: u64,
    /// This frame's mesh builds and top-level build, in milliseconds (0 when nothing changed).
    pub mesh_build_ms: f64,
    /// See `mesh_build_ms`.
    pub top_build_ms: f64,
    /// How far this light's rays walked the BVH (with `RendererDesc::diagnostics`, in umbra's
    /// own frames; `None` otherwise, or when it cast no ray).
    pub traversal: Option<crate::ray_traced::TraversalReport>,
    /// The meshes' BVH layout the rays walked (`RendererDesc::bvh`).
    pub layout: crate::ray_traced::BvhLayout,
    /// Whether the device offers ray queries (`Capabilities::ray_query`). The rays walk
    /// umbra's BVH in its own shaders either way: the ray-query path has not landed.
    pub ray_query_offered: bool,
}

impl RayTracedReport {
    /// The report of `scene` as last updated.
    pub(crate) fn of(scene: &crate::ray_traced::RayScene, ray_query_offered: bool) -> Self {
        Self {
            instances: scene.instances.len(),
            triangles: scene.triangles.len(),
            bvh_bytes: scene.bytes(),
            depth: scene.depth,
            mesh_builds: scene.stats.mesh_builds,
            top_builds: scene.stats.top_builds,
            mesh_build_ms: scene.stats.mesh_build_ms,
            top_build_ms: scene.stats.top_build_ms,
            traversal: None,
            layout: scene.layout,
            ray_query_offered,
        }
    }
}

/// What the planner looks at besides the scene.
pub(crate) struct PlanInput<'a> {
    /// Each object's world bounds (`Scene::object_bounds`).
    pub boxes: &'a [Option<Aabb>],
    /// The view the frame renders with (far plane at infinity with shadow volumes).
    pub view: &'a View,
    /// Target width and height in pixels.
    pub size: (u32, u32),
    /// Whether to cull (`RendererDesc::cull`).
    pub cull: bool,
    /// Whether the device has `depthBounds`.
    pub depth_bounds: bool,
    /// Shadow-map resolution `auto` lights would get (the light's own size wins); `None`: from
    /// the frame, as the renderer sizes it.
    pub map_resolution: Option<u32>,
    /// How `auto` lights choose.
    pub auto: crate::AutoPolicy,
}

/// Widening of range and cone for shadow-map casters: a lookup's filter reads texels beside
/// it, so casters just outside the lit region stay in the map.
const MAP_REACH_MARGIN: f32 = 0.05;

/// The view of a frame, as planning sees it.
struct ViewVolume {
    view_proj: glam::Mat4,
    /// The view frustum, and its side planes only (shadow volumes reach past near and far).
    view: Planes,
    sides: Planes,
    /// Per object, whether its bounds may be in view.
    visible: Vec<bool>,
}

/// Decides, per light, what to record.
pub(crate) fn plan_frame(scene: &Scene, input: &PlanInput<'_>) -> RenderResult<Vec<LightPlan>> {
    let view_proj = input.view.view_proj;
    let view = Planes::of(view_proj, Clip::All);
    let sides = Planes::of(view_proj, Clip::Sides);
    let visible: Vec<bool> = input.boxes.iter().map(|b| b.as_ref().is_some_and(|b| view.may_hold_box(b))).collect();
    let frame = ViewVolume { view_proj, view, sides, visible };
    scene.lights.iter().enumerate().map(|(i, l)| plan_light(scene, input, &frame, i, l)).collect()
}

/// Light `i`'s plan: its technique (`auto` resolved), whether anything of it is recorded, its
/// scissor and depth bounds, and its casters.
fn plan_light(
    scene: &Scene,
    input: &PlanInput<'_>,
    frame: &ViewVolume,
    i: usize,
    l: &umbra_scene::Light,
) -> RenderResult<LightPlan> {
    let (width, height) = input.size;
    let (view_proj, view, visible) = (frame.view_proj, &frame.view, &frame.visible);
    let mut plan = LightPlan {
        light: i,
        name: l.name.clone(),
        kind: l.kind(),
        requested: l.technique,
        technique: l.technique,
        auto_choice: None,
        recorded: true,
        skipped_because: None,
        shadowed: needs(l.technique).shadows,
        unshadowed_because: None,
        culled: Vec::new(),
        scissor: None,
        depth_bounds: None,
        passes: Vec::new(),
        shadow_map: None,
        shadow_volume: None,
        silhouette_map: None,
        hybrid: None,
        hybrid_rt: None,
        ray_traced: None,
        note: None,
        map_casters: Vec::new(),
        volume_casters: Vec::new(),
    };
    let casters: Vec<usize> = (0..scene.objects.len())
        .filter(|&o| scene.objects[o].casts_shadows && input.boxes.get(o).is_some_and(Option::is_some))
        .collect();
    tally(&mut plan.culled, CullReason::NotACaster, scene.objects.iter().filter(|o| !o.casts_shadows).count());
    if l.technique == Technique::Auto {
        let (technique, why) = auto::choose(scene, i, input, &view_proj, &input.auto);
        plan.technique = technique;
        plan.auto_choice = Some(why);
    }
    if !input.cull {
        plan.map_casters = casters.clone();
        plan.volume_casters = casters;
        return Ok(plan);
    }
    let reached =
        |o: usize, margin: f32| input.boxes.get(o).copied().flatten().map(|b| reach::light_reaches(l, &b, margin));
    let lit_in_view: Vec<usize> =
        (0..scene.objects.len()).filter(|&o| visible[o] && reached(o, 0.0) == Some(Ok(()))).collect();
    let skip = if !l.contributes() {
        Some("zero radiance: cannot change the image")
    } else if scene.objects.is_empty() {
        Some("no objects to light")
    } else if !reach::light_may_be_seen(l, view) {
        Some("its range misses the view frustum")
    } else if lit_in_view.is_empty() {
        Some("reaches no visible object")
    } else {
        None
    };
    if let Some(why) = skip {
        plan.recorded = false;
        plan.shadowed = false;
        plan.skipped_because = Some(why.into());
        return Ok(plan);
    }
    if let (Some(f), false) = (reach::footprint(l, input.view, width, height), !needs(plan.technique).bounded) {
        plan.scissor = Some(f.scissor);
        plan.depth_bounds = input.depth_bounds.then_some(f.depth);
    }
    if !plan.shadowed {
        return Ok(plan);
    }
    pick_casters(&mut plan, scene, input, &frame.sides, l, &casters, &lit_in_view);
    Ok(plan)
}

/// The casters of a shadowed light's map and volumes (culled ones tallied by reason), and
/// whether it still shadows anything visible.
fn pick_casters(
    plan: &mut LightPlan,
    scene: &Scene,
    input: &PlanInput<'_>,
    sides: &Planes,
    l: &umbra_scene::Light,
    casters: &[usize],
    lit_in_view: &[usize],
) {
    let reached =
        |o: usize, margin: f32| input.boxes.get(o).copied().flatten().map(|b| reach::light_reaches(l, &b, margin));
    let mut map_out = Vec::new();
    for &c in casters {
        match reached(c, MAP_REACH_MARGIN) {
            Some(Ok(())) => plan.map_casters.push(c),
            Some(Err(why)) => map_out.push(why),
            None => {}
        }
    }
    let reason = |u: &Unreached| match u {
        Unreached::Range => CullReason::OutsideRange,
        Unreached::Cone => CullReason::OutsideCone,
    };
    let volumes = needs(plan.technique).volumes.is_some();
    let mut out = Vec::new();
    for &c in casters {
        let Some(b) = input.boxes.get(c).copied().flatten() else { continue };
        match reach::light_reaches(l, &b, 0.0) {
            Err(why) => out.push(reason(&why)),
            Ok(()) if !sides.may_hold_sweep(&b, l.position) => out.push(CullReason::VolumeOutsideView),
            Ok(()) => plan.volume_casters.push(c),
        }
    }
    let culled: Vec<CullReason> = if volumes { out } else { map_out.iter().map(reason).collect() };
    for r in [CullReason::OutsideRange, CullReason::OutsideCone, CullReason::VolumeOutsideView] {
        tally(&mut plan.culled, r, culled.iter().filter(|&&c| c == r).count());
    }
    let receives = lit_in_view.iter().any(|&o| scene.objects[o].receives_shadows);
    let needed = match needs(plan.technique).casters {
        Casters::Volumes => &plan.volume_casters,
        Casters::Map | Casters::None => &plan.map_casters,
    };
    let unshadowed = if !receives {
        Some("no visible object it reaches receives shadows")
    } else if needed.is_empty() {
        Some("no caster can shadow a visible receiver")
    } else {
        None
    };
    if let Some(why) = unshadowed {
        plan.shadowed = false;
        plan.unshadowed_because = Some(why.into());
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    use umbra_scene::Light;

    fn input(s: &Scene) -> PlanInput<'static> {
        let boxes: &'static [Option<Aabb>] = Box::leak(s.object_bounds().into_boxed_slice());
        let view: &'static View = Box::leak(Box::new(View::of_camera(&s.camera, 256.0 / 192.0)));
        let auto = crate::AutoPolicy::for_device(&umbra_vk::Capabilities::default());
        PlanInput { boxes, view, size: (256, 192), cull: true, depth_bounds: true, map_resolution: Some(1024), auto }
    }

    #[test]
    fn dark_lights_are_planned_out_with_a_reason() {
        let mut s = umbra_scene::procedural::build("ball").unwrap();
        s.lights.push(Light::point(Vec3::ONE, 0.0));
        let plan = plan_frame(&s, &input(&s)).unwrap();
        assert!(plan[0].recorded);
        assert!(!plan[1].recorded);
        assert!(plan[1].skipped_because.as_deref().unwrap().contains("zero radiance"));
    }

    #[test]
    fn silhouette_maps_plan_point_and_spot_lights() {
        let mut s = umbra_scene::procedural::build("ball").unwrap();
        s.lights = vec![Light::point(Vec3::new(0.0, 4.0, 0.0), 10.0)];
        s.lights[0].technique = Technique::SilhouetteMap;
        let plan = plan_frame(&s, &input(&s)).unwrap();
        assert!(plan[0].recorded && plan[0].technique == Technique::SilhouetteMap);
        s.lights[0] = Light::spot(Vec3::new(0.0, 4.0, 0.0), -Vec3::Y, 20.0, 30.0, 10.0);
        s.lights[0].technique = Technique::SilhouetteMap;
        assert!(plan_frame(&s, &input(&s)).is_ok());
    }

    #[test]
    fn the_plaza_camera_sees_two_of_eight_lights() {
        let mut s = umbra_scene::procedural::build("plaza").unwrap();
        s.camera.far = None;
        let plan = plan_frame(&s, &input(&s)).unwrap();
        let recorded: Vec<usize> = plan.iter().filter(|l| l.recorded).map(|l| l.light).collect();
        assert_eq!(recorded, vec![1, 2]);
        // The shadow-volume spot in view is bounded on screen and in depth.
        let sv = &plan[1];
        assert_eq!(sv.technique, Technique::ShadowVolume);
        let [_, _, w, h] = sv.scissor.expect("a scissor rectangle");
        assert!(w * h < 256 * 192, "{:?}", sv.scissor);
        assert!(sv.depth_bounds.is_some_and(|[lo, hi]| 0.0 < lo && lo < hi && hi <= 1.0), "{:?}", sv.depth_bounds);
        assert!(sv.culled.iter().any(|c| c.reason == CullReason::OutsideRange && c.count == 7), "{:?}", sv.culled);
        for l in plan.iter().filter(|l| !l.recorded) {
            assert_eq!(l.skipped_because.as_deref(), Some("its range misses the view frustum"), "{}", l.light);
        }
    }

    #[test]
    fn auto_picks_the_map_when_texels_are_smaller_than_pixels() {
        let mut s = umbra_scene::procedural::build("ball").unwrap();
        s.lights[0].technique = Technique::Auto;
        let mut inp = input(&s);
        inp.map_resolution = Some(8192);
        let fine = plan_frame(&s, &inp).unwrap();
        assert_eq!(fine[0].technique, Technique::ShadowMap, "{:?}", fine[0].auto_choice);
        inp.map_resolution = Some(64);
        let coarse = plan_frame(&s, &inp).unwrap();
        // The ball's few hundred triangles: shadow volumes, by the cost model.
        assert_eq!(coarse[0].technique, Technique::ShadowVolume, "{:?}", coarse[0].auto_choice);
        assert!(coarse[0].auto_choice.as_deref().unwrap().contains("Stamminger"));
    }

    #[test]
    fn auto_asked_for_exact_shadows_never_picks_the_map_and_rays_past_the_crossover() {
        let mut s = umbra_scene::procedural::build("ball").unwrap();
        s.lights[0].technique = Technique::Auto;
        let mut inp = input(&s);
        inp.map_resolution = Some(8192);
        inp.auto.accuracy = crate::AutoAccuracy::Exact;
        let exact = plan_frame(&s, &inp).unwrap();
        assert_eq!(exact[0].technique, Technique::ShadowVolume, "{:?}", exact[0].auto_choice);
        let triangles: usize =
            s.objects.iter().filter(|o| o.casts_shadows).map(|o| s.meshes[o.mesh].triangle_count()).sum();
        inp.auto.ray_tracing_above = triangles - 1;
        let rays = plan_frame(&s, &inp).unwrap();
        assert_eq!(rays[0].technique, Technique::RayTraced, "{:?}", rays[0].auto_choice);
        inp.auto.classify_first = true;
        assert_eq!(plan_frame(&s, &inp).unwrap()[0].technique, Technique::HybridRt);
        inp.auto.ray_tracing_above = triangles;
        assert_eq!(plan_frame(&s, &inp).unwrap()[0].technique, Technique::Hybrid);
    }
}
