//! Renders a scene with the techniques its lights ask for (procedural scenes: none, the forward
//! baseline), or with `--technique` for every light, and writes `render.png` and `render.json`
//! (the frame report).
//!
//! ```text
//! cargo run --release --example render -- --scene cubes --size 1024x768 --out out/
//! cargo run --release --example render -- --scene pins --technique shadow_volume
//! ```

mod common;

use clap::Parser;
use umbra::scene::Technique;
use umbra::shadows::{Renderer, RendererDesc};

#[derive(Parser, Debug)]
#[command(about = "Render a scene with umbra's forward passes")]
struct Args {
    #[command(flatten)]
    common: common::CommonArgs,
    /// Use this technique for every light: unshadowed, shadow_map, shadow_volume,
    /// silhouette_map, hybrid or auto.
    #[arg(long, value_parser = parse_technique)]
    technique: Option<Technique>,
}

fn parse_technique(s: &str) -> Result<Technique, String> {
    Technique::from_name(s).ok_or_else(|| {
        let names: Vec<_> = Technique::ALL.iter().map(|t| t.name()).collect();
        format!("{s:?}: expected one of {}", names.join(", "))
    })
}

fn main() -> anyhow::Result<()> {
    common::init_logging();
    let args = Args::parse();
    let scene = match args.technique {
        Some(t) => args.common.scene_with(t)?,
        None => umbra::scene::load(&args.common.scene)?,
    };
    let (width, height) = args.common.size;
    let mut desc = RendererDesc::new(width, height);
    args.common.apply(&mut desc);
    if args.common.window {
        return common::window::run(&args.common, "render", scene, desc);
    }
    let ctx = umbra::vk::Context::new()?;
    let mut renderer = Renderer::new(&ctx, desc)?;
    let frame = common::render_warm(&mut renderer, &scene, &args.common)?;
    common::write_outputs(&args.common, "render", &frame)?;
    common::check_validation(&ctx)
}
