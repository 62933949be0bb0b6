//! `umbra-bench frame-cost`: the host side of a frame, over many frames of one renderer — the
//! CPU time per frame (split into prepare, record and submit-wait) early and late, and the
//! device-memory allocations and queue submissions per frame — so that a frame's host cost
//! can be seen not to grow with the frames rendered and a warm frame to allocate nothing; with
//! `--volume-build gpu`, the GPU time of the volumes' stages (classify, silhouettes, the
//! counting draws) and the process's peak resident memory.

use crate::{scenes, BenchResult};
use umbra_shadows::{FrameReport, PassId, Renderer, RendererDesc, VolumeBuild};

/// Arguments of `umbra-bench frame-cost`.
#[derive(clap::Args, Debug)]
pub struct FrameCostArgs {
    /// Scenes: procedural names, scene files or glTF paths.
    #[arg(long, value_delimiter = ',', default_value = "cubes,tree,sixteen-bunnies.toml")]
    scenes: Vec<String>,
    /// Techniques, by short name (every technique that shadows a light by default).
    #[arg(long, value_delimiter = ',', default_values_t = crate::sweep::short_names())]
    techniques: Vec<String>,
    /// Image size, WIDTHxHEIGHT.
    #[arg(long, default_value = "512x384", value_parser = crate::parse_size)]
    size: (u32, u32),
    /// Frames per scene and technique (at least 21: the first, then two windows of 10).
    #[arg(long, default_value_t = 60, value_parser = clap::value_parser!(u32).range(21..=100_000))]
    frames: u32,
    /// Where shadow volumes (sv, hybrid) are built: auto, cpu or gpu
    /// (`ShadowVolumeSettings::build`).
    #[arg(long, default_value = "auto", value_parser = crate::parse_volume_build)]
    volume_build: VolumeBuild,
    #[command(flatten)]
    lights: scenes::LightArgs,
}

/// Renders every scene × technique `frames` times with one renderer (the lights changed as
/// `--spot-lights` and `--light-range` say, for every technique alike) and prints one line
/// each.
pub fn run(args: &FrameCostArgs) -> BenchResult<()> {
    let ctx = umbra_vk::Context::new()?;
    println!("device: {}; volumes built on the {:?}", ctx.capabilities().driver(), args.volume_build);
    println!(
        "{:<22} {:<7} {:>9} {:>9} {:>9} {:>9} {:>9} {:>8} {:>8} {:>8} {:>7} {:>7} {:>5} {:>8} {:>8} {:>8} {:>7}",
        "scene",
        "tech",
        "first_ms",
        "early_ms",
        "late_ms",
        "host_early",
        "host_late",
        "prep_ms",
        "rec_ms",
        "wait_ms",
        "alloc1",
        "alloc_w",
        "subm",
        "class_ms",
        "silh_ms",
        "draw_ms",
        "rss_mb"
    );
    for name in &args.scenes {
        for short in &args.techniques {
            let Some(technique) = crate::sweep::technique(short) else {
                println!("{name} {short}: not a technique");
                continue;
            };
            let mut scene = scenes::load(name, args.lights)?;
            for light in &mut scene.lights {
                light.technique = technique;
            }
            let mut desc = RendererDesc::new(args.size.0, args.size.1);
            desc.shadow_volume.build = args.volume_build;
            let mut renderer = Renderer::new(&ctx, desc)?;
            let mut reports = Vec::with_capacity(args.frames as usize);
            for _ in 0..args.frames {
                reports.push(renderer.render(&scene)?.report);
            }
            println!("{}", line(name, short, &reports));
        }
    }
    Ok(())
}

/// GPU ms of a frame's passes that `stage` names, over every light; `None` when the frame
/// has no such pass (the CPU path has no classify or silhouettes stage).
fn stage_ms(r: &FrameReport, stage: fn(&PassId) -> bool) -> Option<f64> {
    let mut times = r.passes.iter().filter(|p| stage(&p.id)).filter_map(|p| p.gpu_ms).peekable();
    times.peek()?;
    Some(times.sum())
}

/// The median of the late frames' [`stage_ms`], `-` where no frame ran the stage.
fn stage_cell(late: &[FrameReport], stage: fn(&PassId) -> bool) -> String {
    let mut v: Vec<f64> = late.iter().filter_map(|r| stage_ms(r, stage)).collect();
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).map_or_else(|| "-".into(), |m| format!("{m:.2}"))
}

/// The GPU-built volumes' stages: classify, silhouettes, and the counting draws (shadow
/// volumes' stencil pass or the hybrid's masked volumes).
const STAGES: [fn(&PassId) -> bool; 3] = [
    |id| matches!(id, PassId::VolumeClassify(_)),
    |id| matches!(id, PassId::VolumeSilhouettes(_)),
    |id| matches!(id, PassId::ShadowVolume(_) | PassId::HybridVolumes(_)),
];

/// The process's peak resident memory so far, in MB (`VmHWM` of `/proc/self/status`; 0 where
/// there is none).
fn peak_rss_mb() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let kb = status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<f64>().ok());
    kb.unwrap_or(0.0) / 1024.0
}

/// Host time of a frame: all of it but the submit-wait.
fn host(r: &FrameReport) -> f64 {
    r.cpu_frame_ms - r.cpu_submit_wait_ms
}

/// One table line: frame 1, the median of frames 2–11 and of the last 10 (whole frame, then
/// host time without the submit-wait), the warm frames' medians of the split, the first
/// frame's allocations, the most any warm frame made, the most submissions a warm frame
/// made, the late frames' median GPU ms of the volumes' stages, and the peak RSS so far.
fn line(name: &str, short: &str, reports: &[FrameReport]) -> String {
    let warm = &reports[1..];
    let median = |frames: &[FrameReport], f: fn(&FrameReport) -> f64| {
        let mut v: Vec<f64> = frames.iter().map(f).collect();
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let late = &reports[reports.len() - 10..];
    format!(
        "{:<22} {:<7} {:>9.2} {:>9.2} {:>9.2} {:>9.2} {:>9.2} {:>8.2} {:>8.2} {:>8.2} {:>7} {:>7} {:>5} {:>8} {:>8} {:>8} {:>7.0}",
        name.rsplit('/').next().unwrap_or(name),
        short,
        reports[0].cpu_frame_ms,
        median(&reports[1..11], |r| r.cpu_frame_ms),
        median(late, |r| r.cpu_frame_ms),
        median(&reports[1..11], host),
        median(late, host),
        median(warm, |r| r.cpu_prepare_ms),
        median(warm, |r| r.cpu_record_ms),
        median(warm, |r| r.cpu_submit_wait_ms),
        reports[0].memory_allocations,
        warm.iter().map(|r| r.memory_allocations).max().unwrap_or(0),
        warm.iter().map(|r| r.submissions).max().unwrap_or(0),
        stage_cell(late, STAGES[0]),
        stage_cell(late, STAGES[1]),
        stage_cell(late, STAGES[2]),
        peak_rss_mb(),
    )
}
