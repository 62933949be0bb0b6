//! The frame's render-target formats and descriptions, shared by the renderer, the engine API
//! and every pass that draws into a frame-sized target.

use umbra_vk::{vk, ImageDesc};

/// The colour target format: linear 8-bit RGBA (values are written as computed, no sRGB curve).
pub const COLOR_FORMAT: vk::Format = vk::Format::R8G8B8A8_UNORM;

/// The frame's depth/stencil target, copied out for stencil diagnostics.
pub(crate) fn depth_desc(format: vk::Format, width: u32, height: u32) -> ImageDesc {
    let usage = vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC;
    ImageDesc::new_2d(format, width, height).usage(usage)
}
