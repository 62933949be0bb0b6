//! Renders a scene without shadows (the forward baseline) and writes `render.png` and
//! `render.json` (the frame report).
//!
//! ```text
//! cargo run --release --example render -- --scene cubes --size 1024x768 --out out/
//! ```

mod common;

use clap::Parser;
use umbra::shadows::{Renderer, RendererDesc};

#[derive(Parser, Debug)]
#[command(about = "Render a scene with umbra's forward passes")]
struct Args {
    #[command(flatten)]
    common: common::CommonArgs,
}

fn main() -> anyhow::Result<()> {
    common::init_logging();
    let args = Args::parse();
    let ctx = umbra::vk::Context::new()?;
    let scene = umbra::scene::load(&args.common.scene)?;
    let (width, height) = args.common.size;
    let mut renderer = Renderer::new(&ctx, RendererDesc::new(width, height))?;
    let frame = common::render_warm(&mut renderer, &scene, &args.common)?;
    common::write_outputs(&args.common, "render", &frame)
}
