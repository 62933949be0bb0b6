//! A technique's shadow mask against the exact one: wrong pixels (split into false shadow and
//! false light), the same inside a band around the true shadow edges, how far from the true
//! edge the worst wrong pixel lies, and an error image.
//!
//! Only pixels both masks decide are compared: where one side calls a pixel not in question
//! (its interpolated normal faces away while the geometric one does not, say) the pixel is
//! counted as `undecided`, not as wrong.

use crate::distance::distance_to_seeds;
use crate::mask::ShadowMask;
use crate::{ReferenceError, ReferenceResult};
use serde::{Deserialize, Serialize};

/// Default half-width of the edge band, in pixels.
pub const EDGE_BAND_PX: f32 = 2.0;

/// Wrong pixels among some set of compared pixels.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct WrongPixels {
    /// Pixels both masks decide.
    pub compared: u64,
    /// Pixels whose state differs.
    pub wrong: u64,
    /// Shadowed by the technique, lit in truth.
    pub false_shadow: u64,
    /// Lit by the technique, shadowed in truth.
    pub false_lit: u64,
}

impl WrongPixels {
    /// `wrong / compared` (0 when nothing was compared).
    pub fn fraction(&self) -> f64 {
        ratio(self.wrong, self.compared)
    }

    /// `false_shadow / compared`.
    pub fn false_shadow_fraction(&self) -> f64 {
        ratio(self.false_shadow, self.compared)
    }

    /// `false_lit / compared`.
    pub fn false_lit_fraction(&self) -> f64 {
        ratio(self.false_lit, self.compared)
    }

    fn add(&mut self, technique: bool, truth: bool) {
        self.compared += 1;
        match (technique, truth) {
            (true, false) => self.false_shadow += 1,
            (false, true) => self.false_lit += 1,
            _ => return,
        }
        self.wrong += 1;
    }
}

impl std::ops::AddAssign for WrongPixels {
    fn add_assign(&mut self, other: Self) {
        self.compared += other.compared;
        self.wrong += other.wrong;
        self.false_shadow += other.false_shadow;
        self.false_lit += other.false_lit;
    }
}

fn ratio(a: u64, b: u64) -> f64 {
    if b == 0 {
        0.0
    } else {
        a as f64 / b as f64
    }
}

/// The accuracy of one light's mask.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Comparison {
    /// Every pixel both masks decide.
    pub all: WrongPixels,
    /// Pixels within `edge_band_px` of a true shadow edge.
    pub edge_band: WrongPixels,
    /// Half-width of the edge band, in pixels.
    pub edge_band_px: f32,
    /// Distance in pixels from the worst wrong pixel to the nearest true edge pixel (`None`
    /// when no pixel is wrong; the image diagonal when the truth has no edge at all).
    pub max_wrong_distance_px: Option<f32>,
    /// Pixels exactly one of the masks decides.
    pub undecided: u64,
}

impl Comparison {
    /// Compares `technique` with `truth`; the edge band reaches [`EDGE_BAND_PX`].
    pub fn new(technique: &ShadowMask, truth: &ShadowMask) -> ReferenceResult<Self> {
        Self::with_band(technique, truth, EDGE_BAND_PX)
    }

    /// Compares `technique` with `truth` with an edge band of `band_px` pixels.
    pub fn with_band(technique: &ShadowMask, truth: &ShadowMask, band_px: f32) -> ReferenceResult<Self> {
        if (technique.width, technique.height) != (truth.width, truth.height) {
            return Err(ReferenceError::SizeMismatch {
                what: "technique mask",
                got: (technique.width as usize, technique.height as usize),
                expected: (truth.width as usize, truth.height as usize),
            });
        }
        let distance = edge_distance(truth);
        let mut all = WrongPixels::default();
        let mut edge_band = WrongPixels::default();
        let mut undecided = 0;
        let mut max_wrong: Option<f32> = None;
        let diagonal = (truth.width as f32).hypot(truth.height as f32);
        for (i, (t, r)) in technique.shadowed.iter().zip(&truth.shadowed).enumerate() {
            let (t, r) = match (t, r) {
                (Some(t), Some(r)) => (*t, *r),
                (None, None) => continue,
                _ => {
                    undecided += 1;
                    continue;
                }
            };
            all.add(t, r);
            let d = distance[i];
            if d <= band_px {
                edge_band.add(t, r);
            }
            if t != r {
                let d = if d.is_finite() { d } else { diagonal };
                max_wrong = Some(max_wrong.map_or(d, |m| m.max(d)));
            }
        }
        Ok(Self { all, edge_band, edge_band_px: band_px, max_wrong_distance_px: max_wrong, undecided })
    }
}

/// Per pixel, the distance to the nearest true edge pixel: a decided pixel with a 4-neighbour
/// decided the other way.
pub fn edge_distance(truth: &ShadowMask) -> Vec<f32> {
    let (w, h) = (truth.width as usize, truth.height as usize);
    let at = |x: usize, y: usize| truth.shadowed[y * w + x];
    let seeds: Vec<bool> = (0..w * h)
        .map(|i| {
            let (x, y) = (i % w, i / w);
            let Some(s) = at(x, y) else { return false };
            let other = |nx: usize, ny: usize| at(nx, ny).is_some_and(|n| n != s);
            (x > 0 && other(x - 1, y))
                || (x + 1 < w && other(x + 1, y))
                || (y > 0 && other(x, y - 1))
                || (y + 1 < h && other(x, y + 1))
        })
        .collect();
    distance_to_seeds(w, h, &seeds)
}

/// The error image (RGBA8, row 0 at the top): false shadow red, false light cyan, correct
/// shadow dark grey, correct light light grey, undecided dark blue, elsewhere black.
pub fn error_image(technique: &ShadowMask, truth: &ShadowMask) -> Vec<u8> {
    technique
        .shadowed
        .iter()
        .zip(&truth.shadowed)
        .flat_map(|(t, r)| match (t, r) {
            (Some(true), Some(false)) => [255, 0, 0, 255],
            (Some(false), Some(true)) => [0, 255, 255, 255],
            (Some(true), Some(true)) => [64, 64, 64, 255],
            (Some(false), Some(false)) => [190, 190, 190, 255],
            (None, None) => [0, 0, 0, 255],
            _ => [0, 0, 96, 255],
        })
        .collect()
}

/// Writes [`error_image`] as a PNG.
pub fn save_error_png(technique: &ShadowMask, truth: &ShadowMask, path: &std::path::Path) -> ReferenceResult<()> {
    let rgba = error_image(technique, truth);
    image::save_buffer(path, &rgba, truth.width, truth.height, image::ColorType::Rgba8)
        .map_err(|e| ReferenceError::Output { path: path.to_owned(), message: e.to_string() })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A half-plane mask: shadowed where `x < edge`, every pixel decided.
    fn half_plane(width: u32, height: u32, edge: u32) -> ShadowMask {
        let values = (0..width * height).map(|i| Some(i % width < edge)).collect();
        ShadowMask::new(width, height, values).expect("size")
    }

    #[test]
    fn identical_masks_have_no_error() {
        let m = half_plane(40, 30, 20);
        let c = Comparison::new(&m, &m).expect("same size");
        assert_eq!(c.all, WrongPixels { compared: 1200, wrong: 0, false_shadow: 0, false_lit: 0 });
        assert_eq!(c.max_wrong_distance_px, None);
        // Edge pixels: columns 19 and 20; the band of 2 px covers columns 17..=22.
        assert_eq!(c.edge_band.compared, 6 * 30);
    }

    #[test]
    fn a_shifted_edge_is_all_false_shadow() {
        let truth = half_plane(40, 30, 20);
        let technique = half_plane(40, 30, 23); // columns 20, 21, 22 wrongly shadowed
        let c = Comparison::new(&technique, &truth).expect("same size");
        assert_eq!(c.all.wrong, 3 * 30);
        assert_eq!(c.all.false_shadow, 3 * 30);
        assert_eq!(c.all.false_lit, 0);
        assert!((c.all.fraction() - 90.0 / 1200.0).abs() < 1e-12);
        // Column 22 lies 2 px from the nearest edge pixel (column 20).
        assert_eq!(c.max_wrong_distance_px, Some(2.0));
        // Within the band (columns 17..=22) all three wrong columns count.
        assert_eq!(c.edge_band.wrong, 90);
        let reversed = Comparison::new(&truth, &technique).expect("same size");
        assert_eq!(reversed.all.false_lit, 90);
        assert_eq!(reversed.all.false_shadow, 0);
    }

    #[test]
    fn an_isolated_wrong_pixel_far_from_the_edge() {
        let truth = half_plane(40, 30, 10);
        let mut technique = truth.clone();
        technique.shadowed[15 * 40 + 35] = Some(true); // 25 px right of column 10
        let c = Comparison::new(&technique, &truth).expect("same size");
        assert_eq!(c.all.wrong, 1);
        assert_eq!(c.edge_band.wrong, 0);
        assert_eq!(c.max_wrong_distance_px, Some(25.0));
    }

    #[test]
    fn undecided_pixels_are_not_wrong() {
        let truth = half_plane(8, 8, 4);
        let mut technique = truth.clone();
        technique.shadowed[0] = None;
        let mut truth2 = truth.clone();
        truth2.shadowed[1] = None;
        technique.shadowed[1] = Some(false);
        let c = Comparison::new(&technique, &truth2).expect("same size");
        assert_eq!(c.undecided, 2);
        assert_eq!(c.all.compared, 62);
        assert_eq!(c.all.wrong, 0);
        let img = error_image(&technique, &truth2);
        assert_eq!(&img[..4], &[0, 0, 96, 255]);
        assert_eq!(&img[8..12], &[64, 64, 64, 255]);
    }

    #[test]
    fn sizes_must_match() {
        let a = half_plane(8, 8, 4);
        let b = half_plane(8, 9, 4);
        assert!(matches!(Comparison::new(&a, &b), Err(ReferenceError::SizeMismatch { .. })));
    }
}
