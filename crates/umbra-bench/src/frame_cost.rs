//! `umbra-bench frame-cost`: the host side of a frame, over many frames of one renderer — the
//! CPU time per frame (split into prepare, record and submit-wait) early and late, and the
//! device-memory allocations and queue submissions per frame — so that a frame's host cost
//! can be seen not to grow with the frames rendered and a warm frame to allocate nothing.

use crate::{scenes, BenchResult};
use umbra_shadows::{FrameReport, Renderer, RendererDesc};

/// Arguments of `umbra-bench frame-cost`.
#[derive(clap::Args, Debug)]
pub struct FrameCostArgs {
    /// Scenes: procedural names, scene files or glTF paths.
    #[arg(long, value_delimiter = ',', default_value = "cubes,tree,sixteen-bunnies.toml")]
    scenes: Vec<String>,
    /// Techniques (short names): sm, silmap, sv, hybrid, rt, hybrid-rt.
    #[arg(long, value_delimiter = ',', default_value = "sm,silmap,sv,hybrid,rt,hybrid-rt")]
    techniques: Vec<String>,
    /// Image size, WIDTHxHEIGHT.
    #[arg(long, default_value = "512x384", value_parser = crate::parse_size)]
    size: (u32, u32),
    /// Frames per scene and technique (at least 21: the first, then two windows of 10).
    #[arg(long, default_value_t = 60, value_parser = clap::value_parser!(u32).range(21..=100_000))]
    frames: u32,
}

/// Renders every scene × technique `frames` times with one renderer (point lights turned into
/// spots, as for every technique alike) and prints one line each.
pub fn run(args: &FrameCostArgs) -> BenchResult<()> {
    let ctx = umbra_vk::Context::new()?;
    println!("device: {}", ctx.capabilities().driver());
    println!(
        "{:<22} {:<7} {:>9} {:>9} {:>9} {:>9} {:>9} {:>8} {:>8} {:>8} {:>7} {:>7} {:>5}",
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
        "subm"
    );
    for name in &args.scenes {
        for short in &args.techniques {
            let Some(technique) = crate::sweep::technique(short) else {
                println!("{name} {short}: not a technique");
                continue;
            };
            let mut scene = scenes::load(name, true, None)?;
            for light in &mut scene.lights {
                light.technique = technique;
            }
            let mut renderer = Renderer::new(&ctx, RendererDesc::new(args.size.0, args.size.1))?;
            let mut reports = Vec::with_capacity(args.frames as usize);
            for _ in 0..args.frames {
                reports.push(renderer.render(&scene)?.report);
            }
            println!("{}", line(name, short, &reports));
        }
    }
    Ok(())
}

/// Host time of a frame: all of it but the submit-wait.
fn host(r: &FrameReport) -> f64 {
    r.cpu_frame_ms - r.cpu_submit_wait_ms
}

/// One table line: frame 1, the median of frames 2–11 and of the last 10 (whole frame, then
/// host time without the submit-wait), the warm frames' medians of the split, the first
/// frame's allocations, the most any warm frame made, and the most submissions a warm frame
/// made.
fn line(name: &str, short: &str, reports: &[FrameReport]) -> String {
    let warm = &reports[1..];
    let median = |frames: &[FrameReport], f: fn(&FrameReport) -> f64| {
        let mut v: Vec<f64> = frames.iter().map(f).collect();
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let late = &reports[reports.len() - 10..];
    format!(
        "{:<22} {:<7} {:>9.2} {:>9.2} {:>9.2} {:>9.2} {:>9.2} {:>8.2} {:>8.2} {:>8.2} {:>7} {:>7} {:>5}",
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
    )
}
