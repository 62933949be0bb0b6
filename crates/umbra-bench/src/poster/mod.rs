//! The poster: one scene, every technique on the same frame, each scored against the exact
//! reference, in one picture.
//!
//! Every technique is measured by [`sweep::measure`], the sweep's own function, with the
//! sweep's renderer settings: the poster's numbers are the sweep's numbers for the same
//! configuration, and `poster.json` names the `umbra-bench sweep` command that reproduces them.

mod draw;

use crate::record::{Config, Record, Skipped};
use crate::sweep::{self, Measured};
use crate::{plots, scenes, BenchError, BenchResult};
use serde::Serialize;
use std::path::{Path, PathBuf};
use umbra_reference::SceneBvh;
use umbra_scene::Technique;
use umbra_shadows::{MaskKind, ShadowFilter};
use umbra_vk::Context;

/// Flags of `umbra-bench poster` (and of `cargo run --example demo`).
#[derive(clap::Args, Clone, Debug)]
pub struct PosterArgs {
    /// The scene: a procedural name, a .toml scene file or a .glb/.gltf path. The default,
    /// Chan–Durand's dragon cage, shows every technique's kind of error at once.
    #[arg(long, default_value = "cage")]
    pub scene: String,
    /// Image size per technique, WIDTHxHEIGHT.
    #[arg(long, default_value = "512x384", value_parser = crate::parse_size)]
    pub size: (u32, u32),
    /// Shadow-map size of the shadow map and the silhouette map (at least 64).
    #[arg(long, default_value_t = 1024, value_parser = crate::sm_size_parser())]
    pub sm_size: u32,
    /// Map size of the hybrid and the ray-traced hybrid, whose maps only classify pixels (at
    /// least 64; default: the size the renderer picks for the frame).
    #[arg(long, value_parser = crate::sm_size_parser())]
    pub hybrid_size: Option<u32>,
    /// The shadow map's filter: nearest, pcf2x2, pcf3x3, pcf5x5.
    #[arg(long, default_value = "pcf2x2")]
    pub filter: ShadowFilter,
    /// The hybrid's computation mask (default: depth-bounds where the device has the feature,
    /// the stencil fallback elsewhere).
    #[arg(long)]
    pub mask: Option<MaskKind>,
    /// Timed frames per technique (1 to 10000).
    #[arg(long, default_value_t = 30, value_parser = crate::frames_parser())]
    pub frames: usize,
    /// Frames rendered and discarded first (0 to 1000).
    #[arg(long, default_value_t = 2, value_parser = crate::warmup_parser())]
    pub warmup: usize,
    /// Output folder: `poster.png`, `poster.json`, `images/*-error.png`.
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    /// What to do to the scene's lights first (`--spot-lights`, `--light-range`).
    #[command(flatten)]
    pub lights: scenes::LightArgs,
}

/// What `poster.json` holds.
#[derive(Clone, Debug, Serialize)]
pub struct Poster {
    /// Device name.
    pub device: String,
    /// Driver name and version.
    pub driver: String,
    /// The scene as given.
    pub scene: String,
    /// Image size per technique.
    pub width: u32,
    /// Image size per technique.
    pub height: u32,
    /// The `umbra-bench sweep` command whose records include [`Poster::records`].
    pub bench_command: String,
    /// One record per technique, exactly as the sweep writes them to `results.json`.
    pub records: Vec<Record>,
    /// Techniques the device could not run, with the reason.
    pub skipped: Vec<Skipped>,
}

/// The poster's configurations, one per technique in the sweep's order, for a device with (or without) `depthBounds`.
pub fn configs(args: &PosterArgs, depth_bounds: bool) -> Vec<Config> {
    let mask = args.mask.unwrap_or(MaskKind::best_for(depth_bounds));
    sweep::TECHNIQUES
        .iter()
        .map(|t| t.short())
        .map(|technique| Config {
            scene: args.scene.clone(),
            technique,
            // Shadow volumes and shadow rays have no map; the hybrids' only classifies.
            sm_size: match technique {
                "sv" | "rt" => None,
                "hybrid" | "hybrid-rt" => args.hybrid_size,
                _ => Some(args.sm_size),
            },
            filter: (technique == "sm").then_some(args.filter.name()),
            mask: (technique == "hybrid").then_some(mask.name()),
            bvh: None,
        })
        .collect()
}

/// The sweep command that measures the same configurations (among others, where the hybrids'
/// map size differs from the others').
pub fn bench_command(args: &PosterArgs, depth_bounds: bool) -> String {
    let mask = args.mask.unwrap_or(MaskKind::best_for(depth_bounds));
    let sizes = match args.hybrid_size {
        Some(s) if s == args.sm_size => s.to_string(),
        Some(s) => format!("{},{s}", args.sm_size),
        None => format!("{},default", args.sm_size),
    };
    format!(
        "umbra-bench sweep --scenes {} --techniques {} --sm-sizes {} --filters {} --masks {} --size {}x{} \
         --frames {} --warmup {}{}{}",
        args.scene,
        sweep::TECHNIQUES.iter().map(|t| t.short()).collect::<Vec<_>>().join(","),
        sizes,
        args.filter.name(),
        mask.name(),
        args.size.0,
        args.size.1,
        args.frames,
        args.warmup,
        if args.lights.spot_lights { " --spot-lights" } else { "" },
        args.lights.light_range.map_or_else(String::new, |r| format!(" --light-range {r}"))
    )
}

/// Measures every technique on the scene and writes `poster.png` and `poster.json` to
/// `args.out`, printing a table; the poster.
pub fn run_cli(args: &PosterArgs) -> BenchResult<()> {
    let ctx = Context::new()?;
    let poster = run(&ctx, args)?;
    println!("{}", table(&poster));
    println!("wrote {} and {}", args.out.join("poster.png").display(), args.out.join("poster.json").display());
    Ok(())
}

/// Measures every technique on `ctx`'s device and writes `poster.png` and `poster.json`.
pub fn run(ctx: &Context, args: &PosterArgs) -> BenchResult<Poster> {
    plots::load_font()?;
    std::fs::create_dir_all(&args.out).map_err(|e| BenchError::output(&args.out, e))?;
    let caps = ctx.capabilities().clone();
    let scene = scenes::load(&args.scene, args.lights)?;
    let bvh = SceneBvh::build(&scene);
    let mut measured: Vec<Measured> = Vec::new();
    let mut skipped = Vec::new();
    for config in configs(args, caps.depth_bounds) {
        log::info!("{}: {}", args.scene, config.label());
        let outcome = match sweep::unsupported(ctx, &config) {
            Some(reason) => Err(reason),
            None => sweep::measure(ctx, &scene, &bvh, &config, args.size, args.warmup, args.frames, false, &args.out)?,
        };
        match outcome {
            Ok(m) => measured.push(m),
            Err(reason) => skipped.push(sweep::skip(&config, reason)),
        }
    }
    let poster = Poster {
        device: caps.device_name.clone(),
        driver: caps.driver(),
        scene: args.scene.clone(),
        width: args.size.0,
        height: args.size.1,
        bench_command: bench_command(args, caps.depth_bounds),
        records: measured.iter().map(|m| m.record.clone()).collect(),
        skipped,
    };
    draw::save(&poster, &measured, &args.out.join("poster.png"))?;
    write_json(&poster, &args.out.join("poster.json"))?;
    Ok(poster)
}

fn write_json(poster: &Poster, path: &Path) -> BenchResult<()> {
    let text = serde_json::to_string_pretty(poster).map_err(|e| BenchError::output(path, e))?;
    std::fs::write(path, text).map_err(|e| BenchError::output(path, e))
}

/// What a technique is called on the poster ([`Technique::title`] of its short name).
pub fn technique_title(short: &str) -> &'static str {
    sweep::technique(short).map_or("technique", Technique::title)
}

/// One line per technique: configuration, GPU ms (median, p25–p75), wrong pixels.
pub fn table(poster: &Poster) -> String {
    let mut s = format!(
        "{} on {} ({}), {}x{}\n{:<26} {:>26} {:>9} {:>9}\n",
        poster.scene,
        poster.device,
        poster.driver,
        poster.width,
        poster.height,
        "configuration",
        "GPU ms median (p25–p75)",
        "wrong px",
        "wrong %"
    );
    for r in &poster.records {
        let gpu = r.gpu_ms.map_or_else(|| "n/a".into(), |g| format!("{:.3} ({:.3}–{:.3})", g.median, g.p25, g.p75));
        let a = &r.accuracy;
        s += &format!("{:<26} {:>26} {:>9} {:>9.4}\n", r.config.label(), gpu, a.all.wrong, 100.0 * a.wrong_fraction);
    }
    for k in &poster.skipped {
        s += &format!("{:<26} skipped: {}\n", k.config.label(), k.reason);
    }
    s += &format!("same numbers: {}", poster.bench_command);
    s
}
