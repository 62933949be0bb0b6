//! The renderer: records a frame's passes into a headless target and reads the colour back.
//!
//! A frame, top to bottom:
//! 1. plan: per light, decide what to record (`plan::plan_lights`);
//! 2. upload: the scene's meshes, objects, lights and camera (`gpu_scene`);
//! 3. `ambient`: depth plus ambient term for every object;
//! 4. `light N (kind)`: per planned light, its technique's passes then its additive lighting;
//! 5. `readback`: copy the colour target into a host-visible buffer.
//!
//! Every pass is a debug label with timestamps around it; the [`FrameReport`] lists them.

use crate::forward::Forward;
use crate::gpu_scene::GpuScene;
use crate::plan::plan_lights;
use crate::report::{FrameReport, SceneSummary};
use crate::timing::{PassLog, PassTimer};
use crate::{RenderError, RenderResult};
use std::path::Path;
use std::time::Instant;
use umbra_scene::Scene;
use umbra_vk::{
    vk, Buffer, BufferDesc, ColorAttachment, Context, DepthAttachment, Image, ImageDesc, ImageState, RenderTargets,
};

/// The colour target format: linear 8-bit RGBA (values are written as computed, no sRGB curve).
pub const COLOR_FORMAT: vk::Format = vk::Format::R8G8B8A8_UNORM;

/// What a renderer renders into.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RendererDesc {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
}

/// A rendered frame: RGBA8 pixels (row 0 at the top) and its report.
#[derive(Clone, Debug)]
pub struct Frame {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Tightly packed RGBA8, `width * height * 4` bytes.
    pub rgba: Vec<u8>,
    /// What the frame did.
    pub report: FrameReport,
}

impl Frame {
    /// The RGBA value at `(x, y)`, `y = 0` being the top row.
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 4] {
        let i = 4 * (y as usize * self.width as usize + x as usize);
        let mut p = [0; 4];
        p.copy_from_slice(&self.rgba[i..i + 4]);
        p
    }

    /// Writes the pixels as a PNG.
    pub fn save_png(&self, path: &Path) -> RenderResult<()> {
        image::save_buffer(path, &self.rgba, self.width, self.height, image::ColorType::Rgba8)
            .map_err(|e| RenderError::Output { path: path.to_owned(), message: e.to_string() })
    }

    /// Writes the report as pretty JSON.
    pub fn save_report(&self, path: &Path) -> RenderResult<()> {
        std::fs::write(path, self.report.to_json())
            .map_err(|e| RenderError::Output { path: path.to_owned(), message: e.to_string() })
    }
}

/// Renders scenes into a headless target of a fixed size.
pub struct Renderer {
    ctx: Context,
    desc: RendererDesc,
    color: Image,
    depth: Image,
    readback: Buffer,
    forward: Forward,
}

impl Renderer {
    /// Creates the targets and pipelines.
    pub fn new(ctx: &Context, desc: RendererDesc) -> RenderResult<Self> {
        let caps = ctx.capabilities();
        let max = caps.max_image_dimension_2d;
        if desc.width == 0 || desc.height == 0 || desc.width > max || desc.height > max {
            return Err(RenderError::InvalidSize {
                width: desc.width,
                height: desc.height,
                why: format!("each side must be in 1..={max} on {}", caps.device_name),
            });
        }
        let depth_format = caps.depth_stencil_format;
        if depth_format == vk::Format::UNDEFINED {
            return Err(ctx.unsupported("any depth/stencil attachment format").into());
        }
        let color = Image::new(
            ctx,
            "colour target",
            ImageDesc::new_2d(COLOR_FORMAT, desc.width, desc.height)
                .usage(vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC),
        )?;
        let depth = Image::new(
            ctx,
            "depth/stencil target",
            ImageDesc::new_2d(depth_format, desc.width, desc.height)
                .usage(vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT),
        )?;
        let readback =
            Buffer::new(ctx, "colour readback", BufferDesc::readback(4 * desc.width as u64 * desc.height as u64))?;
        let forward = Forward::new(ctx, COLOR_FORMAT, depth_format)?;
        Ok(Self { ctx: ctx.clone(), desc, color, depth, readback, forward })
    }

    /// The target size.
    pub fn desc(&self) -> RendererDesc {
        self.desc
    }

    /// Renders one frame of `scene` and reads it back.
    pub fn render(&mut self, scene: &Scene) -> RenderResult<Frame> {
        let started = Instant::now();
        let lights = plan_lights(scene)?;
        let aspect = self.desc.width as f32 / self.desc.height as f32;
        let gpu = GpuScene::upload(&self.ctx, &self.forward.set_layout, scene, aspect)?;
        // Poison the readback so a copy that never happened cannot pass for a frame.
        let poison = vec![0xCD; self.readback.desc.size as usize];
        self.readback.write(0, &poison)?;

        let planned = lights.iter().filter(|l| l.recorded).count();
        let timer = PassTimer::new(&self.ctx, 2 + planned)?;
        let mut log = PassLog::default();
        let mut rec = self.ctx.begin_commands("frame")?;
        timer.reset(&mut rec);
        rec.transition(&[
            (&self.color, ImageState::Undefined, ImageState::ColorAttachment),
            (&self.depth, ImageState::Undefined, ImageState::DepthStencilAttachment),
        ]);

        let bg = scene.background;
        timer.begin(&mut rec, &mut log, "ambient".into(), None);
        let clear_color = [ColorAttachment { image: &self.color, clear: Some([bg.x, bg.y, bg.z, 1.0]) }];
        rec.begin_rendering(&RenderTargets {
            color: &clear_color,
            depth: Some(DepthAttachment { image: &self.depth, view: None, clear: Some((1.0, 0)), read_only: false }),
        });
        self.forward.record_ambient(&mut rec, &gpu, scene, &mut log);
        rec.end_rendering();
        timer.end(&mut rec, &log);

        let load_color = [ColorAttachment { image: &self.color, clear: None }];
        for plan in lights.iter().filter(|l| l.recorded) {
            timer.begin(
                &mut rec,
                &mut log,
                format!("light {} ({:?})", plan.light, plan.kind).to_lowercase(),
                Some(plan.light),
            );
            rec.begin_rendering(&RenderTargets {
                color: &load_color,
                depth: Some(DepthAttachment { image: &self.depth, view: None, clear: None, read_only: false }),
            });
            self.forward.record_light(&mut rec, &gpu, scene, plan.light as u32, &mut log);
            rec.end_rendering();
            timer.end(&mut rec, &log);
        }

        timer.begin(&mut rec, &mut log, "readback".into(), None);
        rec.transition(&[(&self.color, ImageState::ColorAttachment, ImageState::TransferSrc)]);
        rec.copy_image_to_buffer(&self.color, 0, &self.readback);
        timer.end(&mut rec, &log);
        self.ctx.submit_and_wait(rec)?;

        let passes = timer.finish(log)?;
        let rgba = self.readback.read()?;
        let caps = self.ctx.capabilities();
        let total_gpu_ms = passes.iter().map(|p| p.gpu_ms).sum::<Option<f64>>();
        let report = FrameReport {
            device: caps.device_name.clone(),
            driver: format!("{} {}", caps.driver_name, caps.driver_info).trim().to_owned(),
            capabilities: caps.clone(),
            scene: SceneSummary::of(scene),
            width: self.desc.width,
            height: self.desc.height,
            lights,
            passes,
            total_gpu_ms,
            cpu_frame_ms: started.elapsed().as_secs_f64() * 1e3,
        };
        Ok(Frame { width: self.desc.width, height: self.desc.height, rgba, report })
    }
}
