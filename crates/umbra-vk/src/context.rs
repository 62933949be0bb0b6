//! The Vulkan context: instance, device, queue, allocator and capabilities.
//!
//! [`Context::new`] creates everything headless. [`Context::from_external`] wraps an engine's
//! own instance and device (bring-your-own-device) and never destroys them.

use crate::capabilities::{self, Capabilities, Probe, DEPTH_STENCIL_PREFERENCE};
use crate::error::{CallContext, VkError, VkResult};
use crate::selection::{self, Candidate, DEVICE_ENV};
use crate::validation::{self, ValidationCounter};
use ash::vk;
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};
use std::ffi::{CStr, CString};
use std::mem::ManuallyDrop;
use std::sync::{Arc, Mutex, MutexGuard};

/// The environment variable that turns on the Khronos validation layer (`1`).
pub const VALIDATION_ENV: &str = "UMBRA_VALIDATION";
/// The environment variable that turns the layer's synchronization validation off (`0`); it is
/// on whenever validation is.
pub const SYNC_VALIDATION_ENV: &str = "UMBRA_SYNC_VALIDATION";
const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// How [`Context::new`] creates its instance and picks its device.
#[derive(Clone, Debug, Default)]
pub struct ContextOptions {
    /// Enable `VK_LAYER_KHRONOS_validation`; it is an error if the layer is missing.
    pub validation: bool,
    /// With `validation`, also the layer's synchronization validation (hazards between
    /// commands: `SYNC-HAZARD-*` messages), through `VK_EXT_validation_features`; it is an
    /// error if the layer does not offer that extension.
    pub synchronization_validation: bool,
    /// The device to pick: a piece of its name or driver, ignoring case, `-` read as a space
    /// (`swiftshader`, `llvmpipe-mesa-25`, …; see [`crate::selection`]). One that fits two
    /// different devices is [`crate::VkError::AmbiguousDevice`].
    pub device: Option<String>,
    /// Instance extensions for presenting to a window (from [`crate::surface_extensions`]);
    /// when not empty, the device also gets `VK_KHR_swapchain` and [`crate::Swapchain`] can be
    /// used. Empty: headless.
    pub surface_extensions: Vec<&'static CStr>,
}

impl ContextOptions {
    /// Reads `UMBRA_VALIDATION` (`1` turns validation on), `UMBRA_SYNC_VALIDATION` (`0` turns
    /// its synchronization validation off; on otherwise) and `UMBRA_DEVICE`.
    pub fn from_env() -> Self {
        Self {
            validation: std::env::var(VALIDATION_ENV).is_ok_and(|v| v == "1"),
            synchronization_validation: std::env::var(SYNC_VALIDATION_ENV).map_or(true, |v| v != "0"),
            device: std::env::var(DEVICE_ENV).ok().filter(|s| !s.is_empty()),
            surface_extensions: Vec::new(),
        }
    }
}

/// An engine's own Vulkan objects, for [`Context::from_external`].
///
/// Requirements on what the engine created:
/// - the instance and device use Vulkan **1.3**;
/// - the device was created with `VkPhysicalDeviceVulkan13Features::dynamicRendering` and
///   `synchronization2` enabled;
/// - `queue` belongs to `queue_family_index`, a family with `GRAPHICS`; umbra submits to it from
///   the calling thread and waits on a fence, so the engine must not use that queue on another
///   thread during an umbra call;
/// - optional core features (`depthBounds`, `depthClamp`, `pipelineStatisticsQuery`,
///   `geometryShader`, `wideLines`, `depthBiasClamp`, `fillModeNonSolid`,
///   `fragmentStoresAndAtomics`, `shaderStorageImageExtendedFormats`): list in
///   `enabled_features` exactly those the engine enabled; umbra's [`Capabilities`] report them and
///   techniques that need a missing one fall back or return [`VkError::Unsupported`];
/// - `VK_EXT_debug_utils` on the instance is optional: with it, umbra names its objects and
///   labels its passes.
pub struct ExternalDevice {
    /// The loaded Vulkan entry points.
    pub entry: ash::Entry,
    /// The engine's instance.
    pub instance: ash::Instance,
    /// The physical device behind `device`.
    pub physical_device: vk::PhysicalDevice,
    /// The engine's logical device.
    pub device: ash::Device,
    /// A graphics queue of `device`.
    pub queue: vk::Queue,
    /// The family of `queue`.
    pub queue_family_index: u32,
    /// The core features the engine enabled on `device`.
    pub enabled_features: vk::PhysicalDeviceFeatures,
    /// Whether `VK_EXT_debug_utils` is enabled on the instance.
    pub debug_utils: bool,
    /// Whether `VK_EXT_conservative_rasterization` is enabled on the device.
    pub conservative_rasterization: bool,
    /// Whether the instance has the window system's surface extensions and the device
    /// `VK_KHR_swapchain`, so that [`crate::Swapchain`] may present with it.
    pub presentation: bool,
}

/// Debug-utils function tables and, when umbra owns the instance, its messenger.
struct DebugUtils {
    instance: ash::ext::debug_utils::Instance,
    device: ash::ext::debug_utils::Device,
    messenger: vk::DebugUtilsMessengerEXT,
}

pub(crate) struct Inner {
    pub(crate) entry: ash::Entry,
    pub(crate) instance: ash::Instance,
    pub(crate) physical_device: vk::PhysicalDevice,
    pub(crate) device: ash::Device,
    queue: Mutex<vk::Queue>,
    pub(crate) queue_family: u32,
    caps: Capabilities,
    allocator: ManuallyDrop<Mutex<Allocator>>,
    pub(crate) command_pool: Mutex<vk::CommandPool>,
    debug: Option<DebugUtils>,
    counter: Arc<ValidationCounter>,
    /// Memory allocations made for buffers and images so far.
    allocations: std::sync::atomic::AtomicU64,
    /// Queue submissions umbra made so far.
    submissions: std::sync::atomic::AtomicU64,
    owns_device: bool,
    pub(crate) presentation: bool,
}

/// A cheaply clonable handle on umbra's Vulkan state; resources keep one to free themselves.
#[derive(Clone)]
pub struct Context {
    pub(crate) inner: Arc<Inner>,
}

impl std::fmt::Debug for Context {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Context").field("device", &self.inner.caps.device_name).finish_non_exhaustive()
    }
}

impl Context {
    /// Creates a headless instance and device from [`ContextOptions::from_env`].
    pub fn new() -> VkResult<Self> {
        Self::with_options(&ContextOptions::from_env())
    }

    /// Creates a headless instance and device.
    pub fn with_options(options: &ContextOptions) -> VkResult<Self> {
        // SAFETY: loading the system loader library; ash checks the symbols it resolves.
        let entry = unsafe { ash::Entry::load()? };
        let counter = Arc::new(ValidationCounter::default());
        let (instance, debug_instance, messenger) = create_instance(&entry, options, &counter)?;
        let presentation = !options.surface_extensions.is_empty();
        let built = pick_and_create_device(&instance, options.device.as_deref(), presentation);
        let (physical_device, device, queue_family, enabled, conservative) = match built {
            Ok(b) => b,
            Err(e) => {
                // SAFETY: nothing else was created from the instance.
                unsafe {
                    if let Some(d) = &debug_instance {
                        d.destroy_debug_utils_messenger(messenger, None);
                    }
                    instance.destroy_instance(None);
                }
                return Err(e);
            }
        };
        // SAFETY: family `queue_family` was requested with one queue at device creation.
        let queue = unsafe { device.get_device_queue(queue_family, 0) };
        let debug = debug_instance.map(|di| DebugUtils {
            device: ash::ext::debug_utils::Device::new(&instance, &device),
            instance: di,
            messenger,
        });
        Self::assemble(Assembly {
            entry,
            instance,
            physical_device,
            device,
            queue,
            queue_family,
            enabled,
            debug,
            conservative,
            counter,
            owns_device: true,
            presentation,
        })
    }

    /// Wraps an engine's own instance and device; see [`ExternalDevice`] for what they need.
    ///
    /// umbra never destroys the external instance or device; it only frees what it created.
    /// Validation messages are counted only by a messenger umbra creates, so with an external
    /// instance [`Context::validation`] stays at zero: the engine's own messenger sees them.
    pub fn from_external(ext: ExternalDevice) -> VkResult<Self> {
        // SAFETY: the caller guarantees `physical_device` belongs to `instance`.
        let props = unsafe { ext.instance.get_physical_device_properties(ext.physical_device) };
        let name = props.device_name_as_c_str().map(|c| c.to_string_lossy().into_owned()).unwrap_or_default();
        if props.api_version < vk::API_VERSION_1_3 {
            return Err(VkError::Unsupported { device: name, what: "Vulkan 1.3 (device reports less)".into() });
        }
        let debug = ext.debug_utils.then(|| DebugUtils {
            instance: ash::ext::debug_utils::Instance::new(&ext.entry, &ext.instance),
            device: ash::ext::debug_utils::Device::new(&ext.instance, &ext.device),
            messenger: vk::DebugUtilsMessengerEXT::null(),
        });
        Self::assemble(Assembly {
            entry: ext.entry,
            instance: ext.instance,
            physical_device: ext.physical_device,
            device: ext.device,
            queue: ext.queue,
            queue_family: ext.queue_family_index,
            enabled: ext.enabled_features,
            debug,
            conservative: ext.conservative_rasterization,
            counter: Arc::new(ValidationCounter::default()),
            owns_device: false,
            presentation: ext.presentation,
        })
    }

    fn assemble(a: Assembly) -> VkResult<Self> {
        let caps = probe(&a.instance, a.physical_device, a.queue_family, &a.enabled, a.conservative);
        let allocator = Allocator::new(&AllocatorCreateDesc {
            instance: a.instance.clone(),
            device: a.device.clone(),
            physical_device: a.physical_device,
            debug_settings: Default::default(),
            buffer_device_address: false,
            allocation_sizes: Default::default(),
        });
        let allocator = match allocator {
            Ok(al) => al,
            Err(source) => {
                a.teardown();
                return Err(VkError::Allocation {
                    name: "umbra-vk's allocator (creating it)".into(),
                    bytes: 0,
                    source,
                });
            }
        };
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(a.queue_family)
            .flags(vk::CommandPoolCreateFlags::TRANSIENT | vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: valid device; the pool is destroyed in `Inner::drop`.
        let pool = match unsafe { a.device.create_command_pool(&pool_info, None) }.call("vkCreateCommandPool") {
            Ok(p) => p,
            Err(e) => {
                drop(allocator);
                a.teardown();
                return Err(e);
            }
        };
        log::info!("umbra-vk: using {} ({}, {})", caps.device_name, caps.driver_name, caps.driver_info);
        let ctx = Context {
            inner: Arc::new(Inner {
                entry: a.entry,
                instance: a.instance,
                physical_device: a.physical_device,
                device: a.device,
                queue: Mutex::new(a.queue),
                queue_family: a.queue_family,
                caps,
                allocator: ManuallyDrop::new(Mutex::new(allocator)),
                command_pool: Mutex::new(pool),
                debug: a.debug,
                counter: a.counter,
                allocations: std::sync::atomic::AtomicU64::new(0),
                submissions: std::sync::atomic::AtomicU64::new(0),
                owns_device: a.owns_device,
                presentation: a.presentation,
            }),
        };
        ctx.set_name(pool, "umbra command pool");
        Ok(ctx)
    }

    /// What the device can do (probed once at creation).
    pub fn capabilities(&self) -> &Capabilities {
        &self.inner.caps
    }

    /// The validation-message counter (zero when validation is off or the instance is external).
    pub fn validation(&self) -> Arc<ValidationCounter> {
        Arc::clone(&self.inner.counter)
    }

    /// The raw `ash` device, for engines that record umbra's work into their own command buffers.
    pub fn device(&self) -> &ash::Device {
        &self.inner.device
    }

    /// The raw instance.
    pub fn instance(&self) -> &ash::Instance {
        &self.inner.instance
    }

    /// The physical device.
    pub fn physical_device(&self) -> vk::PhysicalDevice {
        self.inner.physical_device
    }

    /// The graphics queue family umbra submits to.
    pub fn queue_family(&self) -> u32 {
        self.inner.queue_family
    }

    /// Whether this context can present to windows ([`crate::Swapchain`]): created with
    /// [`ContextOptions::surface_extensions`], or an external device that says so.
    pub fn presentation(&self) -> bool {
        self.inner.presentation
    }

    /// Whether object names and pass labels reach the debug-utils extension.
    pub fn debug_utils(&self) -> bool {
        self.inner.debug.is_some()
    }

    /// Gives a Vulkan object a debug name (RenderDoc, validation messages). No-op without
    /// debug utils.
    pub fn set_name<H: vk::Handle>(&self, handle: H, name: &str) {
        let Some(d) = &self.inner.debug else { return };
        let Ok(name) = CString::new(name.replace('\0', " ")) else {
            return;
        };
        let info = vk::DebugUtilsObjectNameInfoEXT::default().object_handle(handle).object_name(&name);
        // SAFETY: `handle` is a live object of this device; the name outlives the call.
        if let Err(e) = unsafe { d.device.set_debug_utils_object_name(&info) } {
            log::debug!("vkSetDebugUtilsObjectNameEXT({name:?}) failed: {e}");
        }
    }

    pub(crate) fn debug_device(&self) -> Option<&ash::ext::debug_utils::Device> {
        self.inner.debug.as_ref().map(|d| &d.device)
    }

    /// How many device-memory allocations umbra made through this context so far (one per
    /// buffer or image it created): the difference across a frame is what the frame allocated.
    pub fn memory_allocations(&self) -> u64 {
        self.inner.allocations.load(std::sync::atomic::Ordering::Relaxed)
    }

    /// How many command buffers umbra submitted and waited for through this context so far
    /// ([`Context::submit_and_wait`]; not a [`crate::Swapchain`]'s presentation copies, and
    /// never an engine's command buffers, which the engine submits).
    pub fn submissions(&self) -> u64 {
        self.inner.submissions.load(std::sync::atomic::Ordering::Relaxed)
    }

    pub(crate) fn count_submission(&self) {
        self.inner.submissions.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    }

    pub(crate) fn count_allocation(&self) {
        self.inner.allocations.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    }

    pub(crate) fn allocator(&self) -> VkResult<MutexGuard<'_, Allocator>> {
        self.inner.allocator.lock().map_err(|_| VkError::Poisoned)
    }

    pub(crate) fn queue(&self) -> VkResult<MutexGuard<'_, vk::Queue>> {
        self.inner.queue.lock().map_err(|_| VkError::Poisoned)
    }

    /// Waits until the device is idle.
    pub fn wait_idle(&self) -> VkResult<()> {
        let _q = self.queue()?;
        // SAFETY: the queue lock is held, so no submission races the wait.
        unsafe { self.inner.device.device_wait_idle() }.call("vkDeviceWaitIdle")
    }

    /// An `Unsupported` error naming this device.
    pub fn unsupported(&self, what: impl Into<String>) -> VkError {
        VkError::Unsupported { device: self.inner.caps.device_name.clone(), what: what.into() }
    }
}

struct Assembly {
    entry: ash::Entry,
    instance: ash::Instance,
    physical_device: vk::PhysicalDevice,
    device: ash::Device,
    queue: vk::Queue,
    queue_family: u32,
    enabled: vk::PhysicalDeviceFeatures,
    debug: Option<DebugUtils>,
    conservative: bool,
    counter: Arc<ValidationCounter>,
    owns_device: bool,
    presentation: bool,
}

impl Assembly {
    /// Destroys what `Context::with_options` created when assembling the context failed.
    fn teardown(&self) {
        if !self.owns_device {
            return;
        }
        // SAFETY: nothing else was created from this device and instance.
        unsafe {
            self.device.destroy_device(None);
            if let Some(d) = &self.debug {
                d.instance.destroy_debug_utils_messenger(d.messenger, None);
            }
            self.instance.destroy_instance(None);
        }
    }
}

impl Drop for Inner {
    fn drop(&mut self) {
        // SAFETY: last owner of the context: every resource holding a `Context` is gone, so
        // after the idle wait nothing of ours is in use. External instance/device are kept.
        unsafe {
            let _ = self.device.device_wait_idle();
            if let Ok(pool) = self.command_pool.get_mut() {
                self.device.destroy_command_pool(*pool, None);
            }
            ManuallyDrop::drop(&mut self.allocator);
            if self.owns_device {
                self.device.destroy_device(None);
                if let Some(d) = &self.debug {
                    d.instance.destroy_debug_utils_messenger(d.messenger, None);
                }
                self.instance.destroy_instance(None);
            }
        }
    }
}

type InstanceParts = (ash::Instance, Option<ash::ext::debug_utils::Instance>, vk::DebugUtilsMessengerEXT);

fn create_instance(
    entry: &ash::Entry,
    options: &ContextOptions,
    counter: &Arc<ValidationCounter>,
) -> VkResult<InstanceParts> {
    // SAFETY: plain queries of the loader.
    let (layers, exts) = unsafe {
        (
            entry.enumerate_instance_layer_properties().call("vkEnumerateInstanceLayerProperties")?,
            entry.enumerate_instance_extension_properties(None).call("vkEnumerateInstanceExtensionProperties")?,
        )
    };
    let has_ext = |n: &CStr| exts.iter().any(|e| e.extension_name_as_c_str() == Ok(n));
    let mut layer_names = Vec::new();
    if options.validation {
        if !layers.iter().any(|l| l.layer_name_as_c_str() == Ok(VALIDATION_LAYER)) {
            return Err(VkError::ValidationLayerMissing);
        }
        layer_names.push(VALIDATION_LAYER.as_ptr());
    }
    let sync_validation = options.validation && options.synchronization_validation;
    if sync_validation {
        // SAFETY: a plain query of the loader for the layer's own instance extensions.
        let layer_exts = unsafe { entry.enumerate_instance_extension_properties(Some(VALIDATION_LAYER)) }
            .call("vkEnumerateInstanceExtensionProperties")?;
        if !layer_exts.iter().any(|e| e.extension_name_as_c_str() == Ok(ash::ext::validation_features::NAME)) {
            return Err(VkError::Unsupported {
                device: "the validation layer".into(),
                what: "synchronization validation (VK_EXT_validation_features)".into(),
            });
        }
    }
    let debug_utils = has_ext(ash::ext::debug_utils::NAME) || options.validation;
    let mut ext_names = Vec::new();
    if debug_utils {
        ext_names.push(ash::ext::debug_utils::NAME.as_ptr());
    }
    for &name in &options.surface_extensions {
        if !has_ext(name) {
            return Err(VkError::Unsupported {
                device: "the Vulkan instance".into(),
                what: format!("presenting to this window system ({} is missing)", name.to_string_lossy()),
            });
        }
        ext_names.push(name.as_ptr());
    }
    if sync_validation {
        ext_names.push(ash::ext::validation_features::NAME.as_ptr());
    }
    let mut flags = vk::InstanceCreateFlags::empty();
    if has_ext(ash::khr::portability_enumeration::NAME) {
        ext_names.push(ash::khr::portability_enumeration::NAME.as_ptr());
        flags |= vk::InstanceCreateFlags::ENUMERATE_PORTABILITY_KHR;
    }
    let app = vk::ApplicationInfo::default()
        .application_name(c"umbra")
        .engine_name(c"umbra")
        .api_version(vk::API_VERSION_1_3);
    let mut messenger_info = validation::messenger_info(counter);
    let mut info = vk::InstanceCreateInfo::default()
        .application_info(&app)
        .enabled_layer_names(&layer_names)
        .enabled_extension_names(&ext_names)
        .flags(flags);
    if debug_utils {
        info = info.push_next(&mut messenger_info);
    }
    let enabled = [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
    let mut features = vk::ValidationFeaturesEXT::default().enabled_validation_features(&enabled);
    if sync_validation {
        info = info.push_next(&mut features);
    }
    // SAFETY: every pointer in `info` outlives the call.
    let instance = unsafe { entry.create_instance(&info, None) }.call("vkCreateInstance")?;
    if !debug_utils {
        return Ok((instance, None, vk::DebugUtilsMessengerEXT::null()));
    }
    let di = ash::ext::debug_utils::Instance::new(entry, &instance);
    let messenger_info = validation::messenger_info(counter);
    // SAFETY: the counter the messenger points at lives in the context's `Arc` until after the
    // messenger is destroyed in `Inner::drop`.
    match unsafe { di.create_debug_utils_messenger(&messenger_info, None) } {
        Ok(m) => Ok((instance, Some(di), m)),
        Err(result) => {
            // SAFETY: nothing else was created from this instance.
            unsafe { instance.destroy_instance(None) };
            Err(VkError::Call { call: "vkCreateDebugUtilsMessengerEXT", result })
        }
    }
}

type DeviceParts = (vk::PhysicalDevice, ash::Device, u32, vk::PhysicalDeviceFeatures, bool);

fn pick_and_create_device(instance: &ash::Instance, wanted: Option<&str>, presentation: bool) -> VkResult<DeviceParts> {
    // SAFETY: plain queries of a live instance.
    let physical = unsafe { instance.enumerate_physical_devices() }.call("vkEnumeratePhysicalDevices")?;
    // SAFETY: every `pd` comes from this live instance.
    let candidates: Vec<Candidate> = physical.iter().map(|&pd| unsafe { Candidate::query(instance, pd) }).collect();
    let i = selection::choose(&candidates, wanted)?;
    let pd = physical[i];
    let family = candidates[i].graphics_family.ok_or_else(|| VkError::NoDevice { wanted: None, available: vec![] })?;
    // SAFETY: plain queries of a live physical device.
    let (supported, exts) = unsafe {
        (
            instance.get_physical_device_features(pd),
            instance.enumerate_device_extension_properties(pd).call("vkEnumerateDeviceExtensionProperties")?,
        )
    };
    let has_ext = |n: &CStr| exts.iter().any(|e| e.extension_name_as_c_str() == Ok(n));
    let enabled = capabilities::wanted_features(&supported);
    let mut ext_names = Vec::new();
    let conservative = has_ext(ash::ext::conservative_rasterization::NAME);
    if conservative {
        ext_names.push(ash::ext::conservative_rasterization::NAME.as_ptr());
    }
    if has_ext(ash::khr::portability_subset::NAME) {
        ext_names.push(ash::khr::portability_subset::NAME.as_ptr());
    }
    if presentation {
        if !has_ext(ash::khr::swapchain::NAME) {
            let name = candidates[i].name.clone();
            return Err(VkError::Unsupported {
                device: name,
                what: "presenting to a window (VK_KHR_swapchain)".into(),
            });
        }
        ext_names.push(ash::khr::swapchain::NAME.as_ptr());
    }
    let priorities = [1.0f32];
    let queues = [vk::DeviceQueueCreateInfo::default().queue_family_index(family).queue_priorities(&priorities)];
    // maintenance4 (core in 1.3, optional) relaxes vertex-output/fragment-input matching, so
    // one vertex shader serves fragment shaders that read fewer of its outputs.
    let mut supported13 = vk::PhysicalDeviceVulkan13Features::default();
    {
        let mut f2 = vk::PhysicalDeviceFeatures2::default().push_next(&mut supported13);
        // SAFETY: plain query of a live physical device.
        unsafe { instance.get_physical_device_features2(pd, &mut f2) };
    }
    let mut f13 = vk::PhysicalDeviceVulkan13Features::default()
        .dynamic_rendering(true)
        .synchronization2(true)
        .maintenance4(supported13.maintenance4 == vk::TRUE);
    let info = vk::DeviceCreateInfo::default()
        .queue_create_infos(&queues)
        .enabled_extension_names(&ext_names)
        .enabled_features(&enabled)
        .push_next(&mut f13);
    // SAFETY: every pointer in `info` outlives the call; features were checked as supported.
    let device = unsafe { instance.create_device(pd, &info, None) }.call("vkCreateDevice")?;
    Ok((pd, device, family, enabled, conservative))
}

fn probe(
    instance: &ash::Instance,
    pd: vk::PhysicalDevice,
    family: u32,
    enabled: &vk::PhysicalDeviceFeatures,
    conservative: bool,
) -> Capabilities {
    // SAFETY: plain queries of a live physical device.
    unsafe {
        let properties = instance.get_physical_device_properties(pd);
        let mut driver = vk::PhysicalDeviceDriverProperties::default();
        let mut maintenance3 = vk::PhysicalDeviceMaintenance3Properties::default();
        let mut maintenance4 = vk::PhysicalDeviceMaintenance4Properties::default();
        {
            let mut p2 = vk::PhysicalDeviceProperties2::default()
                .push_next(&mut driver)
                .push_next(&mut maintenance3)
                .push_next(&mut maintenance4);
            instance.get_physical_device_properties2(pd, &mut p2);
        }
        let families = instance.get_physical_device_queue_family_properties(pd);
        let queue_family = families.get(family as usize).copied().unwrap_or_default();
        let supports = |f: vk::Format, feat: vk::FormatFeatureFlags| {
            instance.get_physical_device_format_properties(pd, f).optimal_tiling_features.contains(feat)
        };
        let depth_stencil_formats = DEPTH_STENCIL_PREFERENCE
            .into_iter()
            .filter(|&f| supports(f, vk::FormatFeatureFlags::DEPTH_STENCIL_ATTACHMENT))
            .collect();
        let depth32_sampled = supports(
            vk::Format::D32_SFLOAT,
            vk::FormatFeatureFlags::DEPTH_STENCIL_ATTACHMENT | vk::FormatFeatureFlags::SAMPLED_IMAGE,
        );
        Capabilities::from_parts(Probe {
            properties: &properties,
            driver: &driver,
            maintenance3: &maintenance3,
            maintenance4: &maintenance4,
            enabled,
            queue_family: &queue_family,
            conservative_rasterization: conservative,
            depth_stencil_formats,
            depth32_sampled,
            rg32f_blend: supports(
                vk::Format::R32G32_SFLOAT,
                vk::FormatFeatureFlags::COLOR_ATTACHMENT | vk::FormatFeatureFlags::COLOR_ATTACHMENT_BLEND,
            ),
            ray_query: ray_query_offered(instance, pd),
        })
    }
}

/// Whether the physical device offers ray queries: `VK_KHR_ray_query` and
/// `VK_KHR_acceleration_structure` among its extensions and the `rayQuery` feature (asked for
/// only when the extensions are there, as the spec requires).
fn ray_query_offered(instance: &ash::Instance, pd: vk::PhysicalDevice) -> bool {
    // SAFETY: plain queries of a live physical device; the feature struct is chained only when
    // its extension is offered.
    unsafe {
        let Ok(exts) = instance.enumerate_device_extension_properties(pd) else { return false };
        let has = |n: &CStr| exts.iter().any(|e| e.extension_name_as_c_str() == Ok(n));
        if !(has(ash::khr::ray_query::NAME) && has(ash::khr::acceleration_structure::NAME)) {
            return false;
        }
        let mut ray_query = vk::PhysicalDeviceRayQueryFeaturesKHR::default();
        let mut f2 = vk::PhysicalDeviceFeatures2::default().push_next(&mut ray_query);
        instance.get_physical_device_features2(pd, &mut f2);
        ray_query.ray_query == vk::TRUE
    }
}
