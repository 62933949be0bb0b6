//! # umbra-vk — umbra's core Vulkan layer
//!
//! Raw [`ash`] with memory through `gpu-allocator`, knowing nothing of shadows. One small file
//! per Vulkan object kind; every object is RAII (freed on drop) and debug-named; every `unsafe`
//! block of umbra lives here, each with a `// SAFETY:` line.
//!
//! - [`Context`]: instance, device (headless, Vulkan 1.3, dynamic rendering, synchronization2),
//!   queue, allocator and [`Capabilities`]. [`Context::new`] honours `UMBRA_DEVICE` and
//!   `UMBRA_VALIDATION`; [`Context::from_external`] wraps an engine's own device.
//! - [`Buffer`], [`Image`] with `Copy` descriptions ([`BufferDesc`], [`ImageDesc`]).
//! - [`GraphicsPipeline`] from a [`GraphicsPipelineDesc`] with the full depth/stencil state.
//! - [`Recorder`]: a safe command recorder whose borrows keep resources alive until the
//!   submission completes.
//! - [`QueryPool`]: timestamps, occlusion, pipeline statistics.
//! - [`Swapchain`]: a window's surface (through `ash-window`) and swapchain, presenting RGBA8
//!   frames with frames in flight and recreation on resize; the context must be created with
//!   [`ContextOptions::surface_extensions`] (from [`surface_extensions`]).
//!
//! ## Device requirements
//! Required: Vulkan 1.3, `dynamicRendering`, `synchronization2`, a graphics queue.
//! Optional (enabled when present, reported in [`Capabilities`]): `depthBounds`, `depthClamp`,
//! `pipelineStatisticsQuery`, `geometryShader`, `wideLines`, `depthBiasClamp`,
//! `fillModeNonSolid`, `fragmentStoresAndAtomics`, `shaderStorageImageExtendedFormats`,
//! `VK_EXT_conservative_rasterization`; `VK_EXT_debug_utils` on the instance.
//! Presenting: the window system's surface extensions on the instance ([`surface_extensions`])
//! and `VK_KHR_swapchain` on the device.

#![warn(missing_docs)]

mod buffer;
mod capabilities;
mod commands;
mod compute;
mod context;
mod descriptors;
mod error;
mod image;
mod limits;
mod memory;
mod pipeline;
mod query;
mod sampler;
pub mod selection;
mod surface;
mod swapchain;
mod validation;

pub use ash;
pub use ash::vk;
pub use buffer::{Buffer, BufferDesc, BufferState};
pub use bytemuck;
pub use capabilities::{device_type_name, Capabilities, DEPTH_STENCIL_PREFERENCE};
pub use commands::{ColorAttachment, DepthAttachment, Recorder, RenderTargets, VertexStreamBinding};
pub use compute::ComputePipeline;
pub use context::{Context, ContextOptions, ExternalDevice, VALIDATION_ENV};
pub use descriptors::{Binding, DescriptorArena, DescriptorSet, DescriptorSetLayout, Resource};
pub use error::{VkError, VkResult};
pub use image::{format_aspect, texel_size, Image, ImageDesc, ImageState, ImageView};
pub use limits::{element_bytes, human_bytes, ImageLimits, Limit};
pub use memory::Memory;
pub use pipeline::{
    Blend, ColorTarget, DepthState, GraphicsPipeline, GraphicsPipelineDesc, PipelineLayout, StencilFace,
    VertexAttribute,
};
pub use query::{QueryKind, QueryPool, QUERY_WAIT};
pub use raw_window_handle;
pub use sampler::{Sampler, SamplerDesc};
pub use selection::DEVICE_ENV;
pub use surface::surface_extensions;
pub use swapchain::{Presented, Swapchain, SwapchainDesc};
pub use validation::ValidationCounter;
