//! Where a resource's memory lives, and allocating it.

use crate::error::{VkError, VkResult};
use crate::{human_bytes, Context, Limit};
use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;

/// Where a buffer's or image's memory lives.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Memory {
    /// Device-local, not host-visible (attachments, static geometry uploaded once).
    GpuOnly,
    /// Host-visible, written by the CPU every frame (uniforms, staging).
    CpuToGpu,
    /// Host-visible and cached, read back by the CPU.
    GpuToCpu,
}

impl Memory {
    pub(crate) fn location(self) -> MemoryLocation {
        match self {
            Memory::GpuOnly => MemoryLocation::GpuOnly,
            Memory::CpuToGpu => MemoryLocation::CpuToGpu,
            Memory::GpuToCpu => MemoryLocation::GpuToCpu,
        }
    }
}

/// Allocates memory for the buffer or image `name` (`linear`: a buffer or linear image),
/// refusing more than `maxMemoryAllocationSize` up front; an allocator error names `name`.
pub(crate) fn allocate(
    ctx: &Context,
    name: &str,
    requirements: vk::MemoryRequirements,
    memory: Memory,
    linear: bool,
) -> VkResult<Allocation> {
    let max = ctx.capabilities().max_memory_allocation_size;
    if requirements.size > max {
        return Err(ctx.over_limit(
            format!("{name:?} needs {} of memory in one allocation", human_bytes(requirements.size)),
            Limit::bytes("maxMemoryAllocationSize", max),
        ));
    }
    let desc = AllocationCreateDesc {
        name,
        requirements,
        location: memory.location(),
        linear,
        allocation_scheme: AllocationScheme::GpuAllocatorManaged,
    };
    let allocation = ctx.allocator()?.allocate(&desc).map_err(|source| VkError::Allocation {
        name: name.to_owned(),
        bytes: requirements.size,
        source,
    })?;
    ctx.count_allocation();
    log::trace!("allocated {} for {name:?}", human_bytes(requirements.size));
    Ok(allocation)
}
