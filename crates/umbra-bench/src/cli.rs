//! The `umbra-bench` command line: `sweep`, `poster`, `hard-cases`, `fingerprint`, `frame-cost`,
//! `bvh`, `plot` and `compare`.

use crate::record::{Record, Results, CSV_HEADER};
use crate::sweep::{self, Plan};
use crate::{
    bvh, compare, fingerprint, frame_cost, hard_cases, plots, poster, scenes, summary, BenchError, BenchResult,
};
use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use std::path::{Path, PathBuf};
use umbra_reference::SceneBvh;
use umbra_scene::Technique;
use umbra_shadows::ray_traced::BvhLayout;
use umbra_shadows::{MaskKind, ShadowFilter};

#[derive(Parser, Debug)]
#[command(name = "umbra-bench", about = "Accuracy-versus-time sweeps of umbra's shadow techniques")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Render, time and score every configuration; write results, plots and a summary.
    Sweep(SweepArgs),
    /// Render one scene with every technique, score each, and write one poster PNG.
    Poster(poster::PosterArgs),
    /// Run the hard-case conformance suite on several devices; write its table and pictures.
    HardCases(hard_cases::HardCasesArgs),
    /// Print a hash of every frame's pixels, views and report (times left out) per scene,
    /// technique and renderer variant: `diff` two runs to prove a refactor kept behaviour.
    Fingerprint(fingerprint::FingerprintArgs),
    /// Render many frames with one renderer and print the host cost per frame (prepare,
    /// record, submit-wait), early and late, with allocations and submissions per frame.
    FrameCost(frame_cost::FrameCostArgs),
    /// Build ray-traced shadows' two-level BVH per scene and walk every pixel's shadow rays on
    /// the host: build and rebuild times, memory, depth, nodes and triangles per ray.
    Bvh(bvh::BvhArgs),
    /// Read a sweep's `results.json` and write its CSV, plots and summary again, without
    /// rendering: charts follow a change of style without a new sweep.
    Plot(PlotArgs),
    /// Read several devices' sweeps (`results.json`) and write one page: per scene and device
    /// the fastest technique at each accuracy, where the device changes it, and which runs
    /// score different wrong pixels.
    Compare(compare::CompareArgs),
}

#[derive(clap::Args, Debug)]
struct PlotArgs {
    /// A sweep's `results.json`.
    #[arg(long)]
    results: PathBuf,
    /// Output folder (created if missing).
    #[arg(long, default_value = "bench-out")]
    out: PathBuf,
}

#[derive(clap::Args, Debug)]
struct SweepArgs {
    /// Scenes: procedural names (cylinder, ball, cubes, cage, tree, pins), .toml scene files or
    /// .glb/.gltf paths (a bare file name is also looked up in the repository's `assets/`, or in
    /// $UMBRA_ASSETS when set).
    #[arg(long, value_delimiter = ',', default_value = "cubes,cage,tree,cylinder")]
    scenes: Vec<String>,
    /// Techniques, by short name (every technique that shadows a light by default).
    #[arg(long, value_delimiter = ',', default_values_t = sweep::short_names())]
    techniques: Vec<String>,
    /// Shadow-map sizes (sm, silmap, hybrid, hybrid-rt), each at least 64, or `default` for
    /// the size the renderer picks by default.
    #[arg(long, value_delimiter = ',', default_value = "256,512,1024,2048,4096", value_parser = crate::parse_sweep_size)]
    sm_sizes: Vec<Option<u32>>,
    /// Shadow-map filters (sm): nearest, pcf2x2, pcf3x3, pcf5x5.
    #[arg(long, value_delimiter = ',', default_value = "nearest,pcf2x2")]
    filters: Vec<ShadowFilter>,
    /// Hybrid computation masks: depth-bounds, stencil, none.
    #[arg(long, value_delimiter = ',', default_value = "depth-bounds,stencil,none")]
    masks: Vec<MaskKind>,
    /// The meshes' BVH layouts for rt and hybrid-rt: binary, cwbvh.
    #[arg(long, value_delimiter = ',', default_value = "binary")]
    bvh: Vec<BvhLayout>,
    /// Image size, WIDTHxHEIGHT.
    #[arg(long, default_value = "1024x768", value_parser = crate::parse_size)]
    size: (u32, u32),
    /// Timed frames per configuration (1 to 10000).
    #[arg(long, default_value_t = 30, value_parser = crate::frames_parser())]
    frames: usize,
    /// Frames rendered and discarded first (shader compilation, caches), 0 to 1000.
    #[arg(long, default_value_t = 3, value_parser = crate::warmup_parser())]
    warmup: usize,
    /// Output folder (created if missing).
    #[arg(long, default_value = "bench-out")]
    out: PathBuf,
    #[command(flatten)]
    lights: scenes::LightArgs,
    /// Also measure every configuration without frame planning (`RendererDesc::cull` off):
    /// the summary's `--no-cull` column, and a check that the image is the same.
    #[arg(long)]
    no_cull: bool,
    /// Hide the progress bar.
    #[arg(long)]
    quiet: bool,
}

/// Parses the command line and runs it; prints the error and exits 1 on failure.
pub fn main() {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("info")).init();
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Sweep(args) => run_sweep(&args),
        Command::Poster(args) => poster::run_cli(&args),
        Command::HardCases(args) => hard_cases::run(&args),
        Command::Fingerprint(args) => fingerprint::run(&args),
        Command::FrameCost(args) => frame_cost::run(&args),
        Command::Bvh(args) => bvh::run(&args),
        Command::Plot(args) => run_plot(&args),
        Command::Compare(args) => compare::run(&args),
    };
    if let Err(e) = result {
        eprintln!("umbra-bench: {e}");
        std::process::exit(1);
    }
}

fn run_sweep(args: &SweepArgs) -> BenchResult<()> {
    let techniques = args
        .techniques
        .iter()
        .map(|t| {
            sweep::technique(t).map(Technique::short).ok_or_else(|| {
                let names: Vec<_> = sweep::TECHNIQUES.iter().map(|t| t.short()).collect();
                BenchError::Usage(format!("--techniques: {t:?} is not one of {}", names.join(", ")))
            })
        })
        .collect::<BenchResult<Vec<_>>>()?;
    plots::load_font()?;
    let plan = Plan {
        scenes: args.scenes.clone(),
        techniques,
        sm_sizes: args.sm_sizes.clone(),
        filters: args.filters.clone(),
        masks: args.masks.clone(),
        bvhs: args.bvh.clone(),
    };
    std::fs::create_dir_all(&args.out).map_err(|e| BenchError::output(&args.out, e))?;
    let ctx = umbra_vk::Context::new()?;
    let caps = ctx.capabilities().clone();
    log::info!("device: {} ({} {})", caps.device_name, caps.driver_name, caps.driver_info);

    let total: usize = plan.scenes.iter().map(|s| plan.configs(s).len()).sum();
    let bar = if args.quiet { ProgressBar::hidden() } else { ProgressBar::new(total as u64) };
    bar.set_style(
        ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {pos}/{len} {msg}")
            .map_err(|e| BenchError::Usage(e.to_string()))?
            .progress_chars("=> "),
    );
    let mut records: Vec<Record> = Vec::new();
    let mut skipped = Vec::new();
    for name in &plan.scenes {
        let scene = scenes::load(name, args.lights)?;
        let bvh = SceneBvh::build(&scene);
        log::info!("{name}: {} triangles, reference BVH built in {:.1} ms", scene.triangle_count(), bvh.build_ms());
        for config in plan.configs(name) {
            bar.set_message(format!("{name}: {}", config.label()));
            if let Some(reason) = sweep::unsupported(&ctx, &config) {
                skipped.push(sweep::skip(&config, reason));
            } else {
                match sweep::measure(
                    &ctx,
                    &scene,
                    &bvh,
                    &config,
                    args.size,
                    args.warmup,
                    args.frames,
                    args.no_cull,
                    &args.out,
                )? {
                    Ok(m) => records.push(m.record),
                    Err(reason) => skipped.push(sweep::skip(&config, reason)),
                }
            }
            bar.inc(1);
        }
    }
    bar.finish_with_message("done");

    let results = Results {
        device: caps.device_name.clone(),
        driver: caps.driver(),
        depth_bounds: caps.depth_bounds,
        timestamps: caps.timestamps,
        warmup: args.warmup,
        records,
        skipped,
    };
    write_outputs(&results, &plan.scenes, &args.out)
}

fn run_plot(args: &PlotArgs) -> BenchResult<()> {
    plots::load_font()?;
    let text = std::fs::read_to_string(&args.results).map_err(|e| BenchError::input(&args.results, e))?;
    let results: Results = serde_json::from_str(&text).map_err(|e| BenchError::input(&args.results, e))?;
    // The scenes in the order the sweep measured them.
    let mut scenes: Vec<String> = Vec::new();
    for r in &results.records {
        if !scenes.contains(&r.config.scene) {
            scenes.push(r.config.scene.clone());
        }
    }
    std::fs::create_dir_all(&args.out).map_err(|e| BenchError::output(&args.out, e))?;
    write_outputs(&results, &scenes, &args.out)
}

fn write_outputs(results: &Results, scenes: &[String], out: &Path) -> BenchResult<()> {
    let json = out.join("results.json");
    let text = serde_json::to_string_pretty(results).map_err(|e| BenchError::output(&json, e))?;
    std::fs::write(&json, text).map_err(|e| BenchError::output(&json, e))?;
    let csv_path = out.join("results.csv");
    let mut csv = csv::Writer::from_path(&csv_path).map_err(|e| BenchError::output(&csv_path, e))?;
    csv.write_record(CSV_HEADER).map_err(|e| BenchError::output(&csv_path, e))?;
    for r in &results.records {
        csv.write_record(r.csv_row()).map_err(|e| BenchError::output(&csv_path, e))?;
    }
    csv.flush().map_err(|e| BenchError::output(&csv_path, e))?;

    let mut plotted = Vec::new();
    for scene in scenes {
        let records: Vec<&Record> = results.records.iter().filter(|r| &r.config.scene == scene).collect();
        if records.is_empty() {
            continue;
        }
        let stem: String =
            scene.rsplit('/').next().unwrap_or(scene).chars().filter(|c| c.is_ascii_alphanumeric()).collect();
        let mut files = vec![format!("{stem}-accuracy-vs-time.png"), format!("{stem}-passes.png")];
        plots::accuracy_vs_time(&records, scene, &out.join(&files[0]))?;
        plots::pass_breakdown(&records, scene, &out.join(&files[1]))?;
        let fill = format!("{stem}-fill.png");
        if plots::fill_chart(&records, scene, &out.join(&fill))? {
            files.push(fill);
        }
        plotted.push((scene.clone(), files));
    }
    let md = out.join("summary.md");
    std::fs::write(&md, summary::markdown(results, scenes, &plotted)).map_err(|e| BenchError::output(&md, e))?;
    println!(
        "{} runs, {} skipped: wrote {}, {}, {} and {} plots",
        results.records.len(),
        results.skipped.len(),
        json.display(),
        csv_path.display(),
        md.display(),
        plotted.iter().map(|(_, f)| f.len()).sum::<usize>()
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unchecked_numbers_are_refused_naming_the_flag() {
        let cases: [(&[&str], &str); 10] = [
            (&["sweep", "--frames", "0"], "--frames"),
            (&["sweep", "--warmup", "18446744073709551615"], "--warmup"),
            (&["sweep", "--sm-sizes", "256,0"], "--sm-sizes"),
            (&["sweep", "--light-range", "nan"], "--light-range"),
            (&["sweep", "--light-range=-2"], "--light-range"),
            (&["sweep", "--size", "0x10"], "--size"),
            (&["poster", "--sm-size", "32"], "--sm-size"),
            (&["poster", "--frames", "0"], "--frames"),
            (&["poster", "--warmup", "5000"], "--warmup"),
            (&["hard-cases", "--size", "10x0"], "--size"),
        ];
        for (args, flag) in cases {
            let err =
                Cli::try_parse_from(std::iter::once("umbra-bench").chain(args.iter().copied())).expect_err("refused");
            let text = err.to_string();
            assert!(text.contains(&format!("'{flag} <")), "{args:?}: {text}");
        }
        let ok = ["umbra-bench", "sweep", "--frames", "1", "--warmup", "0", "--sm-sizes", "64", "--light-range", "5"];
        assert!(Cli::try_parse_from(ok).is_ok());
        let default = ["umbra-bench", "sweep", "--sm-sizes", "default,256"];
        assert!(Cli::try_parse_from(default).is_ok());
    }
}
