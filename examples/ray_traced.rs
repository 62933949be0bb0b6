//! Renders a scene with ray-traced shadows for every light — one shadow ray per receiver pixel
//! through a two-level BVH of the casters (`umbra::shadows::ray_traced`) — and writes
//! `ray_traced.png` and `ray_traced.json`; prints each light's BVH (instances, triangles,
//! memory, depth, build times). With `--score`, the wrong pixels against the exact reference.
//!
//! ```text
//! cargo run --release --example ray_traced -- --scene tree --score
//! ```

mod common;

use clap::Parser;
use umbra::scene::Technique;
use umbra::shadows::{Renderer, RendererDesc};

#[derive(Parser, Debug)]
#[command(about = "Render a scene with ray-traced shadows (a BVH walked per receiver pixel)")]
struct Args {
    #[command(flatten)]
    common: common::CommonArgs,
}

fn main() -> anyhow::Result<()> {
    common::init_logging();
    let args = Args::parse();
    let scene = args.common.scene_with(Technique::RayTraced)?;
    let (width, height) = args.common.size;
    let mut desc = RendererDesc::new(width, height);
    args.common.apply(&mut desc);
    if args.common.window {
        return common::window::run(&args.common, "ray_traced", scene, desc);
    }
    let ctx = umbra::vk::Context::new()?;
    let mut renderer = Renderer::new(&ctx, desc)?;
    let frame = common::render_warm(&mut renderer, &scene, &args.common)?;
    for l in &frame.report.lights {
        if let Some(r) = &l.ray_traced {
            println!(
                "light {}: BVH of {} instances, {} triangles, {:.1} KiB, depth {}; {} mesh and {} top-level builds so far",
                l.light,
                r.instances,
                r.triangles,
                r.bvh_bytes as f64 / 1024.0,
                r.depth,
                r.mesh_builds,
                r.top_builds
            );
        }
    }
    common::write_outputs(&args.common, "ray_traced", &frame)?;
    common::print_score(&args.common, &scene, &frame)?;
    common::check_validation(&ctx)
}
