//! What each shadow technique asks of a frame, as one row per [`Technique`] in one exhaustive
//! `match` ([`needs`]). The planner and the technique set's preparation (`crate::techniques`)
//! read these rows instead of testing technique names, so a technique added to the enum does
//! not compile until it has its row (see `docs/architecture.md`, "Adding a technique").
//!
//! Per light every technique goes through the same steps: pick casters (`casters`;
//! `crate::plan`), prepare (its map, silhouette edges, volumes, rays; `techniques/prepare.rs`,
//! which assembles what it prepared into one `Prepared` per light), declare its passes
//! (`techniques/declare.rs`, a `match` on `Prepared`, and the technique's own `frame.rs`),
//! report (`techniques/results.rs`).

use crate::shadow_volume::VolumeMode;
use umbra_scene::Technique;

/// Whose casters decide a technique's shadows (and whose culling it reports).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Casters {
    /// None: the light is lit unshadowed.
    None,
    /// The casters of its shadow map.
    Map,
    /// The casters of its shadow volumes.
    Volumes,
}

/// The size of a technique's shadow map when the light names none.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum MapSize {
    /// `ShadowMapSettings::resolution`.
    Settings,
    /// `HybridSettings::resolution`; by default the size a shadow map would get from the frame
    /// (`ShadowMapSettings::resolution_from_frame`) divided by `coarser`: the map only
    /// classifies, so a coarser one trades more silhouette pixels for cheaper bounds.
    Hybrid {
        /// How many times coarser than a shadow map's the default size is (a power of two).
        coarser: u32,
    },
}

/// How a technique's volumes are counted.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Volumes {
    /// As `ShadowVolumeSettings::mode` says (z-pass where safe, or z-fail).
    Settings,
    /// Always z-fail (Chan–Durand §3 step 3); built only when the light has its map.
    ZFailWithMap,
}

/// How a technique's shadowed light is lit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Lighting {
    /// The forward lighting pass, testing the map, the silhouette map or the stencil.
    Forward,
    /// Its own passes after the map (`hybrid::frame`): the classification, then its volumes
    /// or, with `rays`, its shadow rays at the pixels the map leaves uncertain.
    Hybrid,
}

/// What a technique asks of a frame, for one light.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Needs {
    /// Whether the light casts shadows at all.
    pub shadows: bool,
    /// Whose casters decide its shadows.
    pub casters: Casters,
    /// Its shadow map's size, when it renders one.
    pub map: Option<MapSize>,
    /// Whether its map is also a silhouette map's depth map (a cube becomes a face atlas).
    pub silhouette: bool,
    /// Its shadow volumes, when it builds them.
    pub volumes: Option<Volumes>,
    /// Whether its passes may be scissored and depth-bounded to the light's footprint.
    pub bounded: bool,
    /// Whether the scene's camera goes to `P_inf` for it (volumes reach infinity; `auto` may
    /// pick the hybrid).
    pub infinite_camera: bool,
    /// Whether it casts shadow rays through the scene's BVH (`crate::ray_traced`).
    pub rays: bool,
    /// How its light is lit.
    pub lighting: Lighting,
    /// With diagnostics: its classification through the forward classes pass (the hybrid
    /// reads its own classes back; silhouette maps have their own view).
    pub classified: bool,
}

/// The row of `technique`. `auto` is resolved by the planner before any other step reads it;
/// its row only says what holds before: it shadows, and may pick the hybrid.
pub(crate) fn needs(technique: Technique) -> Needs {
    let base = Needs {
        shadows: true,
        casters: Casters::Map,
        map: None,
        silhouette: false,
        volumes: None,
        bounded: true,
        infinite_camera: false,
        rays: false,
        lighting: Lighting::Forward,
        classified: false,
    };
    match technique {
        Technique::Unshadowed => Needs { shadows: false, casters: Casters::None, ..base },
        Technique::ShadowMap => Needs { map: Some(MapSize::Settings), classified: true, ..base },
        Technique::SilhouetteMap => Needs { map: Some(MapSize::Settings), silhouette: true, ..base },
        Technique::ShadowVolume => Needs {
            casters: Casters::Volumes,
            volumes: Some(Volumes::Settings),
            infinite_camera: true,
            classified: true,
            ..base
        },
        // Its silhouette pixels' volumes cost little: half a shadow map's size by default.
        Technique::Hybrid => Needs {
            map: Some(MapSize::Hybrid { coarser: 2 }),
            volumes: Some(Volumes::ZFailWithMap),
            // Its classification reads the whole frame's depth: no scissor.
            bounded: false,
            infinite_camera: true,
            lighting: Lighting::Hybrid,
            ..base
        },
        // Exact: the casters that can shadow a visible receiver are the volumes' (those out
        // of range, cone or sweep cannot block a ray from a visible point to the light).
        Technique::RayTraced => Needs { casters: Casters::Volumes, rays: true, ..base },
        // The hybrid's map and classification, rays for its volumes: as exact as
        // `RayTraced`, so its casters are the same.
        // Its silhouette pixels' rays cost more: a shadow map's size by default.
        Technique::HybridRt => Needs {
            casters: Casters::Volumes,
            map: Some(MapSize::Hybrid { coarser: 1 }),
            bounded: false,
            rays: true,
            lighting: Lighting::Hybrid,
            ..base
        },
        Technique::Auto => Needs { infinite_camera: true, ..base },
    }
}

impl Volumes {
    /// The counting of these volumes, given the renderer's setting.
    pub fn mode(self, setting: VolumeMode) -> VolumeMode {
        match self {
            Volumes::Settings => setting,
            Volumes::ZFailWithMap => VolumeMode::ZFail,
        }
    }
}
