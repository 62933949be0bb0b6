//! The shadow-map memory budget: what every light's shadow storage needs in one frame, summed
//! and compared with `RendererDesc::shadow_map_budget_bytes` before any of it is allocated.

use crate::error::ShadowStorage;
use crate::{RenderError, RenderResult};

/// The default budget: 1 GiB, ten 2048² point-light cube maps or one 16384² map.
pub const DEFAULT_SHADOW_MAP_BUDGET: u64 = 1 << 30;

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
            face_side: 2048,
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
