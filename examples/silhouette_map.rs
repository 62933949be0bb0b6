//! Renders a scene with every light casting silhouette-map shadows (Sen, Cammarano, Hanrahan
//! 2003), and writes `silhouette_map.png` and `silhouette_map.json` (the frame report: the
//! `shadow_map N`, `silhouette_map N` and `light N` passes, silhouette edges drawn and the
//! silhouette-pixel fraction per light).
//!
//! Point lights (and spots wider than 80°) get cube silhouette maps: six 90° faces side by side
//! in one 2D atlas (three columns, two rows), each face with a two-texel border beyond its
//! interior so that a lookup never reads another face.
//!
//! With `--debug-view`, per light N also:
//! - `silhouette_map-points-N.png`: the stored silhouette points over the scene (Sen Fig. 9,
//!   middle), red where a pixel lies on a point;
//! - `silhouette_map-classes-N.png`: per pixel, decided by the depth comparisons (red
//!   shadowed, blue lit) or by the silhouette points (black shadowed, green lit);
//! - `silhouette_map-N.exr`: the silhouette map itself, texel-local points in R and G;
//! - `silhouette_map-texels-N.png`: the map's texels holding a point, white (a point light's
//!   six faces, three across and two down, outlined in blue).
//!
//! ```text
//! cargo run --release --example silhouette_map -- --scene cubes --sm-size 512 --debug-view
//! ```

mod common;

use anyhow::Context as _;
use clap::Parser;
use umbra::scene::Technique;
use umbra::shadows::{LightDiagnostics, Renderer, RendererDesc, ShadowMapSettings};

#[derive(Parser, Debug)]
#[command(about = "Render a scene with shadow silhouette maps (Sen, Cammarano, Hanrahan 2003)")]
struct Args {
    #[command(flatten)]
    common: common::CommonArgs,
    /// Depth-map and silhouette-map resolution, texels per side (default: from the frame, a
    /// texel about a pixel on what the camera sees, within a budget; see
    /// ShadowMapSettings::resolution_from_frame): at least 64, at most what the device takes
    /// (checked per light, naming the limit).
    #[arg(long, value_parser = common::flags::parse_sm_size)]
    sm_size: Option<u32>,
    /// Also write the silhouette-point and classification views and the silhouette map.
    #[arg(long)]
    debug_view: bool,
}

fn write_debug_views(args: &Args, frame: &umbra::shadows::Frame, d: &LightDiagnostics) -> anyhow::Result<()> {
    let (w, h) = (frame.width, frame.height);
    let out = &args.common.out;
    let points = out.join(format!("silhouette_map-points-{}.png", d.light));
    let over = d.points_over(&frame.rgba).ok_or_else(|| anyhow::anyhow!("light {} has no points view", d.light))?;
    common::save_rgba(&points, &over, w, h)?;
    let classes = out.join(format!("silhouette_map-classes-{}.png", d.light));
    common::save_rgba(&classes, &d.classification, w, h)?;
    println!("wrote {} and {}", points.display(), classes.display());
    if let Some(map) = &d.silhouette_map {
        let exr_path = out.join(format!("silhouette_map-{}.exr", d.light));
        exr::prelude::write_rgb_file(&exr_path, map.width as usize, map.height as usize, |x, y| {
            let [u, v] = map.point(x as u32, y as u32);
            (u, v, 0.0f32)
        })
        .with_context(|| format!("writing {}", exr_path.display()))?;
        // Where the points are, over the whole map; a point light's six faces (three across,
        // two down) are outlined in blue.
        let texels_path = out.join(format!("silhouette_map-texels-{}.png", d.light));
        let face = if map.width == map.height { map.width } else { map.height / 2 };
        let texels: Vec<u8> = (0..map.height)
            .flat_map(|y| (0..map.width).map(move |x| (x, y)))
            .flat_map(|(x, y)| match map.point(x, y) {
                [0.5, 0.5] if x % face == 0 || y % face == 0 => [40, 70, 160, 255],
                [0.5, 0.5] => [24, 24, 24, 255],
                _ => [255, 255, 255, 255],
            })
            .collect();
        common::save_rgba(&texels_path, &texels, map.width, map.height)?;
        println!(
            "wrote {} and {} ({} of {} texels hold a silhouette point)",
            exr_path.display(),
            texels_path.display(),
            map.silhouette_texels(),
            map.points.len()
        );
    }
    Ok(())
}

fn main() -> anyhow::Result<()> {
    common::init_logging();
    let args = Args::parse();
    let scene = args.common.scene_with(Technique::SilhouetteMap)?;
    let (width, height) = args.common.size;
    let mut desc = RendererDesc::new(width, height);
    desc.shadow_map = ShadowMapSettings { resolution: args.sm_size, ..ShadowMapSettings::DEFAULT };
    args.common.apply(&mut desc);
    // The silhouette-pixel count comes from the diagnostics pass (left out of the total).
    desc.diagnostics = true;
    if args.common.window {
        return common::window::run(&args.common, "silhouette_map", scene, desc);
    }
    let ctx = umbra::vk::Context::new()?;
    let mut renderer = Renderer::new(&ctx, desc)?;
    let frame = common::render_warm(&mut renderer, &scene, &args.common)?;
    for l in &frame.report.lights {
        let faces = match l.shadow_map.as_ref().is_some_and(|m| m.cube) {
            true => "6 × ",
            false => "",
        };
        match (&l.silhouette_map, &l.note) {
            (Some(m), _) => println!(
                "light {}: {faces}{}² silhouette map, {} silhouette edges ({:.2} ms CPU), silhouette pixels {} ({:.2}% of the image)",
                l.light,
                m.resolution,
                m.silhouette_edges,
                m.cpu_extract_ms,
                m.silhouette_pixels.unwrap_or(0),
                100.0 * m.silhouette_fraction.unwrap_or(0.0)
            ),
            (None, Some(note)) => println!("light {}: {note}", l.light),
            (None, None) => {}
        }
    }
    common::write_outputs(&args.common, "silhouette_map", &frame)?;
    if args.debug_view {
        for d in &frame.diagnostics {
            write_debug_views(&args, &frame, d)?;
        }
    }
    common::print_score(&args.common, &scene, &frame)?;
    common::check_validation(&ctx)
}
