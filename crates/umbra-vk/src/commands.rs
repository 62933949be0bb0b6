//! Recording and submitting command buffers through a safe [`Recorder`].
//!
//! A `Recorder<'a>` borrows every resource it records for `'a`; `'a` outlives the
//! [`Context::submit_and_wait`] that executes it, so nothing recorded can be freed while the GPU
//! still uses it. Every submission waits for completion (umbra renders headless, frame by frame).

use crate::error::{CallContext, VkResult};
use crate::image::format_aspect;
use crate::{
    Buffer, BufferState, ComputePipeline, Context, DescriptorSet, GraphicsPipeline, Image, ImageState, ImageView,
    PipelineLayout, QueryPool,
};
use ash::vk;
use std::ffi::CString;
use std::marker::PhantomData;

/// How long a submission may run before umbra reports `VK_TIMEOUT` (software drivers are slow).
const SUBMIT_TIMEOUT_NS: u64 = 300_000_000_000;

/// The stages and accesses on one side of a memory dependency.
type StageAccess = (vk::PipelineStageFlags2, vk::AccessFlags2);

/// One vertex binding of [`Recorder::bind_vertex_streams`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct VertexStreamBinding {
    /// The buffer (with `VERTEX_BUFFER` usage).
    pub buffer: vk::Buffer,
    /// Byte offset of the first vertex's attribute.
    pub offset: u64,
    /// Bytes from one vertex to the next.
    pub stride: u64,
}

/// A colour attachment of a rendering pass.
#[derive(Clone, Copy, Debug)]
pub struct ColorAttachment<'a> {
    /// The image rendered to, in [`ImageState::ColorAttachment`].
    pub image: &'a Image,
    /// The view rendered to (one layer of an array), or `None` for the image's default view.
    pub view: Option<&'a ImageView>,
    /// Clear to this colour at the start, or keep the content (`None`).
    pub clear: Option<[f32; 4]>,
}

/// The depth(/stencil) attachment of a rendering pass.
#[derive(Clone, Copy, Debug)]
pub struct DepthAttachment<'a> {
    /// The image (its default view unless `view` is set).
    pub image: &'a Image,
    /// A view of one layer (a cube face), made with [`Image::layer_view`]; `None`: default view.
    pub view: Option<&'a ImageView>,
    /// Clear depth and stencil at the start, or keep them (`None`).
    pub clear: Option<(f32, u32)>,
    /// With `clear == None`: keep the depth but clear the stencil to this value (one shadow
    /// volume pass per light).
    pub clear_stencil: Option<u32>,
    /// Tested but never written: the image is in [`ImageState::DepthStencilReadOnly`].
    pub read_only: bool,
}

impl<'a> DepthAttachment<'a> {
    /// `image`'s default view, its depth and stencil kept and written.
    pub fn keep(image: &'a Image) -> Self {
        Self { image, view: None, clear: None, clear_stencil: None, read_only: false }
    }

    /// `image`'s default view, its depth cleared to `depth` and its stencil to `stencil`.
    pub fn cleared(image: &'a Image, depth: f32, stencil: u32) -> Self {
        Self { clear: Some((depth, stencil)), ..Self::keep(image) }
    }

    /// `image`'s default view, its depth kept and its stencil cleared to `stencil`.
    pub fn clearing_stencil(image: &'a Image, stencil: u32) -> Self {
        Self { clear_stencil: Some(stencil), ..Self::keep(image) }
    }
}

/// The attachments of one dynamic-rendering pass. The slice only needs to live for the
/// `begin_rendering` call (`'s`); the images are borrowed for the recording (`'a`).
#[derive(Clone, Copy, Debug, Default)]
pub struct RenderTargets<'s, 'a> {
    /// Colour attachments, in location order.
    pub color: &'s [ColorAttachment<'a>],
    /// Depth/stencil attachment.
    pub depth: Option<DepthAttachment<'a>>,
}

/// A command buffer being recorded: one umbra began (submit it with
/// [`Context::submit_and_wait`]) or an engine's ([`Context::record_into`]), which umbra only
/// records into.
pub struct Recorder<'a> {
    ctx: Context,
    cmd: vk::CommandBuffer,
    labels: u32,
    /// Whether umbra allocated `cmd` (and frees it when dropped).
    owned: bool,
    _borrows: PhantomData<&'a ()>,
}

impl Context {
    /// Starts recording a one-time command buffer named `name`.
    pub fn begin_commands<'a>(&self, name: &str) -> VkResult<Recorder<'a>> {
        let pool = self.inner.command_pool.lock().map_err(|_| crate::VkError::Poisoned)?;
        let info = vk::CommandBufferAllocateInfo::default()
            .command_pool(*pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: the pool is externally synchronised by its mutex.
        let cmd = unsafe { self.inner.device.allocate_command_buffers(&info) }.call("vkAllocateCommandBuffers")?[0];
        drop(pool);
        let rec = Recorder { ctx: self.clone(), cmd, labels: 0, owned: true, _borrows: PhantomData };
        let begin = vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        // SAFETY: fresh command buffer, recorded from this thread only.
        unsafe { self.inner.device.begin_command_buffer(cmd, &begin) }.call("vkBeginCommandBuffer")?;
        self.set_name(cmd, name);
        Ok(rec)
    }

    /// A recorder over `cmd`, a primary command buffer of this context's device that the
    /// engine allocated and began and still records (the engine's frame). umbra records its
    /// commands into it and nothing else: it never begins, ends, submits, waits for or frees
    /// it. Labels opened through the recorder are closed when it is dropped. The engine must
    /// keep every object recorded alive until the buffer completed.
    pub fn record_into<'a>(&self, cmd: vk::CommandBuffer) -> Recorder<'a> {
        Recorder { ctx: self.clone(), cmd, labels: 0, owned: false, _borrows: PhantomData }
    }

    /// Ends, submits and waits for a recording. Open labels are closed first. A recorder over
    /// an engine's command buffer ([`Context::record_into`]) is refused: the engine submits it.
    pub fn submit_and_wait(&self, mut rec: Recorder<'_>) -> VkResult<()> {
        if !rec.owned {
            return Err(crate::VkError::InvalidDesc {
                what: "submit_and_wait",
                why: "the recorder records into an engine's command buffer, which the engine submits".into(),
            });
        }
        while rec.labels > 0 {
            rec.end_label();
        }
        let device = &self.inner.device;
        // SAFETY: the recorder owns `cmd`, which is in the recording state.
        unsafe { device.end_command_buffer(rec.cmd) }.call("vkEndCommandBuffer")?;
        // SAFETY: plain object creation; destroyed below.
        let fence = unsafe { device.create_fence(&vk::FenceCreateInfo::default(), None) }.call("vkCreateFence")?;
        self.set_name(fence, "submit fence");
        let cmds = [vk::CommandBufferSubmitInfo::default().command_buffer(rec.cmd)];
        let submit = [vk::SubmitInfo2::default().command_buffer_infos(&cmds)];
        self.count_submission();
        let result = self.queue().and_then(|q| {
            // SAFETY: the queue is locked; every resource recorded is borrowed for the
            // recorder's lifetime, which covers this call, and we wait for completion below.
            unsafe { device.queue_submit2(*q, &submit, fence) }.call("vkQueueSubmit2")
        });
        // SAFETY: waiting on our own fence, then destroying it once signalled (or never submitted).
        let waited = result.and_then(|()| unsafe {
            device.wait_for_fences(&[fence], true, SUBMIT_TIMEOUT_NS).call("vkWaitForFences")
        });
        if waited.is_err() {
            // SAFETY: make sure nothing still runs before the fence and command buffer go away.
            unsafe {
                let _ = device.device_wait_idle();
            }
        }
        // SAFETY: the fence is signalled or the device is idle.
        unsafe { device.destroy_fence(fence, None) };
        waited
    }
}

impl Drop for Recorder<'_> {
    fn drop(&mut self) {
        if !self.owned {
            // The engine's buffer: close what this recorder opened, leave the rest to it.
            while self.labels > 0 {
                self.end_label();
            }
            return;
        }
        if let Ok(pool) = self.ctx.inner.command_pool.lock() {
            // SAFETY: the buffer finished executing (submit waits) or was never submitted.
            unsafe { self.ctx.inner.device.free_command_buffers(*pool, &[self.cmd]) };
        }
    }
}

impl<'a> Recorder<'a> {
    fn device(&self) -> &ash::Device {
        &self.ctx.inner.device
    }

    /// The raw command buffer, for engines that add their own commands.
    pub fn raw(&self) -> vk::CommandBuffer {
        self.cmd
    }

    /// Opens a debug label (RenderDoc region); close it with [`Recorder::end_label`].
    pub fn begin_label(&mut self, name: &str) {
        self.labels += 1;
        let Some(d) = self.ctx.debug_device() else {
            return;
        };
        let name = CString::new(name.replace('\0', " ")).unwrap_or_default();
        let label = vk::DebugUtilsLabelEXT::default().label_name(&name).color([0.35, 0.2, 0.6, 1.0]);
        // SAFETY: recording command buffer; the label string outlives the call.
        unsafe { d.cmd_begin_debug_utils_label(self.cmd, &label) };
    }

    /// Closes the innermost debug label.
    pub fn end_label(&mut self) {
        if self.labels == 0 {
            return;
        }
        self.labels -= 1;
        if let Some(d) = self.ctx.debug_device() {
            // SAFETY: a label opened by `begin_label` is open.
            unsafe { d.cmd_end_debug_utils_label(self.cmd) };
        }
    }

    /// Moves images between states with one batched barrier. `Undefined` as the old state
    /// discards the content.
    pub fn transition(&mut self, images: &[(&'a Image, ImageState, ImageState)]) {
        let barriers: Vec<_> = images
            .iter()
            .map(|&(image, from, to)| {
                let (src_stage, src_access) = from.stage_access();
                let (dst_stage, dst_access) = to.stage_access();
                vk::ImageMemoryBarrier2::default()
                    .src_stage_mask(src_stage)
                    .src_access_mask(src_access)
                    .dst_stage_mask(dst_stage)
                    .dst_access_mask(dst_access)
                    .old_layout(from.layout())
                    .new_layout(to.layout())
                    .image(image.raw)
                    .subresource_range(image.range(0, image.desc.layers))
            })
            .collect();
        if barriers.is_empty() {
            return;
        }
        let dep = vk::DependencyInfo::default().image_memory_barriers(&barriers);
        // SAFETY: images are alive for 'a; stage masks are never empty on the destination side.
        unsafe { self.device().cmd_pipeline_barrier2(self.cmd, &dep) };
    }

    /// Moves buffers between uses with one batched barrier, each a memory dependency from its
    /// old use's stages and accesses to its new one's.
    pub fn buffer_transition(&mut self, buffers: &[(&'a Buffer, BufferState, BufferState)]) {
        let scopes: Vec<_> = buffers.iter().map(|&(b, from, to)| (b, from.stage_access(), to.stage_access())).collect();
        self.buffer_barriers(&scopes);
    }

    /// A global memory dependency from every use in `from` to every use in `to`, whatever the
    /// buffer (one the caller does not own, an engine's, included).
    pub fn memory_barrier(&mut self, from: BufferState, to: BufferState) {
        let ((src_stage, src_access), (dst_stage, dst_access)) = (from.stage_access(), to.stage_access());
        let barrier = [vk::MemoryBarrier2::default()
            .src_stage_mask(src_stage)
            .src_access_mask(src_access)
            .dst_stage_mask(dst_stage)
            .dst_access_mask(dst_access)];
        let dep = vk::DependencyInfo::default().memory_barriers(&barrier);
        // SAFETY: no resource is named; stage masks are never empty.
        unsafe { self.device().cmd_pipeline_barrier2(self.cmd, &dep) };
    }

    /// One batched barrier of buffer memory dependencies, each whole buffer from its
    /// (stages, accesses) to its (stages, accesses).
    fn buffer_barriers(&mut self, scopes: &[(&'a Buffer, StageAccess, StageAccess)]) {
        let barriers: Vec<_> = scopes
            .iter()
            .map(|&(buffer, (src_stage, src_access), (dst_stage, dst_access))| {
                vk::BufferMemoryBarrier2::default()
                    .src_stage_mask(src_stage)
                    .src_access_mask(src_access)
                    .dst_stage_mask(dst_stage)
                    .dst_access_mask(dst_access)
                    .buffer(buffer.raw)
                    .offset(0)
                    .size(vk::WHOLE_SIZE)
            })
            .collect();
        if barriers.is_empty() {
            return;
        }
        let dep = vk::DependencyInfo::default().buffer_memory_barriers(&barriers);
        // SAFETY: the buffers are alive for 'a; stage masks are never empty.
        unsafe { self.device().cmd_pipeline_barrier2(self.cmd, &dep) };
    }

    /// Copies each staging buffer ([`Buffer::staging`]) whole into its device-local buffer,
    /// then makes the copies visible to every later read (one global barrier).
    pub fn copy_staged(&mut self, pairs: &[(&'a Buffer, &'a Buffer)]) {
        for (staging, buffer) in pairs {
            self.copy_buffer(staging, buffer, staging.desc.size);
        }
        self.transfer_to_reads();
    }

    /// Makes transfer writes to buffers visible to every later read (one global barrier).
    pub fn transfer_to_reads(&mut self) {
        let barrier = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::ALL_TRANSFER)
            .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)
            .dst_access_mask(vk::AccessFlags2::MEMORY_READ)];
        let dep = vk::DependencyInfo::default().memory_barriers(&barrier);
        // SAFETY: plain global barrier in a recording command buffer.
        unsafe { self.device().cmd_pipeline_barrier2(self.cmd, &dep) };
    }

    /// Makes the transfer writes into `buffers` (copies into readbacks) visible to the host
    /// once the submission's fence has signalled: one batched barrier.
    pub fn transfer_to_host(&mut self, buffers: &[&'a Buffer]) {
        let transfer = (vk::PipelineStageFlags2::ALL_TRANSFER, vk::AccessFlags2::TRANSFER_WRITE);
        let host = (vk::PipelineStageFlags2::HOST, vk::AccessFlags2::HOST_READ);
        let scopes: Vec<_> = buffers.iter().map(|&b| (b, transfer, host)).collect();
        self.buffer_barriers(&scopes);
    }

    /// Begins dynamic rendering over the full extent of the first attachment.
    pub fn begin_rendering(&mut self, targets: &RenderTargets<'_, 'a>) {
        let extent = targets
            .color
            .first()
            .map(|c| c.image.extent())
            .or(targets.depth.map(|d| d.image.extent()))
            .unwrap_or_default();
        let color: Vec<_> = targets
            .color
            .iter()
            .map(|c| {
                vk::RenderingAttachmentInfo::default()
                    .image_view(c.view.map_or(c.image.view, |v| v.raw))
                    .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                    .load_op(if c.clear.is_some() { vk::AttachmentLoadOp::CLEAR } else { vk::AttachmentLoadOp::LOAD })
                    .store_op(vk::AttachmentStoreOp::STORE)
                    .clear_value(vk::ClearValue { color: vk::ClearColorValue { float32: c.clear.unwrap_or_default() } })
            })
            .collect();
        let attachment = |d: &DepthAttachment<'a>, clear: bool, stencil: u32| {
            let (layout, store) = if d.read_only {
                (vk::ImageLayout::DEPTH_STENCIL_READ_ONLY_OPTIMAL, vk::AttachmentStoreOp::NONE)
            } else {
                (vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL, vk::AttachmentStoreOp::STORE)
            };
            let depth = d.clear.map_or(1.0, |c| c.0);
            vk::RenderingAttachmentInfo::default()
                .image_view(d.view.map_or(d.image.view, |v| v.raw))
                .image_layout(layout)
                .load_op(if clear { vk::AttachmentLoadOp::CLEAR } else { vk::AttachmentLoadOp::LOAD })
                .store_op(store)
                .clear_value(vk::ClearValue { depth_stencil: vk::ClearDepthStencilValue { depth, stencil } })
        };
        let depth = targets.depth.map(|d| attachment(&d, d.clear.is_some(), d.clear.map_or(0, |c| c.1)));
        let stencil = targets.depth.map(|d| {
            let stencil_clear = d.clear.map(|c| c.1).or(d.clear_stencil);
            attachment(&d, stencil_clear.is_some(), stencil_clear.unwrap_or(0))
        });
        let has_stencil =
            targets.depth.is_some_and(|d| format_aspect(d.image.desc.format).contains(vk::ImageAspectFlags::STENCIL));
        let mut info = vk::RenderingInfo::default()
            .render_area(vk::Rect2D { offset: vk::Offset2D::default(), extent })
            .layer_count(1)
            .color_attachments(&color);
        if let Some(d) = depth.as_ref() {
            info = info.depth_attachment(d);
        }
        if let (true, Some(s)) = (has_stencil, stencil.as_ref()) {
            info = info.stencil_attachment(s);
        }
        // SAFETY: attachments are alive for 'a and in the layouts named (callers transition).
        unsafe { self.device().cmd_begin_rendering(self.cmd, &info) };
        self.set_viewport(extent);
    }

    /// Ends dynamic rendering.
    pub fn end_rendering(&mut self) {
        // SAFETY: paired with `begin_rendering`.
        unsafe { self.device().cmd_end_rendering(self.cmd) };
    }

    /// Sets a y-up viewport (negative height, OpenGL's orientation and winding) and scissor
    /// covering `extent`. `begin_rendering` already does this for the full target.
    pub fn set_viewport(&mut self, extent: vk::Extent2D) {
        self.set_viewport_rect([0, 0, extent.width, extent.height]);
    }

    /// Sets a y-up viewport and a scissor covering the rectangle (x, y, width, height; y down,
    /// in pixels) of the target: drawing into one tile of an atlas.
    pub fn set_viewport_rect(&mut self, rect: [u32; 4]) {
        let [x, y, width, height] = rect;
        let (w, h) = (width as f32, height as f32);
        let viewport =
            vk::Viewport { x: x as f32, y: y as f32 + h, width: w, height: -h, min_depth: 0.0, max_depth: 1.0 };
        // SAFETY: every umbra pipeline has dynamic viewport.
        unsafe { self.device().cmd_set_viewport(self.cmd, 0, &[viewport]) };
        self.set_scissor(rect);
    }

    /// Limits drawing to the rectangle (x, y, width, height; y down, in pixels) until the next
    /// `begin_rendering` or `set_viewport`.
    pub fn set_scissor(&mut self, rect: [u32; 4]) {
        let [x, y, width, height] = rect;
        let scissor = vk::Rect2D {
            offset: vk::Offset2D { x: x.min(i32::MAX as u32) as i32, y: y.min(i32::MAX as u32) as i32 },
            extent: vk::Extent2D { width, height },
        };
        // SAFETY: every umbra pipeline has dynamic scissor; offsets are non-negative.
        unsafe { self.device().cmd_set_scissor(self.cmd, 0, &[scissor]) };
    }

    /// Binds a graphics pipeline.
    pub fn bind_pipeline(&mut self, pipeline: &'a GraphicsPipeline) {
        // SAFETY: the pipeline is alive for 'a.
        unsafe { self.device().cmd_bind_pipeline(self.cmd, vk::PipelineBindPoint::GRAPHICS, pipeline.raw) };
    }

    /// Binds a compute pipeline.
    pub fn bind_compute_pipeline(&mut self, pipeline: &'a ComputePipeline) {
        // SAFETY: the pipeline is alive for 'a.
        unsafe { self.device().cmd_bind_pipeline(self.cmd, vk::PipelineBindPoint::COMPUTE, pipeline.raw) };
    }

    /// Binds a descriptor set at `index` for compute pipelines.
    pub fn bind_compute_set(&mut self, layout: &'a PipelineLayout, index: u32, set: &'a DescriptorSet) {
        // SAFETY: set and layout are alive for 'a.
        unsafe {
            self.device().cmd_bind_descriptor_sets(
                self.cmd,
                vk::PipelineBindPoint::COMPUTE,
                layout.raw,
                index,
                &[set.raw],
                &[],
            )
        };
    }

    /// Dispatches the bound compute pipeline with the workgroup counts at byte `offset` of
    /// `buffer` (a `VkDispatchIndirectCommand`, written by the GPU; the buffer has
    /// `INDIRECT_BUFFER` usage).
    pub fn dispatch_indirect(&mut self, buffer: &'a Buffer, offset: u64) {
        // SAFETY: alive for 'a; the usage and alignment are checked by validation.
        unsafe { self.device().cmd_dispatch_indirect(self.cmd, buffer.raw, offset) };
    }

    /// Dispatches the bound compute pipeline over `groups` workgroups (x, y, z).
    pub fn dispatch(&mut self, groups: [u32; 3]) {
        // SAFETY: a compute pipeline is bound; limits are checked by validation.
        unsafe { self.device().cmd_dispatch(self.cmd, groups[0], groups[1], groups[2]) };
    }

    /// Draws with the bound graphics pipeline from the `VkDrawIndirectCommand` at byte `offset`
    /// of `buffer` (written by the GPU; the buffer has `INDIRECT_BUFFER` usage).
    pub fn draw_indirect(&mut self, buffer: &'a Buffer, offset: u64) {
        // SAFETY: alive for 'a; one command, so no stride; usage checked by validation.
        unsafe { self.device().cmd_draw_indirect(self.cmd, buffer.raw, offset, 1, 16) };
    }

    /// Writes `words` at the start of `buffer` from the command buffer (at most 65,536 bytes;
    /// the buffer has `TRANSFER_DST` usage).
    pub fn update_buffer(&mut self, buffer: &'a Buffer, words: &[u32]) {
        // SAFETY: alive for 'a; size limits are checked by validation.
        unsafe { self.device().cmd_update_buffer(self.cmd, buffer.raw, 0, bytemuck::cast_slice(words)) };
    }

    /// Binds a descriptor set at `index`.
    pub fn bind_descriptor_set(&mut self, layout: &'a PipelineLayout, index: u32, set: &'a DescriptorSet) {
        // SAFETY: set and layout are alive for 'a.
        unsafe {
            self.device().cmd_bind_descriptor_sets(
                self.cmd,
                vk::PipelineBindPoint::GRAPHICS,
                layout.raw,
                index,
                &[set.raw],
                &[],
            )
        };
    }

    /// Pushes constants (vertex and fragment stages) at offset 0.
    pub fn push_constants<T: bytemuck::Pod>(&mut self, layout: &'a PipelineLayout, data: &T) {
        // SAFETY: `PipelineLayout` checked the size; stages match its push range.
        unsafe {
            self.device().cmd_push_constants(self.cmd, layout.raw, layout.push_stages, 0, bytemuck::bytes_of(data))
        };
    }

    /// Binds a vertex buffer at binding 0.
    pub fn bind_vertex_buffer(&mut self, buffer: &'a Buffer) {
        // SAFETY: alive for 'a.
        unsafe { self.device().cmd_bind_vertex_buffers(self.cmd, 0, &[buffer.raw], &[0]) };
    }

    /// Binds `streams[i]` at binding `i` for a pipeline made with
    /// [`crate::GraphicsPipelineDesc::vertex_streams`]: each a buffer (umbra's own, or one the
    /// engine keeps alive until the commands completed), the byte offset of its first vertex
    /// and its stride.
    pub fn bind_vertex_streams(&mut self, streams: &[VertexStreamBinding]) {
        let buffers: Vec<vk::Buffer> = streams.iter().map(|s| s.buffer).collect();
        let offsets: Vec<u64> = streams.iter().map(|s| s.offset).collect();
        let strides: Vec<u64> = streams.iter().map(|s| s.stride).collect();
        // SAFETY: the buffers are alive until the commands completed (umbra's are kept by the
        // frame, the engine's by the engine: `VertexStreamBinding`); the arrays have one entry
        // per binding.
        unsafe { self.device().cmd_bind_vertex_buffers2(self.cmd, 0, &buffers, &offsets, None, Some(&strides)) };
    }

    /// Binds an index buffer of `index_type` from byte `offset` (a multiple of the index size):
    /// umbra's own, or one the engine keeps alive until the commands completed.
    pub fn bind_index_stream(&mut self, buffer: vk::Buffer, offset: u64, index_type: vk::IndexType) {
        // SAFETY: the buffer is alive until the commands completed (the caller's guarantee);
        // the offset's alignment is checked by the caller.
        unsafe { self.device().cmd_bind_index_buffer(self.cmd, buffer, offset, index_type) };
    }

    /// Binds a `u32` index buffer.
    pub fn bind_index_buffer(&mut self, buffer: &'a Buffer) {
        // SAFETY: alive for 'a.
        unsafe { self.device().cmd_bind_index_buffer(self.cmd, buffer.raw, 0, vk::IndexType::UINT32) };
    }

    /// Draws `count` vertices without an index buffer.
    pub fn draw(&mut self, count: u32) {
        self.draw_range(count, 0);
    }

    /// Draws `count` vertices starting at vertex `first` of the bound vertex buffer.
    pub fn draw_range(&mut self, count: u32, first: u32) {
        // SAFETY: recording inside a rendering pass with a bound pipeline.
        unsafe { self.device().cmd_draw(self.cmd, count, 1, first, 0) };
    }

    /// Draws `instances` instances of `count` vertices, from instance `first_instance`
    /// (per-instance attributes advance once per instance).
    pub fn draw_instanced(&mut self, count: u32, instances: u32, first_instance: u32) {
        // SAFETY: recording inside a rendering pass with a bound pipeline (and vertex buffer
        // when the pipeline reads one).
        unsafe { self.device().cmd_draw(self.cmd, count, instances, 0, first_instance) };
    }

    /// Draws `count` vertices from vertex `first` as one instance numbered `instance`
    /// (`gl_InstanceIndex`): for shaders that pull their vertices from storage buffers.
    pub fn draw_range_as_instance(&mut self, count: u32, first: u32, instance: u32) {
        // SAFETY: recording inside a rendering pass with a bound pipeline.
        unsafe { self.device().cmd_draw(self.cmd, count, 1, first, instance) };
    }

    /// Draws `count` indices from `first_index`, adding `vertex_offset` to each.
    pub fn draw_indexed(&mut self, count: u32, first_index: u32, vertex_offset: i32) {
        // SAFETY: recording inside a rendering pass with bound pipeline and buffers.
        unsafe { self.device().cmd_draw_indexed(self.cmd, count, 1, first_index, vertex_offset, 0) };
    }

    /// Sets depth bias (pipelines with `DepthState::bias`).
    pub fn set_depth_bias(&mut self, constant: f32, clamp: f32, slope: f32) {
        // SAFETY: dynamic state of the bound pipeline.
        unsafe { self.device().cmd_set_depth_bias(self.cmd, constant, clamp, slope) };
    }

    /// Sets the depth comparison (pipelines with `DepthState::compare_dynamic`).
    pub fn set_depth_compare_op(&mut self, op: vk::CompareOp) {
        // SAFETY: dynamic state of the bound pipeline (core in Vulkan 1.3, which umbra-vk requires).
        unsafe { self.device().cmd_set_depth_compare_op(self.cmd, op) };
    }

    /// Sets the depth-bounds range (pipelines with `DepthState::bounds_test`).
    pub fn set_depth_bounds(&mut self, min: f32, max: f32) {
        // SAFETY: dynamic state of the bound pipeline; the feature was checked at its creation.
        unsafe { self.device().cmd_set_depth_bounds(self.cmd, min, max) };
    }

    /// Sets the stencil reference of both faces (pipelines with stencil).
    pub fn set_stencil_reference(&mut self, reference: u32) {
        // SAFETY: dynamic state of the bound pipeline.
        unsafe { self.device().cmd_set_stencil_reference(self.cmd, vk::StencilFaceFlags::FRONT_AND_BACK, reference) };
    }

    /// Copies `size` bytes from the start of `src` to the start of `dst`.
    pub fn copy_buffer(&mut self, src: &'a Buffer, dst: &'a Buffer, size: u64) {
        let region = vk::BufferCopy { src_offset: 0, dst_offset: 0, size };
        // SAFETY: both alive for 'a; sizes are the caller's, checked by validation.
        unsafe { self.device().cmd_copy_buffer(self.cmd, src.raw, dst.raw, &[region]) };
    }

    /// Fills a buffer with a repeated `u32` (e.g. a poison value before a readback).
    pub fn fill_buffer(&mut self, buffer: &'a Buffer, value: u32) {
        // SAFETY: alive for 'a; the buffer has TRANSFER_DST usage (readback buffers do).
        unsafe { self.device().cmd_fill_buffer(self.cmd, buffer.raw, 0, vk::WHOLE_SIZE, value) };
    }

    /// Copies one layer of an image in [`ImageState::TransferSrc`] into a buffer, tightly packed.
    /// For depth/stencil images the depth aspect is copied.
    pub fn copy_image_to_buffer(&mut self, image: &'a Image, layer: u32, buffer: &'a Buffer) {
        let aspect = image.desc.aspect();
        let aspect = if aspect.contains(vk::ImageAspectFlags::DEPTH) { vk::ImageAspectFlags::DEPTH } else { aspect };
        self.copy_aspect_to_buffer(image, aspect, layer, buffer);
    }

    /// Copies the stencil aspect of a depth/stencil image in [`ImageState::TransferSrc`] into a
    /// buffer: one byte per texel, tightly packed, row 0 first.
    pub fn copy_stencil_to_buffer(&mut self, image: &'a Image, buffer: &'a Buffer) {
        self.copy_aspect_to_buffer(image, vk::ImageAspectFlags::STENCIL, 0, buffer);
    }

    /// Copies every aspect of `src` (in [`ImageState::TransferSrc`]) into `dst` (in
    /// [`ImageState::TransferDst`]); both have the same format and size.
    pub fn copy_image(&mut self, src: &'a Image, dst: &'a Image) {
        let layers = vk::ImageSubresourceLayers {
            aspect_mask: src.desc.aspect(),
            mip_level: 0,
            base_array_layer: 0,
            layer_count: src.desc.layers,
        };
        let region = vk::ImageCopy {
            src_subresource: layers,
            src_offset: vk::Offset3D::default(),
            dst_subresource: layers,
            dst_offset: vk::Offset3D::default(),
            extent: vk::Extent3D { width: src.desc.width, height: src.desc.height, depth: 1 },
        };
        // SAFETY: both alive for 'a, in TRANSFER_SRC/DST_OPTIMAL (caller transitions); equal
        // formats and extents are the caller's contract, checked by validation.
        unsafe {
            self.device().cmd_copy_image(
                self.cmd,
                src.raw,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                dst.raw,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &[region],
            )
        };
    }

    fn copy_aspect_to_buffer(
        &mut self,
        image: &'a Image,
        aspect: vk::ImageAspectFlags,
        layer: u32,
        buffer: &'a Buffer,
    ) {
        let region = vk::BufferImageCopy {
            buffer_offset: 0,
            buffer_row_length: 0,
            buffer_image_height: 0,
            image_subresource: vk::ImageSubresourceLayers {
                aspect_mask: aspect,
                mip_level: 0,
                base_array_layer: layer,
                layer_count: 1,
            },
            image_offset: vk::Offset3D::default(),
            image_extent: vk::Extent3D { width: image.desc.width, height: image.desc.height, depth: 1 },
        };
        // SAFETY: both alive for 'a; the image is in TRANSFER_SRC_OPTIMAL (caller transitions).
        unsafe {
            self.device().cmd_copy_image_to_buffer(
                self.cmd,
                image.raw,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                buffer.raw,
                &[region],
            )
        };
    }

    /// Clears every layer of a depth image in [`ImageState::TransferDst`] to `depth` (and
    /// stencil to 0).
    pub fn clear_depth_image(&mut self, image: &'a Image, depth: f32) {
        let range = image.range(0, image.desc.layers);
        let value = vk::ClearDepthStencilValue { depth, stencil: 0 };
        // SAFETY: alive for 'a; in TRANSFER_DST_OPTIMAL (caller transitions); TRANSFER_DST usage.
        unsafe {
            self.device().cmd_clear_depth_stencil_image(
                self.cmd,
                image.raw,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &value,
                &[range],
            )
        };
    }

    /// Resets every query of a pool (record before the first write of a frame).
    pub fn reset_queries(&mut self, pool: &'a QueryPool) {
        // SAFETY: alive for 'a; outside a rendering pass.
        unsafe { self.device().cmd_reset_query_pool(self.cmd, pool.raw, 0, pool.count) };
    }

    /// Writes a timestamp once all previous commands completed.
    pub fn write_timestamp(&mut self, pool: &'a QueryPool, index: u32) {
        // SAFETY: alive for 'a; the pool is a timestamp pool (checked at creation).
        unsafe { self.device().cmd_write_timestamp2(self.cmd, vk::PipelineStageFlags2::ALL_COMMANDS, pool.raw, index) };
    }

    /// Begins an occlusion or pipeline-statistics query.
    pub fn begin_query(&mut self, pool: &'a QueryPool, index: u32) {
        // SAFETY: alive for 'a.
        unsafe { self.device().cmd_begin_query(self.cmd, pool.raw, index, vk::QueryControlFlags::empty()) };
    }

    /// Ends a query begun with [`Recorder::begin_query`].
    pub fn end_query(&mut self, pool: &'a QueryPool, index: u32) {
        // SAFETY: paired with `begin_query`.
        unsafe { self.device().cmd_end_query(self.cmd, pool.raw, index) };
    }
}
