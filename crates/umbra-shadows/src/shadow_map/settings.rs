//! Shadow-map settings: resolution, lookup filter, bias, out-of-frustum policy.

use crate::{RenderError, RenderResult};
use serde::{Deserialize, Serialize};

/// How the lighting pass compares against the shadow map.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ShadowFilter {
    /// One comparison with the nearest texel (hard, blocky edges).
    Nearest,
    /// Hardware 2×2 PCF: one fetch through a LINEAR comparison sampler.
    #[default]
    Pcf2x2,
    /// 3×3 nearest comparisons, averaged.
    Pcf3x3,
    /// 5×5 nearest comparisons, averaged.
    Pcf5x5,
}

impl ShadowFilter {
    /// Every filter, in order of cost.
    pub const ALL: [ShadowFilter; 4] = [Self::Nearest, Self::Pcf2x2, Self::Pcf3x3, Self::Pcf5x5];

    /// The value of the shader's `SHADOW_FILTER` specialization constant.
    pub(crate) fn spec_value(self) -> u32 {
        self as u32
    }

    /// Texels the kernel reaches beyond the lookup texel (0, 0, 1, 2).
    pub fn radius(self) -> u32 {
        match self {
            Self::Nearest | Self::Pcf2x2 => 0,
            Self::Pcf3x3 => 1,
            Self::Pcf5x5 => 2,
        }
    }

    /// The name used on command lines and in reports.
    pub fn name(self) -> &'static str {
        match self {
            Self::Nearest => "nearest",
            Self::Pcf2x2 => "pcf2x2",
            Self::Pcf3x3 => "pcf3x3",
            Self::Pcf5x5 => "pcf5x5",
        }
    }
}

impl std::str::FromStr for ShadowFilter {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|f| f.name() == s)
            .ok_or_else(|| format!("{s:?}: expected nearest, pcf2x2, pcf3x3 or pcf5x5"))
    }
}

/// Depth bias applied while rendering the shadow map (`vkCmdSetDepthBias`,
/// Vulkan's `glPolygonOffset`): `constant` units of the depth format's resolution plus
/// `slope` times the polygon's depth slope per shadow-map texel.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct DepthBias {
    /// Constant factor (units of the minimum resolvable depth difference).
    pub constant: f32,
    /// Slope factor, in shadow-map texels of depth slope. The filter's radius is added to it,
    /// since a wider kernel compares up to that many texels away from the lookup point.
    pub slope: f32,
    /// Upper limit of the bias, as a distance along the light's rays in texel widths (measured
    /// at the map's near plane; `vkCmdSetDepthBias`' clamp, needs `depthBiasClamp`), or `None`
    /// for no limit. Triangles seen edge-on from the light have a huge depth slope: unclamped,
    /// their bias pushes a caster's outline behind the receivers and the shadow shrinks there.
    /// `None` uses [`DepthBias::SILHOUETTE_CLAMP_TEXELS`] for silhouette maps, whose
    /// reconstruction needs the corner comparisons to agree with the outline, and no limit for
    /// shadow maps, where steep receivers need the full slope bias.
    pub clamp_texels: Option<f32>,
}

impl DepthBias {
    /// The default limit of silhouette maps' bias, in texel widths.
    pub const SILHOUETTE_CLAMP_TEXELS: f32 = 4.0;
    /// Largest accepted `constant` (units of the depth format's resolution): 10⁵ units already
    /// push a D24 depth by 0.6 % of the depth range, far past any acne.
    pub const MAX_CONSTANT: f32 = 1e5;
    /// Largest accepted `slope` (texels of depth slope): typical values are 1 to 10.
    pub const MAX_SLOPE: f32 = 100.0;
    /// Largest accepted `clamp_texels`.
    pub const MAX_CLAMP_TEXELS: f32 = 1e4;
}

/// How a light's shadow map is made and read.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ShadowMapSettings {
    /// Texels per side (cube maps: per face), 64 up to the device limit; `None`: per light,
    /// from the frame ([`ShadowMapSettings::resolution_from_frame`]). A light's
    /// `shadow_map_size` overrides it.
    pub resolution: Option<u32>,
    /// Lookup filter.
    pub filter: ShadowFilter,
    /// Depth bias of the shadow pass.
    pub bias: DepthBias,
    /// World-space distance the lookup point moves along the surface normal (0 = off).
    pub normal_offset: f32,
    /// Points outside a spot or directional light's shadow frustum are lit (`true`) or in
    /// shadow (`false`); never the clamped border texel's answer.
    pub outside_lit: bool,
}

impl ShadowMapSettings {
    /// The map lookup's specialization constants, as every pass that looks a map up reads
    /// them (`shadow_map/lookup.glsl`): the filter (0) and the out-of-frustum policy (1).
    pub(crate) fn lookup_spec(&self) -> [(u32, u32); 2] {
        [(0, self.filter.spec_value()), (1, u32::from(self.outside_lit))]
    }

    /// Smallest accepted resolution.
    pub const MIN_RESOLUTION: u32 = 64;

    /// The defaults: map size from the frame, hardware 2×2 PCF, bias (constant 2, slope 2.5), no normal offset,
    /// outside lit. The bias leaves no acne on the `cubes` floor at 60° incidence
    /// (`tests/shadow_map.rs` checks a plane at 60° and 75°) with every filter.
    pub const DEFAULT: Self = Self {
        resolution: None,
        filter: ShadowFilter::Pcf2x2,
        bias: DepthBias { constant: 2.0, slope: 2.5, clamp_texels: None },
        normal_offset: 0.0,
        outside_lit: true,
    };

    /// The most map texels a map sized from the frame may have per pixel of the frame.
    pub const TEXELS_PER_PIXEL_BUDGET: u32 = 4;

    /// The map size, from the frame itself, of a light whose size nobody set (shadow maps,
    /// silhouette maps and the hybrid alike), in a `width` × `height` frame: `ratio` is the
    /// largest Stamminger–Drettakis ratio (a texel's world size over a pixel's, where the map
    /// lands on what the camera sees of the receivers) the light's views give at `reference`
    /// texels per side. The size is the power of two that brings it to at most one pixel, at
    /// least 64 and at most the budget: the largest power of two whose square holds no more than
    /// [`Self::TEXELS_PER_PIXEL_BUDGET`] texels per frame pixel (256×192 → 256, 1024×768 →
    /// 1024, 1920×1080 → 2048). Without a ratio (no visible receiver in a view): the budget.
    pub fn resolution_from_frame(ratio: Option<f32>, reference: u32, width: u32, height: u32) -> u32 {
        let texels = u64::from(Self::TEXELS_PER_PIXEL_BUDGET) * u64::from(width) * u64::from(height);
        let budget = pow2_floor(texels.isqrt().clamp(64, 1 << 16) as u32);
        let Some(ratio) = ratio.filter(|r| r.is_finite() && *r > 0.0) else { return budget };
        let needed = (f64::from(reference) * f64::from(ratio)).ceil().clamp(64.0, f64::from(budget)) as u32;
        needed.next_power_of_two().min(budget)
    }

    /// Largest accepted `normal_offset`, in world units (a lookup moved further than this
    /// leaves any scene umbra ships; scale the scene instead).
    pub const MAX_NORMAL_OFFSET: f32 = 1e4;

    /// Checks the values the renderer cannot render sensibly: a bias or normal offset that is
    /// not finite, negative, or beyond its `MAX_*` (every shadow would vanish or every surface
    /// would be in shadow). `resolution` is checked per light against the device when its map
    /// is made. `Renderer::new` calls this; a typed [`RenderError::InvalidSetting`] names the
    /// field and the accepted range.
    pub fn validate(&self) -> RenderResult<()> {
        let b = &self.bias;
        check_range("shadow_map.bias.constant", b.constant, DepthBias::MAX_CONSTANT)?;
        check_range("shadow_map.bias.slope", b.slope, DepthBias::MAX_SLOPE)?;
        if let Some(t) = b.clamp_texels {
            check_range("shadow_map.bias.clamp_texels", t, DepthBias::MAX_CLAMP_TEXELS)?;
        }
        check_range("shadow_map.normal_offset", self.normal_offset, Self::MAX_NORMAL_OFFSET)
    }

    /// The slope factor actually set: `bias.slope` plus the filter's radius.
    pub fn effective_slope(&self) -> f32 {
        self.bias.slope + self.filter.radius() as f32
    }
}

/// The largest power of two not above `n` (n ≥ 1).
fn pow2_floor(n: u32) -> u32 {
    1 << (31 - n.max(1).leading_zeros())
}

/// `value` must be finite and in `0..=max`.
fn check_range(field: &'static str, value: f32, max: f32) -> RenderResult<()> {
    if value.is_finite() && (0.0..=max).contains(&value) {
        return Ok(());
    }
    Err(RenderError::InvalidSetting {
        field,
        value: format!("{value:?}"),
        accepted: format!("a finite number in 0..={max}"),
    })
}

impl Default for ShadowMapSettings {
    fn default() -> Self {
        Self::DEFAULT
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resolution_from_frame_brings_a_texel_to_a_pixel_within_the_budget() {
        let size = ShadowMapSettings::resolution_from_frame;
        // The budget: 4 texels per pixel.
        assert_eq!(size(None, 1024, 256, 192), 256);
        assert_eq!(size(None, 1024, 1024, 768), 1024);
        assert_eq!(size(None, 1024, 1920, 1080), 2048);
        assert_eq!(size(None, 1024, 16, 16), 64);
        // A texel 3 pixels wide at 64² needs 192 → 256; one 0.1 pixel wide at 1024² needs 103 → 128.
        assert_eq!(size(Some(3.0), 64, 1024, 768), 256);
        assert_eq!(size(Some(0.1), 1024, 1024, 768), 128);
        // Never below 64, never above the budget, whatever the ratio.
        assert_eq!(size(Some(1e-9), 1024, 1024, 768), 64);
        assert_eq!(size(Some(1e9), 1024, 256, 192), 256);
        assert_eq!(size(Some(f32::NAN), 1024, 256, 192), 256);
    }

    #[test]
    fn non_finite_negative_and_absurd_values_are_refused_by_name() {
        assert!(ShadowMapSettings::DEFAULT.validate().is_ok());
        let with_bias = |constant, slope| ShadowMapSettings {
            bias: DepthBias { constant, slope, clamp_texels: None },
            ..ShadowMapSettings::DEFAULT
        };
        let cases = [
            (with_bias(f32::NAN, 1.0), "shadow_map.bias.constant"),
            (with_bias(f32::INFINITY, 1.0), "shadow_map.bias.constant"),
            (with_bias(-1.0, 1.0), "shadow_map.bias.constant"),
            (with_bias(1.0, f32::NEG_INFINITY), "shadow_map.bias.slope"),
            (with_bias(1.0, 1e30), "shadow_map.bias.slope"),
            (ShadowMapSettings { normal_offset: f32::NAN, ..ShadowMapSettings::DEFAULT }, "shadow_map.normal_offset"),
            (ShadowMapSettings { normal_offset: 1e30, ..ShadowMapSettings::DEFAULT }, "shadow_map.normal_offset"),
            (
                ShadowMapSettings {
                    bias: DepthBias { clamp_texels: Some(f32::NAN), ..ShadowMapSettings::DEFAULT.bias },
                    ..ShadowMapSettings::DEFAULT
                },
                "shadow_map.bias.clamp_texels",
            ),
        ];
        for (settings, name) in cases {
            let err = settings.validate().unwrap_err();
            assert!(matches!(err, RenderError::InvalidSetting { field, .. } if field == name), "{err}");
            assert!(err.to_string().contains("a finite number in 0..="), "{err}");
        }
        assert!(with_bias(DepthBias::MAX_CONSTANT, DepthBias::MAX_SLOPE).validate().is_ok());
    }
}
