//! `umbra-bench bvh`: ray-traced shadows' two-level BVH (`umbra_shadows::ray_traced`) per
//! scene, on the host, before any shader walks it — what it costs to build (every mesh's BVH,
//! the top level, and the top-level rebuild one moving object costs), its memory and depth,
//! and the walk's work per shadow ray (nodes and triangles visited, mean and p95) over the
//! shadow rays of every pixel to every light, each answer checked against the exact reference.

use crate::{scenes, BenchResult};
use glam::Mat4;
use umbra_reference::{shadow_ray, SceneBvh, SurfaceImage};
use umbra_shadows::ray_traced::{BvhLayout, RayScene, WalkStats};

/// Arguments of `umbra-bench bvh`.
#[derive(clap::Args, Debug)]
pub struct BvhArgs {
    /// Scenes: procedural names, scene files or glTF paths.
    #[arg(long, value_delimiter = ',', default_value = "cubes,cage,tree,pins,plaza,sixteen-bunnies.toml")]
    scenes: Vec<String>,
    /// Pixels whose shadow rays are walked, WIDTHxHEIGHT.
    #[arg(long, default_value = "256x192", value_parser = crate::parse_size)]
    size: (u32, u32),
    /// The meshes' BVH layout: binary or cwbvh (nodes per ray then counts wide nodes, each
    /// eight boxes).
    #[arg(long, default_value = "binary")]
    bvh: BvhLayout,
    #[command(flatten)]
    lights: scenes::LightArgs,
}

/// Prints one line per scene.
pub fn run(args: &BvhArgs) -> BenchResult<()> {
    println!(
        "{:<22} {:>9} {:>5} {:>9} {:>8} {:>8} {:>9} {:>5} {:>7} {:>10} {:>10} {:>6}",
        "scene",
        "triangles",
        "inst",
        "mesh_ms",
        "top_ms",
        "move_ms",
        "KiB",
        "depth",
        "rays",
        "nodes/ray",
        "tris/ray",
        "wrong"
    );
    for name in &args.scenes {
        let mut scene = scenes::load(name, args.lights)?;
        let mut rays = RayScene::build_with(&scene, args.bvh);
        let built = rays.stats;
        let reference = SceneBvh::build(&scene);
        let surfaces = SurfaceImage::ray_cast(&scene, &reference, args.size.0, args.size.1);
        let mut walks = Vec::new();
        let mut wrong = 0;
        for light in &scene.lights {
            for s in surfaces.pixels.iter().flatten() {
                let Some((origin, dir, t_max)) = shadow_ray(light, s) else { continue };
                let (blocked, stats) = rays.occluded(origin, dir, t_max);
                wrong += usize::from(blocked != reference.occluded(origin, dir, t_max));
                walks.push(stats);
            }
        }
        // One caster moved: the top level is rebuilt, no mesh is.
        if let Some(o) = scene.objects.iter_mut().find(|o| o.casts_shadows) {
            o.transform = Mat4::from_translation(glam::Vec3::new(0.01, 0.0, 0.0)) * o.transform;
        }
        rays.update(&scene);
        let moved = rays.stats;
        let meshes_rebuilt = moved.mesh_builds - built.mesh_builds;
        println!(
            "{:<22} {:>9} {:>5} {:>9.2} {:>8.3} {:>8.3} {:>9.1} {:>5} {:>7} {:>10} {:>10} {:>6}{}",
            name,
            scene.triangle_count(),
            rays.instances.len(),
            built.mesh_build_ms,
            built.top_build_ms,
            moved.top_build_ms,
            rays.bytes() as f64 / 1024.0,
            rays.depth,
            walks.len(),
            mean_p95(&walks, |w| w.nodes),
            mean_p95(&walks, |w| w.triangles),
            wrong,
            if meshes_rebuilt > 0 { format!("  ({meshes_rebuilt} meshes rebuilt by a move)") } else { String::new() }
        );
    }
    Ok(())
}

/// `mean/p95` of `f` over `walks`.
fn mean_p95(walks: &[WalkStats], f: fn(&WalkStats) -> u32) -> String {
    if walks.is_empty() {
        return "-".into();
    }
    let mut v: Vec<u32> = walks.iter().map(f).collect();
    v.sort_unstable();
    let mean = v.iter().map(|&x| f64::from(x)).sum::<f64>() / v.len() as f64;
    format!("{mean:.1}/{}", v[(v.len() * 95 / 100).min(v.len() - 1)])
}
