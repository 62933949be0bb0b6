//! Renders a scene with robust stenciled shadow volumes (Everitt–Kilgard) for every light and
//! writes `shadow_volume.png` and `shadow_volume.json`; with `--show-volumes` also
//! `shadow_volume_overdraw.png`, a heat map of volume fragments per pixel (Chan–Durand Fig. 3).
//!
//! ```text
//! cargo run --release --example shadow_volume -- --scene cubes --mode auto --lights 2 --show-volumes
//! ```

mod common;

use clap::Parser;
use umbra::scene::Technique;
use umbra::shadows::{FarPlane, Renderer, RendererDesc, ShadowVolumeSettings, VolumeMode};

#[derive(Parser, Debug)]
#[command(about = "Render a scene with robust stenciled shadow volumes (Everitt–Kilgard)")]
struct Args {
    #[command(flatten)]
    common: common::CommonArgs,
    /// Counting mode: zpass, zfail or auto (per caster, §3.4).
    #[arg(long, default_value = "auto")]
    mode: VolumeMode,
    /// Number of lights, 1 to 64: the scene's first light, plus copies circling it (dimmed to
    /// keep the total). 0 is refused (render with --technique unshadowed for no shadows).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=MAX_LIGHTS))]
    lights: u32,
    /// Also write the volume overdraw heat map and count volume fragments.
    #[arg(long)]
    show_volumes: bool,
    /// Finite far plane with depth clamp instead of the far plane at infinity.
    #[arg(long)]
    depth_clamp: bool,
}

/// Most lights `--lights` makes: each light is a stencil pass and a lighting pass over the
/// whole frame, and its volumes are built on the CPU.
const MAX_LIGHTS: i64 = 64;

fn main() -> anyhow::Result<()> {
    common::init_logging();
    let args = Args::parse();
    let mut scene = args.common.scene_with(Technique::ShadowVolume)?;
    anyhow::ensure!(
        args.lights == 1 || !scene.lights.is_empty(),
        "--lights {}: the scene {:?} has no light to copy",
        args.lights,
        args.common.scene
    );
    if let Some(first) = scene.lights.first().cloned() {
        let n = args.lights as usize;
        let centre = scene.bounds().center();
        scene.lights = (0..n)
            .map(|i| {
                let mut l = first.clone();
                l.intensity /= n as f32;
                if i > 0 && l.position.w != 0.0 {
                    let angle = std::f32::consts::TAU * i as f32 / n as f32;
                    let p = l.position.truncate() - centre;
                    l.position = (centre + glam::Quat::from_rotation_y(angle) * p).extend(1.0);
                } else if i > 0 {
                    let angle = std::f32::consts::TAU * i as f32 / n as f32;
                    l.position = (glam::Quat::from_rotation_y(angle) * l.position.truncate()).extend(0.0);
                }
                l
            })
            .collect();
    }
    let (width, height) = args.common.size;
    let mut desc = RendererDesc::new(width, height);
    desc.shadow_volume = ShadowVolumeSettings {
        mode: args.mode,
        far_plane: if args.depth_clamp { FarPlane::DepthClamp } else { FarPlane::Infinite },
        overdraw: args.show_volumes,
        ..ShadowVolumeSettings::default()
    };
    args.common.apply(&mut desc);
    if args.common.window {
        return common::window::run(&args.common, "shadow_volume", scene, desc);
    }
    let ctx = umbra::vk::Context::new()?;
    let mut renderer = Renderer::new(&ctx, desc)?;
    let frame = common::render_warm(&mut renderer, &scene, &args.common)?;
    for l in &frame.report.lights {
        if let Some(v) = &l.shadow_volume {
            println!(
                "light {}: {} casters ({} z-pass, {} z-fail), {} silhouette edges, {} volume triangles, CPU build {:.2} ms{}",
                l.light,
                v.casters,
                v.zpass_casters,
                v.zfail_casters,
                v.silhouette_edges,
                v.volume_triangles,
                v.cpu_build_ms,
                v.volume_fragments.map(|f| format!(", {f} volume fragments")).unwrap_or_default()
            );
        }
    }
    common::print_warnings(&frame.report);
    common::write_outputs(&args.common, "shadow_volume", &frame)?;
    if let Some(overdraw) = &frame.overdraw {
        let heat: Vec<u8> = overdraw.chunks_exact(4).flat_map(|p| common::views::heat(p[0])).collect();
        let path = args.common.out.join("shadow_volume_overdraw.png");
        common::save_rgba(&path, &heat, width, height)?;
        let max = overdraw.chunks_exact(4).map(|p| p[0]).max().unwrap_or(0);
        println!(
            "wrote {} (max {max} volume fragments on one pixel{})",
            path.display(),
            if max == 255 { ", saturated" } else { "" }
        );
    }
    common::print_score(&args.common, &scene, &frame)?;
    common::check_validation(&ctx)
}
