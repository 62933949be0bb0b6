//! Flags and set-up shared by every example: `--scene`, `--size WxH`, `--out DIR`, `--time`,
//! and `--window` with its options (the interactive viewer, `window.rs`).

pub mod animate;
pub mod controls;
pub mod flags;
pub mod views;
pub mod window;

use anyhow::Context as _;
use std::path::{Path, PathBuf};

/// The flags every example takes.
#[derive(clap::Args, Clone, Debug)]
pub struct CommonArgs {
    /// A procedural scene (cylinder, ball, cubes, cage, tree, pins, plaza), a .toml scene file or a
    /// .glb/.gltf path.
    #[arg(long, default_value = "cubes")]
    pub scene: String,
    /// Target size, WIDTHxHEIGHT.
    #[arg(long, default_value = "1024x768", value_parser = flags::parse_size)]
    pub size: (u32, u32),
    /// Output folder (created if missing).
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    /// Frames rendered and discarded before the reported one (drivers compile shaders and
    /// fill caches on first use, so a cold frame's timings mislead), 0 to 1000.
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u32).range(0..=flags::MAX_WARMUP as i64))]
    pub warmup: u32,
    /// Animation time in seconds: light 0 orbits the scene's vertical axis, a full turn in 12 s
    /// (0: the scene as loaded); finite, at most 10^6 either way. A windowed run prints the
    /// time of its screenshot.
    #[arg(long, default_value_t = 0.0, value_parser = flags::parse_time, allow_negative_numbers = true)]
    pub time: f32,
    /// Open a window and render interactively (keys and mouse: docs/window.md); without it the
    /// example renders one frame headless and writes its files.
    #[arg(long)]
    pub window: bool,
    /// Quit after this many frames (1 to 10^6).
    #[arg(long, requires = "window", value_parser = clap::value_parser!(u64).range(1..=flags::MAX_FRAMES))]
    pub frames: Option<u64>,
    /// Save the last presented image, read back from the swapchain, as PNG (with the frame's
    /// report beside it as JSON); needs --frames.
    #[arg(long, requires = "frames")]
    pub screenshot: Option<PathBuf>,
    /// Ask the window system for a new size after FRAME frames: FRAME:WIDTHxHEIGHT.
    #[arg(long, requires = "window", value_parser = window::parse_resize)]
    pub resize_at: Option<(u64, (u32, u32))>,
    /// Keep the last frame on screen this many seconds before quitting (for screenshots taken
    /// from outside the process), 0 to 3600.
    #[arg(long, requires = "frames", default_value_t = 0.0, value_parser = flags::parse_hold)]
    pub hold: f32,
    /// Present without waiting for vertical blank (mailbox or immediate, where offered).
    #[arg(long, requires = "window")]
    pub no_vsync: bool,
    /// Present every frame through a CPU readback (the frame read back, then copied into the
    /// swapchain from a staging buffer) instead of blitting the renderer's image on the GPU:
    /// for comparing the CPU time per frame (docs/window.md).
    #[arg(long, requires = "window")]
    pub present_readback: bool,
    /// Also score every shadowed light against the exact reference (a shadow ray cast on the
    /// CPU from each pixel of the frame's G-buffer) and print its wrong pixels (headless only).
    #[arg(long, conflicts_with = "window")]
    pub score: bool,
    /// Where shadow volumes (shadow_volume, hybrid) are built: auto (on the GPU where the device
    /// allows it), cpu or gpu.
    #[arg(long, default_value = "auto", value_parser = flags::parse_volume_build)]
    pub volume_build: umbra::shadows::VolumeBuild,
}

impl CommonArgs {
    /// Sets what the shared flags ask of the renderer: `--volume-build`, and what `--score`
    /// reads (the G-buffer, the diagnostics and the visibility images).
    #[allow(dead_code)]
    pub fn apply(&self, desc: &mut umbra::shadows::RendererDesc) {
        desc.shadow_volume.build = self.volume_build;
        if self.score {
            desc.gbuffer = true;
            desc.diagnostics = true;
            desc.read_visibility = true;
        }
    }

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

/// Renders `args.warmup` discarded frames, then the frame that is reported, with the
/// animation at `--time`.
pub fn render_warm(
    renderer: &mut umbra::shadows::Renderer,
    scene: &umbra::scene::Scene,
    args: &CommonArgs,
) -> anyhow::Result<umbra::shadows::Frame> {
    let animated;
    let scene = match args.time {
        0.0 => scene,
        t => {
            let mut s = scene.clone();
            animate::apply(&mut s, t);
            animated = s;
            &animated
        }
    };
    for _ in 0..args.warmup {
        renderer.render(scene)?;
    }
    Ok(renderer.render(scene)?)
}

/// With `--score`: prints, per shadowed light of `frame` (rendered from `scene` with
/// [`CommonArgs::apply_score`]'s settings), its wrong pixels against the exact reference.
#[allow(dead_code)]
pub fn print_score(
    args: &CommonArgs,
    scene: &umbra::scene::Scene,
    frame: &umbra::shadows::Frame,
) -> anyhow::Result<()> {
    use umbra_reference::{Comparison, SceneBvh, ShadowMask, SurfaceImage};
    if !args.score {
        return Ok(());
    }
    let gbuffer = frame.gbuffer.as_ref().context("--score: the frame has no G-buffer")?;
    let surfaces = SurfaceImage::from_gbuffer(frame.width, frame.height, &gbuffer.position, &gbuffer.normal)?;
    let bvh = SceneBvh::build(scene);
    for (light, mask) in frame.shadow_masks() {
        let technique = ShadowMask::new(frame.width, frame.height, mask)?;
        let truth = ShadowMask::reference(scene, &bvh, light, &surfaces)?;
        let c = Comparison::new(&technique, &truth)?;
        println!(
            "light {}: {} of {} compared pixels wrong ({:.4} %: {} false shadow, {} false light), against the exact reference",
            light,
            c.all.wrong,
            c.all.compared,
            100.0 * c.all.fraction(),
            c.all.false_shadow,
            c.all.false_lit
        );
    }
    Ok(())
}

/// Logging to stderr (`RUST_LOG` overrides the `info` default).
pub fn init_logging() {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("info")).init();
}

/// Prints the frame report's warnings for the examples whose shadow volumes depend on closed
/// meshes and on the camera's depth: one line per open or non-manifold caster mesh
/// (`scene.topology`) and one per light whose volumes count against a depth coarser than
/// where they are measured exact (`ShadowVolumeReport::depth_precision`).
#[allow(dead_code)]
pub fn print_warnings(report: &umbra::shadows::FrameReport) {
    for warning in report.scene.topology.iter().filter_map(umbra::shadows::MeshTopology::warning) {
        println!("{warning}");
    }
    for l in &report.lights {
        if let Some(p) = l.shadow_volume.as_ref().and_then(|v| v.depth_precision) {
            println!("{}", p.warning(l.light));
        }
    }
}

/// Creates the folder `dir` (and its parents); the error names it.
pub fn create_dir(dir: &Path) -> anyhow::Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating the output folder {}", dir.display()))
}

/// Writes `rgba` (`width` × `height` RGBA8) as the PNG `path`; the error names it.
#[allow(dead_code)]
pub fn save_rgba(path: &Path, rgba: &[u8], width: u32, height: u32) -> anyhow::Result<()> {
    image::save_buffer(path, rgba, width, height, image::ColorType::Rgba8)
        .with_context(|| format!("writing {}", path.display()))
}

/// Fails when the validation layer (`UMBRA_VALIDATION=1`) reported anything so far: an example
/// never exits 0 over validation errors.
pub fn check_validation(ctx: &umbra::vk::Context) -> anyhow::Result<()> {
    let v = ctx.validation();
    anyhow::ensure!(
        v.total() == 0,
        "the validation layer reported {} errors and {} warnings (messages in the log above)",
        v.errors(),
        v.warnings()
    );
    Ok(())
}

/// Writes `<out>/<stem>.png` and `<out>/<stem>.json` and prints a summary of the report.
pub fn write_outputs(args: &CommonArgs, stem: &str, frame: &umbra::shadows::Frame) -> anyhow::Result<()> {
    create_dir(&args.out)?;
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
    for l in &r.lights {
        if let Some([lo, hi]) = l.shadow_map.as_ref().and_then(|m| m.receiver_texel_size) {
            println!("  light {}: a map texel spans {lo:.4}..{hi:.4} world units on what the camera sees", l.light);
        }
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
