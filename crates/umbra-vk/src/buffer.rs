//! Buffers: a `Copy` description, an RAII buffer, upload and readback.

use crate::error::{CallContext, VkError, VkResult};
use crate::memory::{self, Memory};
use crate::{human_bytes, Context, Limit};
use ash::vk;
use gpu_allocator::vulkan::Allocation;

/// What a buffer is: size, usage and memory.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct BufferDesc {
    /// Size in bytes (non-zero).
    pub size: u64,
    /// Usage flags.
    pub usage: vk::BufferUsageFlags,
    /// Where the memory lives.
    pub memory: Memory,
}

impl BufferDesc {
    /// A device-local buffer of `size` bytes with `usage` (plus `TRANSFER_DST` for uploads).
    pub fn gpu_only(size: u64, usage: vk::BufferUsageFlags) -> Self {
        Self { size, usage: usage | vk::BufferUsageFlags::TRANSFER_DST, memory: Memory::GpuOnly }
    }

    /// A host-visible buffer written by the CPU.
    pub fn cpu_to_gpu(size: u64, usage: vk::BufferUsageFlags) -> Self {
        Self { size, usage, memory: Memory::CpuToGpu }
    }

    /// A host-visible buffer the GPU copies into for the CPU to read.
    pub fn readback(size: u64) -> Self {
        Self { size, usage: vk::BufferUsageFlags::TRANSFER_DST, memory: Memory::GpuToCpu }
    }

    /// Same description with other usage flags.
    pub fn usage(mut self, usage: vk::BufferUsageFlags) -> Self {
        self.usage = usage;
        self
    }
}

/// A Vulkan buffer and its memory; freed on drop.
pub struct Buffer {
    /// The raw handle.
    pub raw: vk::Buffer,
    /// What it was created from.
    pub desc: BufferDesc,
    allocation: Option<Allocation>,
    ctx: Context,
}

impl std::fmt::Debug for Buffer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Buffer").field("raw", &self.raw).field("desc", &self.desc).finish()
    }
}

impl Buffer {
    /// Creates a named buffer (at most `maxBufferSize` bytes).
    pub fn new(ctx: &Context, name: &str, desc: BufferDesc) -> VkResult<Self> {
        if desc.size == 0 {
            return Err(VkError::InvalidDesc { what: "buffer", why: format!("{name}: size is zero") });
        }
        let max = ctx.capabilities().max_buffer_size;
        if desc.size > max {
            return Err(ctx.over_limit(
                format!("buffer {name:?} needs {}", human_bytes(desc.size)),
                Limit::bytes("maxBufferSize", max),
            ));
        }
        let info =
            vk::BufferCreateInfo::default().size(desc.size).usage(desc.usage).sharing_mode(vk::SharingMode::EXCLUSIVE);
        let device = &ctx.inner.device;
        // SAFETY: valid create info (size checked above); the buffer is destroyed in `Drop`.
        let raw = unsafe { device.create_buffer(&info, None) }.call("vkCreateBuffer")?;
        // SAFETY: `raw` was just created from `device`.
        let requirements = unsafe { device.get_buffer_memory_requirements(raw) };
        let allocation = match memory::allocate(ctx, name, requirements, desc.memory, true) {
            Ok(a) => a,
            Err(e) => {
                // SAFETY: unused, unbound buffer.
                unsafe { device.destroy_buffer(raw, None) };
                return Err(e);
            }
        };
        let buffer = Buffer { raw, desc, allocation: Some(allocation), ctx: ctx.clone() };
        // SAFETY: memory and offset come from an allocation made for these requirements.
        unsafe {
            let a = buffer.allocation.as_ref().ok_or(VkError::Poisoned)?;
            device.bind_buffer_memory(raw, a.memory(), a.offset()).call("vkBindBufferMemory")?;
        }
        ctx.set_name(raw, name);
        Ok(buffer)
    }

    /// Creates a device-local buffer holding `data`, uploaded through a staging buffer.
    pub fn with_data(ctx: &Context, name: &str, usage: vk::BufferUsageFlags, data: &[u8]) -> VkResult<Self> {
        let mut buffers = Buffer::upload_many(ctx, &[(name, usage, data)])?;
        buffers.pop().ok_or(VkError::InvalidDesc { what: "upload", why: format!("{name}: no buffer came back") })
    }

    /// Creates one device-local buffer per `(name, usage, data)` and uploads them all with a
    /// single submission (one staging buffer each, every copy in one command buffer).
    pub fn upload_many(ctx: &Context, uploads: &[(&str, vk::BufferUsageFlags, &[u8])]) -> VkResult<Vec<Self>> {
        let mut pairs = Vec::with_capacity(uploads.len());
        for &(name, usage, data) in uploads {
            let buffer = Buffer::new(ctx, name, BufferDesc::gpu_only(data.len() as u64, usage))?;
            pairs.push((Buffer::staging(ctx, name, data)?, buffer));
        }
        let mut rec = ctx.begin_commands("upload")?;
        rec.copy_staged(&pairs.iter().map(|(staging, buffer)| (staging, buffer)).collect::<Vec<_>>());
        ctx.submit_and_wait(rec)?;
        Ok(pairs.into_iter().map(|(_, buffer)| buffer).collect())
    }

    /// A host-visible `TRANSFER_SRC` buffer holding `data`, to be copied into the device-local
    /// buffer `name` by [`crate::Recorder::copy_staged`]; it must live until that copy ran.
    pub fn staging(ctx: &Context, name: &str, data: &[u8]) -> VkResult<Self> {
        let desc = BufferDesc::cpu_to_gpu(data.len() as u64, vk::BufferUsageFlags::TRANSFER_SRC);
        let mut staging = Buffer::new(ctx, &format!("{name} (staging)"), desc)?;
        staging.write(0, data)?;
        Ok(staging)
    }

    /// Writes `data` at `offset` into a host-visible buffer.
    pub fn write(&mut self, offset: u64, data: &[u8]) -> VkResult<()> {
        let end = offset + data.len() as u64;
        let size = self.desc.size;
        let slice = self.mapped_mut()?;
        let dst = slice.get_mut(offset as usize..end as usize).ok_or_else(|| VkError::InvalidDesc {
            what: "buffer write",
            why: format!("bytes {offset}..{end} past the size {size}"),
        })?;
        dst.copy_from_slice(data);
        Ok(())
    }

    /// Sets every byte of a host-visible buffer to `byte` (poisoning a readback, say).
    pub fn fill_host(&mut self, byte: u8) -> VkResult<()> {
        self.mapped_mut()?.fill(byte);
        Ok(())
    }

    /// Reads the whole content of a host-visible buffer.
    pub fn read(&self) -> VkResult<Vec<u8>> {
        Ok(self.mapped()?[..self.desc.size as usize].to_vec())
    }

    fn mapped(&self) -> VkResult<&[u8]> {
        let a = self.allocation.as_ref().ok_or(VkError::Poisoned)?;
        a.mapped_slice().ok_or_else(|| not_mapped(self.desc.memory))
    }

    pub(crate) fn mapped_mut(&mut self) -> VkResult<&mut [u8]> {
        let memory = self.desc.memory;
        let a = self.allocation.as_mut().ok_or(VkError::Poisoned)?;
        a.mapped_slice_mut().ok_or_else(|| not_mapped(memory))
    }
}

fn not_mapped(memory: Memory) -> VkError {
    VkError::InvalidDesc { what: "buffer map", why: format!("buffer of {memory:?} memory is not host-visible") }
}

impl Drop for Buffer {
    fn drop(&mut self) {
        // SAFETY: umbra waits for every submission, so the buffer is no longer in use.
        unsafe { self.ctx.inner.device.destroy_buffer(self.raw, None) };
        if let (Some(a), Ok(mut alloc)) = (self.allocation.take(), self.ctx.allocator()) {
            if let Err(e) = alloc.free(a) {
                log::error!("freeing buffer memory failed: {e}");
            }
        }
    }
}

/// How a pass uses a buffer the GPU itself writes (a compacted list and its dispatch
/// arguments), for the barriers between passes ([`crate::Recorder::buffer_transition`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BufferState {
    /// Not used yet this frame: leaving it waits for every earlier command (an earlier frame's
    /// use of a buffer shared by frames in flight).
    Unknown,
    /// Written by a transfer (`vkCmdUpdateBuffer`, `vkCmdFillBuffer`, a copy).
    TransferDst,
    /// Read by a transfer (a copy into a readback).
    TransferSrc,
    /// Read and written (atomics) by fragment shaders as a storage buffer.
    FragmentStorage,
    /// Read by compute shaders as a storage buffer and as indirect dispatch arguments.
    ComputeRead,
    /// Read and written (atomics) by compute shaders as a storage buffer.
    ComputeStorage,
    /// Read by vertex shaders as a storage buffer and as indirect draw arguments.
    VertexRead,
    /// Read as vertex attributes and indices (vertex input).
    VertexInput,
}

impl BufferState {
    /// The stages and accesses of a use in this state.
    pub(crate) fn stage_access(self) -> (vk::PipelineStageFlags2, vk::AccessFlags2) {
        use vk::AccessFlags2 as A;
        use vk::PipelineStageFlags2 as S;
        match self {
            BufferState::Unknown => (S::ALL_COMMANDS, A::MEMORY_READ | A::MEMORY_WRITE),
            BufferState::TransferDst => (S::ALL_TRANSFER, A::TRANSFER_WRITE),
            BufferState::TransferSrc => (S::ALL_TRANSFER, A::TRANSFER_READ),
            BufferState::FragmentStorage => (S::FRAGMENT_SHADER, A::SHADER_STORAGE_READ | A::SHADER_STORAGE_WRITE),
            BufferState::ComputeRead => {
                (S::DRAW_INDIRECT | S::COMPUTE_SHADER, A::INDIRECT_COMMAND_READ | A::SHADER_STORAGE_READ)
            }
            BufferState::ComputeStorage => (S::COMPUTE_SHADER, A::SHADER_STORAGE_READ | A::SHADER_STORAGE_WRITE),
            BufferState::VertexRead => {
                (S::DRAW_INDIRECT | S::VERTEX_SHADER, A::INDIRECT_COMMAND_READ | A::SHADER_STORAGE_READ)
            }
            BufferState::VertexInput => (S::VERTEX_INPUT, A::VERTEX_ATTRIBUTE_READ | A::INDEX_READ),
        }
    }

    /// Whether a use in this state may write.
    pub fn writes(self) -> bool {
        matches!(
            self,
            BufferState::Unknown
                | BufferState::TransferDst
                | BufferState::FragmentStorage
                | BufferState::ComputeStorage
        )
    }
}
