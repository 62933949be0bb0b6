//! Flags and set-up shared by every example: `--scene`, `--size WxH`, `--out DIR`.

use std::path::PathBuf;

/// The flags every example takes.
#[derive(clap::Args, Debug)]
pub struct CommonArgs {
    /// A procedural scene (cylinder, ball, cubes, cage, tree, pins, plaza), a .toml scene file or a
    /// .glb/.gltf path.
    #[arg(long, default_value = "cubes")]
    pub scene: String,
    /// Target size, WIDTHxHEIGHT.
    #[arg(long, default_value = "1024x768", value_parser = parse_size)]
    pub size: (u32, u32),
    /// Output folder (created if missing).
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    /// Frames rendered and discarded before the reported one (drivers compile shaders and
    /// fill caches on first use, so a cold frame's timings mislead).
    #[arg(long, default_value_t = 2)]
    pub warmup: u32,
}

impl CommonArgs {
    /// Loads `--scene` with every light's shadows set to `technique` (not every example
    /// overrides techniques).
    #[allow(dead_code)]
    pub fn scene_with(&self, technique: umbra::scene::Technique) -> anyhow::Result<umbra::scene::Scene> {
        let mut scene = umbra::scene::load(&self.scene)?;
        for light in &mut scene.lights {
            light.technique = technique;
        }
        Ok(scene)
    }
}

/// Renders `args.warmup` discarded frames, then the frame that is reported.
pub fn render_warm(
    renderer: &mut umbra::shadows::Renderer,
    scene: &umbra::scene::Scene,
    args: &CommonArgs,
) -> anyhow::Result<umbra::shadows::Frame> {
    for _ in 0..args.warmup {
        renderer.render(scene)?;
    }
    Ok(renderer.render(scene)?)
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(|| format!("{s:?} is not WIDTHxHEIGHT"))?;
    let parse = |v: &str| v.trim().parse::<u32>().map_err(|e| format!("{v:?}: {e}"));
    Ok((parse(w)?, parse(h)?))
}

/// Logging to stderr (`RUST_LOG` overrides the `info` default).
pub fn init_logging() {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("info")).init();
}

/// Writes `<out>/<stem>.png` and `<out>/<stem>.json` and prints a summary of the report.
pub fn write_outputs(args: &CommonArgs, stem: &str, frame: &umbra::shadows::Frame) -> anyhow::Result<()> {
    std::fs::create_dir_all(&args.out)?;
    let png = args.out.join(format!("{stem}.png"));
    let json = args.out.join(format!("{stem}.json"));
    frame.save_png(&png)?;
    frame.save_report(&json)?;
    let r = &frame.report;
    println!(
        "{} on {} ({}), {}x{}, {} triangles",
        r.scene.name, r.device, r.driver, r.width, r.height, r.scene.triangles
    );
    for p in &r.passes {
        let t = p.gpu_ms.map(|t| format!("{t:9.3} ms")).unwrap_or_else(|| "      n/a".into());
        println!("  {t}  {:<24} {:>5} draws {:>9} triangles", p.name, p.draws, p.triangles);
    }
    for l in r.lights.iter().filter(|l| !l.recorded) {
        println!("  skipped light {}: {}", l.light, l.skipped_because.as_deref().unwrap_or(""));
    }
    if let Some(t) = r.total_gpu_ms {
        println!("  {t:9.3} ms  total GPU");
    }
    println!("wrote {} and {}", png.display(), json.display());
    Ok(())
}
