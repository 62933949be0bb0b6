//! Parsers and bounds of the examples' numeric flags: every value is checked when the command
//! line is read (clap names the flag and the value in the message), so that a non-finite or
//! absurd number never reaches the renderer, and nothing is blamed on the wrong thing later.

use umbra::shadows::{DepthBias, ShadowMapSettings};

/// Most frames `--warmup` renders and discards before the reported one.
pub const MAX_WARMUP: u32 = 1000;
/// Most frames `--frames` lets a windowed run present.
pub const MAX_FRAMES: u64 = 1_000_000;
/// Longest `--hold`, in seconds.
pub const MAX_HOLD_SECONDS: f32 = 3600.0;
/// Largest `--time` magnitude, in seconds (the animation repeats every 12 s; beyond this, f32
/// seconds lose the precision of a frame).
pub const MAX_TIME_SECONDS: f32 = 1e6;

/// `WIDTHxHEIGHT`, each side at least 1 (the device's maximum is checked by the renderer,
/// which names the limit): the bench's parser, so every binary reads sizes alike.
pub use umbra_bench::parse_size;

/// `--volume-build`: auto, cpu or gpu (the bench's parser).
pub use umbra_bench::parse_volume_build;

/// A finite `f32` in `min..=max`.
fn finite_in(s: &str, min: f32, max: f32) -> Result<f32, String> {
    let v = s.trim().parse::<f32>().map_err(|e| format!("{s:?}: {e}"))?;
    if v.is_finite() && (min..=max).contains(&v) {
        Ok(v)
    } else {
        Err(format!("{} is not a finite number in {min}..={max}", s.trim()))
    }
}

/// `--time`: finite seconds, at most [`MAX_TIME_SECONDS`] either way.
pub fn parse_time(s: &str) -> Result<f32, String> {
    finite_in(s, -MAX_TIME_SECONDS, MAX_TIME_SECONDS)
}

/// `--hold`: finite seconds in `0..=`[`MAX_HOLD_SECONDS`].
pub fn parse_hold(s: &str) -> Result<f32, String> {
    finite_in(s, 0.0, MAX_HOLD_SECONDS)
}

/// `--bias CONSTANT,SLOPE`, each in the range the renderer accepts
/// ([`ShadowMapSettings::validate`]).
#[allow(dead_code)]
pub fn parse_bias(s: &str) -> Result<DepthBias, String> {
    let (c, k) = s.split_once(',').ok_or_else(|| format!("{s:?} is not CONSTANT,SLOPE"))?;
    let num = |v: &str| v.trim().parse::<f32>().map_err(|e| format!("{v:?}: {e}"));
    let bias = DepthBias { constant: num(c)?, slope: num(k)?, clamp_texels: None };
    ShadowMapSettings { bias, ..ShadowMapSettings::DEFAULT }.validate().map_err(|e| e.to_string())?;
    Ok(bias)
}

/// `--normal-offset`: world units, in the range the renderer accepts.
#[allow(dead_code)]
pub fn parse_normal_offset(s: &str) -> Result<f32, String> {
    finite_in(s, 0.0, ShadowMapSettings::MAX_NORMAL_OFFSET)
}

/// `--sm-size`: at least [`ShadowMapSettings::MIN_RESOLUTION`] (the device's maximum is
/// checked per light by the renderer, which names the limit).
#[allow(dead_code)]
pub fn parse_sm_size(s: &str) -> Result<u32, String> {
    let v = s.trim().parse::<u32>().map_err(|e| format!("{s:?}: {e}"))?;
    let min = ShadowMapSettings::MIN_RESOLUTION;
    if v < min {
        return Err(format!("{v} is below the smallest shadow map, {min} texels per side"));
    }
    Ok(v)
}
