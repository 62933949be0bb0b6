//! A window's swapchain: presents RGBA8 frames with a few frames in flight, recreating itself
//! when the window is resized or the swapchain goes out of date.
//!
//! Each frame slot owns a command buffer, a fence, an "image acquired" semaphore and a
//! persistently mapped staging buffer; each swapchain image owns a "copied" semaphore that its
//! present waits on. A frame comes either from the GPU ([`Swapchain::present_image`]: an image
//! blitted into the acquired one, nothing crossing the CPU) or from the CPU
//! ([`Swapchain::present`]: pixels written into the slot's staging buffer and copied): nothing
//! is allocated per frame (the staging buffers follow the swapchain's size, so only a resize
//! reallocates them).

use crate::buffer::{Buffer, BufferDesc};
use crate::context::Context;
use crate::error::{CallContext, VkError, VkResult};
use crate::image::Image;
use crate::surface::Surface;
use ash::vk;
use raw_window_handle::{HasDisplayHandle, HasWindowHandle};
use std::ffi::CString;
use std::sync::Arc;

/// How long presentation waits for an image or a fence before reporting a timeout.
const TIMEOUT_NS: u64 = 60_000_000_000;

/// Formats the swapchain takes, best first: 8-bit RGBA/BGRA, written byte for byte (umbra's
/// frames are already the values to show, so no sRGB conversion is applied either way).
const FORMAT_PREFERENCE: [vk::Format; 4] =
    [vk::Format::B8G8R8A8_UNORM, vk::Format::R8G8B8A8_UNORM, vk::Format::B8G8R8A8_SRGB, vk::Format::R8G8B8A8_SRGB];

/// The formats [`Swapchain::present_image`] takes.
const PRESENTABLE: [vk::Format; 2] = [vk::Format::R8G8B8A8_UNORM, vk::Format::B8G8R8A8_UNORM];

/// How a [`Swapchain`] is created.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SwapchainDesc {
    /// Width wanted when the window system leaves the size to the application.
    pub width: u32,
    /// Height wanted when the window system leaves the size to the application.
    pub height: u32,
    /// Frames the CPU may prepare while earlier ones are still being copied and presented.
    pub frames_in_flight: u32,
    /// Wait for vertical blank (`FIFO`); off picks `MAILBOX` or `IMMEDIATE` where offered.
    pub vsync: bool,
}

impl SwapchainDesc {
    /// Two frames in flight, vsync on.
    pub fn new(width: u32, height: u32) -> Self {
        Self { width, height, frames_in_flight: 2, vsync: true }
    }
}

/// What one [`Swapchain::present`] did.
#[derive(Clone, Debug)]
pub struct Presented {
    /// The swapchain image shown.
    pub image: u32,
    /// Its size (the window's size when it was acquired).
    pub extent: vk::Extent2D,
    /// Whether the swapchain was recreated before this frame (resize or out of date).
    pub recreated: bool,
    /// With `capture`: the presented image read back, tightly packed RGBA8, top row first.
    pub capture: Option<Vec<u8>>,
}

/// Where a presented frame's pixels come from.
#[derive(Clone, Copy)]
enum Source<'a> {
    /// RGBA8 pixels from the CPU, through the slot's staging buffer ([`Swapchain::present`]).
    Pixels { pixels: &'a [u8], width: u32, height: u32 },
    /// An image on the GPU, in `TRANSFER_SRC_OPTIMAL` ([`Swapchain::present_image`]).
    Image(&'a Image),
}

/// One frame in flight.
struct Slot {
    cmd: vk::CommandBuffer,
    /// Signalled when the slot's copy has finished (created signalled).
    fence: vk::Fence,
    /// Signalled by the acquire, waited on by the copy.
    acquired: vk::Semaphore,
    /// The frame's pixels in the swapchain's format and size.
    staging: Option<Buffer>,
}

/// A window's swapchain. Needs a [`Context`] that can present ([`Context::presentation`]).
///
/// The swapchain keeps the window alive (an `Arc` of it) until it is dropped.
pub struct Swapchain {
    ctx: Context,
    desc: SwapchainDesc,
    fns: ash::khr::swapchain::Device,
    raw: vk::SwapchainKHR,
    images: Vec<vk::Image>,
    /// Per image: signalled by the copy into it, waited on by its present.
    copied: Vec<vk::Semaphore>,
    format: vk::SurfaceFormatKHR,
    extent: vk::Extent2D,
    /// Recreate before the next frame (resized, suboptimal or out of date).
    stale: bool,
    /// Whether swapchain images can be copied from (for captures).
    capturable: bool,
    /// Whether [`Swapchain::present_image`] can blit into the swapchain's format, and from
    /// which source formats (R8G8B8A8_UNORM, B8G8R8A8_UNORM); probed once.
    blit_into: bool,
    blit_from: [bool; 2],
    pool: vk::CommandPool,
    slots: Vec<Slot>,
    next: usize,
    capture: Option<Buffer>,
    recreations: u32,
    /// Staging and capture buffers created so far (only when the size changes).
    buffers_created: u32,
    /// Destroyed after the swapchain (field order).
    surface: Surface,
}

impl Swapchain {
    /// Creates the surface of `window` and its swapchain.
    pub fn new<W>(ctx: &Context, window: Arc<W>, desc: SwapchainDesc) -> VkResult<Self>
    where
        W: HasWindowHandle + HasDisplayHandle + Send + Sync + 'static,
    {
        let surface = Surface::new(ctx, window)?;
        let formats = surface.formats()?;
        let format =
            FORMAT_PREFERENCE.iter().find_map(|&f| formats.iter().find(|s| s.format == f).copied()).ok_or_else(
                || ctx.unsupported(format!("a swapchain of 8-bit RGBA or BGRA (the surface offers {formats:?})")),
            )?;
        let device = &ctx.inner.device;
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(ctx.inner.queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: valid device; the pool is destroyed in `Drop`.
        let pool = unsafe { device.create_command_pool(&pool_info, None) }.call("vkCreateCommandPool")?;
        ctx.set_name(pool, "swapchain command pool");
        let mut swapchain = Swapchain {
            ctx: ctx.clone(),
            desc,
            fns: ash::khr::swapchain::Device::new(&ctx.inner.instance, device),
            raw: vk::SwapchainKHR::null(),
            images: Vec::new(),
            copied: Vec::new(),
            format,
            extent: vk::Extent2D::default(),
            stale: true,
            capturable: false,
            blit_into: false,
            blit_from: [false; 2],
            pool,
            slots: Vec::new(),
            next: 0,
            capture: None,
            recreations: 0,
            buffers_created: 0,
            surface,
        };
        for i in 0..desc.frames_in_flight.max(1) {
            let slot = swapchain.new_slot(i)?;
            swapchain.slots.push(slot);
        }
        let unorm = matches!(format.format, vk::Format::B8G8R8A8_UNORM | vk::Format::R8G8B8A8_UNORM);
        swapchain.blit_into = unorm && swapchain.blits(format.format, vk::FormatFeatureFlags::BLIT_DST);
        swapchain.blit_from = PRESENTABLE.map(|f| swapchain.blits(f, vk::FormatFeatureFlags::BLIT_SRC));
        swapchain.recreate()?;
        swapchain.recreations = 0;
        Ok(swapchain)
    }

    /// The swapchain's size now (zero while the window has no area).
    pub fn extent(&self) -> vk::Extent2D {
        self.extent
    }

    /// The surface format chosen.
    pub fn format(&self) -> vk::SurfaceFormatKHR {
        self.format
    }

    /// Swapchains created after the first (resizes and out-of-date recoveries).
    pub fn recreations(&self) -> u32 {
        self.recreations
    }

    /// Staging and capture buffers created so far: one per frame in flight at each size the
    /// swapchain had, plus one per size a capture was taken at. A steady window allocates none.
    pub fn buffers_created(&self) -> u32 {
        self.buffers_created
    }

    /// Whether [`Swapchain::present`] can read back what it presents (the surface allows
    /// `TRANSFER_SRC` on its images).
    pub fn can_capture(&self) -> bool {
        self.capturable
    }

    /// Tells the swapchain the window's new size; it is recreated before the next frame.
    pub fn resize(&mut self, width: u32, height: u32) {
        self.desc.width = width;
        self.desc.height = height;
        self.stale = true;
    }

    /// Presents `pixels` (RGBA8, `width` × `height`, top row first). A frame whose size differs
    /// from the swapchain's (a resize not yet rendered for) is shown in the top-left corner over
    /// black. With `capture`, waits for the copy and returns the presented image (needs
    /// [`Swapchain::can_capture`]). `None` while the window has no area.
    pub fn present(&mut self, pixels: &[u8], width: u32, height: u32, capture: bool) -> VkResult<Option<Presented>> {
        if pixels.len() != 4 * width as usize * height as usize {
            return Err(VkError::InvalidDesc {
                what: "presented frame",
                why: format!("{} bytes for {width}x{height} RGBA8", pixels.len()),
            });
        }
        self.show(Source::Pixels { pixels, width, height }, capture)
    }

    /// Whether [`Swapchain::present_image`] can show images: the swapchain's format is 8-bit
    /// UNORM (a blit then moves bytes unchanged, as [`Swapchain::present`] does) and the
    /// device blits into it.
    pub fn can_present_images(&self) -> bool {
        self.blit_into
    }

    /// Presents `image` straight from the GPU: an `R8G8B8A8_UNORM` or `B8G8R8A8_UNORM` image
    /// with `TRANSFER_SRC` usage, in `TRANSFER_SRC_OPTIMAL`, whose writes were made visible to
    /// transfers by earlier submissions on the queue (umbra's `Renderer` leaves its colour
    /// target so: `Renderer::color_image`). It is blitted into the
    /// acquired image (top-left, over black where the sizes differ, like [`Swapchain::present`]),
    /// which is presented; nothing is read back or written by the CPU. The image must stay
    /// alive and unwritten until the copy completed: later submissions on the same queue that
    /// first wait for all earlier commands (umbra's frame graph does) may write it;
    /// [`Swapchain::wait`] before destroying it. With `capture` as in [`Swapchain::present`].
    pub fn present_image(&mut self, image: &Image, capture: bool) -> VkResult<Option<Presented>> {
        let f = image.desc.format;
        let source = PRESENTABLE.iter().position(|&p| p == f);
        if source.is_none()
            || !image.desc.usage.contains(vk::ImageUsageFlags::TRANSFER_SRC)
            || image.desc.layers != 1
            || image.desc.samples != vk::SampleCountFlags::TYPE_1
        {
            return Err(VkError::InvalidDesc {
                what: "presented image",
                why: format!(
                    "{f:?} {:?}: an R8G8B8A8_UNORM or B8G8R8A8_UNORM single-sampled 2D image with TRANSFER_SRC usage",
                    image.desc.usage
                ),
            });
        }
        if !self.blit_into || !source.is_some_and(|i| self.blit_from[i]) {
            return Err(self
                .ctx
                .unsupported(format!("blitting {f:?} images into a {:?} swapchain", self.format.format)));
        }
        self.show(Source::Image(image), capture)
    }

    /// Acquires an image, copies `source` into it (pixels through the slot's staging buffer),
    /// presents it, and with `capture` reads it back.
    fn show(&mut self, source: Source<'_>, capture: bool) -> VkResult<Option<Presented>> {
        if capture && !self.capturable {
            return Err(self.ctx.unsupported("reading back swapchain images (no TRANSFER_SRC usage)"));
        }
        let before = self.recreations;
        let Some(image) = self.acquire()? else { return Ok(None) };
        let recreated = self.recreations != before;
        let slot = self.next;
        self.next = (self.next + 1) % self.slots.len();
        if let Source::Pixels { pixels, width, height } = source {
            self.fill_staging(slot, pixels, width, height)?;
        }
        if capture {
            self.ensure_capture_buffer()?;
        }
        self.record_copy(slot, image, source, capture)?;
        self.submit_and_present(slot, image)?;
        let capture = match capture {
            true => Some(self.read_capture(slot)?),
            false => None,
        };
        Ok(Some(Presented { image, extent: self.extent, recreated, capture }))
    }

    /// Waits until every frame handed to the swapchain has been copied out of its source.
    pub fn wait(&self) -> VkResult<()> {
        let fences: Vec<vk::Fence> = self.slots.iter().map(|s| s.fence).collect();
        // SAFETY: waiting on the swapchain's own fences.
        unsafe { self.ctx.inner.device.wait_for_fences(&fences, true, TIMEOUT_NS) }.call("vkWaitForFences")
    }

    /// Whether the device supports `feature` for optimal-tiling images of `format`.
    fn blits(&self, format: vk::Format, feature: vk::FormatFeatureFlags) -> bool {
        // SAFETY: plain query of the context's physical device.
        let props = unsafe {
            self.ctx.inner.instance.get_physical_device_format_properties(self.ctx.inner.physical_device, format)
        };
        props.optimal_tiling_features.contains(feature)
    }

    /// Acquires the next image into the current slot, recreating the swapchain when needed.
    fn acquire(&mut self) -> VkResult<Option<u32>> {
        for _ in 0..2 {
            if self.stale {
                self.recreate()?;
            }
            if self.raw == vk::SwapchainKHR::null() {
                return Ok(None);
            }
            let slot = &self.slots[self.next];
            let device = &self.ctx.inner.device;
            // SAFETY: the fence belongs to this device; waiting has no other precondition.
            unsafe { device.wait_for_fences(&[slot.fence], true, TIMEOUT_NS) }.call("vkWaitForFences")?;
            // SAFETY: the slot's fence is signalled, so its semaphore has no pending wait.
            let acquired =
                unsafe { self.fns.acquire_next_image(self.raw, TIMEOUT_NS, slot.acquired, vk::Fence::null()) };
            match acquired {
                Ok((index, suboptimal)) => {
                    self.stale |= suboptimal;
                    return Ok(Some(index));
                }
                Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => self.stale = true,
                Err(result) => return Err(VkError::Call { call: "vkAcquireNextImageKHR", result }),
            }
        }
        Err(VkError::Call { call: "vkAcquireNextImageKHR", result: vk::Result::ERROR_OUT_OF_DATE_KHR })
    }

    /// Writes the frame into the slot's staging buffer in the swapchain's format and size.
    fn fill_staging(&mut self, slot: usize, pixels: &[u8], width: u32, height: u32) -> VkResult<()> {
        let (w, h) = (self.extent.width as usize, self.extent.height as usize);
        let size = 4 * w as u64 * h as u64;
        if self.slots[slot].staging.as_ref().map(|b| b.desc.size) != Some(size) {
            let desc = BufferDesc::cpu_to_gpu(size, vk::BufferUsageFlags::TRANSFER_SRC);
            let name = format!("swapchain staging {slot}");
            self.slots[slot].staging = None;
            self.slots[slot].staging = Some(Buffer::new(&self.ctx, &name, desc)?);
            self.buffers_created += 1;
        }
        let bgra = matches!(self.format.format, vk::Format::B8G8R8A8_UNORM | vk::Format::B8G8R8A8_SRGB);
        let staging = self.slots[slot].staging.as_mut().ok_or(VkError::Poisoned)?;
        let dst = staging.mapped_mut()?;
        let (fw, fh) = (width as usize, height as usize);
        for (y, row) in dst.chunks_exact_mut(4 * w).enumerate() {
            let shown = if y < fh { fw.min(w) } else { 0 };
            let src = &pixels[4 * y.min(fh.saturating_sub(1)) * fw..][..4 * shown];
            for (d, s) in row[..4 * shown].chunks_exact_mut(4).zip(src.chunks_exact(4)) {
                match bgra {
                    true => d.copy_from_slice(&[s[2], s[1], s[0], s[3]]),
                    false => d.copy_from_slice(s),
                }
            }
            row[4 * shown..].iter_mut().enumerate().for_each(|(i, b)| *b = if i % 4 == 3 { 255 } else { 0 });
        }
        Ok(())
    }

    fn ensure_capture_buffer(&mut self) -> VkResult<()> {
        let size = 4 * self.extent.width as u64 * self.extent.height as u64;
        if self.capture.as_ref().map(|b| b.desc.size) != Some(size) {
            self.capture = None;
            self.capture = Some(Buffer::new(&self.ctx, "swapchain capture", BufferDesc::readback(size))?);
            self.buffers_created += 1;
        }
        Ok(())
    }

    /// Records `source` → image, and with `capture` image → capture buffer, ending in
    /// `PRESENT_SRC`.
    fn record_copy(&self, slot: usize, image: u32, source: Source<'_>, capture: bool) -> VkResult<()> {
        let device = &self.ctx.inner.device;
        let s = &self.slots[slot];
        let target = self.images[image as usize];
        let range =
            vk::ImageSubresourceRange::default().aspect_mask(vk::ImageAspectFlags::COLOR).level_count(1).layer_count(1);
        let barrier = |from, to, src: (vk::PipelineStageFlags2, vk::AccessFlags2), dst: (_, _)| {
            vk::ImageMemoryBarrier2::default()
                .image(target)
                .subresource_range(range)
                .old_layout(from)
                .new_layout(to)
                .src_stage_mask(src.0)
                .src_access_mask(src.1)
                .dst_stage_mask(dst.0)
                .dst_access_mask(dst.1)
        };
        // Copies, blits and clears all write in ALL_TRANSFER.
        let copy_write = (vk::PipelineStageFlags2::ALL_TRANSFER, vk::AccessFlags2::TRANSFER_WRITE);
        let copy_read = (vk::PipelineStageFlags2::COPY, vk::AccessFlags2::TRANSFER_READ);
        let presented = (vk::PipelineStageFlags2::NONE, vk::AccessFlags2::NONE);
        let layers = vk::ImageSubresourceLayers::default().aspect_mask(vk::ImageAspectFlags::COLOR).layer_count(1);
        let region = [vk::BufferImageCopy::default().image_subresource(layers).image_extent(vk::Extent3D {
            width: self.extent.width,
            height: self.extent.height,
            depth: 1,
        })];
        let begin = vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        let label = CString::new("present").unwrap_or_default();
        // SAFETY: the slot's fence is signalled (waited in `acquire`), so its command buffer is
        // not pending; every handle recorded lives until the fence signals again (`Drop` waits).
        unsafe {
            device.reset_command_buffer(s.cmd, vk::CommandBufferResetFlags::empty()).call("vkResetCommandBuffer")?;
            device.begin_command_buffer(s.cmd, &begin).call("vkBeginCommandBuffer")?;
            if let Some(d) = self.ctx.debug_device() {
                d.cmd_begin_debug_utils_label(s.cmd, &vk::DebugUtilsLabelEXT::default().label_name(&label));
            }
            // The acquire semaphore is waited on at ALL_TRANSFER, which this barrier's source
            // scope joins.
            let to_dst = barrier(
                vk::ImageLayout::UNDEFINED,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                (vk::PipelineStageFlags2::ALL_TRANSFER, vk::AccessFlags2::NONE),
                copy_write,
            );
            let deps = [to_dst];
            device.cmd_pipeline_barrier2(s.cmd, &vk::DependencyInfo::default().image_memory_barriers(&deps));
            let dst = vk::ImageLayout::TRANSFER_DST_OPTIMAL;
            match source {
                Source::Pixels { .. } => {
                    let staging = s.staging.as_ref().ok_or(VkError::Poisoned)?;
                    device.cmd_copy_buffer_to_image(s.cmd, staging.raw, target, dst, &region);
                }
                Source::Image(src) => {
                    let (w, h) = (src.desc.width.min(self.extent.width), src.desc.height.min(self.extent.height));
                    if (w, h) != (self.extent.width, self.extent.height) {
                        let black = vk::ClearColorValue { float32: [0.0, 0.0, 0.0, 1.0] };
                        device.cmd_clear_color_image(s.cmd, target, dst, &black, &[range]);
                        let deps = [barrier(dst, dst, copy_write, copy_write)];
                        device
                            .cmd_pipeline_barrier2(s.cmd, &vk::DependencyInfo::default().image_memory_barriers(&deps));
                    }
                    // The source's writes, from earlier submissions, made visible to the blit.
                    let src_layout = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
                    let source = vk::ImageMemoryBarrier2::default()
                        .image(src.raw)
                        .subresource_range(range)
                        .old_layout(src_layout)
                        .new_layout(src_layout)
                        .src_stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)
                        .src_access_mask(vk::AccessFlags2::MEMORY_WRITE)
                        .dst_stage_mask(vk::PipelineStageFlags2::BLIT)
                        .dst_access_mask(vk::AccessFlags2::TRANSFER_READ);
                    let deps = [source];
                    device.cmd_pipeline_barrier2(s.cmd, &vk::DependencyInfo::default().image_memory_barriers(&deps));
                    let corner = [vk::Offset3D::default(), vk::Offset3D { x: w as i32, y: h as i32, z: 1 }];
                    let blit = [vk::ImageBlit::default()
                        .src_subresource(layers)
                        .src_offsets(corner)
                        .dst_subresource(layers)
                        .dst_offsets(corner)];
                    device.cmd_blit_image(s.cmd, src.raw, src_layout, target, dst, &blit, vk::Filter::NEAREST);
                }
            }
            let last = match (&self.capture, capture) {
                (Some(out), true) => {
                    let src = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
                    let deps = [barrier(dst, src, copy_write, copy_read)];
                    device.cmd_pipeline_barrier2(s.cmd, &vk::DependencyInfo::default().image_memory_barriers(&deps));
                    device.cmd_copy_image_to_buffer(s.cmd, target, src, out.raw, &region);
                    barrier(src, vk::ImageLayout::PRESENT_SRC_KHR, copy_read, presented)
                }
                _ => barrier(dst, vk::ImageLayout::PRESENT_SRC_KHR, copy_write, presented),
            };
            let deps = [last];
            device.cmd_pipeline_barrier2(s.cmd, &vk::DependencyInfo::default().image_memory_barriers(&deps));
            if let Some(d) = self.ctx.debug_device() {
                d.cmd_end_debug_utils_label(s.cmd);
            }
            device.end_command_buffer(s.cmd).call("vkEndCommandBuffer")?;
        }
        Ok(())
    }

    fn submit_and_present(&mut self, slot: usize, image: u32) -> VkResult<()> {
        let device = &self.ctx.inner.device;
        let s = &self.slots[slot];
        let copied = self.copied[image as usize];
        let waits = [vk::SemaphoreSubmitInfo::default()
            .semaphore(s.acquired)
            .stage_mask(vk::PipelineStageFlags2::ALL_TRANSFER)];
        let signals =
            [vk::SemaphoreSubmitInfo::default().semaphore(copied).stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)];
        let cmds = [vk::CommandBufferSubmitInfo::default().command_buffer(s.cmd)];
        let submit = [vk::SubmitInfo2::default()
            .wait_semaphore_infos(&waits)
            .command_buffer_infos(&cmds)
            .signal_semaphore_infos(&signals)];
        let swapchains = [self.raw];
        let indices = [image];
        let wait = [copied];
        let info = vk::PresentInfoKHR::default().wait_semaphores(&wait).swapchains(&swapchains).image_indices(&indices);
        let presented = {
            let queue = self.ctx.queue()?;
            // SAFETY: the fence is signalled (waited in `acquire`), so it may be reset and reused.
            unsafe { device.reset_fences(&[s.fence]) }.call("vkResetFences")?;
            // SAFETY: the queue is locked; the command buffer and what it uses stay alive until
            // its fence signals (`acquire` and `Drop` wait on it).
            unsafe { device.queue_submit2(*queue, &submit, s.fence) }.call("vkQueueSubmit2")?;
            // SAFETY: the queue is locked; the image was acquired and is in PRESENT_SRC once the
            // semaphore signals.
            unsafe { self.fns.queue_present(*queue, &info) }
        };
        match presented {
            Ok(suboptimal) => self.stale |= suboptimal,
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => self.stale = true,
            Err(result) => return Err(VkError::Call { call: "vkQueuePresentKHR", result }),
        }
        Ok(())
    }

    /// Waits for the slot's copy and returns the captured image as RGBA8.
    fn read_capture(&self, slot: usize) -> VkResult<Vec<u8>> {
        let device = &self.ctx.inner.device;
        // SAFETY: waiting on our own fence.
        unsafe { device.wait_for_fences(&[self.slots[slot].fence], true, TIMEOUT_NS) }.call("vkWaitForFences")?;
        let mut rgba = self.capture.as_ref().ok_or(VkError::Poisoned)?.read()?;
        if matches!(self.format.format, vk::Format::B8G8R8A8_UNORM | vk::Format::B8G8R8A8_SRGB) {
            rgba.chunks_exact_mut(4).for_each(|p| p.swap(0, 2));
        }
        Ok(rgba)
    }

    /// (Re)creates the swapchain at the surface's current size; none while it has no area.
    fn recreate(&mut self) -> VkResult<()> {
        self.ctx.wait_idle()?;
        let caps = self.surface.capabilities()?;
        let extent = match caps.current_extent.width {
            u32::MAX => vk::Extent2D {
                width: self.desc.width.clamp(caps.min_image_extent.width, caps.max_image_extent.width),
                height: self.desc.height.clamp(caps.min_image_extent.height, caps.max_image_extent.height),
            },
            _ => caps.current_extent,
        };
        let old = std::mem::replace(&mut self.raw, vk::SwapchainKHR::null());
        self.extent = extent;
        self.stale = false;
        self.recreations += 1;
        if extent.width == 0 || extent.height == 0 {
            self.destroy_swapchain(old);
            self.stale = true;
            return Ok(());
        }
        if !caps.supported_usage_flags.contains(vk::ImageUsageFlags::TRANSFER_DST) {
            self.destroy_swapchain(old);
            return Err(self.ctx.unsupported("swapchain images written by copies (TRANSFER_DST)"));
        }
        self.capturable = caps.supported_usage_flags.contains(vk::ImageUsageFlags::TRANSFER_SRC);
        let usage = match self.capturable {
            true => vk::ImageUsageFlags::TRANSFER_DST | vk::ImageUsageFlags::TRANSFER_SRC,
            false => vk::ImageUsageFlags::TRANSFER_DST,
        };
        let mut count = caps.min_image_count + 1;
        if caps.max_image_count > 0 {
            count = count.min(caps.max_image_count);
        }
        let modes = self.surface.present_modes()?;
        let mode = match self.desc.vsync {
            true => vk::PresentModeKHR::FIFO,
            false => [vk::PresentModeKHR::MAILBOX, vk::PresentModeKHR::IMMEDIATE]
                .into_iter()
                .find(|m| modes.contains(m))
                .unwrap_or(vk::PresentModeKHR::FIFO),
        };
        let alpha = [vk::CompositeAlphaFlagsKHR::OPAQUE, vk::CompositeAlphaFlagsKHR::INHERIT]
            .into_iter()
            .find(|&a| caps.supported_composite_alpha.contains(a))
            .unwrap_or(vk::CompositeAlphaFlagsKHR::from_raw(caps.supported_composite_alpha.as_raw() & 0xf));
        let info = vk::SwapchainCreateInfoKHR::default()
            .surface(self.surface.raw)
            .min_image_count(count)
            .image_format(self.format.format)
            .image_color_space(self.format.color_space)
            .image_extent(extent)
            .image_array_layers(1)
            .image_usage(usage)
            .image_sharing_mode(vk::SharingMode::EXCLUSIVE)
            .pre_transform(caps.current_transform)
            .composite_alpha(alpha)
            .present_mode(mode)
            .clipped(true)
            .old_swapchain(old);
        // SAFETY: valid create info for a live surface; `old` (retired here) is destroyed below
        // once the device is idle.
        let created = unsafe { self.fns.create_swapchain(&info, None) };
        self.destroy_swapchain(old);
        self.raw = match created {
            Ok(raw) => raw,
            // The loader made the surface through another driver's window-system extension
            // (SwiftShader's own has none for X11): this device cannot present to it.
            Err(vk::Result::ERROR_NATIVE_WINDOW_IN_USE_KHR | vk::Result::ERROR_INITIALIZATION_FAILED)
                if self.images.is_empty() =>
            {
                return Err(self.ctx.unsupported(
                    "a swapchain for this window (vkCreateSwapchainKHR refused it: the driver lacks this window system's surface extension)",
                ));
            }
            Err(result) => return Err(VkError::Call { call: "vkCreateSwapchainKHR", result }),
        };
        self.ctx.set_name(self.raw, "swapchain");
        // SAFETY: plain query of a live swapchain.
        self.images = unsafe { self.fns.get_swapchain_images(self.raw) }.call("vkGetSwapchainImagesKHR")?;
        for (i, &image) in self.images.iter().enumerate() {
            self.ctx.set_name(image, &format!("swapchain image {i}"));
        }
        while self.copied.len() < self.images.len() {
            let name = format!("swapchain copied {}", self.copied.len());
            let semaphore = self.semaphore(&name)?;
            self.copied.push(semaphore);
        }
        log::info!(
            "umbra-vk: swapchain {}x{} {:?} {:?}, {} images",
            extent.width,
            extent.height,
            self.format.format,
            mode,
            self.images.len()
        );
        Ok(())
    }

    /// Destroys a retired swapchain (the device is idle).
    fn destroy_swapchain(&self, old: vk::SwapchainKHR) {
        if old != vk::SwapchainKHR::null() {
            // SAFETY: the device is idle (waited in `recreate` or `Drop`), so the retired
            // swapchain's images are no longer used.
            unsafe { self.fns.destroy_swapchain(old, None) };
        }
    }

    fn semaphore(&self, name: &str) -> VkResult<vk::Semaphore> {
        // SAFETY: plain object creation; destroyed in `Drop`.
        let s = unsafe { self.ctx.inner.device.create_semaphore(&vk::SemaphoreCreateInfo::default(), None) }
            .call("vkCreateSemaphore")?;
        self.ctx.set_name(s, name);
        Ok(s)
    }

    fn new_slot(&self, i: u32) -> VkResult<Slot> {
        let device = &self.ctx.inner.device;
        let info = vk::CommandBufferAllocateInfo::default()
            .command_pool(self.pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: the pool is used by this swapchain only, from the thread that owns it (`&self`
        // methods are not called concurrently with `&mut self` ones).
        let cmd = unsafe { device.allocate_command_buffers(&info) }.call("vkAllocateCommandBuffers")?[0];
        self.ctx.set_name(cmd, &format!("present commands {i}"));
        let signalled = vk::FenceCreateInfo::default().flags(vk::FenceCreateFlags::SIGNALED);
        // SAFETY: plain object creation; destroyed in `Drop`.
        let fence = unsafe { device.create_fence(&signalled, None) }.call("vkCreateFence")?;
        self.ctx.set_name(fence, &format!("present fence {i}"));
        let acquired = self.semaphore(&format!("swapchain acquired {i}"))?;
        Ok(Slot { cmd, fence, acquired, staging: None })
    }
}

impl Drop for Swapchain {
    fn drop(&mut self) {
        let _ = self.ctx.wait_idle();
        let device = &self.ctx.inner.device;
        self.destroy_swapchain(self.raw);
        // SAFETY: the device is idle, so no command buffer, fence or semaphore is in use; the
        // staging buffers drop with the slots afterwards.
        unsafe {
            for s in &self.slots {
                device.destroy_fence(s.fence, None);
                device.destroy_semaphore(s.acquired, None);
            }
            for &s in &self.copied {
                device.destroy_semaphore(s, None);
            }
            device.destroy_command_pool(self.pool, None);
        }
    }
}
