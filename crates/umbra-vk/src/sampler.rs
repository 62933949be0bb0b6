//! Samplers, including comparison samplers for shadow lookups.

use crate::error::{CallContext, VkResult};
use crate::Context;
use ash::vk;

/// What a sampler does.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SamplerDesc {
    /// Magnification and minification filter (`LINEAR` with `compare` = hardware 2×2 PCF).
    pub filter: vk::Filter,
    /// Addressing in u, v and w.
    pub address: vk::SamplerAddressMode,
    /// Depth comparison (`sampler2DShadow`), or `None` for plain sampling.
    pub compare: Option<vk::CompareOp>,
}

impl SamplerDesc {
    /// Nearest filtering, clamp to edge, no comparison.
    pub const NEAREST_CLAMP: Self =
        Self { filter: vk::Filter::NEAREST, address: vk::SamplerAddressMode::CLAMP_TO_EDGE, compare: None };
}

/// A sampler; destroyed on drop.
pub struct Sampler {
    /// The raw sampler.
    pub raw: vk::Sampler,
    ctx: Context,
}

impl Sampler {
    /// Creates a named sampler.
    pub fn new(ctx: &Context, name: &str, desc: SamplerDesc) -> VkResult<Self> {
        let info = vk::SamplerCreateInfo::default()
            .mag_filter(desc.filter)
            .min_filter(desc.filter)
            .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
            .address_mode_u(desc.address)
            .address_mode_v(desc.address)
            .address_mode_w(desc.address)
            .compare_enable(desc.compare.is_some())
            .compare_op(desc.compare.unwrap_or(vk::CompareOp::ALWAYS))
            .max_lod(0.0)
            .border_color(vk::BorderColor::FLOAT_OPAQUE_WHITE);
        // SAFETY: valid create info; destroyed in `Drop`.
        let raw = unsafe { ctx.inner.device.create_sampler(&info, None) }.call("vkCreateSampler")?;
        ctx.set_name(raw, name);
        Ok(Self { raw, ctx: ctx.clone() })
    }
}

impl Drop for Sampler {
    fn drop(&mut self) {
        // SAFETY: umbra waits for every submission, so the sampler is no longer in use.
        unsafe { self.ctx.inner.device.destroy_sampler(self.raw, None) };
    }
}
