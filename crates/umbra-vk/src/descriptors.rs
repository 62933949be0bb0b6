//! Descriptor set layouts and sets: a set with its own small pool, or a [`DescriptorArena`]'s,
//! reset every frame.

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
    /// The first `size` bytes of a buffer the caller owns and keeps alive while the set is
    /// used (an engine's: created with the usage the binding's type needs).
    ExternalBuffer {
        /// The buffer.
        buffer: vk::Buffer,
        /// Its size in bytes, checked against the descriptor type's range limit.
        size: u64,
    },
    /// A sampled image with its sampler, in `layout`.
    SampledImage {
        /// The view read.
        view: vk::ImageView,
        /// The sampler (comparison samplers for shadow lookups).
        sampler: vk::Sampler,
        /// Layout the image is in while read.
        layout: vk::ImageLayout,
    },
    /// A storage image, written by compute shaders in `GENERAL` layout
    /// ([`crate::ImageState::ComputeWrite`]).
    StorageImage(vk::ImageView),
}

/// A descriptor set: with its own pool (freed on drop), or one of a [`DescriptorArena`]'s
/// (freed when the arena is reset; only ever borrowed from the arena).
pub struct DescriptorSet {
    /// The raw set.
    pub raw: vk::DescriptorSet,
    /// The set's own pool; `None` for an arena's set.
    pool: Option<vk::DescriptorPool>,
    ctx: Context,
}

impl DescriptorSet {
    /// Allocates a set of `layout` and writes `resources[i]` to the layout's `i`-th binding.
    ///
    /// Buffers are bound whole: one larger than `maxStorageBufferRange` (storage) or
    /// `maxUniformBufferRange` (uniform) is a typed [`crate::VkError::DeviceLimit`].
    pub fn new(ctx: &Context, name: &str, layout: &DescriptorSetLayout, resources: &[Resource<'_>]) -> VkResult<Self> {
        check_ranges(ctx, name, layout, resources)?;
        let pool = create_pool(ctx, layout, 1)?;
        ctx.set_name(pool, &format!("{name} pool"));
        let raw = match allocate(ctx, pool, layout) {
            Ok(raw) => raw,
            Err(e) => {
                // SAFETY: unused pool.
                unsafe { ctx.inner.device.destroy_descriptor_pool(pool, None) };
                return Err(e);
            }
        };
        let set = Self { raw, pool: Some(pool), ctx: ctx.clone() };
        write(ctx, raw, layout, resources);
        ctx.set_name(raw, name);
        Ok(set)
    }
}

/// Sets of one layout made every frame from one pool that is reset instead of freed: a frame
/// allocates its sets with [`DescriptorArena::allocate`] after [`DescriptorArena::reset`] and
/// reads them with [`DescriptorArena::get`]. No pool is created while the frame needs no more
/// sets than an earlier one did. The borrow checker keeps every set from outliving a reset: sets
/// are only lent out by `get`, and `reset` takes the arena mutably.
pub struct DescriptorArena {
    name: String,
    pool: vk::DescriptorPool,
    capacity: u32,
    sets: Vec<DescriptorSet>,
    ctx: Context,
}

impl DescriptorArena {
    /// An arena named `name` with room for `capacity` sets of `layout` (at least 1).
    pub fn new(ctx: &Context, name: &str, layout: &DescriptorSetLayout, capacity: u32) -> VkResult<Self> {
        let capacity = capacity.max(1);
        let pool = create_pool(ctx, layout, capacity)?;
        ctx.set_name(pool, &format!("{name} pool"));
        Ok(Self { name: name.to_owned(), pool, capacity, sets: Vec::new(), ctx: ctx.clone() })
    }

    /// Frees every set and makes room for `count` sets of `layout` (a larger pool only when the
    /// current one holds fewer). The GPU must be done with the sets: umbra waits for every
    /// submission.
    pub fn reset(&mut self, layout: &DescriptorSetLayout, count: u32) -> VkResult<()> {
        self.sets.clear();
        let device = &self.ctx.inner.device;
        if count > self.capacity {
            let pool = create_pool(&self.ctx, layout, count)?;
            // SAFETY: no set of the old pool is left (cleared above) and none is in use.
            unsafe { device.destroy_descriptor_pool(self.pool, None) };
            self.ctx.set_name(pool, &format!("{} pool", self.name));
            (self.pool, self.capacity) = (pool, count);
            return Ok(());
        }
        // SAFETY: every set of the pool was dropped above and none is in use by the GPU.
        unsafe { device.reset_descriptor_pool(self.pool, vk::DescriptorPoolResetFlags::empty()) }
            .call("vkResetDescriptorPool")
    }

    /// Allocates a set of `layout` (the arena's) named `name` and writes `resources[i]` to its
    /// `i`-th binding, as [`DescriptorSet::new`]; returns its index for [`Self::get`].
    pub fn allocate(
        &mut self,
        name: &str,
        layout: &DescriptorSetLayout,
        resources: &[Resource<'_>],
    ) -> VkResult<usize> {
        check_ranges(&self.ctx, name, layout, resources)?;
        if self.sets.len() as u32 >= self.capacity {
            return Err(crate::VkError::InvalidDesc {
                what: "descriptor arena",
                why: format!("{:?} holds {} sets this frame: reset it for more", self.name, self.capacity),
            });
        }
        let raw = allocate(&self.ctx, self.pool, layout)?;
        write(&self.ctx, raw, layout, resources);
        self.ctx.set_name(raw, name);
        self.sets.push(DescriptorSet { raw, pool: None, ctx: self.ctx.clone() });
        Ok(self.sets.len() - 1)
    }

    /// Set `index` of this frame's.
    pub fn get(&self, index: usize) -> Option<&DescriptorSet> {
        self.sets.get(index)
    }
}

impl Drop for DescriptorArena {
    fn drop(&mut self) {
        self.sets.clear();
        // SAFETY: umbra waits for every submission; destroying the pool frees its sets.
        unsafe { self.ctx.inner.device.destroy_descriptor_pool(self.pool, None) };
    }
}

/// Refuses a buffer larger than its descriptor type can bind.
fn check_ranges(ctx: &Context, name: &str, layout: &DescriptorSetLayout, resources: &[Resource<'_>]) -> VkResult<()> {
    for (b, r) in layout.bindings.iter().zip(resources) {
        let size = match *r {
            Resource::Buffer(buffer) => buffer.desc.size,
            Resource::ExternalBuffer { size, .. } => size,
            _ => continue,
        };
        if let Some(limit) = range_limit(ctx, b.ty).filter(|limit| size > limit.value) {
            return Err(ctx.over_limit(
                format!("descriptor set {name:?}, binding {}: {} of {:?}", b.binding, human_bytes(size), b.ty),
                limit,
            ));
        }
    }
    Ok(())
}

/// A pool with room for `sets` sets of `layout`.
fn create_pool(ctx: &Context, layout: &DescriptorSetLayout, sets: u32) -> VkResult<vk::DescriptorPool> {
    let sizes: Vec<_> =
        layout.bindings.iter().map(|b| vk::DescriptorPoolSize { ty: b.ty, descriptor_count: sets }).collect();
    let info = vk::DescriptorPoolCreateInfo::default().max_sets(sets).pool_sizes(&sizes);
    // SAFETY: valid create info; the caller destroys the pool.
    unsafe { ctx.inner.device.create_descriptor_pool(&info, None) }.call("vkCreateDescriptorPool")
}

/// One set of `layout` from `pool`.
fn allocate(ctx: &Context, pool: vk::DescriptorPool, layout: &DescriptorSetLayout) -> VkResult<vk::DescriptorSet> {
    let layouts = [layout.raw];
    let alloc = vk::DescriptorSetAllocateInfo::default().descriptor_pool(pool).set_layouts(&layouts);
    // SAFETY: the caller sized the pool for sets of this layout.
    Ok(unsafe { ctx.inner.device.allocate_descriptor_sets(&alloc) }.call("vkAllocateDescriptorSets")?[0])
}

/// Writes `resources[i]` to binding `i` of `raw` (a set of `layout`).
fn write(ctx: &Context, raw: vk::DescriptorSet, layout: &DescriptorSetLayout, resources: &[Resource<'_>]) {
    let buffer_infos: Vec<_> = resources
        .iter()
        .map(|r| match r {
            Resource::Buffer(b) => [vk::DescriptorBufferInfo { buffer: b.raw, offset: 0, range: vk::WHOLE_SIZE }],
            &Resource::ExternalBuffer { buffer, size } => [vk::DescriptorBufferInfo { buffer, offset: 0, range: size }],
            _ => [vk::DescriptorBufferInfo::default()],
        })
        .collect();
    let image_infos: Vec<_> = resources
        .iter()
        .map(|r| match *r {
            Resource::SampledImage { view, sampler, layout } => {
                [vk::DescriptorImageInfo { sampler, image_view: view, image_layout: layout }]
            }
            Resource::StorageImage(view) => [vk::DescriptorImageInfo {
                sampler: vk::Sampler::null(),
                image_view: view,
                image_layout: vk::ImageLayout::GENERAL,
            }],
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
                Resource::Buffer(_) | Resource::ExternalBuffer { .. } => w.buffer_info(&buffer_infos[i]),
                Resource::SampledImage { .. } | Resource::StorageImage(_) => w.image_info(&image_infos[i]),
            }
        })
        .collect();
    // SAFETY: writes match the layout's binding types; resources are alive now and the caller
    // keeps them alive while the set is used (they are borrowed by recorders).
    unsafe { ctx.inner.device.update_descriptor_sets(&writes, &[]) };
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
        if let Some(pool) = self.pool {
            // SAFETY: umbra waits for every submission; destroying the pool frees the set.
            unsafe { self.ctx.inner.device.destroy_descriptor_pool(pool, None) };
        }
    }
}
