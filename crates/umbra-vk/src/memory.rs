//! Where a resource's memory lives.

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
