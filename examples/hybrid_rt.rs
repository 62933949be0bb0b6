//! Renders a scene with the ray-traced hybrid for every light — the hybrid's conservative
//! shadow-map classification, then one shadow ray per pixel it leaves uncertain, compacted into
//! a list and dispatched indirectly (`docs/techniques/ray-traced.md`) — and writes
//! `hybrid_rt.png` and `hybrid_rt.json`; prints each light's rays (how many, the fraction of
//! the image, their GPU time) and BVH. With `--score`, the wrong pixels against the exact
//! reference.
//!
//! ```text
//! cargo run --release --example hybrid_rt -- --scene tree --score
//! ```

mod common;

use clap::Parser;
use umbra::scene::Technique;
use umbra::shadows::{Renderer, RendererDesc};

#[derive(Parser, Debug)]
#[command(about = "Render a scene with the ray-traced hybrid (a shadow map classifies, rays decide the rest)")]
struct Args {
    #[command(flatten)]
    common: common::CommonArgs,
}

fn main() -> anyhow::Result<()> {
    common::init_logging();
    let args = Args::parse();
    let scene = args.common.scene_with(Technique::HybridRt)?;
    let (width, height) = args.common.size;
    let mut desc = RendererDesc::new(width, height);
    args.common.apply(&mut desc);
    if args.common.window {
        return common::window::run(&args.common, "hybrid_rt", scene, desc);
    }
    let ctx = umbra::vk::Context::new()?;
    let mut renderer = Renderer::new(&ctx, desc)?;
    let frame = common::render_warm(&mut renderer, &scene, &args.common)?;
    for l in &frame.report.lights {
        let (Some(h), Some(b)) = (&l.hybrid_rt, &l.ray_traced) else { continue };
        let rays = h.rays.map_or("?".into(), |n| n.to_string());
        let fraction = h.ray_fraction.map_or(String::new(), |f| format!(" ({:.2}% of the image)", 100.0 * f));
        let ms = h.rays_gpu_ms.map_or(String::new(), |t| format!(" in {t:.3} ms"));
        println!(
            "light {}: {rays} shadow rays{fraction}{ms}, {} dropped; BVH of {} instances, {} triangles",
            l.light,
            h.rays_dropped.unwrap_or(0),
            b.instances,
            b.triangles
        );
    }
    common::write_outputs(&args.common, "hybrid_rt", &frame)?;
    common::print_score(&args.common, &scene, &frame)?;
    common::check_validation(&ctx)
}
