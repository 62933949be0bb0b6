//! Renders a scene with every light casting shadow-map shadows, and writes `shadow_map.png`
//! and `shadow_map.json` (the frame report, with a `shadow_map N` pass per light and the
//! settings used).
//!
//! ```text
//! cargo run --release --example shadow_map -- --scene cubes --sm-size 2048 --filter pcf2x2 --bias 2,2.5
//! ```

mod common;

use clap::Parser;
use umbra::scene::Technique;
use umbra::shadows::{DepthBias, Renderer, RendererDesc, ShadowFilter, ShadowMapSettings};

#[derive(Parser, Debug)]
#[command(about = "Render a scene with shadow maps (Williams; Chan–Durand §3, Arneson §3)")]
struct Args {
    #[command(flatten)]
    common: common::CommonArgs,
    /// Shadow-map resolution, texels per side (cube maps: per face; default: from the frame, a
    /// texel about a pixel on what the camera sees, within a budget; see
    /// ShadowMapSettings::resolution_from_frame): at least 64, at most what the device takes
    /// (checked per light, naming the limit).
    #[arg(long, value_parser = common::flags::parse_sm_size)]
    sm_size: Option<u32>,
    /// Lookup filter: nearest, pcf2x2 (hardware), pcf3x3 or pcf5x5.
    #[arg(long, default_value = "pcf2x2")]
    filter: ShadowFilter,
    /// Depth bias CONSTANT,SLOPE (vkCmdSetDepthBias; the filter's radius is added to SLOPE):
    /// CONSTANT in 0..=1e5, SLOPE in 0..=100.
    #[arg(long, value_parser = common::flags::parse_bias)]
    bias: Option<DepthBias>,
    /// Normal offset of the lookup point, in world units (0..=1e4).
    #[arg(long, default_value_t = 0.0, value_parser = common::flags::parse_normal_offset)]
    normal_offset: f32,
    /// Shade points outside a light's shadow frustum as shadowed instead of lit.
    #[arg(long)]
    outside_shadowed: bool,
}

fn main() -> anyhow::Result<()> {
    common::init_logging();
    let args = Args::parse();
    let scene = args.common.scene_with(Technique::ShadowMap)?;
    let (width, height) = args.common.size;
    let mut desc = RendererDesc::new(width, height);
    desc.shadow_map = ShadowMapSettings {
        resolution: args.sm_size,
        filter: args.filter,
        bias: args.bias.unwrap_or(ShadowMapSettings::DEFAULT.bias),
        normal_offset: args.normal_offset,
        outside_lit: !args.outside_shadowed,
    };
    args.common.apply(&mut desc);
    if args.common.window {
        return common::window::run(&args.common, "shadow_map", scene, desc);
    }
    let ctx = umbra::vk::Context::new()?;
    let mut renderer = Renderer::new(&ctx, desc)?;
    let frame = common::render_warm(&mut renderer, &scene, &args.common)?;
    for l in &frame.report.lights {
        match (&l.shadow_map, &l.note) {
            (Some(m), _) => println!(
                "light {}: {}{}² shadow map, {} casters, depth range {:.3}..{:.3}",
                l.light,
                if m.cube { "6 x " } else { "" },
                m.resolution,
                m.casters,
                m.near,
                m.far
            ),
            (None, Some(note)) => println!("light {}: {note}", l.light),
            (None, None) => {}
        }
    }
    common::write_outputs(&args.common, "shadow_map", &frame)?;
    common::print_score(&args.common, &scene, &frame)?;
    common::check_validation(&ctx)
}
