//! Descriptor set layouts and sets (each set owns a small pool sized for its layout).

use crate::error::{CallContext, VkResult};
use crate::{human_bytes, Buffer, Context, Limit};
use ash::vk;

/// One binding of a set layout.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Binding {
    /// Binding number.
    pub binding: u32,
    /// Descriptor type.
    pub ty: vk::DescriptorType,
    /// Stages that read it.
    pub stages: vk::ShaderStageFlags,
}

/// A descriptor set layout; destroyed on drop.
pub struct DescriptorSetLayout {
    /// The raw layout.
    pub raw: vk::DescriptorSetLayout,
    bindings: Vec<Binding>,
    ctx: Context,
}

impl DescriptorSetLayout {
    /// Creates a layout of single-descriptor bindings.
    pub fn new(ctx: &Context, name: &str, bindings: &[Binding]) -> VkResult<Self> {
        let raw_bindings: Vec<_> = bindings
            .iter()
            .map(|b| {
                vk::DescriptorSetLayoutBinding::default()
                    .binding(b.binding)
                    .descriptor_type(b.ty)
                    .descriptor_count(1)
                    .stage_flags(b.stages)
            })
            .collect();
        let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&raw_bindings);
        // SAFETY: valid create info; destroyed in `Drop`.
        let raw = unsafe { ctx.inner.device.create_descriptor_set_layout(&info, None) }
            .call("vkCreateDescriptorSetLayout")?;
        ctx.set_name(raw, name);
        Ok(Self { raw, bindings: bindings.to_vec(), ctx: ctx.clone() })
    }
}

impl Drop for DescriptorSetLayout {
    fn drop(&mut self) {
        // SAFETY: umbra waits for every submission, so the layout is no longer in use.
        unsafe { self.ctx.inner.device.destroy_descriptor_set_layout(self.raw, None) };
    }
}

/// What one binding of a set points at.
#[derive(Clone, Copy, Debug)]
pub enum Resource<'a> {
    /// A whole uniform or storage buffer.
    Buffer(&'a Buffer),
    /// A sampled image with its sampler, in `layout`.
    SampledImage {
        /// The view read.
        view: vk::ImageView,
        /// The sampler (comparison samplers for shadow lookups).
        sampler: vk::Sampler,
        /// Layout the image is in while read.
        layout: vk::ImageLayout,
    },
}

/// A descriptor set with its own pool; freed on drop.
pub struct DescriptorSet {
    /// The raw set.
    pub raw: vk::DescriptorSet,
    pool: vk::DescriptorPool,
    ctx: Context,
}

impl DescriptorSet {
    /// Allocates a set of `layout` and writes `resources[i]` to the layout's `i`-th binding.
    ///
    /// Buffers are bound whole: one larger than `maxStorageBufferRange` (storage) or
    /// `maxUniformBufferRange` (uniform) is a typed [`crate::VkError::DeviceLimit`].
    pub fn new(ctx: &Context, name: &str, layout: &DescriptorSetLayout, resources: &[Resource<'_>]) -> VkResult<Self> {
        for (b, r) in layout.bindings.iter().zip(resources) {
            if let (Resource::Buffer(buffer), Some(limit)) = (r, range_limit(ctx, b.ty)) {
                if buffer.desc.size > limit.value {
                    return Err(ctx.over_limit(
                        format!(
                            "descriptor set {name:?}, binding {}: {} of {:?}",
                            b.binding,
                            human_bytes(buffer.desc.size),
                            b.ty
                        ),
                        limit,
                    ));
                }
            }
        }
        let device = &ctx.inner.device;
        let sizes: Vec<_> =
            layout.bindings.iter().map(|b| vk::DescriptorPoolSize { ty: b.ty, descriptor_count: 1 }).collect();
        let info = vk::DescriptorPoolCreateInfo::default().max_sets(1).pool_sizes(&sizes);
        // SAFETY: valid create info; destroyed in `Drop`.
        let pool = unsafe { device.create_descriptor_pool(&info, None) }.call("vkCreateDescriptorPool")?;
        let layouts = [layout.raw];
        let alloc = vk::DescriptorSetAllocateInfo::default().descriptor_pool(pool).set_layouts(&layouts);
        // SAFETY: the pool was sized for exactly this layout.
        let raw = match unsafe { device.allocate_descriptor_sets(&alloc) }.call("vkAllocateDescriptorSets") {
            Ok(sets) => sets[0],
            Err(e) => {
                // SAFETY: unused pool.
                unsafe { device.destroy_descriptor_pool(pool, None) };
                return Err(e);
            }
        };
        let set = Self { raw, pool, ctx: ctx.clone() };
        let buffer_infos: Vec<_> = resources
            .iter()
            .map(|r| match r {
                Resource::Buffer(b) => [vk::DescriptorBufferInfo { buffer: b.raw, offset: 0, range: vk::WHOLE_SIZE }],
                _ => [vk::DescriptorBufferInfo::default()],
            })
            .collect();
        let image_infos: Vec<_> = resources
            .iter()
            .map(|r| match *r {
                Resource::SampledImage { view, sampler, layout } => {
                    [vk::DescriptorImageInfo { sampler, image_view: view, image_layout: layout }]
                }
                _ => [vk::DescriptorImageInfo::default()],
            })
            .collect();
        let writes: Vec<_> = layout
            .bindings
            .iter()
            .zip(resources)
            .enumerate()
            .map(|(i, (b, r))| {
                let w = vk::WriteDescriptorSet::default().dst_set(raw).dst_binding(b.binding).descriptor_type(b.ty);
                match r {
                    Resource::Buffer(_) => w.buffer_info(&buffer_infos[i]),
                    Resource::SampledImage { .. } => w.image_info(&image_infos[i]),
                }
            })
            .collect();
        // SAFETY: writes match the layout's binding types; resources are alive now and the
        // caller keeps them alive while the set is used (they are borrowed by recorders).
        unsafe { device.update_descriptor_sets(&writes, &[]) };
        ctx.set_name(raw, name);
        ctx.set_name(pool, &format!("{name} pool"));
        Ok(set)
    }
}

/// The most a descriptor of type `ty` can bind, for buffer descriptors.
fn range_limit(ctx: &Context, ty: vk::DescriptorType) -> Option<Limit> {
    let caps = ctx.capabilities();
    match ty {
        vk::DescriptorType::STORAGE_BUFFER => {
            Some(Limit::bytes("maxStorageBufferRange", caps.max_storage_buffer_range))
        }
        vk::DescriptorType::UNIFORM_BUFFER => {
            Some(Limit::bytes("maxUniformBufferRange", caps.max_uniform_buffer_range))
        }
        _ => None,
    }
}

impl Drop for DescriptorSet {
    fn drop(&mut self) {
        // SAFETY: umbra waits for every submission; destroying the pool frees the set.
        unsafe { self.ctx.inner.device.destroy_descriptor_pool(self.pool, None) };
    }
}
