//! `--window`: every example's interactive viewer. A winit window, umbra's renderer, and a
//! [`Swapchain`] that presents each frame; keys and mouse as in [`BINDINGS`]; per-pass GPU
//! times and fill counts in the title.
//!
//! The animation is frame-locked (frame `k` is at `k / 60` s, paused frames do not advance),
//! so `--frames N --screenshot F` shows the same frame as a headless render with the
//! `--time` the run prints.

use super::animate;
use super::controls::{CameraRig, BINDINGS};
use super::views::{self, View};
use super::CommonArgs;
use anyhow::Context as _;
use glam::Vec3;
use std::collections::HashSet;
use std::sync::Arc;
use std::time::{Duration, Instant};
use umbra::scene::{Light, Scene, Technique};
use umbra::shadows::{Frame, MaskKind, RenderError, Renderer, RendererDesc};
use umbra::vk::raw_window_handle::{HasWindowHandle, RawWindowHandle};
use umbra::vk::{Context, ContextOptions, Swapchain, SwapchainDesc, ValidationCounter};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::{Window, WindowId};

/// Shadow-map sizes `M` cycles through (`None`: the example's own).
const MAP_SIZES: [Option<u32>; 5] = [Some(512), Some(1024), Some(2048), Some(4096), None];
/// Techniques of the number keys from 1: umbra's one table, in its order.
const TECHNIQUES: &[Technique] = &Technique::SHADOWING;
/// The number keys, from 1.
const DIGITS: [KeyCode; 9] = [
    KeyCode::Digit1,
    KeyCode::Digit2,
    KeyCode::Digit3,
    KeyCode::Digit4,
    KeyCode::Digit5,
    KeyCode::Digit6,
    KeyCode::Digit7,
    KeyCode::Digit8,
    KeyCode::Digit9,
];
// Every technique has its key.
const _: () = assert!(TECHNIQUES.len() <= DIGITS.len());
/// How often the title is refreshed.
const TITLE_EVERY: Duration = Duration::from_millis(500);

/// Opens the window and runs until it is closed, Esc, or `--frames`. Fails when a frame fails
/// or the validation layer reported anything.
pub fn run(args: &CommonArgs, name: &'static str, scene: Scene, desc: RendererDesc) -> anyhow::Result<()> {
    println!("umbra {name} --window; keys:");
    for (key, what) in BINDINGS {
        println!("  {key:<22} {what}");
    }
    let event_loop = EventLoop::new().context("opening the window system (is DISPLAY set?)")?;
    event_loop.set_control_flow(ControlFlow::Poll);
    let mut app = App { args, name, start: Some((scene, desc)), viewer: None, error: None, validation: None };
    event_loop.run_app(&mut app)?;
    let summary = app.viewer.as_ref().map(Viewer::summary);
    // Everything Vulkan is dropped before the count is read, so leak reports are counted too.
    app.viewer = None;
    if let Some(e) = app.error {
        return Err(e);
    }
    if let Some(s) = summary {
        println!("{s}");
    }
    if let Some(v) = app.validation {
        println!("validation messages: {} errors, {} warnings", v.errors(), v.warnings());
        anyhow::ensure!(v.total() == 0, "the validation layer reported {} messages", v.total());
    }
    Ok(())
}

struct App<'a> {
    args: &'a CommonArgs,
    name: &'static str,
    start: Option<(Scene, RendererDesc)>,
    viewer: Option<Viewer>,
    error: Option<anyhow::Error>,
    validation: Option<Arc<ValidationCounter>>,
}

impl ApplicationHandler for App<'_> {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        let Some((scene, desc)) = self.start.take() else { return };
        match Viewer::new(event_loop, self.args, self.name, scene, desc) {
            Ok(v) => {
                self.validation = Some(v.ctx.validation());
                self.viewer = Some(v);
            }
            Err(e) => {
                self.error = Some(e);
                event_loop.exit();
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        let Some(v) = self.viewer.as_mut() else { return };
        let outcome = match event {
            WindowEvent::CloseRequested => Ok(false),
            WindowEvent::RedrawRequested => v.frame(),
            event => Ok(v.input(event)),
        };
        match outcome {
            Ok(true) => {}
            Ok(false) => event_loop.exit(),
            Err(e) => {
                self.error = Some(e);
                event_loop.exit();
            }
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        let Some(v) = self.viewer.as_ref() else { return };
        match v.holding_until {
            Some(until) if Instant::now() >= until => event_loop.exit(),
            Some(until) => event_loop.set_control_flow(ControlFlow::WaitUntil(until)),
            None => v.window.request_redraw(),
        }
    }
}

/// What the keys changed.
#[derive(Clone, Copy, Debug)]
struct Settings {
    /// Every light's technique, or `None` for the example's own.
    technique: Option<Technique>,
    /// Index into [`MAP_SIZES`].
    map_size: usize,
    /// The hybrid's mask, or `None` for the device's best.
    mask: Option<MaskKind>,
    view: View,
    paused: bool,
}

/// The window, its swapchain and renderer, and the scene being moved about.
struct Viewer {
    args: CommonArgs,
    name: &'static str,
    window: Arc<Window>,
    // Field order: the swapchain (whose drop waits for its last copy out of the renderer's
    // image), then the renderer, before the context.
    swapchain: Swapchain,
    renderer: Renderer,
    ctx: Context,
    /// The example's renderer settings; the window's size and keys adjust a copy.
    base_desc: RendererDesc,
    desc: RendererDesc,
    settings: Settings,
    rebuild: bool,
    scene: Scene,
    /// The lights as loaded, and per light the user's turn (yaw, pitch) from there.
    base_lights: Vec<Light>,
    turns: Vec<(f32, f32)>,
    centre: Vec3,
    extent: f32,
    rig: CameraRig,
    selected: usize,
    frames: u64,
    animation_frame: u64,
    held: HashSet<KeyCode>,
    cursor: Option<(f64, f64)>,
    buttons: HashSet<MouseButton>,
    screenshot_now: bool,
    message: Option<String>,
    scratch: Vec<u8>,
    title_at: Instant,
    title_frames: u64,
    started: Instant,
    holding_until: Option<Instant>,
    /// CPU time of every frame (render and present), for the summary.
    cpu: CpuTimes,
}

/// Milliseconds spent per frame, summed over the run: wall time of rendering and presenting,
/// and the main thread's own CPU time (with a CPU driver, the wall time is mostly the driver's
/// threads doing the GPU's work; the thread's CPU time is what the viewer itself costs).
#[derive(Default)]
struct CpuTimes {
    frames: u64,
    render_ms: f64,
    present_ms: f64,
    /// `None` where the thread's CPU time cannot be read (`/proc/thread-self/schedstat`).
    thread_ms: Option<f64>,
    /// Where the schedstat line is read into (kept: nothing allocated per frame).
    stat: String,
}

impl CpuTimes {
    /// Nanoseconds the calling thread has run on a CPU (Linux), or `None`.
    fn thread_ns(&mut self) -> Option<u64> {
        use std::io::Read;
        self.stat.clear();
        std::fs::File::open("/proc/thread-self/schedstat").ok()?.read_to_string(&mut self.stat).ok()?;
        self.stat.split_whitespace().next()?.parse().ok()
    }
}

impl Viewer {
    fn new(
        event_loop: &ActiveEventLoop,
        args: &CommonArgs,
        name: &'static str,
        scene: Scene,
        desc: RendererDesc,
    ) -> anyhow::Result<Self> {
        let attributes = Window::default_attributes()
            .with_title(format!("umbra {name}"))
            .with_inner_size(PhysicalSize::new(desc.width, desc.height));
        let window = Arc::new(event_loop.create_window(attributes)?);
        let options = ContextOptions {
            surface_extensions: umbra::vk::surface_extensions(event_loop)?,
            ..ContextOptions::from_env()
        };
        let ctx = Context::with_options(&options)?;
        let size = window.inner_size();
        let mut swapchain_desc = SwapchainDesc::new(size.width, size.height);
        swapchain_desc.vsync = !args.no_vsync;
        let swapchain = Swapchain::new(&ctx, Arc::clone(&window), swapchain_desc)?;
        let mut current = desc;
        (current.width, current.height) = (size.width.max(1), size.height.max(1));
        // The plain image view from the GPU (`gpu_present`), unless told otherwise.
        current.read_color = args.present_readback || !swapchain.can_present_images() || !swapchain.can_capture();
        let renderer = Renderer::new(&ctx, current)?;
        if let Ok(RawWindowHandle::Xlib(h)) = window.window_handle().map(|h| h.as_raw()) {
            println!("window id 0x{:x}", h.window);
        }
        let bounds = scene.bounds();
        Ok(Self {
            args: args.clone(),
            name,
            window,
            renderer,
            swapchain,
            ctx,
            base_desc: desc,
            desc: current,
            settings: Settings {
                technique: None,
                map_size: MAP_SIZES.len() - 1,
                mask: None,
                view: View::Image,
                paused: false,
            },
            rebuild: false,
            base_lights: scene.lights.clone(),
            turns: vec![(0.0, 0.0); scene.lights.len()],
            centre: bounds.center(),
            extent: (bounds.max - bounds.min).length().max(1e-3),
            rig: CameraRig::new(scene.camera),
            scene,
            selected: 0,
            frames: 0,
            animation_frame: 0,
            held: HashSet::new(),
            cursor: None,
            buttons: HashSet::new(),
            screenshot_now: false,
            message: None,
            scratch: Vec::new(),
            title_at: Instant::now(),
            title_frames: 0,
            started: Instant::now(),
            holding_until: None,
            cpu: CpuTimes::default(),
        })
    }

    /// Renders and presents one frame; `false` once the run is over.
    fn frame(&mut self) -> anyhow::Result<bool> {
        if self.holding_until.is_some() {
            return Ok(true);
        }
        let size = self.window.inner_size();
        if size.width == 0 || size.height == 0 {
            return Ok(true);
        }
        if (size.width, size.height) != (self.desc.width, self.desc.height) {
            self.swapchain.resize(size.width, size.height);
            self.rebuild = true;
        }
        if self.rebuild || self.desc.read_color == self.gpu_present() {
            self.rebuild_renderer(size)?;
        }
        self.apply_held_keys();
        let time = animate::frame_time(self.animation_frame);
        self.update_scene(time);
        let (rendering, thread_before) = (Instant::now(), self.cpu.thread_ns());
        let frame = match self.renderer.render(&self.scene) {
            Ok(f) => f,
            Err(e @ RenderError::UnsupportedLight { .. }) => {
                // E.g. ray tracing asked of a device without ray queries: back to the example's
                // techniques.
                self.message = Some(e.to_string());
                self.settings.technique = None;
                return Ok(true);
            }
            Err(e) => return Err(e.into()),
        };
        let last = self.args.frames == Some(self.frames + 1);
        let wanted = (last && self.args.screenshot.is_some()) || self.screenshot_now;
        let presenting = Instant::now();
        let (presented, copied, note) = match self.desc.read_color {
            // The renderer's image, blitted on the GPU: nothing read back.
            false => (self.swapchain.present_image(self.renderer.color_image()?, wanted)?, None, None),
            true => {
                let (pixels, note) = views::pixels(self.settings.view, &frame, self.selected, &mut self.scratch);
                // Read back from the swapchain image; where the surface forbids that, the pixels
                // copied into it (the same bytes) stand in.
                let capture = wanted && self.swapchain.can_capture();
                let copied = (wanted && !capture).then(|| pixels.to_vec());
                (self.swapchain.present(pixels, frame.width, frame.height, capture)?, copied, note)
            }
        };
        self.cpu.frames += 1;
        self.cpu.render_ms += (presenting - rendering).as_secs_f64() * 1e3;
        self.cpu.present_ms += presenting.elapsed().as_secs_f64() * 1e3;
        let thread_after = self.cpu.thread_ns();
        self.cpu.thread_ms = match (thread_before, thread_after, self.cpu.thread_ms) {
            (Some(a), Some(b), Some(sum)) if self.cpu.frames > 1 => Some(sum + (b - a) as f64 / 1e6),
            (Some(a), Some(b), _) if self.cpu.frames == 1 => Some((b - a) as f64 / 1e6),
            _ => None,
        };
        let shot = match (presented.and_then(|p| p.capture.map(|c| (c, p.extent))), copied) {
            (Some((c, extent)), _) => Some((c, extent.width, extent.height)),
            (None, Some(c)) => Some((c, frame.width, frame.height)),
            (None, None) => None,
        };
        if let Some((rgba, width, height)) = shot {
            self.save_screenshot(&rgba, width, height, &frame, time)?;
        }
        self.screenshot_now = false;
        self.frames += 1;
        if !self.settings.paused {
            self.animation_frame += 1;
        }
        if let Some((at, (w, h))) = self.args.resize_at {
            if self.frames == at {
                println!("frame {at}: asking the window system for {w}x{h}");
                let _ = self.window.request_inner_size(PhysicalSize::new(w, h));
            }
        }
        self.update_title(&frame, note);
        if last {
            if self.args.hold > 0.0 {
                println!("holding the last frame for {} s", self.args.hold);
                self.holding_until = Some(Instant::now() + Duration::from_secs_f32(self.args.hold));
                return Ok(true);
            }
            return Ok(false);
        }
        Ok(true)
    }

    /// Handles input; `false` to quit.
    fn input(&mut self, event: WindowEvent) -> bool {
        match event {
            WindowEvent::KeyboardInput { event, .. } => {
                let PhysicalKey::Code(key) = event.physical_key else { return true };
                if event.state == ElementState::Released {
                    self.held.remove(&key);
                    return true;
                }
                if event.repeat {
                    return true;
                }
                self.held.insert(key);
                return self.key(key);
            }
            WindowEvent::MouseInput { state, button, .. } => {
                match state {
                    ElementState::Pressed => self.buttons.insert(button),
                    ElementState::Released => self.buttons.remove(&button),
                };
            }
            WindowEvent::CursorMoved { position, .. } => {
                if let Some((x, y)) = self.cursor {
                    let (dx, dy) = ((position.x - x) as f32, (position.y - y) as f32);
                    if self.buttons.contains(&MouseButton::Left) {
                        self.rig.orbit(dx, dy);
                    } else if self.buttons.contains(&MouseButton::Right) || self.buttons.contains(&MouseButton::Middle)
                    {
                        self.rig.pan(dx, dy);
                    }
                }
                self.cursor = Some((position.x, position.y));
            }
            WindowEvent::CursorLeft { .. } => self.cursor = None,
            WindowEvent::MouseWheel { delta, .. } => {
                let lines = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / 40.0,
                };
                self.rig.zoom(lines);
            }
            _ => {}
        }
        true
    }

    /// A key press; `false` to quit.
    fn key(&mut self, key: KeyCode) -> bool {
        let s = &mut self.settings;
        match key {
            KeyCode::Escape => return false,
            key if DIGITS[..TECHNIQUES.len()].contains(&key) => {
                let i = DIGITS.iter().position(|&k| k == key).unwrap_or(0);
                s.technique = Some(TECHNIQUES[i]);
                self.message = None;
            }
            KeyCode::Digit0 => s.technique = None,
            KeyCode::KeyM => {
                s.map_size = (s.map_size + 1) % MAP_SIZES.len();
                self.rebuild = true;
            }
            KeyCode::KeyK => {
                let depth_bounds = self.ctx.capabilities().depth_bounds;
                let kinds: Vec<Option<MaskKind>> = MaskKind::ALL
                    .into_iter()
                    .filter(|&m| m != MaskKind::DepthBounds || depth_bounds)
                    .map(Some)
                    .collect();
                let now = kinds.iter().position(|&m| m == s.mask.or(Some(self.renderer.mask()))).unwrap_or(0);
                s.mask = kinds[(now + 1) % kinds.len()];
                self.rebuild = true;
            }
            KeyCode::KeyV => {
                s.view = s.view.next();
                self.rebuild = true;
            }
            KeyCode::Space | KeyCode::KeyP => s.paused = !s.paused,
            KeyCode::Tab => self.selected = (self.selected + 1) % self.base_lights.len().max(1),
            KeyCode::KeyR => {
                self.rig.reset();
                self.turns.iter_mut().for_each(|t| *t = (0.0, 0.0));
                self.animation_frame = 0;
            }
            KeyCode::F12 => self.screenshot_now = true,
            _ => {}
        }
        true
    }

    /// Fly and light keys act every frame while held.
    fn apply_held_keys(&mut self) {
        let axis = |plus: KeyCode, minus: KeyCode| {
            f32::from(u8::from(self.held.contains(&plus))) - f32::from(u8::from(self.held.contains(&minus)))
        };
        let (forward, right, up) = (
            axis(KeyCode::KeyW, KeyCode::KeyS),
            axis(KeyCode::KeyD, KeyCode::KeyA),
            axis(KeyCode::KeyE, KeyCode::KeyQ),
        );
        if (forward, right, up) != (0.0, 0.0, 0.0) {
            self.rig.fly(forward, right, up, self.extent * 0.01);
        }
        let (yaw, pitch) = (axis(KeyCode::ArrowRight, KeyCode::ArrowLeft), axis(KeyCode::ArrowUp, KeyCode::ArrowDown));
        if let Some(turn) = self.turns.get_mut(self.selected) {
            turn.0 += 0.02 * yaw;
            turn.1 += 0.02 * pitch;
        }
    }

    /// Lights and camera for animation time `time`.
    fn update_scene(&mut self, time: f32) {
        for (i, (light, base)) in self.scene.lights.iter_mut().zip(&self.base_lights).enumerate() {
            let (mut yaw, pitch) = self.turns[i];
            if i == 0 {
                yaw += animate::orbit_angle(time);
            }
            *light = animate::turned(base, self.centre, yaw, pitch);
            if let Some(t) = self.settings.technique {
                light.technique = t;
            }
        }
        self.scene.camera = self.rig.camera();
        self.scene.fit_near_plane();
    }

    /// Whether frames go to the window straight from the GPU: the plain image view, unless
    /// `--present-readback`, where the swapchain can blit it (and capture screenshots).
    fn gpu_present(&self) -> bool {
        !self.args.present_readback
            && self.settings.view == View::Image
            && self.swapchain.can_present_images()
            && self.swapchain.can_capture()
    }

    /// A renderer for the window's size and the keys' settings.
    fn rebuild_renderer(&mut self, size: PhysicalSize<u32>) -> anyhow::Result<()> {
        let mut desc = self.base_desc;
        desc.read_color = !self.gpu_present();
        (desc.width, desc.height) = (size.width, size.height);
        if let Some(resolution) = MAP_SIZES[self.settings.map_size] {
            desc.shadow_map.resolution = Some(resolution);
            desc.hybrid.resolution = Some(resolution);
        }
        if self.settings.mask.is_some() {
            desc.hybrid.mask = self.settings.mask;
        }
        desc.diagnostics |= self.settings.view.needs_diagnostics();
        desc.shadow_volume.overdraw |= self.settings.view.needs_overdraw();
        if desc != self.desc {
            // The swapchain may still be copying the old renderer's image.
            self.swapchain.wait()?;
            self.renderer = Renderer::new(&self.ctx, desc)?;
            self.desc = desc;
        }
        self.rebuild = false;
        Ok(())
    }

    fn save_screenshot(&self, rgba: &[u8], width: u32, height: u32, frame: &Frame, time: f32) -> anyhow::Result<()> {
        let path = match &self.args.screenshot {
            Some(p) => p.clone(),
            None => self.args.out.join(format!("{}-window-{}.png", self.name, self.frames)),
        };
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            super::create_dir(dir)?;
        }
        super::save_rgba(&path, rgba, width, height)?;
        frame.save_report(&path.with_extension("json"))?;
        let same = (width, height) == (frame.width, frame.height);
        println!(
            "screenshot of frame {} ({width}x{height}{}): {} (animation as --time {time})",
            self.frames,
            if same { "" } else { ", NOT the rendered size" },
            path.display()
        );
        Ok(())
    }

    fn update_title(&mut self, frame: &Frame, note: Option<&str>) {
        let now = Instant::now();
        if self.frames > 1 && now.duration_since(self.title_at) < TITLE_EVERY {
            return;
        }
        let fps = (self.frames - self.title_frames) as f64 / now.duration_since(self.title_at).as_secs_f64().max(1e-6);
        self.title_at = now;
        self.title_frames = self.frames;
        let status = Status {
            settings: self.settings,
            map: MAP_SIZES[self.settings.map_size],
            mask: self.renderer.mask(),
            selected: self.selected,
            fps,
            note: note.or(self.message.as_deref()),
        };
        let title = title(self.name, frame, &status);
        self.window.set_title(&title);
    }

    fn summary(&self) -> String {
        let secs = self.started.elapsed().as_secs_f64();
        let n = self.cpu.frames.max(1) as f64;
        let how = if self.desc.read_color { "through a CPU readback" } else { "from the GPU" };
        let thread = self.cpu.thread_ms.map_or(String::new(), |ms| format!(", main thread on a CPU {:.2}", ms / n));
        format!(
            "presented {} frames in {secs:.1} s ({:.1} fps), {} swapchain recreation(s), {} presentation buffer(s) \
             allocated, last size {}x{}; per frame {:.2} ms (render {:.2} + present {:.2}{thread}), presented {how}",
            self.frames,
            self.frames as f64 / secs.max(1e-6),
            self.swapchain.recreations(),
            self.swapchain.buffers_created(),
            self.desc.width,
            self.desc.height,
            (self.cpu.render_ms + self.cpu.present_ms) / n,
            self.cpu.render_ms / n,
            self.cpu.present_ms / n,
        )
    }
}

/// What the title shows besides the frame's report.
struct Status<'a> {
    settings: Settings,
    /// The shadow-map size `M` chose (`None`: the example's).
    map: Option<u32>,
    mask: MaskKind,
    selected: usize,
    fps: f64,
    note: Option<&'a str>,
}

/// The window title: technique and settings, GPU time per pass, fill counts, frame rate.
fn title(name: &str, frame: &Frame, status: &Status) -> String {
    let (r, s) = (&frame.report, &status.settings);
    let technique = s.technique.map_or("as loaded", |t| t.name());
    let map = status.map.map_or("default".into(), |m| m.to_string());
    let mut passes: Vec<_> = r.passes.iter().filter_map(|p| p.gpu_ms.map(|t| (t, p.name.as_str()))).collect();
    passes.sort_by(|a, b| b.0.total_cmp(&a.0));
    let passes: Vec<String> = passes.iter().take(5).map(|(t, n)| format!("{n} {t:.2}")).collect();
    let mut fill = Vec::new();
    for l in &r.lights {
        if let Some(h) = &l.hybrid {
            fill.push(format!("L{} silhouette {:.2}%", l.light, 100.0 * h.silhouette_fraction));
        }
        if let Some(n) = l.shadow_volume.as_ref().and_then(|v| v.volume_fragments) {
            fill.push(format!("L{} {n} volume frags", l.light));
        }
        if let Some(n) = l.silhouette_map.as_ref().and_then(|m| m.silhouette_pixels) {
            fill.push(format!("L{} {n} silhouette px", l.light));
        }
    }
    let total = r.total_gpu_ms.map_or("n/a".into(), |t| format!("{t:.2} ms"));
    let mut title = format!(
        "umbra {name} · {}x{} · {technique} · map {map} · mask {} · view {} (L{}) · GPU {total} [{}]",
        frame.width,
        frame.height,
        status.mask.name(),
        s.view.name(),
        status.selected,
        passes.join(", ")
    );
    if !fill.is_empty() {
        title += &format!(" · {}", fill.join(", "));
    }
    title += &format!(" · {:.1} fps", status.fps);
    if s.paused {
        title += " · paused";
    }
    if let Some(n) = status.note {
        title += &format!(" · {n}");
    }
    title
}

/// `FRAME:WxH` for `--resize-at`.
pub fn parse_resize(s: &str) -> Result<(u64, (u32, u32)), String> {
    let (frame, size) = s.split_once(':').ok_or_else(|| format!("{s:?} is not FRAME:WIDTHxHEIGHT"))?;
    let frame = frame.trim().parse::<u64>().map_err(|e| format!("{frame:?}: {e}"))?;
    if frame == 0 {
        return Err(format!("{s:?}: FRAME counts from 1 (the first presented frame)"));
    }
    Ok((frame, super::flags::parse_size(size)?))
}
