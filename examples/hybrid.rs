//! Renders a scene with every light casting hybrid shadows (Chan–Durand 2004): a shadow map
//! finds the silhouette pixels, and z-fail shadow volumes run only there, behind the
//! computation mask. Writes `hybrid.png` and `hybrid.json` (the frame report: per light the
//! `mask`, the silhouette-pixel fraction P, volume fragments with and without the mask, the
//! stencil pass's GPU time, and blocker culling's count).
//!
//! With `--debug-view`, per light N also:
//! - `hybrid-classes-N.png`: Chan–Durand Fig. 6b, pixels the shadow map decided (red shadowed,
//!   blue lit) and silhouette pixels the volumes decided (black shadowed, green lit);
//! - `hybrid-fill-N.png`: Fig. 10, volume overdraw in yellow (brighter where more volume
//!   fragments land) with the silhouette pixels, the only place they still update the stencil,
//!   in green;
//! - `hybrid-stencil-N.png`: the stencil after the volume pass (black 0, white non-zero count).
//!
//! ```text
//! cargo run --release --example hybrid -- --scene cage --sm-size 256 --mask depth-bounds --debug-view
//! ```

mod common;

use clap::Parser;
use umbra::scene::Technique;
use umbra::shadows::{HybridSettings, LightDiagnostics, MaskKind, Renderer, RendererDesc};

#[derive(Parser, Debug)]
#[command(about = "Render a scene with the hybrid of shadow maps and shadow volumes (Chan–Durand 2004)")]
struct Args {
    #[command(flatten)]
    common: common::CommonArgs,
    /// Shadow-map resolution, texels per side (default: from the frame, half the size a shadow
    /// map gets there, which brings a texel to about a pixel on what the camera sees, within a
    /// budget; see HybridSettings::resolution): at least 64, at most what the device takes.
    #[arg(long, value_parser = common::flags::parse_sm_size)]
    sm_size: Option<u32>,
    /// Computation mask: depth-bounds, stencil or none (default: depth-bounds where the
    /// device has depthBounds, else stencil).
    #[arg(long)]
    mask: Option<MaskKind>,
    /// Skip the volumes of casters no shadow-map texel sees (§6.3).
    #[arg(long)]
    cull_blockers: bool,
    /// Also write the classification, fill and stencil images.
    #[arg(long)]
    debug_view: bool,
}

fn write_debug_views(args: &Args, frame: &umbra::shadows::Frame, d: &LightDiagnostics) -> anyhow::Result<()> {
    let (w, h) = (frame.width, frame.height);
    let out = &args.common.out;
    let save = |name: String, rgba: &[u8]| -> anyhow::Result<()> {
        let path = out.join(name);
        common::save_rgba(&path, rgba, w, h)?;
        println!("wrote {}", path.display());
        Ok(())
    };
    save(format!("hybrid-classes-{}.png", d.light), &d.classification)?;
    if let Some(overdraw) = &frame.overdraw {
        save(format!("hybrid-fill-{}.png", d.light), &d.fill_image(overdraw))?;
    }
    if let Some(stencil) = &d.stencil {
        let rgba: Vec<u8> = stencil.iter().flat_map(|&s| common::views::stencil_texel(s)).collect();
        save(format!("hybrid-stencil-{}.png", d.light), &rgba)?;
    }
    Ok(())
}

fn main() -> anyhow::Result<()> {
    common::init_logging();
    let args = Args::parse();
    let scene = args.common.scene_with(Technique::Hybrid)?;
    let (width, height) = args.common.size;
    let mut desc = RendererDesc::new(width, height);
    desc.hybrid = HybridSettings { resolution: args.sm_size, mask: args.mask, cull_blockers: args.cull_blockers };
    // Volume fragments without the mask (O) and through it come from diagnostic passes, left
    // out of the total.
    desc.shadow_volume.overdraw = true;
    desc.diagnostics = args.debug_view;
    args.common.apply(&mut desc);
    if args.common.window {
        return common::window::run(&args.common, "hybrid", scene, desc);
    }
    let ctx = umbra::vk::Context::new()?;
    let mut renderer = Renderer::new(&ctx, desc)?;
    println!("computation mask: {}", renderer.mask().name());
    let frame = common::render_warm(&mut renderer, &scene, &args.common)?;
    for l in &frame.report.lights {
        match (&l.hybrid, &l.shadow_map, &l.note) {
            (Some(hy), Some(m), _) => {
                let ms = |t: Option<f64>| t.map_or("n/a".to_owned(), |t| format!("{t:.3} ms"));
                let count = |n: Option<u64>| n.map_or("n/a".to_owned(), |n| n.to_string());
                println!(
                    "light {}: {}² shadow map, mask {}, silhouette pixels {} (P = {:.2}%), volume fragments {} unmasked / {} masked, stencil pass {}, {} casters{}",
                    l.light,
                    m.resolution,
                    hy.mask.name(),
                    hy.silhouette_pixels,
                    100.0 * hy.silhouette_fraction,
                    count(hy.volume_fragments),
                    count(hy.masked_volume_fragments),
                    ms(hy.stencil_gpu_ms),
                    hy.volume_casters,
                    hy.culled_casters.map_or(String::new(), |n| format!(" ({n} culled)")),
                );
            }
            (_, _, Some(note)) => println!("light {}: {note}", l.light),
            _ => {}
        }
    }
    common::print_warnings(&frame.report);
    common::write_outputs(&args.common, "hybrid", &frame)?;
    common::print_score(&args.common, &scene, &frame)?;
    if args.debug_view {
        for d in &frame.diagnostics {
            write_debug_views(&args, &frame, d)?;
        }
    }
    common::check_validation(&ctx)
}
