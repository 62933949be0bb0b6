//! What the chosen device can do, probed once; everything downstream asks this value.

use ash::vk;
use serde::Serialize;

/// Depth/stencil formats umbra may use, best first.
pub const DEPTH_STENCIL_PREFERENCE: [vk::Format; 3] =
    [vk::Format::D32_SFLOAT_S8_UINT, vk::Format::D24_UNORM_S8_UINT, vk::Format::D16_UNORM_S8_UINT];

/// The device's identity and the optional features umbra uses, as enabled on the device.
///
/// A feature is `true` only when the device supports it **and** it is enabled on the logical
/// device (umbra enables every optional feature it finds; a bring-your-own device reports what
/// its owner enabled). `Default` is a device with nothing: every feature off, every limit 0
/// (for tests of code that reads capabilities).
#[derive(Clone, Debug, Default, Serialize)]
pub struct Capabilities {
    /// Device name as reported by the driver (`llvmpipe (LLVM 15.0.6, 256 bits)`, …).
    pub device_name: String,
    /// Driver name (`llvmpipe`, `SwiftShader driver`, …), from `VkPhysicalDeviceDriverProperties`.
    pub driver_name: String,
    /// Driver version details (`Mesa 22.3.6 (LLVM 15.0.6)`, …).
    pub driver_info: String,
    /// Device type: `discrete`, `integrated`, `virtual`, `cpu` or `other`.
    pub device_type: String,
    /// Vulkan version the device supports, as `major.minor.patch`.
    pub api_version: String,
    /// `depthBounds`: the depth-bounds test (Chan–Durand's computation mask).
    pub depth_bounds: bool,
    /// `depthClamp`: clamp instead of clipping at near/far (Everitt–Kilgard's caps).
    pub depth_clamp: bool,
    /// `depthBiasClamp`: an upper limit on the depth bias of shadow passes.
    pub depth_bias_clamp: bool,
    /// `pipelineStatisticsQuery`: fragment-invocation counts for fill metrics.
    pub pipeline_statistics: bool,
    /// Timestamps on the graphics queue (`timestampValidBits > 0` and `timestampComputeAndGraphics`
    /// or a graphics queue with valid bits).
    pub timestamps: bool,
    /// Nanoseconds per timestamp tick.
    pub timestamp_period_ns: f32,
    /// Significant bits in a timestamp.
    pub timestamp_valid_bits: u32,
    /// `geometryShader`.
    pub geometry_shader: bool,
    /// `fragmentStoresAndAtomics`: fragment shaders write storage buffers (the ray-traced
    /// hybrid appends its uncertain pixels to a list).
    pub fragment_stores_and_atomics: bool,
    /// `shaderStorageImageExtendedFormats`: storage images of formats such as `rg32f` (the
    /// ray-traced hybrid's rays write the visibility image, RG32F).
    pub storage_image_extended_formats: bool,
    /// The graphics queue also runs compute (`VK_QUEUE_COMPUTE_BIT`): umbra's compute passes
    /// are recorded beside its draws.
    pub compute_queue: bool,
    /// `wideLines`: line widths other than 1.0.
    pub wide_lines: bool,
    /// Supported line width range (`[1, 1]` without wide lines).
    pub line_width_range: [f32; 2],
    /// `VK_EXT_conservative_rasterization` is available and enabled.
    pub conservative_rasterization: bool,
    /// Depth/stencil formats usable as optimal-tiling attachments, best first.
    pub depth_stencil_formats: Vec<String>,
    /// The depth/stencil attachment format umbra uses (D32_SFLOAT_S8_UINT when present).
    #[serde(serialize_with = "ser_format")]
    pub depth_stencil_format: vk::Format,
    /// `D32_SFLOAT` usable as a sampled depth attachment (shadow maps).
    pub depth32_sampled: bool,
    /// `R32G32_SFLOAT` colour attachments blend (the hybrid's depth bounds, kept by `MIN`).
    pub rg32f_blend: bool,
    /// `maxImageDimension2D`.
    pub max_image_dimension_2d: u32,
    /// `maxImageDimensionCube`.
    pub max_image_dimension_cube: u32,
    /// `maxImageArrayLayers`.
    pub max_image_array_layers: u32,
    /// `maxFramebufferWidth`: the widest attachment (and rendering area).
    pub max_framebuffer_width: u32,
    /// `maxFramebufferHeight`: the tallest attachment (and rendering area).
    pub max_framebuffer_height: u32,
    /// `maxViewportDimensions`: umbra's viewport covers the whole attachment, so attachments
    /// are bounded by it too.
    pub max_viewport_dimensions: [u32; 2],
    /// `maxStorageBufferRange` in bytes: the most a storage-buffer descriptor can bind.
    pub max_storage_buffer_range: u32,
    /// `maxUniformBufferRange` in bytes: the most a uniform-buffer descriptor can bind.
    pub max_uniform_buffer_range: u32,
    /// `maxBufferSize` (`VkPhysicalDeviceMaintenance4Properties`) in bytes: the largest buffer.
    pub max_buffer_size: u64,
    /// `maxMemoryAllocationSize` (`VkPhysicalDeviceMaintenance3Properties`) in bytes: the
    /// largest single allocation (one buffer's or image's memory).
    pub max_memory_allocation_size: u64,
    /// `maxPushConstantsSize` in bytes.
    pub max_push_constants_size: u32,
    /// `subPixelPrecisionBits`: vertices are snapped to 1/2^bits of a pixel before
    /// rasterization (silhouette maps snap their edges the same way).
    pub sub_pixel_precision_bits: u32,
    /// Whether the driver's clipping against the view's x and y planes keeps closed meshes
    /// watertight (two triangles sharing an edge cover each pixel along it once). False on
    /// SwiftShader, measured: `tests/shadow_volume.rs`
    /// (`swiftshaders_clipper_leaves_a_hole_that_clipping_inside_the_view_closes`); shadow volumes
    /// are then clipped on the host (`umbra_shadows::HostClip`).
    pub watertight_clipping: bool,
    /// The device offers ray queries (`VK_KHR_ray_query`, `VK_KHR_acceleration_structure`,
    /// `rayQuery`). umbra does not enable them: its shadow rays walk umbra's own BVH in
    /// shaders on every device (`umbra_shadows::ray_traced`); a ray-query path waits for a
    /// device that has them to be tested on. Neither lavapipe (Mesa 22.3) nor SwiftShader
    /// offers them.
    pub ray_query: bool,
}

fn ser_format<S: serde::Serializer>(f: &vk::Format, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(&format!("{f:?}"))
}

/// Everything `Capabilities::from_parts` needs, gathered by the context from the instance.
pub(crate) struct Probe<'a> {
    pub properties: &'a vk::PhysicalDeviceProperties,
    pub driver: &'a vk::PhysicalDeviceDriverProperties<'a>,
    pub maintenance3: &'a vk::PhysicalDeviceMaintenance3Properties<'a>,
    pub maintenance4: &'a vk::PhysicalDeviceMaintenance4Properties<'a>,
    pub enabled: &'a vk::PhysicalDeviceFeatures,
    pub queue_family: &'a vk::QueueFamilyProperties,
    pub conservative_rasterization: bool,
    pub depth_stencil_formats: Vec<vk::Format>,
    pub depth32_sampled: bool,
    pub rg32f_blend: bool,
    pub ray_query: bool,
}

impl Capabilities {
    /// Driver name and version in one string (`llvmpipe Mesa 22.3.6 (LLVM 15.0.6)`), as frame
    /// reports and bench results name it.
    pub fn driver(&self) -> String {
        driver_label(&self.driver_name, &self.driver_info)
    }

    pub(crate) fn from_parts(p: Probe<'_>) -> Self {
        let limits = &p.properties.limits;
        let c_str = |s: Result<&std::ffi::CStr, _>| {
            s.map(|c: &std::ffi::CStr| c.to_string_lossy().into_owned()).unwrap_or_default()
        };
        let v = p.properties.api_version;
        let timestamp_valid_bits = p.queue_family.timestamp_valid_bits;
        let wide_lines = p.enabled.wide_lines == vk::TRUE;
        Self {
            device_name: c_str(p.properties.device_name_as_c_str()),
            driver_name: c_str(p.driver.driver_name_as_c_str()),
            driver_info: c_str(p.driver.driver_info_as_c_str()),
            device_type: device_type_name(p.properties.device_type).to_owned(),
            api_version: format!(
                "{}.{}.{}",
                vk::api_version_major(v),
                vk::api_version_minor(v),
                vk::api_version_patch(v)
            ),
            depth_bounds: p.enabled.depth_bounds == vk::TRUE,
            watertight_clipping: p.driver.driver_id != vk::DriverId::GOOGLE_SWIFTSHADER,
            depth_clamp: p.enabled.depth_clamp == vk::TRUE,
            depth_bias_clamp: p.enabled.depth_bias_clamp == vk::TRUE,
            pipeline_statistics: p.enabled.pipeline_statistics_query == vk::TRUE,
            timestamps: timestamp_valid_bits > 0 && limits.timestamp_period > 0.0,
            timestamp_period_ns: limits.timestamp_period,
            timestamp_valid_bits,
            geometry_shader: p.enabled.geometry_shader == vk::TRUE,
            fragment_stores_and_atomics: p.enabled.fragment_stores_and_atomics == vk::TRUE,
            storage_image_extended_formats: p.enabled.shader_storage_image_extended_formats == vk::TRUE,
            compute_queue: p.queue_family.queue_flags.contains(vk::QueueFlags::COMPUTE),
            wide_lines,
            line_width_range: if wide_lines { limits.line_width_range } else { [1.0, 1.0] },
            conservative_rasterization: p.conservative_rasterization,
            depth_stencil_formats: p.depth_stencil_formats.iter().map(|f| format!("{f:?}")).collect(),
            depth_stencil_format: p.depth_stencil_formats.first().copied().unwrap_or(vk::Format::UNDEFINED),
            depth32_sampled: p.depth32_sampled,
            rg32f_blend: p.rg32f_blend,
            ray_query: p.ray_query,
            max_image_dimension_2d: limits.max_image_dimension2_d,
            max_image_dimension_cube: limits.max_image_dimension_cube,
            max_image_array_layers: limits.max_image_array_layers,
            max_framebuffer_width: limits.max_framebuffer_width,
            max_framebuffer_height: limits.max_framebuffer_height,
            max_viewport_dimensions: limits.max_viewport_dimensions,
            max_storage_buffer_range: limits.max_storage_buffer_range,
            max_uniform_buffer_range: limits.max_uniform_buffer_range,
            max_buffer_size: p.maintenance4.max_buffer_size,
            max_memory_allocation_size: p.maintenance3.max_memory_allocation_size,
            max_push_constants_size: limits.max_push_constants_size,
            sub_pixel_precision_bits: limits.sub_pixel_precision_bits,
        }
    }
}

/// `driverName driverInfo` in one string, as [`Capabilities::driver`] and device selection
/// read it.
pub(crate) fn driver_label(name: &str, info: &str) -> String {
    format!("{name} {info}").trim().to_owned()
}

/// Short lower-case name of a device type.
pub fn device_type_name(t: vk::PhysicalDeviceType) -> &'static str {
    match t {
        vk::PhysicalDeviceType::DISCRETE_GPU => "discrete",
        vk::PhysicalDeviceType::INTEGRATED_GPU => "integrated",
        vk::PhysicalDeviceType::VIRTUAL_GPU => "virtual",
        vk::PhysicalDeviceType::CPU => "cpu",
        _ => "other",
    }
}

/// The optional core features umbra enables when the device has them.
pub(crate) fn wanted_features(supported: &vk::PhysicalDeviceFeatures) -> vk::PhysicalDeviceFeatures {
    vk::PhysicalDeviceFeatures {
        depth_bounds: supported.depth_bounds,
        depth_clamp: supported.depth_clamp,
        pipeline_statistics_query: supported.pipeline_statistics_query,
        geometry_shader: supported.geometry_shader,
        wide_lines: supported.wide_lines,
        fill_mode_non_solid: supported.fill_mode_non_solid,
        depth_bias_clamp: supported.depth_bias_clamp,
        fragment_stores_and_atomics: supported.fragment_stores_and_atomics,
        shader_storage_image_extended_formats: supported.shader_storage_image_extended_formats,
        ..Default::default()
    }
}
