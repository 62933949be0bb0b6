//! A minimal engine that links umbra for its shadows, written the way an engine would: its own
//! Vulkan instance and device (`device.rs`), its own depth pre-pass, frames in flight with a
//! command buffer and fence each, and a forward shading shader of its own (`engine.rs`,
//! `shaders-glsl/engine/shade.*`) that multiplies each light by the visibility image umbra hands
//! it. umbra records every light's shadows into the engine's command buffer between the two
//! passes (`Shadows::record`, docs/embedding.md). The teapot moves around Suzanne every frame;
//! only its transform reaches umbra.
//!
//! Headless (the default): renders `--frames` frames and writes the first and the last as PNG
//! with one line per frame (what umbra recorded, uploaded, allocated and submitted, and the GPU
//! time of the slot's previous frame). `--window`: the same frames in a window, presented
//! from the GPU.
//!
//! ```text
//! cargo run --release --example embed -- --out out/embed
//! cargo run --release --example embed -- --technique shadow_volume --frames 48
//! cargo run --release --example embed -- --window
//! cargo run --release --example embed -- --deform
//! ```
//!
//! `--deform`: the engine deforms Suzanne in a compute pass of its own every frame and hands
//! it to umbra as a deforming mesh (`Shadows::add_deforming_mesh`), whose shadow volumes are
//! built on the GPU from each frame's pose.

mod device;
mod engine;
mod window;

use clap::Parser;
use device::EngineDevice;
use engine::Engine;
use glam::Mat4;
use std::path::PathBuf;
use umbra::scene::{Scene, Technique};
use umbra::shadows::{
    FrameInputs, HostClip, Instance, InstanceId, RendererDesc, ShadowFrame, Shadows, ShadowsDesc, VolumeBuild,
};

#[derive(Parser, Debug)]
#[command(about = "A minimal engine recording umbra's shadows into its own frames")]
struct Args {
    /// The scene: a .toml scene file or a .glb/.gltf path.
    #[arg(long, default_value = "examples/scenes/embed.toml")]
    scene: String,
    /// Use this technique for every light (unshadowed, shadow_map, shadow_volume,
    /// silhouette_map, hybrid, auto); default: the scene's.
    #[arg(long, value_parser = parse_technique)]
    technique: Option<Technique>,
    /// Frames rendered (1 to 10000; headless default 12, with `--window` until it is closed);
    /// the last object turns once around the scene's axis every 48 frames.
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..=10_000))]
    frames: Option<u64>,
    /// Show the frames in a window (Esc or closing it quits): the engine's colour target is
    /// blitted into the swapchain on the GPU (`Swapchain::present_image`).
    #[arg(long)]
    window: bool,
    /// Frames in flight (1 to 4).
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u32).range(1..=4))]
    frames_in_flight: u32,
    /// Frame size, WIDTHxHEIGHT.
    #[arg(long, default_value = "960x540", value_parser = parse_size)]
    size: (u32, u32),
    /// Output folder (created if missing).
    #[arg(long, default_value = "out/embed")]
    out: PathBuf,
    /// Deform the first casting object's mesh (Suzanne) in the engine's own compute pass every
    /// frame (a sideways wave, `shaders-glsl/engine/wave.comp`) and hand it to umbra with
    /// `Shadows::add_deforming_mesh`: its shadow volumes are built on the GPU from each frame's
    /// pose (`VolumeBuild::Gpu`), and lights whose technique cannot read the pose (the hybrid,
    /// silhouette maps, rays, auto) use shadow volumes.
    #[arg(long)]
    deform: bool,
}

fn parse_technique(s: &str) -> Result<Technique, String> {
    Technique::from_name(s).ok_or_else(|| format!("{s:?}: not a technique"))
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s.split_once('x').ok_or_else(|| format!("{s:?}: expected WIDTHxHEIGHT"))?;
    let parse = |v: &str| v.parse::<u32>().ok().filter(|v| (1..=8192).contains(v));
    match (parse(w), parse(h)) {
        (Some(w), Some(h)) => Ok((w, h)),
        _ => Err(format!("{s:?}: width and height from 1 to 8192")),
    }
}

fn main() -> anyhow::Result<()> {
    let args = Args::parse();
    if args.window {
        return window::run(&args);
    }
    std::fs::create_dir_all(&args.out)?;
    let mut run = Run::new(&args, &[])?;
    let frames = args.frames.unwrap_or(12);
    for frame in 0..frames {
        let last = frame + 1 == frames;
        let recorded = run.frame(frame, if last { Finish::CopyOut } else { Finish::Nothing })?;
        println!("{}", summary(frame, &recorded));
        if let (true, Some(passes)) = (last, &recorded.earlier_passes) {
            print!("{}", per_light(&recorded, passes));
        }
        if frame == 0 || last {
            run.device.wait_all()?;
            let path = args.out.join(format!("embed-frame-{frame}.png"));
            let (width, height) = args.size;
            image::save_buffer(&path, &run.engine.pixels()?, width, height, image::ColorType::Rgba8)?;
            println!("wrote {}", path.display());
        }
    }
    run.finish()
}

/// What the engine does with its colour target at the end of a frame.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Finish {
    Nothing,
    /// Copy it into the readback buffer (headless: the frames written as PNG).
    CopyOut,
    /// Leave it for the swapchain's blit (`--window`).
    Present,
}

/// The engine with umbra linked: its device, umbra's context over it, its renderer, umbra's
/// shadows, and the scene. Fields drop in order: umbra's shadows, the engine's renderer,
/// umbra's context, the engine's device.
struct Run {
    scene: Scene,
    ids: Vec<InstanceId>,
    moving: (usize, Mat4),
    frames_in_flight: u32,
    shadows: Shadows,
    engine: Engine,
    ctx: umbra::vk::Context,
    device: EngineDevice,
}

impl Run {
    /// Loads the scene and sets everything up (with a window's `surface_extensions`, a device
    /// that can present).
    fn new(args: &Args, surface_extensions: &[&std::ffi::CStr]) -> anyhow::Result<Self> {
        let mut scene = umbra::scene::load(&args.scene)?;
        if let Some(t) = args.technique {
            scene.lights.iter_mut().for_each(|l| l.technique = t);
        }
        anyhow::ensure!(!scene.objects.is_empty(), "{}: no objects", args.scene);
        let deform = match args.deform {
            true => Some(deformed_mesh(&mut scene)?),
            false => None,
        };
        let device = EngineDevice::new(args.frames_in_flight, surface_extensions)?;
        let ctx = device.umbra_context()?;
        let (width, height) = args.size;
        let engine = Engine::new(&ctx, &scene, width, height, args.frames_in_flight as usize, deform)?;
        let mut settings = RendererDesc::new(width, height);
        if deform.is_some() {
            // Built on the GPU, never clipped on the host (which the GPU path cannot do).
            settings.shadow_volume.build = VolumeBuild::Gpu;
            settings.shadow_volume.host_clip = HostClip::Never;
        }
        let desc =
            ShadowsDesc { settings, depth_format: engine.depth_format(), frames_in_flight: args.frames_in_flight };
        let mut shadows = Shadows::new(&ctx, desc)?;
        let ids = register(&mut shadows, &scene, &engine, deform)?;
        let device_name = &ctx.capabilities().device_name;
        let in_place = (0..scene.meshes.len()).filter(|&m| !casts(&scene, m)).count();
        println!(
            "engine on {device_name}: {} objects, {in_place} of {} meshes drawn by umbra from the engine's buffers, {} lights, {width}x{height}",
            scene.objects.len(),
            scene.meshes.len(),
            scene.lights.len()
        );
        if let Some(m) = deform {
            println!(
                "deforming {} on the GPU: its shadow volumes built on the GPU from each frame's pose",
                scene.meshes[m].name
            );
        }
        let moving = (scene.objects.len() - 1, scene.objects[scene.objects.len() - 1].transform);
        let frames_in_flight = args.frames_in_flight;
        Ok(Self { scene, ids, moving, frames_in_flight, shadows, engine, ctx, device })
    }

    /// Frame `frame`: the last object moved, then depth pre-pass, umbra's shadows and shading
    /// recorded into the slot's command buffer and submitted with its fence.
    fn frame(&mut self, frame: u64, finish: Finish) -> anyhow::Result<ShadowFrame> {
        let (moving, start) = self.moving;
        let angle = frame as f32 * std::f32::consts::TAU / 48.0;
        self.scene.objects[moving].transform = Mat4::from_rotation_y(angle) * start;
        self.shadows.set_transform(self.ids[moving], self.scene.objects[moving].transform)?;
        let slot = (frame % u64::from(self.frames_in_flight)) as usize;
        let cmd = self.device.begin_frame(slot)?;
        let (scene, engine) = (&self.scene, &mut self.engine);
        let aspect = engine.width as f32 / engine.height as f32;
        let (view, proj) = (scene.camera.view(), scene.camera.projection(aspect));
        let inputs =
            FrameInputs { depth: engine.depth_target(), view, proj, lights: &scene.lights, frame_index: frame };
        {
            let mut rec = self.ctx.record_into(cmd);
            engine.deform(&mut rec, angle * 4.0);
            engine.depth_prepass(&mut rec, slot, scene)?;
        }
        let recorded = self.shadows.record(cmd, &inputs)?;
        // Host writes before the submission: the pre-pass recorded above reads them too.
        engine.write_frame(slot, scene, proj * view, &recorded.lights)?;
        {
            let mut rec = self.ctx.record_into(cmd);
            engine.shade(&mut rec, slot, scene)?;
            match finish {
                Finish::Nothing => {}
                Finish::CopyOut => engine.copy_out(&mut rec),
                Finish::Present => engine.to_transfer(&mut rec),
            }
        }
        self.device.submit_frame(slot)?;
        Ok(recorded)
    }

    /// Waits for every frame, drops umbra and the engine's renderer, and fails if the
    /// engine's messenger heard from the validation layer.
    fn finish(self) -> anyhow::Result<()> {
        self.device.wait_all()?;
        drop(self);
        let messages = device::MESSAGES.load(std::sync::atomic::Ordering::Relaxed);
        println!("validation messages: {messages}");
        anyhow::ensure!(messages == 0, "{messages} validation messages");
        Ok(())
    }
}

impl Drop for Run {
    /// On an error too, nothing is destroyed while a frame may still use it.
    fn drop(&mut self) {
        let _ = self.device.wait_all();
    }
}

/// Registers every mesh and object of `scene` with umbra: a mesh that casts shadows from its
/// CPU data (volumes and the hybrid build geometry from it), one that only receives them from
/// the engine's own buffers, which umbra draws in place, and mesh `deform` from the engine's
/// buffers with its rest pose (its bounds grown by the wave's reach).
fn register(
    shadows: &mut Shadows,
    scene: &Scene,
    engine: &Engine,
    deform: Option<usize>,
) -> anyhow::Result<Vec<InstanceId>> {
    let meshes = (scene.meshes.iter().enumerate())
        .map(|(i, m)| match (deform == Some(i), casts(scene, i)) {
            (true, _) => {
                let mut bounds = m.bounds();
                bounds.min.x -= engine::WAVE_AMPLITUDE;
                bounds.max.x += engine::WAVE_AMPLITUDE;
                shadows.add_deforming_mesh(engine.mesh_buffers(i, bounds), m)
            }
            (false, true) => shadows.add_mesh(m.clone()),
            (false, false) => shadows.add_mesh_buffers(engine.mesh_buffers(i, m.bounds())),
        })
        .collect::<Result<Vec<_>, _>>()?;
    let mut ids = Vec::new();
    for o in &scene.objects {
        ids.push(shadows.add_instance(Instance::of_object(o, meshes[o.mesh]))?);
    }
    Ok(ids)
}

/// `--deform`: the mesh of `scene`'s first casting object, every light whose technique cannot
/// read a pose deformed on the GPU switched to shadow volumes.
fn deformed_mesh(scene: &mut Scene) -> anyhow::Result<usize> {
    let object = scene.objects.iter().find(|o| o.casts_shadows).ok_or_else(|| anyhow::anyhow!("no casting object"))?;
    for light in &mut scene.lights {
        if !matches!(light.technique, Technique::ShadowMap | Technique::ShadowVolume | Technique::Unshadowed) {
            println!("--deform: a {:?} light uses ShadowVolume (only it and ShadowMap read the pose)", light.technique);
            light.technique = Technique::ShadowVolume;
        }
    }
    Ok(object.mesh)
}

/// Whether an object drawing mesh `mesh` casts shadows.
fn casts(scene: &Scene, mesh: usize) -> bool {
    scene.objects.iter().any(|o| o.mesh == mesh && o.casts_shadows)
}

/// What umbra's passes cost on the GPU per light in the slot's previous frame (and what no
/// light owns: the mesh upload, a depth rebuild, the hand-off).
fn per_light(frame: &ShadowFrame, passes: &[umbra::shadows::PassReport]) -> String {
    let mut out = String::from("umbra's GPU time per light (the slot's previous frame):\n");
    let lights = frame.lights.iter().map(|l| (Some(l.light), format!("light {} ({:?})", l.light, l.plan.technique)));
    for (light, name) in lights.chain([(None, "no light".to_string())]) {
        let mine: Vec<_> = passes.iter().filter(|p| p.light == light).collect();
        let ms: f64 = mine.iter().filter_map(|p| p.gpu_ms).sum();
        let names: Vec<&str> = mine.iter().map(|p| p.name.as_str()).collect();
        out += &format!("  {name}: {ms:.3} ms [{}]\n", names.join(", "));
    }
    out
}

/// One line about what umbra did in a frame.
pub(crate) fn summary(frame: u64, f: &ShadowFrame) -> String {
    let shadowed = f.lights.iter().filter(|l| l.visibility.is_some()).count();
    let earlier = f.earlier_passes.as_ref().map_or("-".to_string(), |p| {
        let ms: f64 = p.iter().filter_map(|p| p.gpu_ms).sum();
        format!("{ms:.3} ms over {} passes", p.len())
    });
    let rebuilt = f.depth_rebuilt.map_or(String::new(), |r| format!(", depth rebuilt: {r}"));
    let techniques: Vec<String> = f.lights.iter().map(|l| format!("{:?}", l.plan.technique)).collect();
    format!(
        "frame {frame} (slot {}): {shadowed}/{} lights shadowed [{}], uploaded {} B, {} allocations, {} submissions by umbra, slot's previous frame on the GPU: {earlier}{rebuilt}",
        f.slot,
        f.lights.len(),
        techniques.join(", "),
        f.geometry_uploaded_bytes,
        f.memory_allocations,
        f.submissions,
    )
}
