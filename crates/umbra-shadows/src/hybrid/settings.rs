//! Hybrid settings: the shadow map's resolution, the computation mask, blocker culling.

use serde::{Deserialize, Serialize};

/// How the shadow volumes of a hybrid light are kept to its silhouette pixels (Chan–Durand §4).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum MaskKind {
    /// The real computation mask: non-silhouette pixels get depth 0 and the volume pass runs
    /// with the depth-bounds test on `[DEPTH_BOUNDS_EPSILON, 1]`, which discards their volume
    /// fragments before any stencil update. Needs the `depthBounds` feature.
    #[serde(rename = "depth-bounds")]
    DepthBounds,
    /// The portable fallback: the stencil's high bit ([`SILHOUETTE_BIT`]) marks silhouette
    /// pixels, the volume pass compares only that bit and counts in the low seven bits
    /// ([`COUNT_BITS`]) through the write mask. Counts are exact modulo 128.
    #[serde(rename = "stencil")]
    Stencil,
    /// No mask: every volume fragment updates the stencil (the full fill of shadow volumes),
    /// for comparison. The image is the same.
    #[serde(rename = "none")]
    None,
}

impl MaskKind {
    /// Every kind, real mask first.
    pub const ALL: [MaskKind; 3] = [Self::DepthBounds, Self::Stencil, Self::None];

    /// The name used on command lines and in reports.
    pub fn name(self) -> &'static str {
        match self {
            Self::DepthBounds => "depth-bounds",
            Self::Stencil => "stencil",
            Self::None => "none",
        }
    }

    /// The kind a device gets by default: `depth-bounds` where it has `depthBounds`.
    pub fn best_for(depth_bounds: bool) -> Self {
        if depth_bounds {
            Self::DepthBounds
        } else {
            Self::Stencil
        }
    }

    /// The stencil bits that hold the volume count under this mask.
    pub(crate) fn count_bits(self) -> u8 {
        match self {
            Self::Stencil => COUNT_BITS as u8,
            _ => 0xff,
        }
    }
}

impl std::str::FromStr for MaskKind {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| format!("{s:?}: expected depth-bounds, stencil or none"))
    }
}

/// The lower depth bound of the `depth-bounds` mask. Masked pixels hold depth 0; with the far
/// plane at infinity (P_inf, depth `1 - n/z` for a surface `z` along the view axis) a visible
/// surface stores 0 only exactly on the near plane, and the smallest non-zero depth a D24
/// attachment can store is 2⁻²⁴, so 2⁻²⁵ separates the two on every depth format: no visible
/// surface is masked by mistake (a float depth of 2⁻²⁵ lies 3·10⁻⁸ of `n` beyond the near plane).
pub const DEPTH_BOUNDS_EPSILON: f32 = 1.0 / (1u32 << 25) as f32;

/// The stencil bit that marks silhouette pixels with the `stencil` mask.
pub const SILHOUETTE_BIT: u32 = 0x80;

/// The stencil bits that count volume crossings with the `stencil` mask.
pub const COUNT_BITS: u32 = 0x7f;

/// How lights whose technique is `hybrid` are rendered.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct HybridSettings {
    /// Texels per side of the light's map and depth bounds, which only classify pixels (a
    /// light's `shadow_map_size` wins); `None`: from the frame, half the size
    /// [`ShadowMapSettings::resolution_from_frame`](crate::ShadowMapSettings::resolution_from_frame)
    /// gives a shadow map for the hybrid (a coarser map leaves more silhouette pixels to the
    /// volumes, which cost less there than finer bounds), the same size for the ray-traced
    /// hybrid (whose silhouette pixels' rays cost more); at least 64.
    pub resolution: Option<u32>,
    /// The computation mask; `None`: [`MaskKind::best_for`] the device.
    pub mask: Option<MaskKind>,
    /// Skip the volumes of casters that no texel of the shadow map sees (§6.3: an occlusion
    /// query per caster's bounding box from the light). Off by default: it splits the frame
    /// into two submissions to read the queries back.
    pub cull_blockers: bool,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mask_names_round_trip() {
        for m in MaskKind::ALL {
            assert_eq!(m.name().parse::<MaskKind>(), Ok(m));
            assert_eq!(serde_json::to_string(&m).unwrap(), format!("\"{}\"", m.name()));
        }
        assert!("depth".parse::<MaskKind>().is_err());
    }

    #[test]
    fn epsilon_separates_masked_pixels_from_every_stored_depth() {
        let d24_step = 1.0 / (1u32 << 24) as f32;
        assert!(0.0 < DEPTH_BOUNDS_EPSILON && DEPTH_BOUNDS_EPSILON < d24_step);
    }
}
