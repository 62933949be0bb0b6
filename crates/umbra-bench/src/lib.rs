//! # umbra-bench — what accuracy costs in time
//!
//! `umbra-bench sweep` renders every configuration of every scene (technique × shadow-map size
//! × filter × computation mask), times each pass on the GPU over N frames after a warm-up,
//! scores the last frame of each against the exact reference (`umbra-reference`: obvhs shadow
//! rays from the frame's own G-buffer), and writes to `--out`:
//! `results.json` (one record per run), `results.csv`, `summary.md`, per scene
//! `<scene>-accuracy-vs-time.png` (with the Pareto front), `<scene>-passes.png` (Chan–Durand
//! Fig. 12) and `<scene>-fill.png` (Fig. 11), and `images/<run>-error.png` (false shadow red,
//! false light cyan).
//!
//! ```text
//! cargo run --release -p umbra-bench -- sweep --scenes cubes,cage --techniques sm,sv,hybrid \
//!     --sm-sizes 256,512,1024 --size 1024x768 --frames 30 --out bench-out
//! ```
//!
//! `umbra-bench plot --results DIR/results.json --out DIR2` reads a sweep's `results.json` back
//! and writes its CSV, summary and plots again without rendering (the JSON and CSV come out
//! byte for byte the same): a chart's style can change without a new sweep.
//!
//! `umbra-bench poster` renders one scene with every technique on the same frame, scores each
//! against the exact reference, and writes `poster.png` (per technique its image, its error
//! image and a caption with GPU ms and wrong pixels), `poster.json` with the same numbers and a
//! table on stdout; the numbers come from the same measurement as the sweep's
//! ([`sweep::measure`]), so the poster's wrong-pixel counts equal the sweep's for the same
//! configuration. `cargo run --release --example demo` is this poster.
//!
//! `umbra-bench hard-cases` runs the hard-case conformance suite (`tests/hard-cases/`,
//! `umbra-conformance`) on each device named by `--devices` with the validation layer on, and
//! writes `hard-cases.md` (cases × techniques × devices), a picture per case and
//! `results/hard-cases.json` under `--out` (`bash ci/hard-cases.sh` writes `docs/`).
//!
//! `umbra-bench compare --results A/results.json,B/results.json,… --out PAGE.md` sets several
//! devices' sweeps side by side: per scene and device the fastest run at shadow-volume and at
//! ray-tracing accuracy, where the device changes which technique that is, and which runs score
//! different wrong pixels (`bash ci/results.sh` writes `docs/results/drivers.md`).
//!
//! Configurations the device cannot run (the depth-bounds mask without `depthBounds`, a
//! silhouette map for a light that needs a cube map, …) are skipped with the reason logged and
//! listed in `results.json` and `summary.md`.

#![warn(missing_docs)]

pub mod bvh;
pub mod cli;
pub mod compare;
mod error;
pub mod fingerprint;
pub mod frame_cost;
pub mod hard_cases;
pub mod plots;
pub mod poster;
pub mod record;
pub mod scenes;
pub mod summary;
pub mod sweep;

pub use error::{BenchError, BenchResult};

/// Most frames `--frames` times per configuration.
pub const MAX_FRAMES: u64 = 10_000;
/// Most frames `--warmup` renders and discards first.
pub const MAX_WARMUP: u64 = 1_000;

/// `--frames`: 1 to [`MAX_FRAMES`].
pub(crate) fn frames_parser() -> clap::builder::RangedU64ValueParser<usize> {
    clap::builder::RangedU64ValueParser::<usize>::new().range(1..=MAX_FRAMES)
}

/// `--warmup`: 0 to [`MAX_WARMUP`].
pub(crate) fn warmup_parser() -> clap::builder::RangedU64ValueParser<usize> {
    clap::builder::RangedU64ValueParser::<usize>::new().range(0..=MAX_WARMUP)
}

/// `--sm-size(s)`: at least `ShadowMapSettings::MIN_RESOLUTION` (the device's maximum is
/// checked per light by the renderer, which names the limit; the sweep skips such sizes).
pub(crate) fn sm_size_parser() -> clap::builder::RangedI64ValueParser<u32> {
    clap::value_parser!(u32).range(i64::from(umbra_shadows::ShadowMapSettings::MIN_RESOLUTION)..)
}

/// Parses a sweep's map size: a resolution of at least `ShadowMapSettings::MIN_RESOLUTION`,
/// or `default` (`None`: the size the renderer picks by default).
pub fn parse_sweep_size(s: &str) -> Result<Option<u32>, String> {
    let min = umbra_shadows::ShadowMapSettings::MIN_RESOLUTION;
    match s.trim() {
        "default" => Ok(None),
        t => match t.parse::<u32>() {
            Ok(v) if v >= min => Ok(Some(v)),
            Ok(v) => Err(format!("{v} is below the least map size, {min}")),
            Err(e) => Err(format!("{t:?}: {e} (a size of at least {min}, or `default`)")),
        },
    }
}

/// Parses a light range: a finite distance above 0, at most `umbra_scene::MAX_COORDINATE`.
pub fn parse_light_range(s: &str) -> Result<f32, String> {
    let v = s.trim().parse::<f32>().map_err(|e| format!("{s:?}: {e}"))?;
    if v.is_finite() && v > 0.0 && v <= umbra_scene::MAX_COORDINATE {
        Ok(v)
    } else {
        Err(format!("{} is not a finite distance in (0, {:e}]", s.trim(), umbra_scene::MAX_COORDINATE))
    }
}

/// Parses where shadow volumes are built: `auto`, `cpu` or `gpu`.
pub fn parse_volume_build(s: &str) -> Result<umbra_shadows::VolumeBuild, String> {
    use umbra_shadows::VolumeBuild;
    match s {
        "auto" => Ok(VolumeBuild::Auto),
        "cpu" => Ok(VolumeBuild::Cpu),
        "gpu" => Ok(VolumeBuild::Gpu),
        _ => Err(format!("{s:?}: expected auto, cpu or gpu")),
    }
}

/// Parses `WIDTHxHEIGHT`, each side at least 1.
pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(|| format!("{s:?} is not WIDTHxHEIGHT"))?;
    let parse = |v: &str| v.trim().parse::<u32>().map_err(|e| format!("{v:?}: {e}"));
    match (parse(w)?, parse(h)?) {
        (0, _) | (_, 0) => Err(format!("{s:?}: the size must be at least 1x1")),
        size => Ok(size),
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn sizes_parse_and_zero_sides_are_refused() {
        assert_eq!(super::parse_size("512x384"), Ok((512, 384)));
        assert_eq!(super::parse_size("64X48"), Ok((64, 48)));
        assert!(super::parse_size("0x384").is_err());
        assert!(super::parse_size("512x0").is_err());
        assert!(super::parse_size("512").is_err());
    }
}
