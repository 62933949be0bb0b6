//! Every pass a frame can record, by a typed id: its debug label, its report name, the light it
//! serves and whether it is a diagnostic are all read from the id, never from its name.

use serde::Serialize;
use umbra_scene::LightKind;

/// Which pass of a frame, and for which light.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PassId {
    /// The scene's meshes copied from staging into their buffers (frames after a mesh changed).
    MeshUpload,
    /// Depth from the light into its shadow map (all techniques with a map).
    ShadowMap(usize),
    /// Sen et al. §3 pass 2: the silhouette points on the dual grid.
    SilhouetteMap(usize),
    /// Chan–Durand §6.3: every hybrid light's caster boxes against its map.
    BlockerCulling,
    /// Depth plus the ambient term of every object.
    Ambient,
    /// An engine's frame: every object's depth re-drawn into umbra's own depth/stencil, in its
    /// convention (the engine's depth has none or another; `crate::shadows`).
    DepthRebuild,
    /// Diagnostic: world positions and normals for the exact reference.
    GBuffer,
    /// Shadow volumes built on the GPU: the meshes an engine deforms on the GPU copied into the
    /// volumes' positions, once a frame.
    VolumePositions,
    /// Shadow volumes built on the GPU: every job's indirect draw and counts set to their
    /// initial values, once a frame.
    VolumeDrawsReset,
    /// Shadow volumes built on the GPU: every job's draw and counts copied out for the report
    /// (umbra's own frames).
    VolumeCounts,
    /// Shadow volumes built on the GPU: how each caster's triangles face the light.
    VolumeClassify(usize),
    /// Shadow volumes built on the GPU: each caster's silhouette edges, listed for its draw.
    VolumeSilhouettes(usize),
    /// Everitt–Kilgard: the stencil counts of a shadow-volume light.
    ShadowVolume(usize),
    /// A shadow-volume light's stencil counts resolved into its visibility image.
    StencilVisibility(usize),
    /// A shadow-map or silhouette-map light's map looked up into its visibility image.
    MapVisibility(usize),
    /// A ray-traced light's shadow rays, one per receiver pixel, into its visibility image.
    RayVisibility(usize),
    /// The additive lighting of a light, times its visibility image.
    Light(usize, LightKind),
    /// The hybrid's conservative depth bounds from the light (its classification reads them).
    HybridBounds(usize),
    /// Chan–Durand §3 step 2: classify every visible pixel; the depth bounds decide the
    /// visibility of all but the silhouette pixels.
    HybridClassify(usize),
    /// Chan–Durand §4: the computation mask.
    ComputationMask(usize),
    /// Chan–Durand §3 step 3: z-fail volumes through the mask.
    HybridVolumes(usize),
    /// Chan–Durand §3 step 4: the silhouette pixels' visibility from their stencil counts.
    HybridVisibility(usize),
    /// The ray-traced hybrid: its ray list emptied before the classification appends to it.
    HybridRayList(usize),
    /// The ray-traced hybrid: the silhouette pixels' shadow rays, dispatched indirectly.
    HybridRays(usize),
    /// The ray-traced hybrid: its ray count copied out for the report (umbra's own frames).
    HybridRayCount(usize),
    /// Diagnostic: the volume fragments the hybrid's mask lets through.
    MaskedVolumeFragments(usize),
    /// Diagnostic: the hybrid's classes and stencil copied out.
    HybridDiagnostics(usize),
    /// Diagnostic: the classification (and stencil) of a shadow-map or shadow-volume light.
    LightDiagnostics(usize),
    /// Diagnostic: a light's volumes into the overdraw image.
    VolumeOverdraw(usize),
    /// Diagnostic: a silhouette-map light's classification and silhouette points.
    SilhouetteDiagnostics(usize),
    /// Diagnostic: a light's visibility image copied out (`RendererDesc::read_visibility`).
    VisibilityReadback(usize),
    /// Diagnostic: the shadow rays' counters emptied (`crate::ray_traced::stats`).
    RayStatsReset,
    /// Diagnostic: a ray-traced or hybrid-RT light's rays cast again, counting the BVH nodes
    /// and triangles each visits.
    RayStats(usize),
    /// Diagnostic: the shadow rays' counters copied out.
    RayStatsReadback,
    /// The colour target copied out.
    Readback,
    /// An engine's frame: the lights' visibility images made readable by its shaders and its
    /// depth returned in the layout it was handed over in (barriers only).
    HandOff,
}

impl PassId {
    /// The pass's name: its debug label and `PassReport::name` (`shadow_map 0`,
    /// `light 1 (spot)`, `hybrid volumes 2`, `readback`).
    pub fn name(self) -> String {
        match self {
            PassId::MeshUpload => "mesh upload".into(),
            PassId::ShadowMap(l) => format!("shadow_map {l}"),
            PassId::SilhouetteMap(l) => format!("silhouette_map {l}"),
            PassId::BlockerCulling => "blocker culling".into(),
            PassId::Ambient => "ambient".into(),
            PassId::DepthRebuild => "depth rebuild".into(),
            PassId::GBuffer => "g-buffer".into(),
            PassId::VolumePositions => "volume positions".into(),
            PassId::VolumeDrawsReset => "volume draws reset".into(),
            PassId::VolumeCounts => "volume counts readback".into(),
            PassId::VolumeClassify(l) => format!("volume classify {l}"),
            PassId::VolumeSilhouettes(l) => format!("volume silhouettes {l}"),
            PassId::ShadowVolume(l) => format!("shadow_volume {l}"),
            PassId::StencilVisibility(l) => format!("visibility {l} (stencil)"),
            PassId::MapVisibility(l) => format!("visibility {l}"),
            PassId::RayVisibility(l) => format!("visibility {l} (rays)"),
            PassId::Light(l, kind) => format!("light {l} ({kind:?})").to_lowercase(),
            PassId::HybridBounds(l) => format!("hybrid bounds {l}"),
            PassId::HybridClassify(l) => format!("hybrid classify {l}"),
            PassId::ComputationMask(l) => format!("computation mask {l}"),
            PassId::HybridVolumes(l) => format!("hybrid volumes {l}"),
            PassId::HybridVisibility(l) => format!("hybrid visibility {l}"),
            PassId::HybridRayList(l) => format!("hybrid ray list {l}"),
            PassId::HybridRays(l) => format!("hybrid rays {l}"),
            PassId::HybridRayCount(l) => format!("hybrid ray count {l}"),
            PassId::MaskedVolumeFragments(l) => format!("masked volume fragments {l}"),
            PassId::HybridDiagnostics(l) => format!("hybrid diagnostics {l}"),
            PassId::LightDiagnostics(l) => format!("light diagnostics {l}"),
            PassId::VolumeOverdraw(l) => format!("volume overdraw {l}"),
            PassId::SilhouetteDiagnostics(l) => format!("silhouette diagnostics {l}"),
            PassId::VisibilityReadback(l) => format!("visibility readback {l}"),
            PassId::RayStatsReset => "ray stats reset".into(),
            PassId::RayStats(l) => format!("ray stats {l}"),
            PassId::RayStatsReadback => "ray stats readback".into(),
            PassId::Readback => "readback".into(),
            PassId::HandOff => "hand-off".into(),
        }
    }

    /// The light the pass serves, if any.
    pub fn light(self) -> Option<usize> {
        match self {
            PassId::MeshUpload
            | PassId::BlockerCulling
            | PassId::Ambient
            | PassId::DepthRebuild
            | PassId::GBuffer
            | PassId::VolumePositions
            | PassId::VolumeDrawsReset
            | PassId::VolumeCounts
            | PassId::Readback
            | PassId::RayStatsReset
            | PassId::RayStatsReadback
            | PassId::HandOff => None,
            PassId::ShadowMap(l)
            | PassId::SilhouetteMap(l)
            | PassId::VolumeClassify(l)
            | PassId::VolumeSilhouettes(l)
            | PassId::ShadowVolume(l)
            | PassId::StencilVisibility(l)
            | PassId::MapVisibility(l)
            | PassId::RayVisibility(l)
            | PassId::Light(l, _)
            | PassId::HybridBounds(l)
            | PassId::HybridClassify(l)
            | PassId::ComputationMask(l)
            | PassId::HybridVolumes(l)
            | PassId::HybridVisibility(l)
            | PassId::HybridRayList(l)
            | PassId::HybridRays(l)
            | PassId::HybridRayCount(l)
            | PassId::MaskedVolumeFragments(l)
            | PassId::HybridDiagnostics(l)
            | PassId::LightDiagnostics(l)
            | PassId::VolumeOverdraw(l)
            | PassId::SilhouetteDiagnostics(l)
            | PassId::VisibilityReadback(l)
            | PassId::RayStats(l) => Some(l),
        }
    }

    /// Whether it is a diagnostic pass: not part of any technique's cost (left out of
    /// `FrameReport::total_gpu_ms`).
    pub fn diagnostic(self) -> bool {
        matches!(
            self,
            PassId::GBuffer
                | PassId::MaskedVolumeFragments(_)
                | PassId::HybridRayCount(_)
                | PassId::VolumeCounts
                | PassId::HybridDiagnostics(_)
                | PassId::LightDiagnostics(_)
                | PassId::VolumeOverdraw(_)
                | PassId::SilhouetteDiagnostics(_)
                | PassId::VisibilityReadback(_)
                | PassId::RayStatsReset
                | PassId::RayStats(_)
                | PassId::RayStatsReadback
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every pass a frame can record for lights 0 and 1.
    fn every_pass() -> Vec<PassId> {
        let mut all = vec![
            PassId::BlockerCulling,
            PassId::Ambient,
            PassId::DepthRebuild,
            PassId::MeshUpload,
            PassId::GBuffer,
            PassId::VolumePositions,
            PassId::VolumeDrawsReset,
            PassId::VolumeCounts,
            PassId::Readback,
            PassId::HandOff,
            PassId::RayStatsReset,
            PassId::RayStatsReadback,
        ];
        for l in 0..2 {
            all.extend([
                PassId::ShadowMap(l),
                PassId::SilhouetteMap(l),
                PassId::VolumeClassify(l),
                PassId::VolumeSilhouettes(l),
                PassId::ShadowVolume(l),
                PassId::StencilVisibility(l),
                PassId::MapVisibility(l),
                PassId::RayVisibility(l),
                PassId::Light(l, LightKind::Spot),
                PassId::HybridBounds(l),
                PassId::HybridClassify(l),
                PassId::ComputationMask(l),
                PassId::HybridVolumes(l),
                PassId::HybridVisibility(l),
                PassId::HybridRayList(l),
                PassId::HybridRays(l),
                PassId::HybridRayCount(l),
                PassId::MaskedVolumeFragments(l),
                PassId::HybridDiagnostics(l),
                PassId::LightDiagnostics(l),
                PassId::VolumeOverdraw(l),
                PassId::SilhouetteDiagnostics(l),
                PassId::VisibilityReadback(l),
                PassId::RayStats(l),
            ]);
        }
        all
    }

    #[test]
    fn every_pass_has_its_own_name_and_its_light() {
        let all = every_pass();
        let names: std::collections::HashSet<String> = all.iter().map(|p| p.name()).collect();
        assert_eq!(names.len(), all.len(), "two passes share a name: {names:?}");
        for p in &all {
            // A per-light pass names its light; the frame's own passes name none.
            match p.light() {
                Some(l) => assert!(p.name().contains(&l.to_string()), "{p:?}: {}", p.name()),
                None => assert!(!p.name().chars().any(|c| c.is_ascii_digit()), "{p:?}: {}", p.name()),
            }
        }
        assert_eq!(PassId::Light(3, LightKind::Point).name(), "light 3 (point)");
        assert_eq!(PassId::HybridVisibility(2).name(), "hybrid visibility 2");
        assert_eq!(PassId::StencilVisibility(1).name(), "visibility 1 (stencil)");
    }

    #[test]
    fn diagnostic_passes_are_the_views_only() {
        let diagnostic: Vec<String> = every_pass().iter().filter(|p| p.diagnostic()).map(|p| p.name()).collect();
        assert_eq!(diagnostic.len(), 4 + 8 * 2, "{diagnostic:?}");
        for p in [PassId::Ambient, PassId::ShadowMap(0), PassId::MapVisibility(0), PassId::HybridVolumes(0)] {
            assert!(!p.diagnostic(), "{p:?} is part of the technique's cost");
        }
    }
}
