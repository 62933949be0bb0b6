//! Device limits a resource must fit, under the names the Vulkan specification gives them, so
//! that every error can say which limit a size broke, its value, and on which device.

use crate::error::{VkError, VkResult};
use crate::{texel_size, Context, ImageDesc};
use ash::vk;

/// One device limit: its name in the specification and its value on a device.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Limit {
    /// The limit's name (`maxFramebufferWidth`, `maxStorageBufferRange`, …).
    pub name: &'static str,
    /// Its value on the device.
    pub value: u64,
    /// Whether the value counts bytes (shown with a binary unit beside it).
    pub bytes: bool,
}

impl Limit {
    /// A limit counting texels, layers or items.
    pub fn count(name: &'static str, value: impl Into<u64>) -> Self {
        Self { name, value: value.into(), bytes: false }
    }

    /// A limit counting bytes.
    pub fn bytes(name: &'static str, value: impl Into<u64>) -> Self {
        Self { name, value: value.into(), bytes: true }
    }
}

impl std::fmt::Display for Limit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.bytes {
            true => write!(f, "{} is {} bytes ({})", self.name, self.value, human_bytes(self.value)),
            false => write!(f, "{} is {}", self.name, self.value),
        }
    }
}

/// `bytes` with a binary unit: `512 B`, `96 MiB`, `1.5 GiB`.
pub fn human_bytes(bytes: u64) -> String {
    const UNITS: [&str; 5] = ["KiB", "MiB", "GiB", "TiB", "PiB"];
    if bytes < 1024 {
        return format!("{bytes} B");
    }
    let mut value = bytes as f64 / 1024.0;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < UNITS.len() {
        value /= 1024.0;
        unit += 1;
    }
    match value.fract() {
        0.0 => format!("{value} {}", UNITS[unit]),
        _ => format!("{value:.1} {}", UNITS[unit]),
    }
}

/// The tightest limits on an image on a device: on its width and height the smallest of
/// `maxImageDimension2D` (or `maxImageDimensionCube`), the format's `maxExtent` from
/// `vkGetPhysicalDeviceImageFormatProperties` for the image's usage, and, for attachments,
/// `maxFramebufferWidth`/`Height` and `maxViewportDimensions` (umbra's viewport covers the
/// whole attachment); on its layers `maxImageArrayLayers` and the format's `maxArrayLayers`;
/// on its texel bytes the format's `maxResourceSize`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ImageLimits {
    /// The limit on the width.
    pub width: Limit,
    /// The limit on the height.
    pub height: Limit,
    /// The limit on the array layers.
    pub layers: Limit,
    /// The limit on the texel bytes of all layers.
    pub bytes: Limit,
}

impl ImageLimits {
    /// The first limit `desc` breaks (width, height, layers, then texel bytes, counted with
    /// [`element_bytes`] where umbra knows the format), with what breaks it (`width 8256`).
    pub fn broken_by(&self, desc: &ImageDesc) -> Option<(String, Limit)> {
        let sides = [("width", desc.width, self.width), ("height", desc.height, self.height)];
        let extent = sides.into_iter().chain([("layers", desc.layers, self.layers)]);
        if let Some((side, size, limit)) = extent.into_iter().find(|&(_, size, limit)| u64::from(size) > limit.value) {
            return Some((format!("{side} {size}"), limit));
        }
        let texels = u64::from(desc.width) * u64::from(desc.height) * u64::from(desc.layers);
        let bytes = element_bytes(desc.format)?.saturating_mul(texels);
        (bytes > self.bytes.value).then(|| (format!("{} of texels", human_bytes(bytes)), self.bytes))
    }
}

/// Bytes per texel of the formats umbra creates images in, as the validation layer counts
/// them (`None` for other formats: their size is not checked before creation).
pub fn element_bytes(format: vk::Format) -> Option<u64> {
    let bytes = match format {
        vk::Format::D16_UNORM => 2,
        vk::Format::D16_UNORM_S8_UINT => 3,
        vk::Format::D24_UNORM_S8_UINT | vk::Format::X8_D24_UNORM_PACK32 => 4,
        vk::Format::D32_SFLOAT_S8_UINT | vk::Format::R32G32_SFLOAT => 8,
        vk::Format::S8_UINT => 1,
        f => texel_size(f)?,
    };
    Some(u64::from(bytes))
}

/// The smallest of `candidates` (the first on a tie).
fn tightest(candidates: &[Limit]) -> Limit {
    candidates.iter().copied().fold(candidates[0], |best, l| if l.value < best.value { l } else { best })
}

impl Context {
    /// The limits `desc`'s extent must fit on this device (see [`ImageLimits`]); a typed
    /// [`VkError::Unsupported`] when the device has no such image at all (format, usage and
    /// cube flag together).
    pub fn image_limits(&self, desc: &ImageDesc) -> VkResult<ImageLimits> {
        let caps = self.capabilities();
        let flags = if desc.cube { vk::ImageCreateFlags::CUBE_COMPATIBLE } else { vk::ImageCreateFlags::empty() };
        // SAFETY: a plain query of the live physical device the context was created from.
        let format = unsafe {
            self.instance().get_physical_device_image_format_properties(
                self.physical_device(),
                desc.format,
                vk::ImageType::TYPE_2D,
                vk::ImageTiling::OPTIMAL,
                desc.usage,
                flags,
            )
        }
        .map_err(|result| VkError::Unsupported {
            device: caps.device_name.clone(),
            what: format!(
                "{:?} {}images with usage {:?} (vkGetPhysicalDeviceImageFormatProperties: {result})",
                desc.format,
                if desc.cube { "cube " } else { "" },
                desc.usage
            ),
        })?;
        let dimension = match desc.cube {
            true => Limit::count("maxImageDimensionCube", caps.max_image_dimension_cube),
            false => Limit::count("maxImageDimension2D", caps.max_image_dimension_2d),
        };
        let attachment = desc
            .usage
            .intersects(vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT);
        let extent = |name, value: u32, framebuffer: (&'static str, u32), viewport: (&'static str, u32)| {
            let mut candidates = vec![dimension, Limit::count(name, value)];
            if attachment {
                candidates.push(Limit::count(framebuffer.0, framebuffer.1));
                candidates.push(Limit::count(viewport.0, viewport.1));
            }
            tightest(&candidates)
        };
        let viewport = caps.max_viewport_dimensions;
        Ok(ImageLimits {
            width: extent(
                "maxExtent.width (vkGetPhysicalDeviceImageFormatProperties)",
                format.max_extent.width,
                ("maxFramebufferWidth", caps.max_framebuffer_width),
                ("maxViewportDimensions[0]", viewport[0]),
            ),
            height: extent(
                "maxExtent.height (vkGetPhysicalDeviceImageFormatProperties)",
                format.max_extent.height,
                ("maxFramebufferHeight", caps.max_framebuffer_height),
                ("maxViewportDimensions[1]", viewport[1]),
            ),
            layers: tightest(&[
                Limit::count("maxImageArrayLayers", caps.max_image_array_layers),
                Limit::count("maxArrayLayers (vkGetPhysicalDeviceImageFormatProperties)", format.max_array_layers),
            ]),
            bytes: Limit::bytes("maxResourceSize (vkGetPhysicalDeviceImageFormatProperties)", format.max_resource_size),
        })
    }

    /// A [`VkError::DeviceLimit`] on this device: `what` needs more than `limit`.
    pub fn over_limit(&self, what: impl Into<String>, limit: Limit) -> VkError {
        VkError::DeviceLimit { what: what.into(), limit, device: self.capabilities().device_name.clone() }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bytes_read_with_binary_units() {
        assert_eq!(human_bytes(512), "512 B");
        assert_eq!(human_bytes(96 << 20), "96 MiB");
        assert_eq!(human_bytes(3 << 29), "1.5 GiB");
        assert_eq!(
            Limit::bytes("maxStorageBufferRange", 1u64 << 27).to_string(),
            "maxStorageBufferRange is 134217728 bytes (128 MiB)"
        );
        assert_eq!(Limit::count("maxFramebufferWidth", 8192u32).to_string(), "maxFramebufferWidth is 8192");
    }

    #[test]
    fn the_tightest_limit_wins_and_the_first_on_a_tie() {
        let a = Limit::count("a", 16384u32);
        let b = Limit::count("b", 8192u32);
        let c = Limit::count("c", 8192u32);
        assert_eq!(tightest(&[a, b, c]).name, "b");
        let bytes = Limit::bytes("bytes", 1u64 << 30);
        let limits = ImageLimits { width: b, height: a, layers: Limit::count("layers", 6u32), bytes };
        let desc = ImageDesc::new_2d(vk::Format::D32_SFLOAT, 8200, 8);
        assert_eq!(limits.broken_by(&desc), Some(("width 8200".into(), b)));
        assert_eq!(limits.broken_by(&ImageDesc::new_2d(vk::Format::D32_SFLOAT, 8192, 16384)), None);
        let rgba32f = ImageDesc::new_2d(vk::Format::R32G32B32A32_SFLOAT, 8192, 16384);
        assert_eq!(limits.broken_by(&rgba32f), Some(("2 GiB of texels".into(), bytes)));
    }
}
