//! Images: a `Copy` description, an RAII image with its default view, and layout states.

use crate::error::{CallContext, VkError, VkResult};
use crate::memory::{self, Memory};
use crate::Context;
use ash::vk;
use gpu_allocator::vulkan::Allocation;

/// What an image is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ImageDesc {
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// Array layers (6 for a cube).
    pub layers: u32,
    /// Whether the layers form a cube (its default view is then `CUBE`).
    pub cube: bool,
    /// Texel format.
    pub format: vk::Format,
    /// Usage flags.
    pub usage: vk::ImageUsageFlags,
    /// Samples per texel (`TYPE_1` unless multisampled).
    pub samples: vk::SampleCountFlags,
}

impl ImageDesc {
    /// A single-layer 2D image.
    pub fn new_2d(format: vk::Format, width: u32, height: u32) -> Self {
        let (usage, samples) = (vk::ImageUsageFlags::empty(), vk::SampleCountFlags::TYPE_1);
        Self { width, height, layers: 1, cube: false, format, usage, samples }
    }

    /// A cube image: six square layers.
    pub fn new_cube(format: vk::Format, size: u32) -> Self {
        let (usage, samples) = (vk::ImageUsageFlags::empty(), vk::SampleCountFlags::TYPE_1);
        Self { width: size, height: size, layers: 6, cube: true, format, usage, samples }
    }

    /// Same description with `usage`.
    pub fn usage(mut self, usage: vk::ImageUsageFlags) -> Self {
        self.usage = usage;
        self
    }

    /// Same description, multisampled with `samples` per texel (an attachment only).
    pub fn samples(mut self, samples: vk::SampleCountFlags) -> Self {
        self.samples = samples;
        self
    }

    /// Aspects of the format (colour, depth, stencil).
    pub fn aspect(&self) -> vk::ImageAspectFlags {
        format_aspect(self.format)
    }
}

/// Aspects a format has.
pub fn format_aspect(format: vk::Format) -> vk::ImageAspectFlags {
    match format {
        vk::Format::D16_UNORM | vk::Format::D32_SFLOAT | vk::Format::X8_D24_UNORM_PACK32 => vk::ImageAspectFlags::DEPTH,
        vk::Format::D16_UNORM_S8_UINT | vk::Format::D24_UNORM_S8_UINT | vk::Format::D32_SFLOAT_S8_UINT => {
            vk::ImageAspectFlags::DEPTH | vk::ImageAspectFlags::STENCIL
        }
        vk::Format::S8_UINT => vk::ImageAspectFlags::STENCIL,
        _ => vk::ImageAspectFlags::COLOR,
    }
}

/// Bytes per texel of the colour formats umbra reads back.
pub fn texel_size(format: vk::Format) -> Option<u32> {
    match format {
        vk::Format::R8G8B8A8_UNORM | vk::Format::R8G8B8A8_SRGB | vk::Format::B8G8R8A8_UNORM => Some(4),
        vk::Format::R32_SFLOAT | vk::Format::D32_SFLOAT | vk::Format::R32_UINT => Some(4),
        vk::Format::R16G16B16A16_SFLOAT | vk::Format::R32G32_SFLOAT => Some(8),
        vk::Format::R32G32B32A32_SFLOAT => Some(16),
        _ => None,
    }
}

/// A state an image is in: its layout plus the stages and accesses that use it there.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ImageState {
    /// Content undefined (before first use; discards). Leaving it waits for every earlier
    /// command and makes its writes available, so that an image reused from a frame that may
    /// still run (an engine's frames in flight) is never raced.
    Undefined,
    /// Written as a colour attachment.
    ColorAttachment,
    /// Read and written as a depth/stencil attachment.
    DepthStencilAttachment,
    /// Depth/stencil tested but not written, and sampled by fragment shaders.
    DepthStencilReadOnly,
    /// Sampled by fragment shaders.
    FragmentRead,
    /// Source of a copy.
    TransferSrc,
    /// Destination of a copy, a blit or a clear.
    TransferDst,
    /// Written by compute shaders as a storage image (`GENERAL` layout; the image needs
    /// `STORAGE` usage).
    ComputeWrite,
    /// Read by compute shaders as a storage image (`GENERAL` layout, `STORAGE` usage).
    ComputeRead,
}

impl ImageState {
    pub(crate) fn layout(self) -> vk::ImageLayout {
        match self {
            ImageState::Undefined => vk::ImageLayout::UNDEFINED,
            ImageState::ColorAttachment => vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
            ImageState::DepthStencilAttachment => vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
            ImageState::DepthStencilReadOnly => vk::ImageLayout::DEPTH_STENCIL_READ_ONLY_OPTIMAL,
            ImageState::FragmentRead => vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            ImageState::TransferSrc => vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
            ImageState::TransferDst => vk::ImageLayout::TRANSFER_DST_OPTIMAL,
            ImageState::ComputeWrite | ImageState::ComputeRead => vk::ImageLayout::GENERAL,
        }
    }

    pub(crate) fn stage_access(self) -> (vk::PipelineStageFlags2, vk::AccessFlags2) {
        use vk::AccessFlags2 as A;
        use vk::PipelineStageFlags2 as S;
        let depth_stages = S::EARLY_FRAGMENT_TESTS | S::LATE_FRAGMENT_TESTS;
        match self {
            ImageState::Undefined => (S::ALL_COMMANDS, A::MEMORY_WRITE),
            ImageState::ColorAttachment => {
                (S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_READ | A::COLOR_ATTACHMENT_WRITE)
            }
            ImageState::DepthStencilAttachment => {
                (depth_stages, A::DEPTH_STENCIL_ATTACHMENT_READ | A::DEPTH_STENCIL_ATTACHMENT_WRITE)
            }
            ImageState::DepthStencilReadOnly => {
                (depth_stages | S::FRAGMENT_SHADER, A::DEPTH_STENCIL_ATTACHMENT_READ | A::SHADER_SAMPLED_READ)
            }
            ImageState::FragmentRead => (S::FRAGMENT_SHADER, A::SHADER_SAMPLED_READ),
            // Copies and blits (a swapchain's `present_image`) read in ALL_TRANSFER.
            ImageState::TransferSrc => (S::ALL_TRANSFER, A::TRANSFER_READ),
            // Copies, blits and clears (vkCmdClear*Image runs in the CLEAR stage, not COPY).
            ImageState::TransferDst => (S::ALL_TRANSFER, A::TRANSFER_WRITE),
            ImageState::ComputeWrite => (S::COMPUTE_SHADER, A::SHADER_STORAGE_WRITE),
            ImageState::ComputeRead => (S::COMPUTE_SHADER, A::SHADER_STORAGE_READ),
        }
    }
}

/// A Vulkan image, its memory and its default view; freed on drop.
pub struct Image {
    /// The raw image.
    pub raw: vk::Image,
    /// The default view over every layer (`2D`, `2D_ARRAY` or `CUBE`).
    pub view: vk::ImageView,
    /// What it was created from.
    pub desc: ImageDesc,
    allocation: Option<Allocation>,
    /// Whether umbra created it (and destroys it on drop); false for an engine's image.
    owned: bool,
    ctx: Context,
}

impl std::fmt::Debug for Image {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Image").field("raw", &self.raw).field("desc", &self.desc).finish()
    }
}

impl Image {
    /// Creates a named device-local image and its default view, checking its extent against
    /// the device limits first ([`Context::image_limits`]: a typed [`VkError::DeviceLimit`]
    /// naming the limit it breaks).
    pub fn new(ctx: &Context, name: &str, desc: ImageDesc) -> VkResult<Self> {
        let invalid = |why: String| VkError::InvalidDesc { what: "image", why: format!("{name}: {why}") };
        if desc.width == 0 || desc.height == 0 || desc.layers == 0 {
            return Err(invalid(format!("zero extent {}x{}x{}", desc.width, desc.height, desc.layers)));
        }
        if desc.cube && (desc.width != desc.height || desc.layers % 6 != 0) {
            return Err(invalid(format!(
                "cube faces must be square with 6n layers, got {}x{}x{}",
                desc.width, desc.height, desc.layers
            )));
        }
        if let Some((what, limit)) = ctx.image_limits(&desc)?.broken_by(&desc) {
            return Err(ctx.over_limit(format!("image {name:?} ({:?}): {what}", desc.format), limit));
        }
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(desc.format)
            .extent(vk::Extent3D { width: desc.width, height: desc.height, depth: 1 })
            .mip_levels(1)
            .array_layers(desc.layers)
            .samples(desc.samples)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(desc.usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE)
            .initial_layout(vk::ImageLayout::UNDEFINED)
            .flags(if desc.cube { vk::ImageCreateFlags::CUBE_COMPATIBLE } else { vk::ImageCreateFlags::empty() });
        let device = &ctx.inner.device;
        // SAFETY: valid create info (limits checked above); destroyed in `Drop`.
        let raw = unsafe { device.create_image(&info, None) }.call("vkCreateImage")?;
        // SAFETY: `raw` was just created from `device`.
        let requirements = unsafe { device.get_image_memory_requirements(raw) };
        let allocation = memory::allocate(ctx, name, requirements, Memory::GpuOnly, false);
        let mut image =
            Image { raw, view: vk::ImageView::null(), desc, allocation: None, owned: true, ctx: ctx.clone() };
        image.allocation = Some(allocation?);
        if let Some(a) = &image.allocation {
            // SAFETY: memory and offset come from an allocation made for these requirements.
            unsafe { device.bind_image_memory(raw, a.memory(), a.offset()) }.call("vkBindImageMemory")?;
        }
        let view_type = match (desc.cube, desc.layers) {
            (true, 6) => vk::ImageViewType::CUBE,
            (true, _) => vk::ImageViewType::CUBE_ARRAY,
            (false, 1) => vk::ImageViewType::TYPE_2D,
            (false, _) => vk::ImageViewType::TYPE_2D_ARRAY,
        };
        image.view = image.create_view(view_type, 0, desc.layers)?;
        ctx.set_name(raw, name);
        ctx.set_name(image.view, &format!("{name} view"));
        Ok(image)
    }

    /// An engine's image and view, described by `desc` (format, extent, layers, usage as the
    /// engine created them), for umbra's passes to use: never destroyed or freed by umbra. The
    /// engine keeps both alive while umbra's commands that use them may run.
    pub fn external(ctx: &Context, raw: vk::Image, view: vk::ImageView, desc: ImageDesc) -> Self {
        Image { raw, view, desc, allocation: None, owned: false, ctx: ctx.clone() }
    }

    /// A 2D view of one layer (a cube face or array slice to render to).
    pub fn layer_view(&self, layer: u32, name: &str) -> VkResult<ImageView> {
        if layer >= self.desc.layers {
            return Err(VkError::InvalidDesc {
                what: "image view",
                why: format!("{name}: layer {layer} of {} layers", self.desc.layers),
            });
        }
        let raw = self.create_view(vk::ImageViewType::TYPE_2D, layer, 1)?;
        self.ctx.set_name(raw, name);
        Ok(ImageView { raw, ctx: self.ctx.clone() })
    }

    /// A 2D-array view of every layer, whatever their count (the default view of a one-layer
    /// image is `2D`; a shader declaring an array reads this one).
    pub fn array_view(&self, name: &str) -> VkResult<ImageView> {
        let raw = self.create_view(vk::ImageViewType::TYPE_2D_ARRAY, 0, self.desc.layers)?;
        self.ctx.set_name(raw, name);
        Ok(ImageView { raw, ctx: self.ctx.clone() })
    }

    fn create_view(&self, view_type: vk::ImageViewType, first: u32, count: u32) -> VkResult<vk::ImageView> {
        let info = vk::ImageViewCreateInfo::default()
            .image(self.raw)
            .view_type(view_type)
            .format(self.desc.format)
            .subresource_range(self.range(first, count));
        // SAFETY: the range lies inside the image (callers check layers against `desc`).
        unsafe { self.ctx.inner.device.create_image_view(&info, None) }.call("vkCreateImageView")
    }

    /// The subresource range of `count` layers from `first`, every aspect.
    pub fn range(&self, first: u32, count: u32) -> vk::ImageSubresourceRange {
        vk::ImageSubresourceRange {
            aspect_mask: self.desc.aspect(),
            base_mip_level: 0,
            level_count: 1,
            base_array_layer: first,
            layer_count: count,
        }
    }

    /// Width and height as an extent.
    pub fn extent(&self) -> vk::Extent2D {
        vk::Extent2D { width: self.desc.width, height: self.desc.height }
    }
}

/// An extra view of an image (see [`Image::layer_view`]); destroyed on drop. Keep the image
/// alive as long as the view.
pub struct ImageView {
    /// The raw view.
    pub raw: vk::ImageView,
    ctx: Context,
}

impl std::fmt::Debug for ImageView {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ImageView").field("raw", &self.raw).finish()
    }
}

impl Drop for ImageView {
    fn drop(&mut self) {
        // SAFETY: umbra waits for every submission, so the view is no longer in use.
        unsafe { self.ctx.inner.device.destroy_image_view(self.raw, None) };
    }
}

impl Drop for Image {
    fn drop(&mut self) {
        if !self.owned {
            return;
        }
        // SAFETY: umbra waits for every submission, so the image is no longer in use.
        unsafe {
            if self.view != vk::ImageView::null() {
                self.ctx.inner.device.destroy_image_view(self.view, None);
            }
            self.ctx.inner.device.destroy_image(self.raw, None);
        }
        if let (Some(a), Ok(mut alloc)) = (self.allocation.take(), self.ctx.allocator()) {
            if let Err(e) = alloc.free(a) {
                log::error!("freeing image memory failed: {e}");
            }
        }
    }
}
