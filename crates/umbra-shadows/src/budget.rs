//! The shadow-map memory budget: what every light's shadow storage needs in one frame, summed
//! and compared with `RendererDesc::shadow_map_budget_bytes` before any of it is allocated.

use crate::{RenderError, RenderResult};
use serde::Serialize;

/// The default budget: 1 GiB, ten 2048² point-light cube maps or one 16384² map.
pub const DEFAULT_SHADOW_MAP_BUDGET: u64 = 1 << 30;

/// What one light's shadow storage takes in a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct ShadowStorage {
    /// Index of the light.
    pub light: usize,
    /// Texels per side of its maps.
    pub resolution: u32,
    /// Whether its depth map is a cube (six faces).
    pub cube: bool,
    /// Whether it has a depth map (a hybrid light without blocker culling has only its depth
    /// bounds, of the same size).
    pub depth: bool,
    /// Whether it also has a silhouette map (and, with diagnostics, its readback).
    pub silhouette: bool,
    /// Whether it also has the hybrid's depth bounds (two depth layers per map face).
    pub bounds: bool,
    /// Bytes of its depth map, silhouette map and silhouette-map readback, and depth bounds.
    pub bytes: u64,
}

impl std::fmt::Display for ShadowStorage {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let faces = if self.cube { "6 x " } else { "" };
        // A silhouette map's cube is a face atlas: its faces carry borders.
        let (side, borders) = match (self.cube, self.silhouette) {
            (true, true) => (crate::shadow_map::atlas::face_side(self.resolution), " (faces with their borders)"),
            _ => (self.resolution, ""),
        };
        let silhouette = if self.silhouette { " + silhouette map" } else { "" };
        let bounds = match (self.bounds, self.depth) {
            (false, _) => "",
            (true, true) => " + depth bounds",
            (true, false) => " depth bounds",
        };
        let bytes = umbra_vk::human_bytes(self.bytes);
        write!(f, "light {}: {faces}{side}²{borders}{silhouette}{bounds} = {bytes}", self.light)
    }
}

/// Bytes of an image of `desc` whose texels take `texel` bytes (every layer).
pub(crate) fn desc_bytes(desc: &umbra_vk::ImageDesc, texel: u64) -> u64 {
    let texels = u64::from(desc.width).saturating_mul(u64::from(desc.height));
    texels.saturating_mul(u64::from(desc.layers)).saturating_mul(texel)
}

/// A typed [`RenderError::ShadowBudget`] when `needs` sum to more than `budget` bytes.
pub(crate) fn check(needs: &[ShadowStorage], budget: u64) -> RenderResult<()> {
    let bytes = needs.iter().fold(0u64, |sum, n| sum.saturating_add(n.bytes));
    if bytes > budget {
        return Err(RenderError::ShadowBudget { lights: needs.to_vec(), bytes, budget });
    }
    Ok(())
}

/// Releases every per-light target whose light `keep` does not mark (lights beyond `keep`
/// too) into `retired`.
pub(crate) fn release_unused<T: std::any::Any + Send>(
    targets: &mut Vec<Option<T>>,
    keep: &[bool],
    retired: &mut crate::retired::Retired,
) {
    for (l, target) in targets.iter_mut().enumerate() {
        if !keep.get(l).copied().unwrap_or(false) {
            retired.take(target);
        }
    }
    targets.truncate(keep.len());
}

#[cfg(test)]
mod tests {
    use super::*;
    use umbra_vk::vk;

    fn cube(light: usize) -> ShadowStorage {
        ShadowStorage {
            light,
            resolution: 2048,
            cube: true,
            depth: true,
            silhouette: false,
            bounds: false,
            bytes: desc_bytes(&umbra_vk::ImageDesc::new_cube(vk::Format::D32_SFLOAT, 2048), 4),
        }
    }

    #[test]
    fn ten_cube_maps_fit_the_default_and_eleven_do_not() {
        assert_eq!(cube(0).bytes, 96 << 20);
        let ten: Vec<_> = (0..10).map(cube).collect();
        assert!(check(&ten, DEFAULT_SHADOW_MAP_BUDGET).is_ok());
        let eleven: Vec<_> = (0..11).map(cube).collect();
        let err = check(&eleven, DEFAULT_SHADOW_MAP_BUDGET).unwrap_err();
        let text = err.to_string();
        assert!(
            matches!(err, RenderError::ShadowBudget { bytes, budget, ref lights }
            if bytes == 11 * (96 << 20) && budget == 1 << 30 && lights.len() == 11),
            "{text}"
        );
        assert!(text.contains("1.0 GiB (light 0: 6 x 2048² = 96 MiB, light 1"), "{text}");
        assert!(text.contains("shadow_map_budget_bytes = 1 GiB"), "{text}");
    }

    #[test]
    fn sizes_saturate_instead_of_wrapping() {
        assert_eq!(desc_bytes(&umbra_vk::ImageDesc::new_cube(vk::Format::D32_SFLOAT, u32::MAX), 16), u64::MAX);
        let huge = ShadowStorage { bytes: u64::MAX, ..cube(0) };
        assert!(check(&[huge, huge], u64::MAX).is_ok(), "u64::MAX is unlimited");
    }
}
