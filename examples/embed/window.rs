//! `--window`: the engine's frames in a winit window. Each frame is the headless one with the
//! colour target left for transfers; umbra-vk's swapchain blits it into the acquired image on
//! the GPU and presents it (`Swapchain::present_image`): nothing is read back. The window keeps
//! its size (the engine's targets and umbra's `Shadows` are made for one).

use super::{summary, Args, Finish, Run};
use std::sync::Arc;
use std::time::Instant;
use umbra::vk::{Swapchain, SwapchainDesc};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, KeyEvent, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::{Window, WindowId};

/// Opens the window and runs until it is closed, Esc, or `--frames`.
pub fn run(args: &Args) -> anyhow::Result<()> {
    let event_loop =
        EventLoop::new().map_err(|e| anyhow::anyhow!("opening the window system (is DISPLAY set?): {e}"))?;
    event_loop.set_control_flow(ControlFlow::Poll);
    let mut app = App { args, shown: None, frame: 0, started: Instant::now(), error: None };
    event_loop.run_app(&mut app)?;
    let frames = app.frame;
    let secs = app.started.elapsed().as_secs_f64();
    let shown = app.shown.take();
    let result = match shown {
        // The swapchain goes first: its drop waits for the last blit out of the engine's image.
        Some(Shown { swapchain, run, .. }) => {
            drop(swapchain);
            run.finish()
        }
        None => Ok(()),
    };
    if let Some(e) = app.error {
        return Err(e);
    }
    println!("presented {frames} frames in {secs:.1} s ({:.1} fps) from the GPU", frames as f64 / secs.max(1e-6));
    result
}

/// The window, its swapchain and the engine.
struct Shown {
    swapchain: Swapchain,
    run: Run,
    window: Arc<Window>,
}

struct App<'a> {
    args: &'a Args,
    shown: Option<Shown>,
    frame: u64,
    started: Instant,
    error: Option<anyhow::Error>,
}

impl App<'_> {
    fn open(&self, event_loop: &ActiveEventLoop) -> anyhow::Result<Shown> {
        let (width, height) = self.args.size;
        let attributes = Window::default_attributes()
            .with_title("umbra embed: an engine's frame")
            .with_inner_size(PhysicalSize::new(width, height))
            .with_resizable(false);
        let window = Arc::new(event_loop.create_window(attributes)?);
        let run = Run::new(self.args, &umbra::vk::surface_extensions(event_loop)?)?;
        let swapchain = Swapchain::new(&run.ctx, Arc::clone(&window), SwapchainDesc::new(width, height))?;
        if !swapchain.can_present_images() {
            return Err(run.ctx.unsupported("blitting images into this window's swapchain").into());
        }
        Ok(Shown { swapchain, run, window })
    }

    /// One frame recorded, submitted and presented; `false` once `--frames` are shown.
    fn frame(&mut self) -> anyhow::Result<bool> {
        let Some(shown) = self.shown.as_mut() else { return Ok(true) };
        let recorded = shown.run.frame(self.frame, Finish::Present)?;
        shown.swapchain.present_image(shown.run.engine.color(), false)?;
        if self.frame % 60 == 0 {
            println!("{}", summary(self.frame, &recorded));
        }
        self.frame += 1;
        Ok(self.args.frames != Some(self.frame))
    }
}

impl ApplicationHandler for App<'_> {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.shown.is_some() || self.error.is_some() {
            return;
        }
        match self.open(event_loop) {
            Ok(shown) => self.shown = Some(shown),
            Err(e) => {
                self.error = Some(e);
                event_loop.exit();
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        let escape =
            |e: &KeyEvent| e.state == ElementState::Pressed && e.physical_key == PhysicalKey::Code(KeyCode::Escape);
        let outcome = match event {
            WindowEvent::CloseRequested => Ok(false),
            WindowEvent::KeyboardInput { event, .. } if escape(&event) => Ok(false),
            WindowEvent::RedrawRequested => self.frame(),
            _ => Ok(true),
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

    fn about_to_wait(&mut self, _: &ActiveEventLoop) {
        if let Some(shown) = &self.shown {
            shown.window.request_redraw();
        }
    }
}
