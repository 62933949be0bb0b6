//! Simulate only the effects a scene calls for: renders `plaza` (eight bounded lights, every
//! technique and `auto` among them, two of which can reach the camera's view), prints the frame
//! plan (per light: the technique, the passes recorded, what was culled and why) and writes
//! `effects.png` and `effects.json`. `--no-cull` renders the same frame without planning;
//! `--compare` renders both and prints what planning saved and whether the images are equal.
//!
//! ```text
//! cargo run --release --example effects
//! cargo run --release --example effects -- --compare --size 256x192
//! cargo run --release --example effects -- --scene cubes --no-cull
//! ```

mod common;

use clap::Parser;
use umbra::shadows::{Frame, Renderer, RendererDesc};

#[derive(Parser, Debug)]
#[command(about = "Render with the frame planner and print its plan", mut_arg("scene", |a| a.default_value("plaza")))]
struct Args {
    #[command(flatten)]
    common: common::CommonArgs,
    /// Record every pass of every light over every caster (no planning).
    #[arg(long, conflicts_with = "compare")]
    no_cull: bool,
    /// Render with and without planning; print both plans, the time saved and the difference.
    #[arg(long)]
    compare: bool,
}

fn main() -> anyhow::Result<()> {
    common::init_logging();
    let args = Args::parse();
    let scene = umbra::scene::load(&args.common.scene)?;
    let (width, height) = args.common.size;
    let desc = |cull: bool| {
        let mut desc = RendererDesc::new(width, height);
        desc.cull = cull;
        // Volume fragments are counted (an occlusion query per light) so the plan shows them.
        desc.shadow_volume.overdraw = true;
        desc.hybrid.cull_blockers = cull;
        desc
    };
    if args.common.window {
        return common::window::run(&args.common, "effects", scene, desc(!args.no_cull));
    }
    let ctx = umbra::vk::Context::new()?;
    let render = |cull: bool| -> anyhow::Result<Frame> {
        let mut renderer = Renderer::new(&ctx, desc(cull))?;
        common::render_warm(&mut renderer, &scene, &args.common)
    };
    let frame = render(!args.no_cull)?;
    print_plan(&frame);
    let stem = if args.no_cull { "effects-no-cull" } else { "effects" };
    common::write_outputs(&args.common, stem, &frame)?;
    if args.compare {
        let unplanned = render(false)?;
        print_plan(&unplanned);
        common::write_outputs(&args.common, "effects-no-cull", &unplanned)?;
        let differing = frame.rgba.chunks_exact(4).zip(unplanned.rgba.chunks_exact(4)).filter(|(a, b)| a != b).count();
        let gpu = |f: &Frame| f.report.total_gpu_ms.unwrap_or(f64::NAN);
        println!(
            "planned: {} passes, {:.3} ms GPU, {:.1} ms CPU; --no-cull: {} passes, {:.3} ms GPU, {:.1} ms CPU; \
             {differing} pixels differ",
            frame.report.passes.len(),
            gpu(&frame),
            frame.report.cpu_frame_ms,
            unplanned.report.passes.len(),
            gpu(&unplanned),
            unplanned.report.cpu_frame_ms,
        );
        anyhow::ensure!(differing == 0, "planning changed {differing} pixels");
    }
    common::check_validation(&ctx)
}

/// Prints the plan: per light its technique (and `auto`'s reason), passes and culled casters.
fn print_plan(frame: &Frame) {
    let plan = &frame.report.plan;
    println!(
        "plan ({}): {} lights recorded, {} skipped, {} shadowed",
        if plan.culling { "culling" } else { "--no-cull" },
        plan.lights_recorded,
        plan.lights_skipped,
        plan.lights_shadowed
    );
    for l in &frame.report.lights {
        print!("  light {} {:?} ({:?}) {}", l.light, l.name, l.kind, l.technique.name());
        if let Some(why) = &l.auto_choice {
            print!(" [auto: {why}]");
        }
        if let Some(why) = &l.skipped_because {
            println!(": skipped, {why}");
            continue;
        }
        println!();
        if let Some(why) = &l.unshadowed_because {
            println!("    unshadowed: {why}");
        }
        println!("    passes: {}", l.passes.join(", "));
        for c in &l.culled {
            println!("    culled {:>4} casters: {:?}", c.count, c.reason);
        }
        if let Some([x, y, w, h]) = l.scissor {
            print!("    scissor {w}x{h} at ({x}, {y})");
            match l.depth_bounds {
                Some([lo, hi]) => println!(", depth bounds [{lo:.5}, {hi:.5}]"),
                None => println!(", no depth bounds (device lacks depthBounds)"),
            }
        }
        if let Some(n) = l.shadow_volume.as_ref().and_then(|v| v.volume_fragments) {
            println!("    volume fragments: {n}");
        }
    }
}
